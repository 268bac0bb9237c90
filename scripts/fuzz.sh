#!/usr/bin/env bash
# Builds exoid's libFuzzer targets (fuzz/) with clang, ASan and UBSan in build-fuzz/ and runs each
# for SECONDS (default 60) from its seed corpus (fuzz/corpus/<target>/), new inputs going to
# build-fuzz/corpus/. Installs clang and its fuzzer runtime when missing (scripts/deps.sh --with-fuzz).
# A crash stops the run with the reproducer in build-fuzz/ and a non-zero exit.
#   scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
seconds=${1:-60}
scripts/deps.sh --with-fuzz
# libFuzzer's recommended flags (-O1, line tables only): a quarter of -O2 -g's compile time.
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" \
  -DEXOID_FUZZ=ON -DEXOID_WITH_MUJOCO=OFF -DEXOID_WITH_PYTHON=OFF -DEXOID_BUILD_TESTS=OFF -DEXOID_BUILD_BENCH=OFF > /dev/null
cmake --build build-fuzz --target dataset_fuzz log_profile_fuzz controller_json_fuzz
for target in dataset_fuzz log_profile_fuzz controller_json_fuzz; do
  corpus=build-fuzz/corpus/${target%_fuzz}
  mkdir -p "$corpus"
  echo "== $target: ${seconds} s"
  (cd build-fuzz && UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 "./fuzz/$target" -max_total_time="$seconds" \
    -max_len=65536 -print_final_stats=1 "../$corpus" "../fuzz/corpus/${target%_fuzz}" 2>&1 | tail -n 12)
done
