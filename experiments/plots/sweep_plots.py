#!/usr/bin/env python3
"""Figures of `exoid sweep` from summary.json: error vs torque noise per method (95 % CIs), and a
torque noise x vibration map of the RLS-PSO / LS parameter error ratio."""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# One distinct colour per method, as in reproduce_plots.py (the default cycle has 10).
COLORS = {"ls": "#1f77b4", "rls": "#9467bd", "pso": "#ff7f0e", "rls-pso": "#2ca02c", "lad": "#7f7f7f",
          "ls-exact": "#17becf", "ls-stacked": "#8c564b", "ls-parallel": "#d62728", "idim-iv": "#e377c2",
          "ls-base": "#bcbd22", "idim-iv-base": "#393b79"}


def main(summary_path, out_dir):
    with open(summary_path) as f:
        s = json.load(f)
    methods = s["config"]["sweep"]["methods"]
    conds = s["conditions"]
    panels = {}
    for c in conds:
        k = c["condition"]
        key = (k["cylinder_mass_scale"], k["vibration_level"], k["angle_noise_deg"], k["quantisation_deg"],
               k.get("trajectories", "paper"))
        panels.setdefault(key, []).append(c)
    keys = sorted(panels)
    cols = min(3, len(keys))
    rows = (len(keys) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(5 * cols, 3.8 * rows), squeeze=False)
    for ax, key in zip(axes.flat, keys):
        cs = sorted(panels[key], key=lambda c: c["condition"]["torque_noise_Nm"])
        x = [c["condition"]["torque_noise_Nm"] for c in cs]
        for m in methods:
            st = [c["methods"][m]["metrics"]["torque_err_mean"] for c in cs]
            y = [100 * (v["mean"] if v["mean"] is not None else float("nan")) for v in st]
            lo = [100 * (v["mean"] - v["ci95_low"]) if v["ci95_low"] is not None else 0 for v in st]
            hi = [100 * (v["ci95_high"] - v["mean"]) if v["ci95_high"] is not None else 0 for v in st]
            ax.errorbar(x, y, yerr=[lo, hi], marker="o", ms=3, capsize=3, label=m, color=COLORS.get(m))
        ax.set_title("cyl %g, vib %g, q noise %g deg, %s trajectories" % (key[:3] + key[4:]), fontsize=9)
        ax.set_xlabel("torque noise std (N m)")
        ax.set_ylabel("torque-space error vs best fit (%)")
        ax.set_yscale("log")
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(keys):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out_dir + "/error_vs_noise.png", dpi=110)
    plt.close(fig)

    if "rls-pso" in methods and "ls" in methods:
        groups = {}
        for c in conds:
            k = c["condition"]
            groups.setdefault((k["cylinder_mass_scale"], k["angle_noise_deg"], k["quantisation_deg"],
                               k.get("trajectories", "paper")), []).append(c)
        gkeys = sorted(groups)
        fig, axes = plt.subplots(1, len(gkeys), figsize=(5 * len(gkeys), 4), squeeze=False)
        for ax, key in zip(axes.flat, gkeys):
            taus = sorted({c["condition"]["torque_noise_Nm"] for c in groups[key]})
            vibs = sorted({c["condition"]["vibration_level"] for c in groups[key]})
            grid = [[float("nan")] * len(taus) for _ in vibs]
            for c in groups[key]:
                a = c["methods"]["rls-pso"]["metrics"]["torque_err_mean"]["mean"]
                b = c["methods"]["ls"]["metrics"]["torque_err_mean"]["mean"]
                if a is not None and b:
                    grid[vibs.index(c["condition"]["vibration_level"])][taus.index(c["condition"]["torque_noise_Nm"])] = a / b
            im = ax.imshow(grid, origin="lower", cmap="RdBu_r", vmin=0, vmax=2, aspect="auto")
            for i in range(len(vibs)):
                for j in range(len(taus)):
                    ax.text(j, i, "%.2f" % grid[i][j], ha="center", va="center", fontsize=8)
            ax.set_xticks(range(len(taus)), [str(t) for t in taus])
            ax.set_yticks(range(len(vibs)), [str(v) for v in vibs])
            ax.set_xlabel("torque noise std (N m)")
            ax.set_ylabel("vibration level")
            ax.set_title("RLS-PSO / LS torque-space error, cyl %g, %s trajectories" % (key[0], key[3]), fontsize=9)
            fig.colorbar(im, ax=ax)
        fig.tight_layout()
        fig.savefig(out_dir + "/ratio_map.png", dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
