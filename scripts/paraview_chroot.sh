#!/usr/bin/env bash
# Makes the minimal Debian 12 chroot in which scripts/paraview_check.sh runs Debian's own
# ParaView 5.11 (its python3-paraview cannot be installed beside libvtk9-dev):
#   bash scripts/paraview_chroot.sh
# PARAVIEW_ROOT, default /srv/ishibashi-paraview; about 1.5 GiB, a few minutes of download
# (.ci/run starts it while the code builds); needs root. Returns at once when it is made.
set -euo pipefail
chroot_dir=${PARAVIEW_ROOT:-/srv/ishibashi-paraview}
[ -x "$chroot_dir/usr/bin/pvbatch" ] && exit 0
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "paraview_chroot: making a Debian 12 chroot with ParaView in $chroot_dir (once)"
export DEBIAN_FRONTEND=noninteractive
if ! command -v debootstrap > /dev/null; then
  $sudo apt-get update -q
  $sudo apt-get install -y -q --no-install-recommends debootstrap
fi
$sudo debootstrap --variant=minbase bookworm "$chroot_dir" http://deb.debian.org/debian > "$chroot_dir.log" 2>&1 ||
  { tail -20 "$chroot_dir.log"; exit 1; }
$sudo chroot "$chroot_dir" apt-get install -y -q --no-install-recommends paraview python3-paraview xvfb xauth \
  >> "$chroot_dir.log" 2>&1 || { tail -20 "$chroot_dir.log"; exit 1; }
