# Project-wide compile settings, applied through the interface target exoid_warnings
# (warnings) and directory-level flags (architecture, sanitizers).
add_library(exoid_warnings INTERFACE)
target_compile_options(exoid_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                       -Wno-sign-conversion)

if(EXOID_NATIVE)
  add_compile_options(-march=native)
  # GCC 12 warns about its own AVX-512 intrinsics header when Eigen vectorises (GCC bug 105593).
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    target_compile_options(exoid_warnings INTERFACE -Wno-maybe-uninitialized -Wno-uninitialized)
  endif()
endif()

if(EXOID_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# Version and source revision stamped into every output.
execute_process(COMMAND git -C ${CMAKE_SOURCE_DIR} describe --always --dirty --abbrev=12
                OUTPUT_VARIABLE EXOID_GIT_REVISION OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT EXOID_GIT_REVISION)
  set(EXOID_GIT_REVISION "unknown")
endif()
