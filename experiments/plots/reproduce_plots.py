#!/usr/bin/python3
"""Figures of `exoid reproduce` from the CSV/JSON it wrote. Usage: reproduce_plots.py RESULTS_DIR

The paper's question is "is RLS-PSO better than LS (and PSO)?", so every figure puts ls, rls-pso
and pso first and in strong colours; the harness's other arms come after, in lighter styles."""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from plot_style import COLORS, ORDER, STYLES, ordered, read_columns, save_figure  # noqa: E402

PAPER_ARMS = ORDER[:3]  # ls, rls-pso, pso
VALIDATION_KEYS = {"knee": "knee_on_trajectory_2", "hip": "hip_on_trajectory_4"}
OFF_SCALE = 5.0  # an arm whose RMS error exceeds 5x the best one would flatten the others: not drawn
PARAMS = ["Mxt", "Myt", "Jt", "fc1", "fv1", "Mxs", "Mys", "Js", "fc2", "fv2"]


def save(fig, out_dir, name):
    # Figures use constrained layout, which keeps the outside legends inside the canvas.
    save_figure(fig, os.path.join(out_dir, name))


def note(label):
    """A legend entry without a line: for arms listed but not drawn."""
    return Line2D([], [], color="none", label=label)


def outside_legend(ax, handles=None):
    kw = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "fontsize": 8, "frameon": False}
    if handles is None:
        ax.legend(**kw)
    else:
        ax.legend(handles=handles, **kw)


def limits(ax, traces, include_zero=True):
    """Y-limits covering every drawn trace, so nothing on scale is clipped."""
    lo = min(float(np.min(y)) for y in traces)
    hi = max(float(np.max(y)) for y in traces)
    if include_zero:
        lo, hi = min(lo, 0.0), max(hi, 0.0)
    pad = 0.05 * (hi - lo if hi > lo else 1.0)
    ax.set_ylim(lo - pad, hi + pad)


def validation(out_dir, joint, trajectory):
    cols = read_columns(os.path.join(out_dir, f"series_validation_{joint}.csv"))
    t, measured = cols.pop("t"), cols.pop("measured")
    methods = ordered(cols)
    err = {m: cols[m] - measured for m in methods}
    rms = {m: float(np.sqrt(np.mean(err[m] ** 2))) for m in methods}
    limit = OFF_SCALE * min(rms.values())
    lead = [m for m in ["ls", "rls-pso"] if m in cols]  # always drawn: they are the comparison
    lead += ["pso"] if "pso" in cols and rms["pso"] <= limit else []
    notes = [note(f"pso: RMS {rms['pso']:.3g}, off scale, not drawn")] if "pso" in cols and "pso" not in lead else []
    rls_diff = float(np.max(np.abs(cols["rls"] - cols["ls"]))) if "rls" in cols and "ls" in cols else None
    rls_is_ls = rls_diff is not None and rls_diff <= 1e-3 * rms["ls"]  # invisible at any plot scale
    others = [m for m in methods if m not in PAPER_ARMS and not (m == "rls" and rls_is_ls)]
    shown = [m for m in others if rms[m] <= limit]
    notes_others = [note(f"{m}: RMS {rms[m]:.3g}, off scale (> {OFF_SCALE:g}x best), not drawn")
                    for m in others if m not in shown]

    fig, (ax1, ax2, ax3) = plt.subplots(3, 1, figsize=(11, 9.5), sharex=True, layout="constrained",
                                        gridspec_kw={"height_ratios": [1.2, 1, 1]})
    fig.suptitle(f"Validation on trajectory {trajectory}: {joint} torque, identified vs measured "
                 f"(RMS of the error over the whole record, N m)", fontsize=11)
    ax1.plot(t, measured, color="black", lw=2.6, label="measured (processed)")
    draw(ax1, t, cols, rms, lead, lw=1.6)
    limits(ax1, [measured] + [cols[m] for m in lead], include_zero=False)
    ax1.set_ylabel(f"{joint} torque (N m)")
    panel(ax1, "Measured torque and the paper's methods' predictions", notes)
    if rls_is_ls:  # said once, next to ls's error, instead of a second line on top of it
        notes = notes + [note(f"rls = ls (identical estimate; max diff {rls_diff:.1g} N m), not drawn")]
    draw(ax2, t, err, rms, lead, lw=2.0)
    panel(ax2, "Prediction error of the paper's methods", notes)
    draw(ax3, t, err, rms, shown, lw=1.1)
    panel(ax3, "Prediction error of the harness's other arms (same y scale)", notes_others)
    # One y scale for both error panels, from every drawn trace, so levels compare across them.
    for ax in (ax2, ax3):
        limits(ax, [err[m] for m in lead + shown])
        ax.axhline(0.0, color="black", lw=0.6)
        ax.set_ylabel("predicted - measured (N m)")
    ax3.set_xlabel("t (s)")
    save(fig, out_dir, f"fig_validation_{joint}.png")


