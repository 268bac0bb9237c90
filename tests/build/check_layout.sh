#!/usr/bin/env bash
# One pipeline (issue 35): no non-test source is a chain-only twin of an APAL-leg one, so none is
# named chain_*. Usage: check_layout.sh SOURCE_DIR
set -euo pipefail
cd "$1"
twins=$(find core ident sim experiments render bench python fuzz -type f \
          \( -name 'chain_*.cpp' -o -name 'chain_*.hpp' -o -name 'chain_*.h' \) | sort)
if [[ -n "$twins" ]]; then
  echo "non-test sources named chain_* (a twin of the APAL leg's; one implementation serves every leg):"
  echo "$twins"
  exit 1
fi
echo "no non-test source is named chain_*"
