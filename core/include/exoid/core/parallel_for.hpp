#pragma once
// fn(0), ..., fn(n - 1) on up to `threads` threads (0 = the machine's cores), each index once. The
// caller makes each call write only its own slot, so the result is the same bytes whatever the
// number of threads. An exception from a call is rethrown here (that of the lowest index), after
// every thread has stopped.
#include <cstddef>
#include <functional>

namespace exoid::core {

/// The number of threads `threads` means: itself if positive, else the machine's cores (>= 1).
int resolveThreads(int threads);

void parallelFor(std::size_t n, int threads, const std::function<void(std::size_t)>& fn);
/// The same, fn(i, worker) also told which worker (0 .. resolveThreads(threads) - 1) runs it, so
/// that each worker can reuse its own buffers from one call to the next.
void parallelForWorkers(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t)>& fn);

}  // namespace exoid::core