def draw(ax, t, series, rms, methods, lw):
    for m in methods:
        ax.plot(t, series[m], color=COLORS.get(m), ls=STYLES.get(m, "-"), lw=lw, label=f"{m} (RMS {rms[m]:.3g})")


def panel(ax, title, notes):
    ax.set_title(title, fontsize=9, loc="left")
    handles = ax.get_legend_handles_labels()[0] + notes
    if handles:
        outside_legend(ax, handles)


def convergence(out_dir, results):
    cols = read_columns(os.path.join(out_dir, "series_convergence.csv"))
    it = cols.pop("iteration")
    # Only the swarms' best L1 cost (paper Figs. 8, 11); IDIM-IV's history is in standard errors, not a cost.
    swarms = [m for m in ["pso", "rls-pso"] if f"{m}_knee" in cols or f"{m}_hip" in cols]
    if not swarms:
        return
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), sharex=True, layout="constrained")
    fig.suptitle("Swarm convergence (paper Figs. 8, 11): best L1 cost per iteration, and how far it is above "
                 "the exact L1 optimum", fontsize=10)
    for k, stage in enumerate(["knee", "hip"]):
        convergence_stage(axes[0, k], axes[1, k], it, cols, results, stage, swarms)
    axes[0, 0].set_ylabel("best L1 cost (N m, sum over samples)")
    axes[1, 0].set_ylabel("above the exact optimum (%)")
    save(fig, out_dir, "fig_convergence.png")


def convergence_stage(ax_cost, ax_gap, it, cols, results, stage, swarms):
    for m in swarms:
        h = cols.get(f"{m}_{stage}")
        if h is None:
            continue
        style = {"color": COLORS.get(m), "ls": STYLES[m], "lw": 2.0}
        ax_cost.plot(it, h, **style)
        optimum = stage_info(results, m, stage).get("optimum_l1_cost")
        if optimum:  # the dotted line: this method's own exact optimum (hip costs differ by method)
            ax_cost.axhline(optimum, color=COLORS.get(m), ls=":", lw=1.5)
            gap = 100.0 * np.maximum(h / optimum - 1.0, 1e-6)  # round-off can dip a hair below 0
            own = " given its own knee estimate" if stage == "hip" else ""
            ax_gap.plot(it, gap, label=f"{m}: final {num(h[-1])}, {gap[-1]:.3g} % above the optimum {num(optimum)}{own}",
                        **style)
    ls = stage_info(results, "ls", stage).get("l1_cost")
    optimum = stage_info(results, "rls-pso", stage).get("optimum_l1_cost")
    if stage == "knee" and ls and optimum:  # every method's knee stage fits the same record: comparable
        ax_cost.axhline(ls, color=COLORS["ls"], ls="--", lw=1.2)
        ax_gap.axhline(100.0 * max(ls / optimum - 1.0, 1e-6), color=COLORS["ls"], ls="--", lw=1.2,
                       label=f"ls estimate: {num(ls)}, {100 * (ls / optimum - 1):.3g} % above")
    for ax in (ax_cost, ax_gap):
        ax.set_yscale("log")
        ax.set_xscale("symlog", linthresh=10)
        ax.set_xlim(0, it[-1])
        ax.grid(alpha=0.3, which="both")
    ax_cost.set_title(f"{stage} stage; dotted: each method's exact L1 optimum", fontsize=9)
    if stage == "hip":  # not a small print: the costs below differ by method for this reason alone
        ax_cost.text(0.5, 0.5, "Hip costs are NOT comparable across methods: each fits the hip torque left\n"
                     "by its own knee estimate, so each has its own optimum (dotted)", transform=ax_cost.transAxes,
                     ha="center", va="center", fontsize=9, color="#8b0000",
                     bbox={"facecolor": "white", "edgecolor": "#8b0000", "alpha": 0.9})
    ax_gap.set_xlabel("iteration")
    ax_gap.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), fontsize=8, frameon=False)


