#!/usr/bin/python3
"""Identify the DFKI double pendulum's swing-up (shipped with exoid) from Python and plot the
measured torque against the identified model's. Run from the repository after building:

    PYTHONPATH=build/python /usr/bin/python3 examples/identify_real_log.py [out.png]
"""
import gzip
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import exoid  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
log = os.path.join(here, "..", "data", "real", "dfki_double_pendulum", "design_A0_20220815_trajectory_11.csv.gz")
columns = {"t": "time", "q_hip": "pos_meas1", "q_knee": "pos_meas2", "tau_hip": "tau_meas1", "tau_knee": "tau_meas2"}
with gzip.open(log, "rt") as f:
    data = exoid.parse_dataset(f.read(), source=log, columns=columns)
print("sampling:", data["sampling"])

rows = exoid.process_record(data, thigh_length_m=0.3)  # the arm's upper link is 0.3 m
H = np.vstack([rows["hip"], rows["knee"]])
y = np.concatenate([rows["tau"][:, 0], rows["tau"][:, 1]])
result = exoid.identify(H, y, method="ls")
print(result["status"], "condition number", round(result["condition_number"], 2))
for name, value in zip(exoid.param_names(), result["x"]):
    print(f"{name:4s} {value: .5f}")

n = rows["hip"].shape[0]
fig, axes = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
for ax, joint, A, k in zip(axes, ("hip (shoulder)", "knee (elbow)"), (rows["hip"], rows["knee"]), (0, 1)):
    ax.plot(rows["t"], rows["tau"][:, k], color="#999999", label="measured (processed)")
    ax.plot(rows["t"], A @ result["x"], color="#1f77b4", lw=1.2, label="identified model")
    ax.set_ylabel(f"{joint} torque (N m)")
    ax.grid(alpha=0.3)
axes[0].legend()
axes[1].set_xlabel("time (s)")
out = sys.argv[1] if len(sys.argv) > 1 else "identify_real_log.png"
fig.tight_layout()
fig.savefig(out, dpi=110)
print("wrote", out)
