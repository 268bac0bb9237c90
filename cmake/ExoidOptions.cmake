# Project-wide compile settings, applied through the interface target exoid_warnings
# (warnings) and directory-level flags (architecture, sanitizers).
add_library(exoid_warnings INTERFACE)
target_compile_options(exoid_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                       -Wno-sign-conversion)

# Eigen's object layout and allocator follow the widest vector the compiler targets (Eigen 3.4
# aligns heap blocks to 64 bytes under AVX-512, 16 under SSE2, and frees them differently), so code
# built with different -m flags (a -march=native build, the benchmarks, a user's project) would
# disagree and crash on the first matrix one side allocates and the other frees. Pinning the
# alignment Eigen assumes to the x86-64 baseline's 16 bytes and its allocator to the one that
# records each block's origin makes both independent of the instruction set (the first is Eigen's
# documented way to mix SSE and AVX code); exoid::ident exports the same definitions to its users.
set(EXOID_EIGEN_ABI_DEFINITIONS EIGEN_MAX_ALIGN_BYTES=16 EIGEN_MALLOC_ALREADY_ALIGNED=0)
add_compile_definitions(${EXOID_EIGEN_ABI_DEFINITIONS})

# Flags that target this machine's CPU: the whole build with EXOID_NATIVE (off by default: a
# binary must run on every node of a mixed cluster), the benchmarks always (they measure it).
set(EXOID_NATIVE_FLAGS -march=native)
# GCC 12 warns about its own AVX-512 intrinsics header when Eigen vectorises (GCC bug 105593).
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  list(APPEND EXOID_NATIVE_FLAGS -Wno-maybe-uninitialized -Wno-uninitialized)
endif()
if(EXOID_NATIVE)
  add_compile_options(${EXOID_NATIVE_FLAGS})
endif()

# ASan + UBSan in every library; a fuzzing tree has them too (its targets add libFuzzer's coverage to
# the parsers they drive only: fuzz/CMakeLists.txt), so one tree can serve both.
if(EXOID_SANITIZE OR EXOID_FUZZ)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()


# Heavy third-party headers (Eigen, CLI11, nlohmann_json, gtest) parsed, and their templates
# instantiated, once per target instead of once per source. Off by default: a tree whose objects
# ccache shares with another configuration (.ci/run's Release and no-MuJoCo builds) must compile
# each source on its own; .ci/run turns it on for its throwaway sanitizer tree.
option(EXOID_PRECOMPILE_HEADERS "Precompile the heavy third-party headers once per target (for throwaway build trees)" OFF)
function(exoid_precompile_headers target)
  if(EXOID_PRECOMPILE_HEADERS)
    target_precompile_headers(${target} PRIVATE ${ARGN})
  endif()
endfunction()
