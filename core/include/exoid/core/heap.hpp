#pragma once
// Process-wide heap settings for long logs: called first thing in main() (both exoid binaries,
// and the long-log benchmark for its library path, so the two compare like with like).

namespace exoid::core {

/// On glibc: freed buffers stay in the heap for the next block of a long log, and the heap's
/// next 256 MB (address space only) are marked for transparent huge pages. With one_heap, every
/// thread allocates from that heap (for a process whose threads allocate few, large buffers: a
/// long log's blocks), instead of from arenas of its own on ordinary pages. Elsewhere: nothing.
void tuneHeapForLongLogs(bool one_heap);

}  // namespace exoid::core
