#!/usr/bin/env python3
"""Figures of `exoid sweep` from summary.json: error vs torque noise per method (95 % CIs), and a
torque noise x vibration map of the RLS-PSO / LS torque-space error ratio.
Usage: sweep_plots.py SUMMARY_JSON OUT_DIR"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import Normalize  # noqa: E402

from plot_style import COLORS, STYLES, ordered, save_figure  # noqa: E402

LEAD = ["ls", "rls-pso"]  # the paper's comparison: thick, with 95 % CI bands
METRIC = "torque_err_mean"
NAN = float("nan")


def save(fig, out_dir, name):
    save_figure(fig, os.path.join(out_dir, name))


def row_key(k):
    """Everything but torque noise and vibration; the paper's trajectories before the designed ones."""
    traj = k.get("trajectories", "paper")
    play = k.get("encoder_backlash_deg", 0.0)  # absent in sweeps from before the axis
    return (k["cylinder_mass_scale"], k["angle_noise_deg"], k["quantisation_deg"], traj != "paper", traj, play)


def row_title(key):
    play = ", backlash %g deg" % key[5] if key[5] else ""
    return "cyl %g, q noise %g deg%s, %s trajectories" % (key[0], key[1], play, key[4])


def stat(c, m):
    """Mean and 95 % CI of the metric in %, NaN where missing."""
    v = c["methods"][m]["metrics"][METRIC]
    return tuple(100 * v[k] if v.get(k) is not None else NAN for k in ("mean", "ci95_low", "ci95_high"))


def rls_equals_ls(conds, methods):
    """rls gives LS's estimate up to round-off (~1e-6 relative): drawn on top of ls it would only hide it."""
    if "rls" not in methods or "ls" not in methods:
        return False
    pairs = [(stat(c, "rls")[0], stat(c, "ls")[0]) for c in conds]
    return all(abs(a - b) <= 1e-4 * max(abs(b), 1e-12) for a, b in pairs if not (math.isnan(a) or math.isnan(b)))


def error_vs_noise(s, out_dir):
    conds = s["conditions"]
    methods = ordered(s["config"]["sweep"]["methods"])
    rls_hidden = rls_equals_ls(conds, methods)
    drawn = [m for m in methods if not (m == "rls" and rls_hidden)]
    rows = sorted({row_key(c["condition"]) for c in conds})
    vibs = sorted({c["condition"]["vibration_level"] for c in conds})
    fig, axes = plt.subplots(len(rows), len(vibs), figsize=(max(9.0, 4.2 * len(vibs) + 2.6), 3.4 * len(rows)),
                             squeeze=False, sharex=True, layout="constrained")
    fig.suptitle("Torque-space error vs the best fit, mean over seeds (log scale)\nls and rls-pso with 95 % CI "
                 "bands (a band reaching the bottom: the CI includes 0)", fontsize=10)
    for r, key in enumerate(rows):
        cells = {v: sorted((c for c in conds if row_key(c["condition"]) == key
                            and c["condition"]["vibration_level"] == v), key=lambda c: c["condition"]["torque_noise_Nm"])
                 for v in vibs}
        ylim = row_limits([c for cs in cells.values() for c in cs], drawn)
        for ax, v in zip(axes[r], vibs):
            noise_panel(ax, cells[v], drawn, ylim)
            ax.set_title(f"{row_title(key)}, vibration {v:g}", fontsize=8)
        axes[r][0].set_ylabel("torque-space error (%)")
    for ax in axes[-1]:
        ax.set_xlabel("torque noise std (N m)")
    # One legend for the figure, in the methods' order (lead arms first), outside the panels.
    pairs = sorted(zip(*axes[0][0].get_legend_handles_labels()), key=lambda p: drawn.index(p[1]))
    handles, labels = [p[0] for p in pairs], [p[1] for p in pairs]
    if rls_hidden:
        handles.append(plt.Line2D([], [], color="none"))
        labels.append("rls = ls (same means\nto < 0.01 %), not drawn")
    axes[0][-1].legend(handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False)
    save(fig, out_dir, "error_vs_noise.png")


def row_limits(cells, methods):
    """Log y-limits from the means and the positive CI ends, so a CI <= 0 does not set the scale."""
    vals = []
    for c in cells:
        for m in methods:
            mean, lo, hi = stat(c, m)
            vals += [x for x in ([mean, lo, hi] if m in LEAD else [mean]) if x > 0]
    if not vals:
        return None
    return min(vals) / 1.6, max(vals) * 1.6


def noise_panel(ax, cells, methods, ylim):
    if not cells:
        ax.axis("off")
        return
    x = [c["condition"]["torque_noise_Nm"] for c in cells]
    for m in reversed(methods):  # the lead arms last, on top
        mean, lo, hi = (np.array(v) for v in zip(*(stat(c, m) for c in cells)))
        style = {"color": COLORS.get(m), "ls": STYLES.get(m, "-")}
        if m in LEAD:
            ax.plot(x, mean, marker="o", ms=5, lw=2.4, label=m, zorder=4, **style)
            bottom = ylim[0] if ylim else 1e-12
            ax.fill_between(x, np.where(lo > 0, lo, bottom), hi, color=COLORS.get(m), alpha=0.15, lw=0, zorder=2)
        else:
            strong = m == "pso"  # the paper's third arm: its own colour at medium weight
            ax.plot(x, mean, marker=".", ms=4, lw=1.4 if strong else 0.9, alpha=0.9 if strong else 0.55,
                    label=m, zorder=3, **style)
    ax.set_yscale("log")
    if ylim:
        ax.set_ylim(*ylim)
    ax.set_xticks(sorted(set(x)))
    ax.grid(alpha=0.3, which="both")


