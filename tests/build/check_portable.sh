#!/usr/bin/env bash
# A portable build (EXOID_NATIVE=OFF) must run on any x86-64 CPU: no function of BINARY may use
# AVX or wider instructions (VEX/EVEX-encoded, ymm/zmm registers) except the swarm-cost kernels,
# which linear_cost.cpp calls only on CPUs that have them. Usage: check_portable.sh BINARY...
set -euo pipefail
status=0
for binary in "$@"; do
  offenders=$(objdump -d --no-show-raw-insn "$binary" | c++filt |
    awk '/^[0-9a-f]+ <.*>:$/ { fn = $0; next }
         $2 ~ /^v/ && /%[xyz]mm/ && fn !~ /exoid::ident::kernels::/ { print fn }' | sort -u)
  if [[ -n "$offenders" ]]; then
    echo "$binary: functions outside the dispatched kernels use AVX instructions:"
    echo "$offenders" | head -20
    status=1
  else
    echo "$binary: AVX only in exoid::ident::kernels"
  fi
done
exit $status
