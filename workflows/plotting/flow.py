"""Measures of a collapsing column computed from the snapshots, and errors against a reference run."""
import numpy as np


def runout(series):
    """Front position minus its initial value [m], per row of series.csv."""
    return series["front"] - series["front"][0]


def front_error(series, reference, min_runout=0.01):
    """Worst relative runout error against the reference over their common rows, counting only rows
    where the reference runout exceeds `min_runout` [m] (before that the ratio is noise over a tiny
    number); 0 when the reference never gets there."""
    ref_runout = dict(zip(np.round(reference["t"], 9), runout(reference)))
    worst = 0.0
    for t, r in zip(np.round(series["t"], 9), runout(series)):
        if t in ref_runout and ref_runout[t] > min_runout:
            worst = max(worst, abs(r - ref_runout[t]) / ref_runout[t])
    return worst


# The share of the mass behind the mass edge: the front is the farthest point, so a few stress-free
# points sliding ahead of the toe set it; the mass edge and the centroid follow the bulk, and converge
# with the grid where the front does not (README, "Convergence").
MASS_EDGE_QUANTILE = 0.95


def bulk_advance(snapshot, initial):
    """How far the bulk has gone along x since `initial` [m]: (the 95 % mass edge, the centroid), over
    points, which in the demo's columns have equal masses (one uniform region)."""
    x, x0 = snapshot.xy[:, 0], initial.xy[:, 0]
    return (float(np.quantile(x, MASS_EDGE_QUANTILE) - np.quantile(x0, MASS_EDGE_QUANTILE)),
            float(x.mean() - x0.mean()))


def mean_damage(snapshot):
    """Mean bond damage D = 1 − N_b/N_b(0) over the points (0 for a law without bonds, whose
    snapshots carry D = 0), equal masses as in bulk_advance."""
    return float(np.mean(snapshot.fields["damage"])) if len(snapshot) else 0.0


def stress_error(snapshot, reference):
    """Relative L2 difference of the in-plane stress fields of two snapshots of the same scene (points
    matched by id): ‖σ − σ_ref‖ / ‖σ_ref‖ over all points and components."""
    a = snapshot.by_id(snapshot.in_plane_stress())
    b = reference.by_id(reference.in_plane_stress())
    norm = np.linalg.norm(b)
    return float(np.linalg.norm(a - b) / norm) if norm > 0 else float("nan")


def stress_error_nearest(snapshot, reference):
    """As stress_error for two discretisations of the same scene: each point of `snapshot` is compared
    with the reference point nearest to it."""
    d = np.hypot(*(snapshot.xy[:, None, k] - reference.xy[None, :, k] for k in (0, 1)))
    b = reference.in_plane_stress()[d.argmin(axis=1)]
    norm = np.linalg.norm(b)
    return float(np.linalg.norm(snapshot.in_plane_stress() - b) / norm) if norm > 0 else float("nan")


def smoothed_stress(snapshot, at, width, block=512):
    """The in-plane stress of `snapshot` (n × 3: σ_xx, σ_yy, σ_xy) averaged at the positions `at` over
    a Gaussian of standard deviation `width` [m]; `block` positions at a time, so that memory stays
    linear in the points."""
    at, stress = np.asarray(at, dtype=float), snapshot.in_plane_stress()
    averaged = np.empty((len(at), 3))
    for start in range(0, len(at), block):
        d2 = ((at[start:start + block, None, :] - snapshot.xy[None, :, :]) ** 2).sum(axis=-1)
        weights = np.exp(-d2 / (2 * width ** 2))
        averaged[start:start + block] = weights @ stress / weights.sum(axis=1)[:, None]
    return averaged


def smoothed_stress_error(snapshot, reference):
    """As stress_error, on both fields averaged over a Gaussian of one point spacing of the reference,
    at the reference's points. The grid's forces see a point's stress only through its B-spline
    neighbourhood, and a dense packing's pressure swings from 0 to kPa within a fraction of a percent
    of volume, so two runs can put a column's weight on different points of the same neighbourhood
    (docs/surrogate.md, "Stop 52"); this measure does not count that."""
    width = reference.spacing()
    b = smoothed_stress(reference, reference.xy, width)
    norm = np.linalg.norm(b)
    if norm == 0:
        return float("nan")
    return float(np.linalg.norm(smoothed_stress(snapshot, reference.xy, width) - b) / norm)


def deposit_profile(snapshot, bins):
    """Free-surface height over x: the highest point in each bin of `bins` (edges [m]); 0 where empty."""
    x, y = snapshot.xy[:, 0], snapshot.xy[:, 1]
    which = np.digitize(x, bins) - 1
    height = np.zeros(len(bins) - 1)
    for k in range(len(height)):
        inside = which == k
        if inside.any():
            height[k] = y[inside].max()
    return height


def profile_error(snapshot, reference, bins):
    """RMS difference of the deposit profiles over the bins [m]."""
    return float(np.sqrt(np.mean((deposit_profile(snapshot, bins) - deposit_profile(reference, bins)) ** 2)))