def ratio_grid(cells, taus, vibs):
    """RLS-PSO / LS mean torque-space error per (vibration, torque noise), and RLS-PSO's win counts."""
    ratio = np.full((len(vibs), len(taus)), NAN)
    wins = [[None] * len(taus) for _ in vibs]
    for c in cells:
        i, j = vibs.index(c["condition"]["vibration_level"]), taus.index(c["condition"]["torque_noise_Nm"])
        a = c["methods"]["rls-pso"]["metrics"][METRIC]["mean"]
        b = c["methods"]["ls"]["metrics"][METRIC]["mean"]
        if a is not None and b:
            ratio[i, j] = a / b
        paired = c["methods"]["rls-pso"].get("vs_ls", {}).get(METRIC, {})
        if paired.get("win_rate") is not None and paired.get("n"):
            wins[i][j] = (paired["win_rate"] * paired["n"], paired["n"])
    return ratio, wins


def ratio_ticks(limit):
    """Colour-bar ticks at readable ratios inside +-limit (log2)."""
    nice = [1 / 16, 1 / 8, 1 / 4, 1 / 3, 1 / 2, 2 / 3, 0.8, 1, 1.25, 1.5, 2, 3, 4, 8, 16]
    ticks = [r for r in nice if abs(math.log2(r)) <= limit + 1e-9]
    if len(ticks) > 9:
        ticks = [r for r in ticks if float(math.log2(r)).is_integer()]
    return ticks


def ratio_map(s, out_dir):
    conds = s["conditions"]
    groups = {}
    for c in conds:
        groups.setdefault(row_key(c["condition"]), []).append(c)
    keys = sorted(groups)
    grids = {}
    for key in keys:
        taus = sorted({c["condition"]["torque_noise_Nm"] for c in groups[key]})
        vibs = sorted({c["condition"]["vibration_level"] for c in groups[key]})
        grids[key] = (taus, vibs) + ratio_grid(groups[key], taus, vibs)
    logs = np.concatenate([np.log2(g[2][np.isfinite(g[2]) & (g[2] > 0)]) for g in grids.values()])
    # Diverging scale centred on a ratio of 1, symmetric limits from the data (one scale for all panels).
    limit = max(float(np.max(np.abs(logs))) if logs.size else 0.0, math.log2(1.25))
    limit = math.ceil(limit * 2) / 2  # up to a ratio of 2^(k/2), so the colour bar ends on a labelled tick
    norm, cmap = Normalize(-limit, limit), plt.get_cmap("RdBu_r").copy()
    cmap.set_bad("#d9d9d9")  # missing cells grey, not the white of a ratio of 1
    fig, axes = plt.subplots(1, len(keys), figsize=(max(7.0, 4.6 * len(keys) + 1.6), 4.6), squeeze=False,
                             layout="constrained")
    fig.suptitle("RLS-PSO / LS mean torque-space error\n(red: RLS-PSO farther from the truth, blue: closer)",
                 fontsize=10)
    for ax, key in zip(axes.flat, keys):
        im = ratio_panel(ax, grids[key], norm, cmap)
        ax.set_title(row_title(key), fontsize=9)
    bar = fig.colorbar(im, ax=axes.ravel().tolist(), shrink=0.9)
    ticks = ratio_ticks(limit)
    bar.set_ticks([math.log2(r) for r in ticks], labels=["%.3g" % r for r in ticks])
    bar.set_label("RLS-PSO / LS (<1: RLS-PSO closer to truth)")
    save(fig, out_dir, "ratio_map.png")


def ratio_panel(ax, grid, norm, cmap):
    taus, vibs, ratio, wins = grid
    logs = np.where(np.isfinite(ratio) & (ratio > 0), np.log2(np.where(ratio > 0, ratio, 1.0)), np.nan)
    im = ax.imshow(logs, origin="lower", cmap=cmap, norm=norm, aspect="auto")
    for i in range(len(vibs)):
        for j in range(len(taus)):
            ax.text(j, i, cell_label(ratio[i, j], wins[i][j]), ha="center", va="center", fontsize=9,
                    color=text_colour(cmap, norm, logs[i, j]))
    ax.set_xticks(range(len(taus)), ["%g" % t for t in taus])
    ax.set_yticks(range(len(vibs)), ["%g" % v for v in vibs])
    ax.set_xlabel("torque noise std (N m)")
    ax.set_ylabel("vibration level")
    return im


def cell_label(r, win):
    if math.isnan(r):
        return "n/a"
    text = "%.2f" % r
    if win is not None:
        text += "\nRLS-PSO lower\nin %g/%d seeds" % win
    return text


def text_colour(cmap, norm, v):
    """White on dark cells, black on light ones (luminance of the cell's colour)."""
    if math.isnan(v):
        return "black"
    r, g, b, _ = cmap(norm(v))
    return "white" if 0.299 * r + 0.587 * g + 0.114 * b < 0.5 else "black"


def main(summary_path, out_dir):
    with open(summary_path) as f:
        s = json.load(f)
    error_vs_noise(s, out_dir)
    methods = s["config"]["sweep"]["methods"]
    if "rls-pso" in methods and "ls" in methods:
        ratio_map(s, out_dir)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: sweep_plots.py SUMMARY_JSON OUT_DIR")
    main(sys.argv[1], sys.argv[2])
