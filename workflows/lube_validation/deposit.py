"""The deposit of a column run, read from its last snapshot: the height profile h(x) and the edges
where it thins below a fraction of H0.

Why more than the front: the front (the largest x of any material point) is where the deposit's
tail ends, and a continuum tail keeps thinning until it is one or two grid cells thick, so the
front moves out by about the same amount at every halving of h while the bulk of the deposit stays
put. The edges at a few per cent of H0 and the profile itself are what can converge with h; the
study reports them beside the front.
"""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from plotting.vtu import read_pvd, read_vtu  # noqa: E402

EDGE_FRACTIONS = (0.05, 0.10, 0.15)  # deposit thickness / H0 at which the edges are reported


def profile(run_folder, geometry, h, until=float("inf")):
    """(x, height, time) of the deposit in the last snapshot at or before `until` [s], in units of L0
    and H0: x from the column's initial right edge, one bin per grid cell, height = highest point top in
    the bin above the base (bins without points are left out); time [s] is the snapshot's."""
    time, file = [entry for entry in read_pvd(Path(run_folder) / "points.pvd") if entry[0] <= until][-1]
    snapshot = read_vtu(file)
    x = (snapshot.xy[:, 0] - geometry["wall"] - geometry["L0"]) / geometry["L0"]
    top = (snapshot.xy[:, 1] + geometry["radius"] - geometry["base"]) / geometry["H0"]
    bins = np.floor(x * geometry["L0"] / h).astype(int)
    edges = np.unique(bins)
    heights = np.array([top[bins == b].max() for b in edges])
    return (edges + 1) * h / geometry["L0"], heights, float(time)


def edge(x, height, fraction):
    """ΔL/L0 at the last bin whose deposit is at least `fraction` of H0 thick (nan if none is)."""
    thick = x[height >= fraction]
    return float(thick.max()) if thick.size else float("nan")


def edges(x, height):
    return {f"{f:g}": edge(x, height, f) for f in EDGE_FRACTIONS}
