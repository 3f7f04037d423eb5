"""How a body at rest carries its weight, row by row of material points.

  row_load.py RUN_FOLDER TIME

For each row of points (points within half a spacing of their neighbour in height) of the snapshot nearest TIME: the row's mean
σ_yy against the weight per unit width above the row's centre (the points above it and half the
row's own, each a square of the median point spacing at its density), and their ratio. A column at
rest between walls of no friction, or with free sides, carries ratio 1 in every row; the rows at a
floor show how the floor's reaction reaches the points (README, "Where an obstacle's force acts").
The widths assume the rows keep their points' initial spacing across, so read it on bodies that do
not spread.
"""
import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from plotting import vtu  # noqa: E402


def row_loads(snapshot):
    """[(row height, points, mean σ_yy, weight above per unit width)] from the top row down."""
    syy = snapshot.fields["stress"].reshape(-1, 3, 3)[:, 1, 1]
    rho = snapshot.fields["density"]
    y = snapshot.xy[:, 1]
    spacing = snapshot.spacing()
    order = np.argsort(-y)
    row_of = np.cumsum(np.r_[0, np.diff(-y[order]) > spacing / 2])  # a new row at every gap
    rows = []
    for r in range(row_of[-1] + 1):
        own = order[row_of == r]
        above = order[row_of < r]
        width = len(own) * spacing
        weight = (rho[above].sum() + 0.5 * rho[own].sum()) * spacing**2 * 9.81 / width
        rows.append((float(y[own].mean()), len(own), float(syy[own].mean()), -weight))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("time", type=float)
    args = parser.parse_args()
    snapshots = vtu.read_run(args.run)
    if not snapshots:
        sys.exit(f"row_load.py: no snapshots in {args.run}")
    snapshot = min(snapshots, key=lambda s: abs(s.time - args.time))
    print(f"t = {snapshot.time:.3f} s, point spacing {snapshot.spacing():.4f} m")
    print("| row height [m] | points | mean σ_yy [Pa] | weight above [Pa] | ratio |")
    print("|---|---|---|---|---|")
    for height, count, syy, weight in row_loads(snapshot):
        print(f"| {height:.4f} | {count} | {syy:.1f} | {weight:.1f} | {syy / weight:.2f} |")


if __name__ == "__main__":
    main()
