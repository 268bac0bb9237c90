#!/usr/bin/python3
"""Figures of `exoid reproduce` from the CSV/JSON it wrote. Usage: reproduce_plots.py RESULTS_DIR"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# One distinct colour per method (matplotlib's default cycle has 10, the protocol 11 arms).
COLORS = {"ls": "#1f77b4", "rls": "#9467bd", "pso": "#ff7f0e", "rls-pso": "#2ca02c", "lad": "#7f7f7f",
          "ls-exact": "#17becf", "ls-stacked": "#8c564b", "ls-parallel": "#d62728", "idim-iv": "#e377c2",
          "ls-base": "#bcbd22", "idim-iv-base": "#393b79"}


def read_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], rows[1:]
    return {name: [float(r[i]) for r in data] for i, name in enumerate(header)}


def save(fig, out_dir, name):
    fig.tight_layout()
    tmp = os.path.join(out_dir, name + ".tmp.png")
    fig.savefig(tmp, dpi=110, metadata={"Software": None})  # no timestamps: same data, same bytes
    os.replace(tmp, os.path.join(out_dir, name))
    plt.close(fig)


def validation(out_dir, joint, trajectory):
    cols = read_columns(os.path.join(out_dir, f"series_validation_{joint}.csv"))
    t = cols.pop("t")
    measured = cols.pop("measured")
    errors = {name: [p - m for p, m in zip(pred, measured)] for name, pred in cols.items()}
    rms = {name: (sum(e * e for e in err) / len(err)) ** 0.5 for name, err in errors.items()}
    # Methods far off (more than 5x the best RMS) would flatten everything else: keep the axes
    # on the others and mark the off-scale ones in the legend, where every RMS error is given.
    best = min(rms.values())
    shown = [n for n in cols if rms[n] <= 5 * best + 1e-12]
    off = [n for n in cols if n not in shown]
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    ax1.plot(t, measured, color="black", lw=2.0, label="measured (processed)")
    for name in cols:
        label = f"{name} (RMS {rms[name]:.3g}{', off scale' if name in off else ''})"
        ax1.plot(t, cols[name], lw=1.0, color=COLORS.get(name), label=label)
        ax2.plot(t, errors[name], lw=1.0, color=COLORS.get(name), label=label)
    lo, hi = min(measured), max(measured)
    pad = 0.3 * (hi - lo)
    ax1.set_ylim(lo - pad, hi + pad)
    emax = max(max(abs(e) for e in errors[n]) for n in shown)
    ax2.set_ylim(-1.2 * emax, 1.2 * emax)
    ax1.set_ylabel(f"{joint} torque (N m)")
    title = f"Validation on trajectory {trajectory}: measured vs identified {joint} torque (RMS errors in N m)"
    ax1.set_title(title, fontsize=10)
    ax1.legend(ncol=3, fontsize=7)
    ax2.set_ylabel("predicted - measured (N m)")
    ax2.set_xlabel("t (s)")
    save(fig, out_dir, f"fig_validation_{joint}.png")


def convergence(out_dir):
    cols = read_columns(os.path.join(out_dir, "series_convergence.csv"))
    it = cols.pop("iteration")
    if not cols:
        return
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, stage in zip(axes, ["knee", "hip"]):
        for name, h in cols.items():
            if name.endswith("_" + stage):
                method = name[: -len(stage) - 1]
                ax.semilogy(it, h, color=COLORS.get(method), label=method)
        ax.set_title(f"{stage} stage: best L1 cost")
        ax.set_xlabel("iteration")
        ax.set_xscale("symlog", linthresh=10)
        ax.legend()
    axes[0].set_ylabel("best cost (N m, sum over samples)")
    save(fig, out_dir, "fig_convergence.png")


def error_bars(out_dir, results):
    methods = list(results["methods"].keys())
    fig, ax = plt.subplots(figsize=(9, 4))
    width = 0.38
    for k, joint, key in [(0, "knee", "knee_on_trajectory_2"), (1, "hip", "hip_on_trajectory_4")]:
        mean = [results["methods"][m]["validation"][key]["mean_abs_Nm"] for m in methods]
        std = [results["methods"][m]["validation"][key]["std_abs_Nm"] for m in methods]
        x = [i + (k - 0.5) * width for i in range(len(methods))]
        ax.bar(x, mean, width, yerr=std, capsize=3, label=f"{joint} (validation trajectory {2 if k == 0 else 4})")
    ax.set_xticks(range(len(methods)))
    ax.set_xticklabels(methods)
    ax.set_ylabel("|measured - predicted| (N m), mean +- std")
    ax.legend()
    save(fig, out_dir, "fig_validation_errors.png")


def parameter_errors(out_dir, results):
    methods = list(results["methods"].keys())
    names = list(results["truth"]["best_fit"]["parameters"].keys())
    order = ["Mxt", "Myt", "Jt", "fc1", "fv1", "Mxs", "Mys", "Js", "fc2", "fv2"]
    names = [n for n in order if n in names]
    fig, ax = plt.subplots(figsize=(10, 4))
    width = 0.8 / max(1, len(methods))
    for k, m in enumerate(methods):
        rel = results["methods"][m]["parameter_error"]["best_fit"]["rel"]
        vals = [100.0 * abs(rel[n]) for n in names]
        ax.bar([i + (k - len(methods) / 2 + 0.5) * width for i in range(len(names))], vals, width,
               color=COLORS.get(m), label=m)
    ax.set_xticks(range(len(names)))
    ax.set_xticklabels(names)
    ax.set_yscale("log")
    ax.set_ylabel("|relative error| vs best-fit truth (%)")
    ax.legend(ncol=4, fontsize=8)
    save(fig, out_dir, "fig_parameter_errors.png")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: reproduce_plots.py RESULTS_DIR")
    out_dir = sys.argv[1]
    with open(os.path.join(out_dir, "results.json")) as f:
        results = json.load(f)
    validation(out_dir, "knee", 2)
    validation(out_dir, "hip", 4)
    convergence(out_dir)
    error_bars(out_dir, results)
    parameter_errors(out_dir, results)


if __name__ == "__main__":
    main()
