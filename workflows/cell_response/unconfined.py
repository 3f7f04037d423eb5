"""Unconfined compression of the two-scale material: its strength q_u, and the highest vertical cut of
it that stands (issue 18, "cohesive column": the cell's macroscopic strength from a biaxial test).

A block of material points (--size W H, one point per grid cell of --cell-size h), each answered by
its own live DEM cell of CELL.json, stands without gravity between two smooth platens; the top one
moves down at --strain-rate × H per second, the sides are free. Plane strain, σ_xx = 0 at the sides:
the biaxial test of a vertical cut's face. q_u is the peak of the points' mean −σ_yy.

For a Mohr–Coulomb material q_u = 2 c tan(45° + φ/2), so limit analysis of a vertical cut (γ H_c / c =
N_s tan(45° + φ/2), N_s = 3.83 for Chen's log-spiral, 4 for Culmann's wedge) gives H_c = (N_s / 2)
q_u / (ρ g) whatever the split into c and φ, ρ being the block's bulk density at the start.

  /usr/bin/python3 unconfined.py OUT [--cell CELL.json] [--size 0.05 0.1] [--cell-size 0.0125]
                                 [--strain-rate 0.01] [--strain 0.006] [--build BUILD] [--threads N]

Writes OUT/unconfined.json, OUT/unconfined.md and OUT/unconfined.png (−σ_yy against the platen's
strain); a finished run in OUT/run is kept.
"""
import argparse
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, run_compare, scenes, vtu  # noqa: E402
from plotting.figures import finish_and_save, plt  # noqa: E402
from strength import CHEN_N_S  # noqa: E402

CELL = HERE.parent / "demo" / "cell_soft_snow_125.json"
G = 9.81
N_S = {"Chen (N_s = 3.83)": CHEN_N_S, "Culmann (N_s = 4)": 4.0}
PLATEN_K_N = 2e5  # [N/m per m], as the demo's walls
SNAPSHOTS = 120


def scene(cell, width, height, h, strain_rate, strain):
    """The test's scene: the block from (2h, 2h), platens on its bottom and top faces."""
    x0, y0 = 2 * h, 2 * h
    x1, y1 = x0 + width, y0 + height
    end = strain / strain_rate
    room = [x1 + width + 2 * h, y1 + 2 * h]
    return {
        "grid": {"origin": [0, 0], "cell_size": h, "cells": [round(room[0] / h), round(room[1] / h)]},
        "time": {"end": end, "output_interval": end / SNAPSHOTS, "series_interval": end / SNAPSHOTS},
        "effects": {"gravity": False, "boundary_friction": False, "cohesion": True, "kinetic_stress": False,
                    "rolling_resistance": False},
        "materials": [{"name": "cell", "law": "live", "cell": str(Path(cell).resolve())}],
        "regions": [{"material": "cell", "rectangle": {"min": [x0, y0], "max": [x1, y1]}, "points_per_cell": 1}],
        "obstacles": [{"line": [[0, y0], [room[0], y0]], "k_n": PLATEN_K_N, "damping": 0.5},
                      {"line": [[0, y1], [room[0], y1]], "k_n": PLATEN_K_N, "damping": 0.5,
                       "velocity": [0, -strain_rate * height]}],
    }


def measure(run_folder, strain_rate):
    """(rows of t, platen strain, mean and spread of −σ_yy and mean σ_xx, mean damage; initial density)."""
    snapshots = vtu.read_run(run_folder)
    rows = []
    for s in snapshots:
        stress = s.fields["stress"]
        rows.append({"t": s.time, "strain": strain_rate * s.time, "compression": float(-stress[:, 4].mean()),
                     "compression_min": float(-stress[:, 4].max()), "compression_max": float(-stress[:, 4].min()),
                     "lateral": float(-stress[:, 0].mean()), "damage": float(s.fields["damage"].mean())})
    return rows, float(snapshots[0].fields["density"].mean())


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("unconfined"))
    parser.add_argument("--cell", type=Path, default=CELL)
    parser.add_argument("--size", type=float, nargs=2, default=[0.05, 0.1], metavar=("W", "H"), help="block [m]")
    parser.add_argument("--cell-size", type=float, default=0.0125, help="grid cell size h [m]")
    parser.add_argument("--strain-rate", type=float, default=0.01, help="platen speed / H [1/s]")
    parser.add_argument("--strain", type=float, default=0.006, help="platen strain at the end")
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--threads", type=int, default=environment.threads())
    args = parser.parse_args()
    width, height = args.size
    scenes.require_whole_cells(parser, args.cell_size, [("--size W", width), ("--size H", height)])
    args.out.mkdir(parents=True, exist_ok=True)
    scene_file = args.out / "scene.json"
    scene_file.write_text(json.dumps(scene(args.cell, width, height, args.cell_size, args.strain_rate, args.strain),
                                     indent=2) + "\n")
    cost = run_compare.timed_scene_run(args.build.resolve(), scene_file, args.out / "run", args.threads)
    rows, density = measure(args.out / "run", args.strain_rate)
    peak = max(rows, key=lambda r: r["compression"])
    q_u = peak["compression"]
    # A peak is one the stress has fallen from: at the end still at the largest, q_u is only a bound.
    peak_reached = rows[-1]["compression"] < 0.9 * q_u
    critical = {name: n_s / 2 * q_u / (density * G) for name, n_s in N_S.items()}
    result = {"cell": str(args.cell), "cell_json": json.loads(args.cell.read_text()), "q_u": q_u,
              "peak_reached": peak_reached, "peak_strain": peak["strain"], "peak_time": peak["t"],
              "lateral_at_peak": peak["lateral"], "damage_at_peak": peak["damage"], "density": density,
              "critical_height": critical, "after_peak": rows[-1]["compression"], "cpu_s": cost["cpu_s"],
              "failed": cost["failed"], "rows": rows}
    (args.out / "unconfined.json").write_text(json.dumps(result, indent=2))
    text = (f"Cell {args.cell.name}, block {width:g} × {height:g} m, h = {args.cell_size:g} m, strain rate "
            f"{args.strain_rate:g} /s: " + ("" if peak_reached else
                                            f"NO PEAK by platen strain {args.strain:g} (raise --strain): ")
            + f"q_u {'=' if peak_reached else '≥'} {q_u:.0f} Pa at platen strain {peak['strain']:.2e} "
            f"(points {peak['compression_min']:.0f}–{peak['compression_max']:.0f} Pa, "
            f"mean σ_xx {-peak['lateral']:.0f} Pa, "
            f"damage {peak['damage']:.2f}); at the end {rows[-1]['compression']:.0f} Pa, "
            f"damage {rows[-1]['damage']:.2f}. "
            f"ρ = {density:.0f} kg/m³; highest vertical cut: "
            + ", ".join(f"{name} {value:.3f} m" for name, value in critical.items())
            + f". {cost['cpu_s']:.0f} CPU-s" + (f"; stopped: {cost['failed']}" if cost["failed"] else "") + "\n")
    (args.out / "unconfined.md").write_text(text)
    fig, ax = plt.subplots(figsize=(6, 4))
    strain = np.array([r["strain"] for r in rows])
    ax.plot(strain, [r["compression"] for r in rows], label="−σ_yy, mean over points")
    ax.fill_between(strain, [r["compression_min"] for r in rows], [r["compression_max"] for r in rows], alpha=0.2,
                    label="range over points")
    ax.plot(strain, [r["lateral"] for r in rows], label="−σ_xx, mean")
    finish_and_save(fig, ax, args.out / "unconfined.png", "platen strain", "stress [Pa]")
    print(text, end="")


if __name__ == "__main__":
    main()
