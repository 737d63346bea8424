#!/usr/bin/env bash
# Fuzzes every input reader with libFuzzer (clang, AddressSanitizer and UBSan), RUNS
# executions each (default 1,000,000), then merges the inputs that found new code into
# the committed corpus tests/fuzz/corpus/<reader> (which every test run replays).
#   bash scripts/fuzz.sh [reader...]     (default: all; see tests/fuzz/CMakeLists.txt)
# A crash, hang (> 10 s) or allocation above 2 GiB stops with the input saved as
# build-fuzz/crash-* etc.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/setup.sh"
if ! command -v clang++ > /dev/null || [ ! -d /usr/lib/llvm-14/lib/clang ]; then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get install -y -q --no-install-recommends clang libclang-rt-14-dev
fi
build="$root/build-fuzz"
# vptr left out, as in the sanitizer build (CMakeLists.txt): CGAL's arrangements (the
# validation's shared faces) downcast their iterators through a filtering base, which
# UBSan's vptr check reports at each use, and each report's demangled names leak.
# No recovery: UBSan's default prints a report and goes on, which libFuzzer does not count
# (a checkpoint's signed overflow went by so in session 79, found by CI's sanitizer replay).
flags="-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize=vptr -fno-sanitize-recover=all -fno-omit-frame-pointer -g"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DISHIBASHI_FUZZ=ON \
  -DISHIBASHI_BUILD_PERF=OFF -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > /dev/null
readers=("$@")
[ ${#readers[@]} -gt 0 ] || readers=(at2 knet columns model scenario study sweep off obj stl checkpoint)
cmake --build "$build" --target "${readers[@]/#/fuzz_}"
cd "$build"
for reader in "${readers[@]}"; do
  corpus="$root/tests/fuzz/corpus/$reader" work="$build/corpus/$reader"
  mkdir -p "$work"
  echo "== $reader"
  ASAN_OPTIONS=detect_leaks=1 "./tests/fuzz/fuzz_$reader" -runs="${RUNS:-1000000}" -max_len=4096 -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 "$work" "$corpus" 2>&1 | grep -E "stat::number_of_executed_units|ERROR|Done" || true
  "./tests/fuzz/fuzz_$reader" -merge=1 "$corpus" "$work" > /dev/null 2>&1  # keep what covers new code
done
findings=$(find . -maxdepth 1 \( -name 'crash-*' -o -name 'timeout-*' -o -name 'oom-*' -o -name 'leak-*' \) -newer "$build/build.ninja")
if [ -n "$findings" ]; then echo "fuzz: findings: $findings"; exit 1; fi
echo "fuzz: no crash, hang or runaway allocation"
