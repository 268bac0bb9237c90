// exoid: thin entry point; everything lives in the experiments library.
#include "exoid/experiments/commands/cli.hpp"

#include <cstdlib>  // defines __GLIBC__ on glibc systems

#ifdef __GLIBC__
#include <malloc.h>
#endif

int main(int argc, char** argv) {
#ifdef __GLIBC__
  // Long logs are processed a block at a time (~15-45 MB of buffers per block): keep freed
  // blocks in the heap for the next one instead of unmapping and faulting them in again
  // (1M-row LS: 0.51-0.57 s instead of 0.70-0.84 s, peak memory +2 %).
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
  return exoid::experiments::runCli(argc, argv);
}
