// The swarm-cost kernel for the baseline of the target (SSE2 on x86-64); flags set in ident/CMakeLists.txt.
#define EXOID_KERNEL_NAME swarmCostGeneric
#define EXOID_KERNEL_LANES 8
#include "swarm_cost_kernel.inc"
