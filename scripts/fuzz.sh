#!/usr/bin/env bash
# Builds exoid's libFuzzer targets (fuzz/) with clang, ASan and UBSan and runs each for SECONDS
# (default 60) from its seed corpus (fuzz/corpus/<target>/), new inputs going to <build>/corpus/.
# The five targets run at the same time, one process each (model_fuzz, the URDF and MJCF readers,
# and excitation_fuzz, the design files, in a tree built with MuJoCo). Installs clang and its fuzzer runtime
# when missing (scripts/deps.sh --with-fuzz). A crash fails the run, with the reproducer in the
# build folder and a non-zero exit.
#   scripts/fuzz.sh [SECONDS]
# FUZZ_SEED (default 1): libFuzzer's seed, so that a run's first inputs are the same every time.
# FUZZ_BUILD_DIR (default build-fuzz): a folder already configured with -DEXOID_FUZZ=ON is reused as
# it is; any other is configured for fuzzing alone (no tests or benchmarks; the heavy
# headers precompiled: a fuzzing tree is throwaway).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$PWD
seconds=${1:-60}
dir=${FUZZ_BUILD_DIR:-build-fuzz}
targets=(dataset_fuzz log_profile_fuzz controller_json_fuzz model_fuzz excitation_fuzz)
scripts/deps.sh --with-fuzz
if ! grep -qs '^EXOID_FUZZ:BOOL=ON' "$dir/CMakeCache.txt"; then
  # libFuzzer's recommended flags (-O1, line tables only): a quarter of -O2 -g's compile time.
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" \
    -DEXOID_FUZZ=ON -DEXOID_PRECOMPILE_HEADERS=ON -DEXOID_WITH_MUJOCO=ON -DEXOID_WITH_PYTHON=OFF -DEXOID_BUILD_TESTS=OFF \
    -DEXOID_BUILD_BENCH=OFF > /dev/null
fi
cmake --build "$dir" --target "${targets[@]}"
dir=$(cd "$dir" && pwd)
pids=()
for target in "${targets[@]}"; do
  name=${target%_fuzz}
  mkdir -p "$dir/corpus/$name"
  (cd "$dir" && UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 "./fuzz/$target" -max_total_time="$seconds" -seed="${FUZZ_SEED:-1}" \
    -max_len=65536 -print_final_stats=1 "corpus/$name" "$root/fuzz/corpus/$name" > "$dir/$target.log" 2>&1) &
  pids+=($!)
done
failed=0
for i in "${!targets[@]}"; do
  status=0
  wait "${pids[$i]}" || status=$?
  echo "== ${targets[$i]}: ${seconds} s, exit $status"
  tail -n 12 "$dir/${targets[$i]}.log"
  [[ $status -eq 0 ]] || failed=1
done
exit $failed
