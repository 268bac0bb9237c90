#!/usr/bin/env python3
"""How far records of one robot scatter against their own standard errors (docs/findings.md, 4.7).

Fits each shipped DFKI A.0 record 00-05 alone with `exoid identify`'s defaults and prints, for Mxt,
Jt, Mxs and Js, sqrt(chi^2 / (K - 1)) of the estimates about their inverse-variance mean (1 when
the reported errors cover the records' differences), then each record's estimate and error.
Usage: scripts/real_log_scatter.py [EXOID_BINARY] [standard_errors|standard_errors_newey_west]
"""
import json
import math
import os
import subprocess
import sys
import tempfile

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
exoid = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build/experiments/exoid")
key = sys.argv[2] if len(sys.argv) > 2 else "standard_errors"
data = os.path.join(root, "data/real/dfki_double_pendulum")
params = ["Mxt", "Jt", "Mxs", "Js"]
fits = {p: [] for p in params}
with tempfile.TemporaryDirectory() as work:
    for r in ["00", "01", "02", "03", "04", "05"]:
        out = os.path.join(work, r + ".json")
        subprocess.run([exoid, "identify", "--profile", os.path.join(data, "profile.toml"), "--data",
                        os.path.join(data, "design_A0_20220815_trajectory_%s.csv.gz" % r), "--json", out], capture_output=True)
        j = json.load(open(out))
        errors = j["methods"]["ls"]["consistency"][key]
        for p in params:
            fits[p].append((j["parameters"][p], errors[p]))
for p in params:
    w = [1 / s ** 2 for _, s in fits[p]]
    mean = sum(wi * x for wi, (x, _) in zip(w, fits[p])) / sum(w)
    chi2 = sum((x - mean) ** 2 / s ** 2 for x, s in fits[p])
    print("%-4s scatter / error %.2f   %s" % (p, math.sqrt(chi2 / (len(fits[p]) - 1)),
                                          "  ".join("%.4g (%.2g)" % f for f in fits[p])))
