"""How much of the points' velocity the grid carries, snapshot by snapshot of a run.

  fluctuations.py RUN_FOLDER --cell-size H [--origin X Y] [--from T]

The points' velocities v_p of each snapshot go to a grid of cell size H and back, as the solver's
transfers do (cubic B-splines, mass-weighted): S R v is what a round trip through the grid brings
back, d = v − S R v what it does not (under APIC-FLIP, the fluctuation FLIP keeps), and d's own round
trip splits it into the part the grid carries, S R d, and the rough rest, d − S R d, that
`noise_rate` blends out (mpm_solver/core/transfers.hpp). Prints the root mean square of each over the
points, in mm/s. Masses are taken as density × an equal volume, which holds for points seeded alike.
--origin is the grid's (the scene's grid.origin, default 0 0).
"""
import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from plotting import vtu  # noqa: E402


def cubic_bspline(u):
    u = np.abs(u)
    return np.where(u < 1, 0.5 * u**3 - u**2 + 2 / 3, np.where(u < 2, (2 - u) ** 3 / 6, 0.0))


class GridRoundTrip:
    """P2G (mass-weighted) and G2P of per-point vectors on a grid of cell size h, for fixed points."""

    def __init__(self, xy, mass, h, origin=(0.0, 0.0)):
        xy = xy - np.asarray(origin)
        base = np.floor(xy / h).astype(int) - 1  # the first of each point's 4 × 4 nodes
        offsets = np.array([(a, b) for b in range(4) for a in range(4)])
        nodes = base[:, None, :] + offsets[None, :, :]  # points × 16 × 2
        u = xy[:, None, :] / h - nodes
        self.weight = cubic_bspline(u[..., 0]) * cubic_bspline(u[..., 1])  # points × 16
        keys, self.node = np.unique(nodes.reshape(-1, 2), axis=0, return_inverse=True)
        self.node = self.node.reshape(len(xy), 16)
        self.mass = mass
        self.node_mass = np.bincount(self.node.ravel(), (self.weight * mass[:, None]).ravel(), len(keys))

    def carried(self, vectors):
        """S R vectors: each point's vector after P2G (Σ_p N m v / m_i) and G2P (Σ_i N v_i)."""
        out = np.empty_like(vectors)
        for c in range(vectors.shape[1]):
            momentum = np.bincount(self.node.ravel(), (self.weight * (self.mass * vectors[:, c])[:, None]).ravel(),
                                   len(self.node_mass))
            nodal = np.divide(momentum, self.node_mass, out=np.zeros_like(momentum), where=self.node_mass > 0)
            out[:, c] = (self.weight * nodal[self.node]).sum(axis=1)
        return out


def split(xy, velocity, mass, h, origin=(0.0, 0.0)):
    """(S R v, d = v − S R v, S R d, d − S R d) for points at `xy` with `velocity` and `mass`."""
    trip = GridRoundTrip(xy, mass, h, origin)
    carried = trip.carried(velocity)
    fluctuation = velocity - carried
    carried_fluctuation = trip.carried(fluctuation)
    return carried, fluctuation, carried_fluctuation, fluctuation - carried_fluctuation


def rms(vectors):
    return float(np.sqrt((vectors**2).sum(axis=1).mean()))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", type=Path)
    parser.add_argument("--cell-size", type=float, required=True, help="the run's grid cell size h [m]")
    parser.add_argument("--origin", type=float, nargs=2, default=[0.0, 0.0], help="the grid's origin [m]")
    parser.add_argument("--from", dest="start", type=float, default=0.0, help="first snapshot time [s]")
    args = parser.parse_args()
    print("t [s] | v | S R v (carried) | d = v - S R v | S R d | d - S R d (rough)   [rms, mm/s]")
    for snapshot in vtu.read_run(args.run):
        if snapshot.time < args.start:
            continue
        velocity = snapshot.fields["velocity"].reshape(len(snapshot.xy), -1)[:, :2]
        parts = split(snapshot.xy, velocity, snapshot.fields["density"], args.cell_size, args.origin)
        print(f"{snapshot.time:.3f} | {rms(velocity) * 1e3:.3f} | "
              + " | ".join(f"{rms(p) * 1e3:.3f}" for p in parts))


if __name__ == "__main__":
    main()
