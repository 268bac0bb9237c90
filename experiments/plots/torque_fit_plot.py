#!/usr/bin/python3
"""Figure of `exoid identify --model ... --plot`: each joint's measured torque (processed as the fit
processed its records) and the torque the estimate predicts, with their difference.
Usage: torque_fit_plot.py SERIES_CSV OUT_PNG TITLE"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from plot_style import read_columns, save_figure  # noqa: E402


def main(series_path, out_png, title):
    cols = read_columns(series_path)
    joints = [h[len("tau_"):] for h in cols if h.startswith("tau_") and not h.endswith("_predicted")]
    t = cols["t_s"]
    fig, axes = plt.subplots(len(joints), 1, figsize=(10, 2.6 * len(joints)), sharex=True, squeeze=False)
    for ax, joint in zip(axes[:, 0], joints):
        measured, predicted = cols[f"tau_{joint}"], cols[f"tau_{joint}_predicted"]
        error = [p - m for p, m in zip(predicted, measured)]
        rms = (sum(e * e for e in error) / len(error)) ** 0.5
        ax.plot(t, measured, color="#333333", lw=1.2, label="measured")
        ax.plot(t, predicted, color="#1f77b4", lw=1.0, ls="--", label="predicted")
        ax.plot(t, error, color="#d62728", lw=0.8, label=f"predicted - measured (RMS {rms:.3g} N m)")
        ax.set_ylabel(f"{joint} torque (N m)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    axes[-1, 0].set_xlabel("time (s)")
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    save_figure(fig, out_png)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3])
