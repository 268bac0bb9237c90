#!/usr/bin/python3
"""Figure of `exoid excite`: the designed trajectory over one period (angle, speed, acceleration,
nominal torque per joint) with the limits it was designed under, and (the APAL leg) the paper's
trajectory on the same axes. Usage: excitation_plot.py SERIES_CSV DESIGN_JSON OUT_PNG"""
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from plot_style import read_columns, save_figure  # noqa: E402


def main(series_path, design_path, out_png):
    cols = read_columns(series_path)
    with open(design_path) as f:
        design = json.load(f)
    lim = design["limits"]
    paper = design["comparison"].get("paper_trajectory")  # the APAL leg's design only
    joints = [j["name"] for j in design["trajectory"]["joints"]]
    t = cols["t_s"]
    quantities = [("q", "angle (deg)", 180 / 3.141592653589793, "q_min_rad", "q_max_rad"),
                  ("qd", "speed (rad/s)", 1.0, None, "qd_max_radps"),
                  ("qdd", "acceleration (rad/s^2)", 1.0, None, "qdd_max_radps2"),
                  ("tau", "nominal torque (N m)", 1.0, None, "tau_max_Nm")]
    fig, axes = plt.subplots(len(quantities), len(joints), figsize=(5.5 * len(joints), 10), sharex=True, squeeze=False)
    for j, joint in enumerate(joints):
        for r, (name, label, scale, low_key, high_key) in enumerate(quantities):
            ax = axes[r][j]
            if paper is not None:
                ax.plot(t, [scale * v for v in cols[f"paper_{name}_{joint}"]], color="#999999", lw=0.8,
                        label=f"paper's trajectory {paper}")
            ax.plot(t, [scale * v for v in cols[f"design_{name}_{joint}"]], color="#1f77b4", lw=1.4, label="design")
            # A limit the model leaves open is written as null (infinite): no line.
            high = lim[high_key][j]
            low = (lim[low_key][j] if low_key else (-high if high is not None else None))
            for v in (low, high):
                if v is not None and math.isfinite(v):
                    ax.axhline(scale * v, color="#d62728", ls="--", lw=0.9)
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
            if r == 0:
                ax.set_title(joint)
        axes[-1][j].set_xlabel("time (s)")
    axes[0][0].legend(fontsize=8, loc="best")
    model = design["model"]["name"] if isinstance(design["model"], dict) else design["model"]  # before 7549e6e: its path
    fig.suptitle("exoid excite: %s, design (seed %s, criterion %s) and limits (%s), red dashed"
                 % (model, design["seed"], design["options"]["criterion"], lim["source"]), fontsize=9)
    fig.tight_layout()
    save_figure(fig, out_png)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3])
