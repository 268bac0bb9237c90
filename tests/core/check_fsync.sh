#!/usr/bin/env bash
# The atomic writer's crash-safety promise, seen from the system calls: for every file it writes,
# the data is fsync'd before the rename and the folder after it (else a power cut can leave a
# "finished" file empty). Runs one core test under strace. Usage: check_fsync.sh CORE_TESTS_BINARY
set -euo pipefail
log=$(mktemp)
trap 'rm -f "$log"' EXIT
if ! strace -f -qq -e trace=openat,fsync,rename,renameat,renameat2 -o "$log" \
     "$1" --gtest_filter=AtomicFile.WritesTheWholeFileAndNothingElse > /dev/null 2>&1; then
  echo "strace cannot trace here (no ptrace?): skipped"; exit 77
fi
# Per written file: a fsync before its rename, and a fsync after it (the folder).
awk '
  /rename/ && /\.tmp\./ { renames++; if (syncs_since_rename < 1) bad = "a rename without a preceding fsync: " $0; after = 1; syncs_since_rename = 0; next }
  /fsync\(/ { if (after) { folder_syncs++; after = 0 } else { syncs_since_rename++ } }
  END {
    if (renames < 2) { print "expected 2 atomic writes, saw " renames " renames"; exit 1 }
    if (bad != "") { print bad; exit 1 }
    if (folder_syncs < renames) { print "only " folder_syncs " folder fsyncs after " renames " renames"; exit 1 }
    print renames " atomic writes, each with its data fsynced before the rename and its folder after"
  }' "$log"
