"""One live run of the demo column for the convergence studies: its DEM cell of N spheres and packing
seed, its grid scaled by a factor (same domain, same points per grid cell), to an end time. Finished
runs in OUT/runs/ are kept, so an interrupted study resumes, and the studies run into one OUT share
their common runs."""
import json
import math
import statistics
from pathlib import Path

from plotting import flow, run_compare, scenes, tables, vtu

HERE = Path(__file__).resolve().parent
SCENE = HERE.parent / "demo" / "column.json"
# Relative differences of runouts below this [m] are noise over a tiny number, and are not reported.
MIN_RUNOUT = 0.01
CELL = HERE.parent / "demo" / "cell_soft_snow_125.json"


def run_name(spheres, seed, grid_factor, nonlocal_length=None):
    return (f"n{spheres}_seed{seed}" + ("" if grid_factor == 1 else f"_h{grid_factor:g}")
            + scenes.regularization_settings(nonlocal_length)[1])


def run(build, out, end, threads, spheres=125, seed=1, grid_factor=1.0, nonlocal_length=None):
    """Returns (series or None when the run failed before writing one, {wall_s, cpu_s, failed}). The run
    is named by what it varies, so that the studies share it: OUT/runs/n125_seed1 is the cell-size
    study's N = 125 and the mesh study's h = 0.05 m. With a `nonlocal_length` [m] the cells are
    regularized over it (the scene's regularization.nonlocal_length)."""
    name = run_name(spheres, seed, grid_factor, nonlocal_length)
    cell = json.loads(CELL.read_text())
    cell["preparation"]["spheres"], cell["preparation"]["seed"] = spheres, seed
    cell_file = out / "cells" / f"{name}.json"
    cell_file.parent.mkdir(parents=True, exist_ok=True)
    cell_file.write_text(json.dumps(cell, indent=2) + "\n")
    settings = {"/time/end": end, **scenes.regularization_settings(nonlocal_length)[0]}
    if grid_factor != 1:
        grid = json.loads(SCENE.read_text())["grid"]
        settings["/grid/cell_size"] = grid["cell_size"] * grid_factor
        settings["/grid/cells"] = [math.ceil(n / grid_factor) for n in grid["cells"]]
    scene_file = out / "scenes" / f"{name}.json"
    scenes.variant(build, SCENE, scene_file, "live", None, {"cell": str(cell_file.resolve())}, settings)
    cost = run_compare.timed_scene_run(build, scene_file, out / "runs" / name, threads)
    series = out / "runs" / name / "series.csv"
    return (tables.read_csv(series) if series.exists() else None), cost


def runout_at(series, t):
    """Runout [m] at the series row nearest t; None when the run stopped before t."""
    if series is None or series["t"][-1] < t - 1e-9:
        return None
    return float(flow.runout(series)[min(range(len(series["t"])), key=lambda k: abs(series["t"][k] - t))])


# What a run is measured by: how far the column has gone along x since the start [m].
MEASURES = {"runout_m": "runout (front)", "mass_edge_advance_m": "advance of the 95 % mass edge",
            "centroid_advance_m": "advance of the centroid"}


def measures_at(run_folder, times):
    """{t: {measure: value [m]}} of MEASURES at each of `times`, a value None when the run stopped before
    t; the run's files are read once. The demo's points have equal mass (one point per grid cell of one
    uniform region), so the mass edge and the centroid are taken over points."""
    series_file = Path(run_folder) / "series.csv"
    series = tables.read_csv(series_file) if series_file.exists() else None
    snapshots = vtu.read_run(run_folder)
    measures = {}
    for t in times:
        at_t = next((s for s in snapshots if abs(s.time - t) < 1e-9), None)
        edge, centroid = (None, None) if at_t is None else flow.bulk_advance(at_t, snapshots[0])
        measures[t] = {"runout_m": runout_at(series, t), "mass_edge_advance_m": edge, "centroid_advance_m": centroid}
    return measures


def spread(values):
    """(max − min) / mean of runs' values of one measure (the packing seeds' spread); None below two runs
    or a mean of MIN_RUNOUT."""
    values = [v for v in values if v is not None]
    if len(values) < 2 or statistics.mean(values) < MIN_RUNOUT:
        return None
    return (max(values) - min(values)) / statistics.mean(values)
