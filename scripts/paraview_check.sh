#!/usr/bin/env bash
# Opens a run's ParaView series with Debian 12's own ParaView 5.11 (pvbatch, headless
# under Xvfb), checks every frame and renders the last one, then loads the run's state
# file (view.pvsm) from a copy of the folder elsewhere and renders its last frame:
#   bash scripts/paraview_check.sh RUN_DIR [PNG_DIR]
# Debian's python3-paraview cannot be installed beside libvtk9-dev, so ParaView lives in
# a minimal Debian chroot made with debootstrap (scripts/paraview_chroot.sh, once).
# Fails when ParaView cannot read a file (as it could not read VTK's appended mode with
# the patched libexpat) or an array is missing.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
run_dir=$(cd "${1:?usage: paraview_check.sh RUN_DIR [PNG_DIR]}" && pwd)
png_dir=$(mkdir -p "${2:-$run_dir/paraview}" && cd "${2:-$run_dir/paraview}" && pwd)
chroot_dir=${PARAVIEW_ROOT:-/srv/ishibashi-paraview}
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi

bash "$root/scripts/paraview_chroot.sh"

# The run goes in a copy inside the chroot; the pictures come back.
work=$($sudo mktemp -d "$chroot_dir/tmp/check.XXXXXX")
trap '$sudo rm -rf "$work"' EXIT
$sudo cp -r "$run_dir" "$work/run"
$sudo cp "$root/scripts/paraview_render.py" "$root/scripts/paraview_state_check.py" "$work/"
$sudo mkdir -p "$work/png"
inside=${work#"$chroot_dir"}
log="$png_dir/pvbatch.log"
# Xvfb sometimes is not ready when pvbatch connects ("bad X server connection"): try again.
for attempt in 1 2 3; do
  status=0
  $sudo chroot "$chroot_dir" xvfb-run -a pvbatch "$inside/paraview_render.py" "$inside/run" "$inside/png" > "$log" 2>&1 ||
    status=$?
  # The run's state file, loaded from the copy: a moved run folder must still open.
  if [ $status -eq 0 ] && [ -f "$run_dir/view.pvsm" ]; then
    $sudo chroot "$chroot_dir" xvfb-run -a pvbatch "$inside/paraview_state_check.py" "$inside/run" "$inside/png" >> "$log" 2>&1 ||
      status=$?
  fi
  grep -q "bad X server connection" "$log" || break
  sleep 2
done
grep -v -e '^\[hwloc' "$log" || true
cp "$work"/png/*.png "$png_dir"/ 2> /dev/null || true
# pvbatch reports reader errors on stderr and may still exit 0.
if grep -q -E "ERROR|not well-formed|Error parsing XML" "$log"; then
  echo "paraview_check: ParaView reported errors reading $run_dir"
  exit 1
fi
exit $status
