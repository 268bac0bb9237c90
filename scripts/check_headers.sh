#!/usr/bin/env bash
# Every public header compiles on its own (clang -fsyntax-only of a file that includes just it).
# The unity build batches sources together, so a header that forgets an include can compile in
# one tree and fail in another (the sanitizer tree compiles some sources alone): this catches it
# in every tree at once. Needs a configured build folder for the generated version header.
#   scripts/check_headers.sh [BUILD_DIR]   (default build)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${1:-build}
[[ -d "$build/experiments/generated" ]] || { echo "check_headers.sh: no $build/experiments/generated (configure the build first)" >&2; exit 1; }
cxx=$(command -v clang++-14 || command -v clang++ || command -v c++)
flags=(-std=c++17 -fsyntax-only -DEIGEN_MALLOC_ALREADY_ALIGNED=0 -DEIGEN_MAX_ALIGN_BYTES=16 -DTOML_HEADER_ONLY=0
       -Icore/include -Iident/include -Isim/include -Irender/include -Iexperiments/include -I"$build/experiments/generated"
       -isystem /usr/include/eigen3)
export cxx
export flags_text="${flags[*]}"
check() {
  local rel=${1#*/include/}
  # shellcheck disable=SC2086
  echo "#include \"$rel\"" | "$cxx" $flags_text -x c++ - -o /dev/null 2>/tmp/check_headers.$$.err || { echo "FAIL $1"; head -5 /tmp/check_headers.$$.err; rm -f /tmp/check_headers.$$.err; return 1; }
  rm -f /tmp/check_headers.$$.err
}
export -f check
headers=$(git ls-files '*/include/*.hpp' | grep -v '^tests/')
if [[ ! -d /usr/include/mujoco ]]; then headers=$(grep -v -e '^sim/' -e '^render/' <<<"$headers"); fi
count=$(wc -l <<<"$headers")
xargs -P "$(nproc)" -I{} bash -c 'check {}' <<<"$headers"
echo "check_headers.sh: $count headers compile on their own"
