#!/usr/bin/env bash
# The README's "Install, and use exoid from your own CMake project", run verbatim: its shell block
# (HOME in a scratch folder, the build tree as ./build; scripts/build.sh is skipped, the tree is
# built) installs and runs the installed exoid; its CMake block (tests/install/consumer/CMakeLists.txt
# must be that block) builds a project against the installed package, once as is and once with
# -march=native. Then the installed Python module imports from the prefix alone, and the package
# must not point back into the source or build tree. Usage: run_consumer.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

block() {  # LANGUAGE: the first fenced block of that language in the README's install section
  awk -v lang="$1" '/^## Install, and use exoid/ { on = 1 } on && /^## / && !/Install, and use exoid/ { exit }
                    on && $0 == "```" lang { inside = 1; next } inside && /^```/ { exit } inside { print }' "$src/README.md"
}

# The shell block, without the build step.
mkdir -p "$work/home" "$work/root"
ln -s "$build" "$work/root/build"
shell=$(block sh | grep -v '^scripts/build.sh')
[[ -n "$shell" ]] || { echo "README: no shell block in the install section"; exit 1; }
if ! grep -q '^  truth' <<<"$("$build/experiments/exoid" --help)"; then
  shell=$(grep -v 'exoid" truth' <<<"$shell")  # built without MuJoCo: no `truth`
  without_mujoco=1
fi
out=$(cd "$work/root" && HOME="$work/home" bash -euo pipefail -c "$shell" 2>&1) || { echo "$out"; exit 1; }
prefix="$work/home/.local"
if [[ -z "${without_mujoco:-}" ]]; then
  grep -q "$prefix/share/exoid/models/apal_leg.xml" <<<"$out" || { echo "exoid truth did not use the installed model:"; echo "$out"; exit 1; }
  echo "installed exoid uses $prefix/share/exoid"
else
  "$prefix/bin/exoid" identify --help > /dev/null
  echo "installed exoid (without MuJoCo) runs"
fi

# The package must not point back into the trees it came from (they may be moved or deleted).
if grep -rlF -e "$src" -e "$build" "$prefix/lib"*/cmake "$prefix/include"; then
  echo "the installed package refers to the source or build tree (files above)"
  exit 1
fi

# The CMake block is the consumer's CMakeLists.txt.
if ! diff <(block cmake) "$src/tests/install/consumer/CMakeLists.txt"; then
  echo "README's CMake block and tests/install/consumer/CMakeLists.txt differ (above)"
  exit 1
fi
cp -r "$src/tests/install/consumer" "$work/consumer_src"
build_consumer() {  # DIR [CXX flags]
  cmake -S "$work/consumer_src" -B "$1" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_CXX_FLAGS="${2:-}" > "$work/configure.log" || { cat "$work/configure.log"; exit 1; }
  cmake --build "$1" > "$work/build.log" || { cat "$work/build.log"; exit 1; }
}
build_consumer "$work/consumer"
"$work/consumer/my_tool"
if [[ -x "$work/consumer/my_sim" ]]; then
  # The library's compiled-in data directory is the prefix it was configured for, not this scratch
  # one: point it there, as a relocated install would.
  EXOID_DATA_DIR="$prefix/share/exoid" "$work/consumer/my_sim"
fi
# A user's project built for its own CPU links the portable libraries: Eigen's object layout and
# allocator must agree across the two (cmake/ExoidOptions.cmake), or this crashes.
if echo 'int main(){}' | c++ -march=native -x c++ - -o "$work/native_probe" 2> /dev/null; then
  build_consumer "$work/consumer_native" -march=native
  "$work/consumer_native/my_tool"
fi

# The installed Python module imports from the prefix alone.
pydir=$(ls -d "$prefix"/lib*/python3/dist-packages 2>/dev/null | head -1 || true)
if [[ -n "$pydir" ]] && ls "$pydir"/exoid*.so > /dev/null 2>&1; then
  # simulate() finds the model in the prefix's share/exoid, above the module's own folder.
  (cd "$work" && PYTHONPATH="$pydir" /usr/bin/python3 -c "
import exoid
assert exoid.param_names()[0] == 'Mxt'
print('python: import exoid from', exoid.__file__)
if exoid.has_simulator:
    model = exoid.simulate(duration=0.05)['sidecar']['model']
    assert model['path'].startswith('$prefix/share/exoid/'), model
    print('python: simulate() uses', model['path'])
")
fi
