#!/usr/bin/env bash
# Packs one device call's programs: this checkout's Release build (after scripts/build.sh)
# as .dev/bin/ishibashi and ishibashi_main, its core_probe, the program of each COMMIT=NAME as
# .dev/bin/ishibashi_NAME (scripts/frozen_binary.sh), and perf/device_*.sh, into
# .devpack/dev.tar.xz: .dev itself, with a second program, passes the 64 MiB that the tree
# and what it carries may weigh together.
#   bash perf/device_pack.sh 41911c5=front
# then the device tool: carry [".devpack"], command
#   tar xJf .devpack/dev.tar.xz && PROGRAMS="front main" bash .dev/device_chunks_ab.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
bash ../shared/tools/device_bundle.sh > /dev/null
cp .dev/bin/ishibashi .dev/bin/ishibashi_main
cp build/perf/core_probe .dev/bin/  # the cores' clock as more are busy (device_threads.sh)
for spec in "$@"; do
  [[ $spec == *=* ]] || { echo "device_pack.sh: '$spec' should be COMMIT=NAME, e.g. 41911c5=front" >&2; exit 1; }
  cp "$(bash scripts/frozen_binary.sh "${spec%%=*}")" ".dev/bin/ishibashi_${spec#*=}"
done
strip .dev/bin/* 2> /dev/null || true
cp perf/device_*.sh .dev/
grep -qx '/.devpack/' .git/info/exclude || echo '/.devpack/' >> .git/info/exclude
mkdir -p .devpack
tar cf - .dev | xz -T0 -6 > .devpack/dev.tar.xz
du -h .devpack/dev.tar.xz
