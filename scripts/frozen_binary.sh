#!/usr/bin/env bash
# The program of one commit, frozen: prints out/bin/ishibashi_COMMIT, building it first
# (Release, in a temporary worktree) when it is missing. Long runs resume on it and device
# comparisons carry it, so that a later build never changes a comparison half way. It is
# built in a fixed folder, so that a new checkout rebuilds the same bytes: a finished ensemble
# member's key holds the program's fingerprint (long_runs.sh keeps such members in the
# repository).
#   bash scripts/frozen_binary.sh COMMIT
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
commit=$1
bin="out/bin/ishibashi_$commit"
# One build at a time per commit: two lanes started together share the worktree's folder,
# and the second would remove the first's tree under its build.
exec 9> "/tmp/ishibashi_frozen_$commit.lock"
flock 9
if [[ ! -x $bin ]]; then
  git rev-parse --verify --quiet "$commit^{commit}" > /dev/null || { echo "frozen_binary.sh: $commit is not a commit of this repository" >&2; exit 1; }
  tree=/tmp/ishibashi_frozen_$commit
  git worktree remove --force "$tree" 2> /dev/null || rm -rf "$tree"
  git worktree prune
  git worktree add --detach "$tree" "$commit" > /dev/null
  cmake -S "$tree" -B "$tree/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DISHIBASHI_BUILD_TESTS=OFF \
    -DISHIBASHI_BUILD_PERF=OFF > /dev/null
  cmake --build "$tree/build" --target ishibashi > /dev/null
  mkdir -p out/bin
  cp "$tree/build/apps/ishibashi" "$bin"
  git worktree remove --force "$tree"
fi
echo "$bin"
