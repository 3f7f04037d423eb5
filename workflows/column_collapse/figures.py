#!/usr/bin/python3
"""Figures of a column-collapse run, after seed Figs. 4 and 5: figures.py RUN_DIR [RUN_DIR_2 ...] OUT_DIR
[--panels N]. Several run folders are the segments of a resumed run (run, run_2, …), in order.

Velocity norm, ε̇_q (seed Eq. 5, the solver's strain_rate_q) and damage D at N times, the front and
height over time, the hit rate (hybrid, cache), the runout on each side and the centroid's shift
(spreading.png), the last deposit with its mirror image and the paths of the two top corners
(deposit.png; numbers in spreading.json, with kinetic energy over its peak), the damage of the
tracked points and the bond count of their DEM cells (cells/*.vtk, written for live points).
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from plotting import collapse_figures  # noqa: E402  (after the path set-up)

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", type=Path, nargs="+")
    parser.add_argument("out", type=Path)
    parser.add_argument("--panels", type=int, default=6)
    args = parser.parse_args()
    for name in collapse_figures.all_figures(args.runs, args.out, args.panels):
        print(args.out / name)
