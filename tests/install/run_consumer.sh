#!/usr/bin/env bash
# Installs the build tree into a scratch prefix, then builds and runs a project that finds exoid
# with find_package and links its libraries, and runs the installed exoid, which must find its
# data beside itself (not in the source tree). Usage: run_consumer.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
src=$(cd "$2" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
# The package must not point back into the trees it came from (they may be moved or deleted).
if grep -rlF -e "$src" -e "$(cd "$build" && pwd)" "$work/prefix/lib"*/cmake "$work/prefix/include"; then
  echo "the installed package refers to the source or build tree (files above)"
  exit 1
fi
cp -r "$src/tests/install/consumer" "$work/consumer_src"
build_consumer() {  # DIR [CXX flags]
  cmake -S "$work/consumer_src" -B "$1" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$work/prefix" \
    -DCMAKE_CXX_FLAGS="${2:-}" > "$work/configure.log"
  cmake --build "$1" > "$work/build.log" || { cat "$work/build.log"; exit 1; }
}
build_consumer "$work/consumer"
"$work/consumer/consumer"
# A user's project built for its own CPU links the portable libraries: Eigen's object layout and
# allocator must agree across the two (cmake/ExoidOptions.cmake), or this crashes.
if echo 'int main(){}' | c++ -march=native -x c++ - -o "$work/native_probe" 2> /dev/null; then
  build_consumer "$work/consumer_native" -march=native
  "$work/consumer_native/consumer"
fi
if [[ -x "$work/consumer/consumer_sim" ]]; then
  # The library's install data directory is the prefix it was configured for, not this scratch
  # one: point it there, as a relocated install would.
  EXOID_DATA_DIR="$work/prefix/share/exoid" "$work/consumer/consumer_sim"
fi
# The installed Python module imports from the prefix alone.
pydir=$(ls -d "$work"/prefix/lib*/python3/dist-packages 2>/dev/null | head -1 || true)
if [[ -n "$pydir" ]] && ls "$pydir"/exoid*.so > /dev/null 2>&1; then
  (cd "$work" && PYTHONPATH="$pydir" /usr/bin/python3 -c "import exoid; assert exoid.param_names()[0] == 'Mxt'; print('python: import exoid from', exoid.__file__)")
fi
# The installed binary finds prefix/share/exoid beside itself (built with MuJoCo: `truth` reads
# the built-in model from there; without, the log commands need no data directory).
help=$("$work/prefix/bin/exoid" --help)
if ! grep -q "^  truth" <<<"$help"; then
  "$work/prefix/bin/exoid" identify --help > /dev/null
  echo "installed exoid (without MuJoCo) runs"
  exit 0
fi
out=$("$work/prefix/bin/exoid" truth)
grep -q "$work/prefix/share/exoid/models/apal_leg.xml" <<<"$out" || { echo "exoid truth did not use the installed model:"; echo "$out"; exit 1; }
echo "installed exoid uses $work/prefix/share/exoid"
