#!/usr/bin/env bash
# The README's quick start on a bare Debian 12: a minimal chroot (debootstrap minbase: no
# compiler, no Python, no sudo, no git) gets a clean copy of this checkout's HEAD, then
# runs the two quick-start commands in it as they stand, scripts/test.sh and then
# scripts/run.sh, which must install everything they need themselves:
#   bash scripts/bare_debian_check.sh
# BARE_ROOT, default /srv/ishibashi-bare, is made anew each time (about 3 GiB when done;
# about 20 minutes on 2 cores, most of it the download and the build); needs root and the
# network. Prints each command's wall time and the main job's summary line.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bare=${BARE_ROOT:-/srv/ishibashi-bare}
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
unmount() {
  for m in dev/pts dev sys proc; do
    mountpoint -q "$bare/$m" && $sudo umount "$bare/$m"
  done
  return 0
}
trap unmount EXIT
if ! command -v debootstrap > /dev/null; then
  $sudo apt-get update -q
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends debootstrap
fi
unmount
$sudo rm -rf "$bare"
echo "bare_debian_check: debootstrap minbase bookworm into $bare (log: $bare.log)"
$sudo debootstrap --variant=minbase bookworm "$bare" http://deb.debian.org/debian > "$bare.log" 2>&1 ||
  { tail -20 "$bare.log"; exit 1; }
$sudo cp /etc/resolv.conf "$bare/etc/resolv.conf"
for m in proc sys dev dev/pts; do $sudo mount --bind "/$m" "$bare/$m"; done
$sudo git clone -q "$root" "$bare/root/ishibashi"  # HEAD, as CI's clean clone: no build/ nor out/
for command in test run; do
  start=$(date +%s)
  $sudo chroot "$bare" /usr/bin/env -i HOME=/root PATH=/usr/sbin:/usr/bin:/sbin:/bin \
    /bin/bash -c "cd /root/ishibashi && bash scripts/$command.sh" > "$bare.$command.log" 2>&1 ||
    { tail -30 "$bare.$command.log"; echo "bare_debian_check: scripts/$command.sh failed"; exit 1; }
  echo "bare_debian_check: scripts/$command.sh passed in $(($(date +%s) - start)) s (log: $bare.$command.log)"
done
grep -a "^done after" "$bare.run.log"
grep -a '"state_hash"' "$bare/root/ishibashi/out/nishida_a_kobe_dry/summary.json"