def num(v):
    return f"{v:.0f}" if abs(v) >= 1000 else f"{v:.4g}"


def stage_info(results, method, stage):
    for st in results["methods"].get(method, {}).get("stages", []):
        if st.get("stage") == stage:
            return st
    return {}


def error_bars(out_dir, results):
    methods = ordered(results["methods"])
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.5), sharey=True, layout="constrained")
    fig.suptitle("Validation |measured - predicted| torque, mean +- std (log scale; "
                 "lower whisker omitted where mean - std <= 0)", fontsize=10)
    for ax, joint in zip(axes, ["knee", "hip"]):
        key = VALIDATION_KEYS[joint]
        stats = {m: results["methods"][m]["validation"][key] for m in methods}
        # The paper's own numbers (Figs. 10, 13), as exoid's report carries them.
        paper = {m: v[key] for m, v in results.get("paper", {}).get("validation", {}).items()}
        error_panel(ax, joint, methods, stats, paper)
    axes[0].set_yticks(range(len(methods)), [label_of(m, results) for m in methods])
    for lab in axes[0].get_yticklabels()[:len([m for m in methods if m in PAPER_ARMS])]:
        lab.set_fontweight("bold")
    axes[0].invert_yaxis()  # paper's arms on top
    handles = [Patch(color="#555555", label="this run\n(paper's arms in colour,\nother arms grey)"),
               Patch(facecolor="white", edgecolor="black", hatch="///", label="paper (Figs. 10, 13)")]
    outside_legend(axes[1], handles)
    save(fig, out_dir, "fig_validation_errors.png")


def label_of(m, results):
    if m == "rls" and "ls" in results["methods"]:
        a, b = results["methods"]["rls"]["parameters"], results["methods"]["ls"]["parameters"]
        if all(abs(a[k] - b[k]) <= 1e-5 * max(1.0, abs(b[k])) for k in b):
            return "rls (= ls)"
    return m


def whisker(mean, std):
    """(lower, upper) error-bar lengths: no lower whisker on a log axis when mean - std <= 0."""
    return (std if mean - std > 0 else 0.0), std


def error_panel(ax, joint, methods, stats, paper_stats):
    n_paper = len([m for m in methods if m in PAPER_ARMS])
    ends = []
    for i, m in enumerate(methods):
        mean, std = stats[m]["mean_abs_Nm"], stats[m]["std_abs_Nm"]
        paper = paper_stats.get(m)
        y, h = (i - 0.19, 0.36) if paper else (i, 0.6)
        colour = COLORS.get(m) if m in PAPER_ARMS else "#b0b0b0"
        lo, hi = whisker(mean, std)
        ax.barh(y, mean, h, color=colour, xerr=[[lo], [hi]], capsize=2, error_kw={"lw": 0.8})
        ax.text(mean + hi, y, f" {mean:.3g}", va="center", fontsize=7)
        ends.append((mean, mean - lo, mean + hi))
        if paper:
            pm, ps = paper["mean_abs_Nm"], paper["std_abs_Nm"]
            plo, phi = whisker(pm, ps)
            ax.barh(i + 0.19, pm, 0.36, facecolor="white", edgecolor=COLORS.get(m), hatch="///",
                    xerr=[[plo], [phi]], capsize=2, error_kw={"lw": 0.8, "ls": ":"})
            ax.text(pm + phi, i + 0.19, f" {pm:.3g}", va="center", fontsize=7, color="#444444")
            ends.append((pm, pm - plo, pm + phi))
    ax.axhline(n_paper - 0.5, color="black", lw=0.6)
    ax.set_xscale("log")
    lo = min(min(e[0], e[1]) for e in ends)
    hi = max(e[2] for e in ends)
    ax.set_xlim(lo / 2, hi * 6)  # room for the value labels
    ax.grid(axis="x", alpha=0.3, which="both")
    traj = VALIDATION_KEYS[joint].rsplit("_", 1)[1]
    ax.set_title(f"{joint} (validated on trajectory {traj})", fontsize=10)
    ax.set_xlabel("mean |error| (N m)")


