// The swarm-cost kernel for AVX2 + FMA (x86-64-v3); flags set in ident/CMakeLists.txt.
#define EXOID_KERNEL_NAME swarmCostAvx2
#define EXOID_KERNEL_LANES 4
#include "swarm_cost_kernel.inc"
