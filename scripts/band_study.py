#!/usr/bin/env python3
"""The band rule's constants, chosen on the simulator (issue 36, item 4; docs/findings.md 4.9).

Runs `exoid sweep` once per candidate rule on two rigs (experiments/configs/band_study_apal.toml:
identify's default on the APAL leg; band_study_leg3.toml: LS in the chosen band on leg3), the same
seeds for every candidate, and scores each run by its median |relative parameter error| against
the simulation's truth (runs.csv's median_abs_rel_err). A candidate is compared with the current
rule run by run: the log of the error ratio, averaged per rig.

The criterion, fixed before any candidate was run: a candidate replaces the centre (at first the
rule as it was) only if its mean log ratio is below 0 on each rig and the upper end of the two
rigs' pooled (equal-weight) 95 % interval, Bonferroni-corrected over the candidates, is below 0;
among such candidates the lowest pooled mean wins. A round's winner is the next round's centre
(--centre), until no candidate passes.

Usage: scripts/band_study.py EXOID OUT_DIR [--seeds N] [--centre KEY=VALUE ...]
Writes OUT_DIR/<rig>/<candidate>/ (each a sweep folder) and OUT_DIR/study.md, study.csv.
"""
import argparse
import csv
import math
import os
import shutil
import subprocess
import sys

import numpy as np

CONFIGS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "experiments", "configs")
RIGS = {"apal": "band_study_apal.toml", "leg3": "band_study_leg3.toml"}
CURRENT = {"inconsistency_ratio": 2.0, "pilot_factor": 1.5, "max_factor": 5.0, "scan_hz": 1.0}
# One constant at a time around the centre: the threshold x0.75 / x1.5, each cutoff factor x0.8 /
# x1.25, the scan's step halved / doubled.
STEPS = {"inconsistency_ratio": (0.75, 1.5), "pilot_factor": (0.8, 1.25), "max_factor": (0.8, 1.25), "scan_hz": (0.5, 2.0)}


def candidates(centre):
    out = [("current", dict(centre))]
    for key, factors in STEPS.items():
        for f in factors:
            c = dict(centre)
            c[key] = round(centre[key] * f, 6)
            out.append((f"{key}={c[key]:g}", c))
    return out


def run_sweep(exoid, rig, name, overrides, out_dir, seeds):
    folder = os.path.join(out_dir, rig, name)
    if os.path.exists(os.path.join(folder, "summary.md")):
        return folder
    os.makedirs(os.path.join(out_dir, rig), exist_ok=True)
    config = os.path.join(out_dir, rig, name + ".toml")
    with open(os.path.join(CONFIGS, RIGS[rig])) as f:
        text = f.read().replace("seeds = 5\n", f"seeds = {seeds}\n", 1)
    text += "".join(f"band_{k} = {float(v)!r}\n" for k, v in overrides.items())
    with open(config, "w") as f:
        f.write(text)
    for design in ("excitation_knee.json", "excitation_both.json"):
        shutil.copy(os.path.join(CONFIGS, design), os.path.join(out_dir, rig, design))
    subprocess.run([exoid, "sweep", "--config", config, "--out", folder], check=True, stdout=subprocess.DEVNULL)
    return folder


