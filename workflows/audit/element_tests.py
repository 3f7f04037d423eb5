#!/usr/bin/python3
"""Element tests of a cached law against its noise floor: one material point driven through a
homogeneous motion (the scene key integration.homogeneous_drive) from the library's template, by the
law under test, then `mpm_solver audit --floor-cell`: every step compared with a live cell of the
template's own packing (the reference) and with one of another packing seed (the noise floor).

  element_tests.py OUT --library LIB --floor-cell CELL.json [--template 1] [--law surrogate]
                   [--material JSON] [--loadings NAME ...] [--rate 0.1] [--strain 0.002] [--build DIR]

The loadings start at the template's state, at |D| = rate [1/s], to a strain of `strain`:
  oedometric   compression along y, x held (a deposit loaded by its own weight: K0)
  unloading    in-plane isotropic expansion (a column released from its preparation pressure)
  extension    stretching along y, x held
  simple_shear L = [[0, √2 rate], [0, 0]]
  pure_shear   D = diag(1, −1) rate/√2
--material is merged into the law's material block (default: read from workflows/demo/column.json,
the demo's live-cell settings and, for the surrogate, its tolerance, error budget, sample span and
fallback). Writes OUT/element_tests.md and OUT/element_tests.json: per
loading, the median and p95 of the run's relative stress error, the same for the floor, their ratio,
the share of live point-steps, and the final in-plane stress of the run, the reference and the floor
cell. The runs stay in OUT/runs/NAME (each with its audit/).
"""
import argparse
import csv
import json
import math
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from plotting import environment, tables  # noqa: E402  (after the path set-up)

DEMO_SCENE = Path(__file__).resolve().parents[1] / "demo" / "column.json"
# The demo material's keys the element tests take: its live cells' settings, and for the surrogate its
# tolerance, budget, sample span and fallback.
LIVE_KEYS = ("substepping", "q_h")
SURROGATE_KEYS = ("tolerance", "error_budget", "sample_span", "fallback")


def material_settings(args):
    demo = json.loads(DEMO_SCENE.read_text())["materials"][0]
    keys = LIVE_KEYS + (SURROGATE_KEYS if args.law == "surrogate" else ())
    return {**{key: demo[key] for key in keys}, **args.material}


def velocity_gradient(loading, rate):
    """The imposed L of each loading; each has |D| = ‖sym L‖ = rate."""
    r = rate
    return {"oedometric": [[0, 0], [0, -r]],
            "unloading": [[r / math.sqrt(2), 0], [0, r / math.sqrt(2)]],
            "extension": [[0, 0], [0, r]],
            "simple_shear": [[0, math.sqrt(2) * r], [0, 0]],
            "pure_shear": [[r / math.sqrt(2), 0], [0, -r / math.sqrt(2)]]}[loading]


LOADINGS = ["oedometric", "unloading", "extension", "simple_shear", "pure_shear"]


def law_block(args):
    """The material block of the law under test, on the library's template."""
    return {"name": "cell", "law": args.law, "library": str(args.library.resolve()), "template": args.template,
            **material_settings(args)}


def one_point_scene(block, drive, end, output_interval):
    """One point of `block`, 0.1 m × 0.1 m, in the middle of a 6 × 6 grid, driven homogeneously about its
    centre by `drive` (the scene key integration.homogeneous_drive, without its origin) until `end` [s]."""
    return {"grid": {"cell_size": 0.1, "cells": [6, 6]},
            "time": {"end": end, "output_interval": output_interval, "max_time_step": 1e-4},
            "integration": {"homogeneous_drive": {**drive, "origin": [0.3, 0.3]}},
            "materials": [{**block, "name": "cell"}],
            "regions": [{"material": "cell", "rectangle": {"min": [0.25, 0.25], "max": [0.35, 0.35]},
                         "points_per_cell": 1}]}


def scene(args, loading):
    end = args.strain / args.rate
    return {**one_point_scene(law_block(args), {"L": velocity_gradient(loading, args.rate)}, end, end),
            "audit": {"points": 1}}


def final_stresses(steps_csv):
    """The last compared step's in-plane stress (xx, yy, xy) of the run, the reference and the floor cell."""
    with open(steps_csv, newline="") as f:
        last = list(csv.DictReader(f))[-1]
    return {who: [round(float(last[f"{who}_{c}"]), 1) for c in ("sxx", "syy", "sxy")] for who in ("run", "live", "other")}


def element_test(args, loading, mpm_solver):
    folder = args.out / "runs" / loading
    folder.mkdir(parents=True, exist_ok=True)
    scene_file = folder / "scene.json"
    scene_file.write_text(json.dumps(scene(args, loading), indent=2) + "\n")
    subprocess.run([mpm_solver, scene_file, "--out", folder / "run", "--threads", "1"], check=True,
                   stdout=subprocess.DEVNULL)
    subprocess.run([mpm_solver, "audit", folder / "run", "--threads", "1", "--floor-cell", args.floor_cell.resolve()],
                   check=True, stdout=subprocess.DEVNULL)
    audit = json.loads((folder / "run" / "audit" / "run_audit.json").read_text())
    run, floor = audit["all"], audit["noise_floor"]["all"]
    stresses = final_stresses(folder / "run" / "audit" / "run_audit_steps.csv")
    return {"loading": loading, "steps": run["count"],
            "live_share": audit["by_source"]["live"]["count"] / run["count"] if run["count"] else 0.0,
            "error_median": run["median"], "error_p95": run["p95"],
            "floor_median": floor["median"], "floor_p95": floor["p95"],
            "median_over_floor": run["median"] / floor["median"] if floor["median"] > 0 else None,
            "final_run_Pa": stresses["run"], "final_live_Pa": stresses["live"], "final_floor_cell_Pa": stresses["other"]}


def add_law_arguments(parser):
    """The output folder, the library and its floor cell, and the law under test with its settings."""
    parser.add_argument("out", type=Path)
    parser.add_argument("--library", type=Path, required=True)
    parser.add_argument("--floor-cell", type=Path, required=True, help="the template's cell.json with another seed")
    parser.add_argument("--template", type=int, default=1)
    parser.add_argument("--law", default="surrogate")
    parser.add_argument("--material", type=json.loads, default={}, help="JSON merged into the law's material block")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_law_arguments(parser)
    parser.add_argument("--loadings", nargs="+", choices=LOADINGS, default=LOADINGS)
    parser.add_argument("--rate", type=float, default=0.1, help="|D| [1/s]")
    parser.add_argument("--strain", type=float, default=0.002)
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    args = parser.parse_args()
    if not (args.rate > 0 and args.strain > 0):
        parser.error("--rate and --strain: expected positive numbers")
    mpm_solver = args.build.resolve() / "mpm_solver" / "mpm_solver"
    rows = [element_test(args, loading, mpm_solver) for loading in args.loadings]
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "element_tests.json").write_text(json.dumps(
        {"library": str(args.library.resolve()), "template": args.template, "law": args.law,
         "material": material_settings(args), "floor_cell": str(args.floor_cell.resolve()),
         "rate": args.rate, "strain": args.strain, "loadings": rows}, indent=2) + "\n")
    tables.write_markdown(args.out / "element_tests.md", rows)
    print((args.out / "element_tests.md").read_text(), end="")


if __name__ == "__main__":
    main()
