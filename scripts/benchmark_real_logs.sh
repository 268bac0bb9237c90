#!/usr/bin/env bash
# The real-log half of the benchmark that chose `exoid identify`'s defaults (README, "Defaults from
# evidence"; the simulator half is `exoid sweep --config experiments/configs/defaults_benchmark.toml`).
# Every processing/method combination a user can pick, on the shipped DFKI double pendulum logs
# (design A.0): the seven records 00-05 and 11 fitted together, and each record alone; each
# estimate of Mxt, Jt, Mxs, Js against the lab's own identified values (their friction is fixed
# by the lab, so it is no target). Prints a Markdown table; exit 0.
# Usage: scripts/benchmark_real_logs.sh [EXOID_BINARY]   (default build/experiments/exoid)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
exoid=${1:-$root/build/experiments/exoid}
[[ -x "$exoid" ]] || { echo "benchmark_real_logs.sh: no exoid binary at $exoid (scripts/build.sh --main builds it)" >&2; exit 1; }
dir=$root/data/real/dfki_double_pendulum
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# name | identify options
combos=(
  "default (no options)|"
  "parallel, fixed 10 Hz (the previous default)|--cutoff-hz 10 --no-consistency"
  "parallel, fixed 10 Hz, consistent|--cutoff-hz 10"
  "paper processing, LS|--processing paper"
  "band from the data, lad|--method lad"
  "band from the data, knee armature|--knee-armature"
  "band from the data, iv-band (instruments from the motion's band)|--method iv-band"
)
sets=("00-05+11" 00 01 02 03 04 05 11 12 13)

record() { echo "$dir/design_A0_20220815_trajectory_$1.csv.gz"; }
for c in "${!combos[@]}"; do
  IFS='|' read -r name opts <<<"${combos[$c]}"
  for s in "${sets[@]}"; do
    data=()
    if [[ $s == "00-05+11" ]]; then
      for r in 00 01 02 03 04 05 11; do data+=(--data "$(record $r)"); done
    else
      data=(--data "$(record "$s")")
    fi
    # shellcheck disable=SC2086
    rc=0; "$exoid" identify --profile "$dir/profile.toml" "${data[@]}" $opts --json "$work/$c-$s.json" >/dev/null 2>&1 || rc=$?
    echo "$rc" > "$work/$c-$s.rc"
  done
done

python3 - "$work" "${#combos[@]}" "${combos[@]}" <<'PY'
import json, sys, os
work, n = sys.argv[1], int(sys.argv[2])
names = [c.split('|')[0] for c in sys.argv[3:3 + n]]
lab = {"Mxt": 0.3491, "Jt": 0.1346, "Mxs": 0.1111, "Js": 0.0267}   # design_A0_model_2.0_parameters.yml, mapped (README there)
sets = ["00-05+11", "00", "01", "02", "03", "04", "05", "11", "12", "13"]
print("| combination | " + " | ".join(sets) + " | mean over single records |")
print("|---|" + "---|" * (len(sets) + 1))
for c, name in enumerate(names):
    cells, singles = [], []
    for s in sets:
        f = os.path.join(work, f"{c}-{s}.json")
        rc = open(os.path.join(work, f"{c}-{s}.rc")).read().strip()
        if not os.path.exists(f):
            cells.append(f"error (exit {rc})"); continue
        p = json.load(open(f))["parameters"]
        err = [100 * (p[k] / v - 1) for k, v in lab.items()]
        worst = max(err, key=abs)
        mean_abs = sum(abs(e) for e in err) / len(err)
        if s != "00-05+11":
            singles.append(mean_abs)
        cells.append(f"{mean_abs:.1f} (worst {worst:+.1f}){'' if rc == '0' else ', exit ' + rc}")
    print(f"| {name} | " + " | ".join(cells) + f" | {sum(singles) / len(singles):.1f} |")
print()
print("Cells: mean |error| of Mxt, Jt, Mxs, Js against the lab's values in %, (worst signed error); exit code when not 0.")
PY
