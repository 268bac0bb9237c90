#!/usr/bin/env bash
# Installs missing dependencies, then configures and builds exoid (Release) into build/.
# Usage: scripts/build.sh [--main] [extra cmake args...]   (BUILD_DIR, BUILD_TYPE, JOBS may be set)
#   --main  only what the main job needs: the `exoid` command (no tests, benchmarks or Python
#           module, and none of their packages); scripts/reproduce.sh uses it.
#   default everything: exoid, tests, benchmarks, the Python module; scripts/test.sh uses it.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${BUILD_DIR:-$root/build}
build_type=${BUILD_TYPE:-Release}
jobs=${JOBS:-$(nproc)}

if [[ "${1:-}" == "--main" ]]; then
  shift
  "$root/scripts/deps.sh" --main
  if [[ -f "$build_dir/CMakeCache.txt" && $# -eq 0 ]]; then
    # Already configured (perhaps with everything by scripts/test.sh): keep that, build one target.
    cmake "$build_dir" >/dev/null
  else
    cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" \
      -DEXOID_BUILD_TESTS=OFF -DEXOID_BUILD_BENCH=OFF -DEXOID_WITH_PYTHON=OFF "$@" >/dev/null
  fi
  cmake --build "$build_dir" -j "$jobs" --target exoid
  exit 0
fi

"$root/scripts/deps.sh"
# Explicit ON: a build folder first configured by --main gets the rest now.
cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" \
  -DEXOID_BUILD_TESTS=ON -DEXOID_BUILD_BENCH=ON -DEXOID_WITH_PYTHON=ON "$@" >/dev/null
cmake --build "$build_dir" -j "$jobs"
