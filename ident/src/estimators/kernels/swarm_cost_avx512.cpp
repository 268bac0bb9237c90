// The swarm-cost kernel for AVX-512F/DQ (x86-64-v4); flags set in ident/CMakeLists.txt.
#define EXOID_KERNEL_NAME swarmCostAvx512
#define EXOID_KERNEL_LANES 8
#include "swarm_cost_kernel.inc"
