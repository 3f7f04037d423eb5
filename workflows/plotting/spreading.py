"""How a column released on both sides spreads: what the paper's description of its column (seed §4)
can be checked against. From a run's snapshots (equal-mass points, as one uniform region seeds them):

- the runout on each side, from the column's initial edges, and their asymmetry: a symmetric column
  on a symmetric base spreads symmetrically unless something breaks the symmetry (the seed's
  "spontaneous symmetry breaking", from the independent microstructures of the cells);
- the edges of the deposit, the mass that hangs together (no gap wider than DETACHED_GAP initial
  point spacings along x), and how many points lie beyond them: a few points thrown ahead of the
  toe set the farthest-point runout but are not the deposit;
- the shift of the mass centroid from the column's axis (the same, weighed by mass, not by the tips);
- the two top corners: the points that started there, followed to the end ("the two initial top
  corners of the column remain distinguishable even in later phases");
- the deposit profile of the last snapshot, with its mirror image about the column's axis.
"""
import numpy as np

from . import figures, flow


def column_edges(first):
    """(left, right, axis): the column's initial edges and its axis midway [m], from the first snapshot."""
    left, right = first.xy[:, 0].min(), first.xy[:, 0].max()
    return left, right, 0.5 * (left + right)


DETACHED_GAP = 3  # initial point spacings: a wider gap along x separates a point from the deposit


def deposit_edges(snapshot, axis, gap):
    """(left, right, detached): the x of the outermost points reached from the point nearest the axis
    through gaps no wider than `gap` [m] between neighbours in x, and how many points lie beyond."""
    x = np.sort(snapshot.xy[:, 0])
    start = int(np.argmin(np.abs(x - axis)))
    steps = np.diff(x) > gap
    right = start + int(np.argmax(np.append(steps[start:], True)))
    left = start - int(np.argmax(np.append(steps[:start][::-1], True)))
    return float(x[left]), float(x[right]), len(x) - (right - left + 1)


def top_corner_ids(first):
    """Ids of the points at the top-left and top-right corners of the first snapshot."""
    x, y = first.xy[:, 0], first.xy[:, 1]
    return int(first.fields["id"][np.argmax(y - x)]), int(first.fields["id"][np.argmax(y + x)])


def position_of(snapshot, point_id):
    return snapshot.xy[np.flatnonzero(snapshot.fields["id"] == point_id)[0]]


def spreading(snapshots):
    """One row per snapshot: t, runout_left, runout_right [m] (the farthest points beyond the initial
    edges), asymmetry (right − left over their mean; 0 when neither has moved), deposit_left,
    deposit_right [m] (the deposit's edges beyond the initial edges, deposit_edges) and
    detached_points, centroid_shift [m] (positive to the right) and height [m] (highest point), and
    the positions of the two top corners."""
    first = snapshots[0]
    left0, right0, axis = column_edges(first)
    corners = top_corner_ids(first)
    gap = DETACHED_GAP * first.spacing()
    rows = []
    for s in snapshots:
        x = s.xy[:, 0]
        left, right = float(left0 - x.min()), float(x.max() - right0)
        mean = 0.5 * (left + right)
        deposit_left, deposit_right, detached = deposit_edges(s, axis, gap)
        rows.append({"t": s.time, "runout_left": left, "runout_right": right,
                     "asymmetry": (right - left) / mean if mean > 0 else 0.0,
                     "deposit_left": left0 - deposit_left, "deposit_right": deposit_right - right0,
                     "detached_points": detached,
                     "centroid_shift": float(x.mean() - axis), "height": float(s.xy[:, 1].max()),
                     "corner_left": position_of(s, corners[0]).tolist(),
                     "corner_right": position_of(s, corners[1]).tolist()})
    return rows


def spreading_figure(rows, out):
    t = np.array([r["t"] for r in rows])
    figures.time_plot(out, [(t, [r["runout_left"] for r in rows], "runout, left [m]", None),
                            (t, [r["runout_right"] for r in rows], "runout, right [m]", {"linestyle": "--"}),
                            (t, [r["deposit_left"] for r in rows], "deposit edge, left [m]", {"linewidth": 0.8}),
                            (t, [r["deposit_right"] for r in rows], "deposit edge, right [m]",
                             {"linestyle": "--", "linewidth": 0.8}),
                            (t, [r["centroid_shift"] for r in rows], "centroid shift (to the right) [m]",
                             {"linestyle": ":"})],
                      "t [s]", "[m]", title="spreading on each side")


def deposit_figure(snapshots, rows, out):
    """The last snapshot's free surface, its mirror image about the column's axis, the initial column
    and the paths of its two top corners."""
    first, last = snapshots[0], snapshots[-1]
    left0, right0, axis = column_edges(first)
    step = first.spacing()
    reach = max(axis - last.xy[:, 0].min(), last.xy[:, 0].max() - axis) + step
    bins = np.arange(axis - reach, axis + reach + step, step)
    centres = 0.5 * (bins[1:] + bins[:-1])
    height = flow.deposit_profile(last, bins)
    height[height == 0] = np.nan  # no point in the bin: no surface to draw
    fig, ax = figures.plt.subplots(figsize=(8, 3.4))
    ax.plot(centres, height, label=f"free surface at t = {last.time:.3g} s")
    ax.plot(2 * axis - centres, height, linestyle="--", label="its mirror image about the column's axis")
    base = first.xy[:, 1].min()
    ax.plot([left0, left0, right0, right0], [base, first.xy[:, 1].max(), first.xy[:, 1].max(), base],
            color="grey", linewidth=0.8, label="initial column (point centres)")
    for side in ("corner_left", "corner_right"):
        path = np.array([r[side] for r in rows])
        ax.plot(path[:, 0], path[:, 1], marker=".", markersize=3, linewidth=0.8,
                label=f"top {side.split('_')[1]} corner's path")
    ax.set_aspect("equal")
    figures.finish_and_save(fig, ax, out, "x [m]", "height [m]")
