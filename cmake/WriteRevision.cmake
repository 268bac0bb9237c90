# Run at build time (target exoid_revision) as well as at configure time: the source tree's git
# revision into the version header, so a rebuild after a pull or an edit stamps the revision it was
# built from. configure_file rewrites the header only when its text changes (no needless rebuilds).
# Inputs: SOURCE_DIR, PROJECT_VERSION, IN, OUT.
execute_process(COMMAND git -C ${SOURCE_DIR} describe --always --dirty --abbrev=12
                OUTPUT_VARIABLE EXOID_GIT_REVISION OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT EXOID_GIT_REVISION)
  set(EXOID_GIT_REVISION "unknown")
endif()
configure_file(${IN} ${OUT} @ONLY)