def parameter_errors(out_dir, results):
    methods = ordered(results["methods"])
    names = [n for n in PARAMS if n in results["truth"]["best_fit"]["parameters"]]
    rel = {m: np.array([100.0 * abs(results["methods"][m]["parameter_error"]["best_fit"]["rel"][n]) for n in names])
           for m in methods}
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(11, 10), layout="constrained",
                                   gridspec_kw={"height_ratios": [1, 1.3]})
    fig.suptitle("|relative error| of each identified parameter vs the best-fit truth (%)", fontsize=11)
    paper_param_bars(ax1, names, rel, [m for m in PAPER_ARMS if m in rel], results)
    param_heatmap(fig, ax2, names, rel, methods, results)
    save(fig, out_dir, "fig_parameter_errors.png")


def paper_param_bars(ax, names, rel, arms, results):
    width = 0.8 / max(1, len(arms))
    for k, m in enumerate(arms):
        x = np.arange(len(names)) + (k - (len(arms) - 1) / 2) * width
        ax.bar(x, rel[m], width, color=COLORS.get(m), label=f"{m}: torque-space error {torque_space(results, m)}")
    ax.set_xticks(range(len(names)), names)
    ax.set_yscale("log")
    ax.set_ylabel("|relative error| (%)")
    ax.grid(axis="y", alpha=0.3, which="both")
    stage_split(ax, names)
    # The verdict's yardstick in the legend: each parameter's error weighed by what it does to the
    # torque. The bars' unweighted errors (or their median) can rank the methods the other way.
    ax.legend(loc="lower left", bbox_to_anchor=(0.0, 1.0), ncol=1, fontsize=9, frameon=False,
              title="the verdict compares the torque-space error (each parameter's error weighed by its effect on "
                    "the torque); the bars are unweighted", title_fontsize=8)


def torque_space(results, m):
    e = results["methods"][m].get("torque_space_error", {}).get("best_fit", {})
    return ", ".join(f"{j} {100 * e[j]:.3g} %" for j in ("knee", "hip") if j in e) or "n/a"


def stage_split(ax, names):
    """A line between the hip-stage (Mxt ... fv1) and knee-stage (Mxs ... fv2) parameters."""
    if "fv1" in names and "Mxs" in names:
        ax.axvline(names.index("fv1") + 0.5, color="black", lw=1.2)
        ax.set_xlabel("hip-stage parameters | knee-stage parameters")


def param_heatmap(fig, ax, names, rel, methods, results):
    grid = np.array([rel[m] for m in methods])
    positive = grid[grid > 0]
    norm = LogNorm(vmin=positive.min(), vmax=positive.max())
    cmap = plt.get_cmap("viridis")
    im = ax.imshow(np.where(grid > 0, grid, positive.min()), cmap=cmap, norm=norm, aspect="auto")
    for i in range(len(methods)):
        for j in range(len(names)):
            r, g, b, _ = cmap(norm(max(grid[i, j], positive.min())))
            dark = 0.299 * r + 0.587 * g + 0.114 * b < 0.5
            ax.text(j, i, pct(grid[i, j]), ha="center", va="center", fontsize=8, color="white" if dark else "black")
    ax.set_xticks(range(len(names)), names)
    ax.set_yticks(range(len(methods)), [label_of(m, results) for m in methods])
    for lab, m in zip(ax.get_yticklabels(), methods):
        lab.set_fontweight("bold" if m in PAPER_ARMS else "normal")
    n_paper = len([m for m in methods if m in PAPER_ARMS])
    ax.axhline(n_paper - 0.5, color="white", lw=2.5)
    stage_split(ax, names)
    ax.set_title("Every arm (paper's arms above the white line); numbers in %, log colour scale",
                 fontsize=9, loc="left")
    fig.colorbar(im, ax=ax, label="|relative error| (%)")


def pct(v):
    return f"{v:.0f}" if v >= 100 else f"{v:.3g}"


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: reproduce_plots.py RESULTS_DIR")
    out_dir = sys.argv[1]
    with open(os.path.join(out_dir, "results.json")) as f:
        results = json.load(f)
    validation(out_dir, "knee", 2)
    validation(out_dir, "hip", 4)
    convergence(out_dir, results)
    error_bars(out_dir, results)
    parameter_errors(out_dir, results)


if __name__ == "__main__":
    main()
