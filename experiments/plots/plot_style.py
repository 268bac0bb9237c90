"""What exoid's figure scripts share: one colour and line style per method, the order methods
are shown in (the paper's comparison first), the series CSVs read by column, and a deterministic
atomic save."""
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# One distinct colour per method (matplotlib's default cycle has 10, the protocol 11 arms).
COLORS = {"ls": "#1f77b4", "rls": "#9467bd", "pso": "#ff7f0e", "rls-pso": "#2ca02c", "lad": "#7f7f7f",
          "ls-exact": "#17becf", "ls-stacked": "#8c564b", "ls-parallel": "#d62728", "idim-iv": "#e377c2",
          "ls-base": "#bcbd22", "idim-iv-base": "#393b79",
          "default": "#000000"}
# Colour alone does not separate seven thin traces: every arm also gets its own line style.
STYLES = {"ls": "-", "rls-pso": "--", "pso": "-.", "rls": ":", "lad": "-", "ls-exact": "--", "ls-stacked": "-.",
          "ls-parallel": ":", "idim-iv": "-", "ls-base": "--", "idim-iv-base": "-.", "default": "-"}
# The paper's question is LS against RLS-PSO (and PSO): they come first.
ORDER = ["ls", "rls-pso", "pso", "rls", "lad", "ls-exact", "ls-stacked", "ls-parallel", "idim-iv", "ls-base",
         "idim-iv-base", "default"]


def ordered(methods):
    """The paper's arms first, then the harness's, then anything unknown (sorted, so stable)."""
    return [m for m in ORDER if m in methods] + sorted(m for m in methods if m not in ORDER)


def read_columns(path):
    """A series CSV (one header row, numbers below) as {column name: numpy array}."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    return {name: data[:, i] for i, name in enumerate(header)}


def save_figure(fig, path):
    """Writes fig to path through a temporary file (never half-written), without timestamps (same
    data, same bytes), and closes it."""
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=110, metadata={"Software": None})
    os.replace(tmp, path)
    plt.close(fig)
