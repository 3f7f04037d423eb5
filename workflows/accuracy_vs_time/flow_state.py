"""The state of a run's flowing points: per run folder, the median stress ratio q/p, damage D and
pressure of the points that flow (ε̇_q above --rate, p above --pressure) in the snapshots from --after
on, split by where each point's stress came from (a live cell or the library). Compares a library run
with its live reference where the runout alone cannot show it: a stronger friction and a faster loss
of bonds may cancel in the runout.

  flow_state.py RUN [RUN ...] [--after 0.15] [--rate 0.5] [--pressure 50]
"""
import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from plotting import vtu  # noqa: E402  (after the path set-up)

def flowing_state(folder, after, rate, pressure):
    """{source name: (points, median q/p, median D, median p [Pa])} of the flowing points of `folder`."""
    fields = [s.fields for s in vtu.read_run(folder) if s.time >= after]
    if not fields:
        raise ValueError(f"{folder}: no snapshot at or after t = {after} s")
    stack = {key: np.concatenate([f[key] for f in fields]) for key in
             ("pressure", "deviatoric_stress", "strain_rate_q", "source", "damage")}
    flowing = (stack["strain_rate_q"] > rate) & (stack["pressure"] > pressure)
    result = {}
    for source in np.unique(stack["source"][flowing]):
        chosen = flowing & (stack["source"] == source)
        result[vtu.STRESS_SOURCES[int(source)]] = (
            int(chosen.sum()), float(np.median(stack["deviatoric_stress"][chosen] / stack["pressure"][chosen])),
            float(np.median(stack["damage"][chosen])), float(np.median(stack["pressure"][chosen])))
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", type=Path, nargs="+")
    parser.add_argument("--after", type=float, default=0.15, help="first snapshot time [s]")
    parser.add_argument("--rate", type=float, default=0.5, help="ε̇_q above which a point flows [1/s]")
    parser.add_argument("--pressure", type=float, default=50.0, help="p above which q/p is read [Pa]")
    args = parser.parse_args()
    print("| run | stress from | point-snapshots | median q/p | median D | median p [Pa] |")
    print("|---|---|---|---|---|---|")
    for run in args.runs:
        for source, (count, ratio, damage, p) in flowing_state(run, args.after, args.rate, args.pressure).items():
            print(f"| {run} | {source} | {count} | {ratio:.2f} | {damage:.2f} | {p:.0f} |")


if __name__ == "__main__":
    main()