def errors(folder):
    out = {}
    with open(os.path.join(folder, "runs.csv")) as f:
        for row in csv.DictReader(f):
            key = (row["cell"], row["replicate"])
            ok = row["status"] == "ok" and row["median_abs_rel_err"] not in ("", "nan")
            out[key] = float(row["median_abs_rel_err"]) if ok else math.inf
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("exoid")
    p.add_argument("out")
    p.add_argument("--seeds", type=int, default=5)
    p.add_argument("--centre", action="append", default=[], metavar="KEY=VALUE",
                   help="the rule to start from (a previous round's winner), e.g. --centre max_factor=4")
    a = p.parse_args()
    centre = dict(CURRENT)
    for kv in a.centre:
        key, value = kv.split("=")
        centre[key] = float(value)
    CANDIDATES = candidates(centre)
    z = 1.959963984540054
    # Bonferroni over the candidates: the normal quantile at 1 - 0.025 / k (k = 8).
    k = len(CANDIDATES) - 1
    z_bonf = {8: 2.7344}[k]
    results = {}
    for rig in RIGS:
        for name, overrides in CANDIDATES:
            print(f"{rig} {name}", file=sys.stderr, flush=True)
            results[(rig, name)] = errors(run_sweep(a.exoid, rig, name, overrides, a.out, a.seeds))
    rows = []
    for name, _ in CANDIDATES:
        per_rig = {}
        for rig in RIGS:
            cur, cand = results[(rig, "current")], results[(rig, name)]
            keys = sorted(set(cur) & set(cand))
            failed = sum(1 for q in keys if not math.isfinite(cand[q]))
            d = np.array([math.log(cand[q] / cur[q]) for q in keys if math.isfinite(cand[q]) and math.isfinite(cur[q])])
            med = float(np.median([cand[q] for q in keys if math.isfinite(cand[q])]))
            se = float(d.std(ddof=1) / math.sqrt(len(d))) if len(d) > 1 else math.nan
            per_rig[rig] = (float(d.mean()), se, len(d), failed, med)
        pooled = 0.5 * sum(v[0] for v in per_rig.values())
        pooled_se = 0.5 * math.sqrt(sum(v[1] ** 2 for v in per_rig.values()))
        passes = name != "current" and all(v[0] < 0 and v[3] == 0 for v in per_rig.values()) and pooled + z_bonf * pooled_se < 0
        rows.append((name, per_rig, pooled, pooled_se, passes))
    winners = sorted((r for r in rows if r[4]), key=lambda r: r[2])
    chosen = winners[0][0] if winners else "current"
    with open(os.path.join(a.out, "study.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["candidate"] + [f"{rig}_{c}" for rig in RIGS for c in ("mean_log_ratio", "se", "n", "failed", "median_err")]
                   + ["pooled_mean_log_ratio", "pooled_se", "passes"])
        for name, per_rig, pooled, pooled_se, passes in rows:
            w.writerow([name] + [f"{x:.6g}" for rig in RIGS for x in per_rig[rig]] + [f"{pooled:.6g}", f"{pooled_se:.6g}", int(passes)])
    with open(os.path.join(a.out, "study.md"), "w") as f:
        f.write("# The band rule's constants (scripts/band_study.py)\n\n")
        f.write(f"{a.seeds} seeds per cell; per rig: the geometric-mean ratio of each run's median |relative parameter error| "
                "to the current rule's on the same run [95 % interval], runs where the candidate failed, and the median error. "
                f"Adopted only if below 1 on each rig and the pooled upper bound (Bonferroni over {k} candidates, z = {z_bonf}) is below 1.\n\n")
        f.write("| candidate | " + " | ".join(f"{rig}: ratio [95 %] | {rig}: failed | {rig}: median error (%)" for rig in RIGS)
                + " | pooled ratio [Bonferroni] | adopted |\n")
        f.write("|---|" + "---|---|---|" * len(RIGS) + "---|---|\n")
        for name, per_rig, pooled, pooled_se, passes in rows:
            cells = []
            for rig in RIGS:
                m, se, n, failed, med = per_rig[rig]
                cells += [f"{math.exp(m):.3f} [{math.exp(m - z * se):.3f}, {math.exp(m + z * se):.3f}]" if n > 1 else "-",
                          str(failed), f"{100 * med:.2f}"]
            f.write(f"| {name} | " + " | ".join(cells) + f" | {math.exp(pooled):.3f} [{math.exp(pooled - z_bonf * pooled_se):.3f}, "
                    f"{math.exp(pooled + z_bonf * pooled_se):.3f}] | {'yes' if name == chosen and name != 'current' else '-'} |\n")
        f.write(f"\nCentre: {centre}. Chosen: {chosen}" + (" (a next round starts from it)" if chosen != "current" else
                " (no candidate passes: the centre stays)") + ".\n")
    print(open(os.path.join(a.out, "study.md")).read())


if __name__ == "__main__":
    main()
