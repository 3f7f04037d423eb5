"""The figures of a column-collapse run (demo and the paper's benchmark), after seed Figs. 4 and 5:
snapshots coloured by velocity norm, by the deviatoric strain rate ε̇_q and by damage D, by the source
of each point's stress, the front and height over time, the hit rate, each side's runout, the deposit
and the top corners (spreading.py), and the tracked cells."""
import json
from pathlib import Path

import matplotlib.colors as colors
import numpy as np

from . import figures, resumed_run, spreading, tables, tracked_cells, vtu


def snapshot_figures(snapshots, out, panels):
    shown = vtu.pick_times(snapshots, panels)
    rate = lambda s: s.fields["strain_rate_q"]  # noqa: E731
    made = {
        "velocity.png": [("|v| [m/s]", lambda s: s.speed(), "viridis", None, None)],
        "strain_rate_damage.png": [
            ("ε̇_q [1/s] (seed Eq. 5)", rate, "inferno", figures.log_norm(shown, rate), None),
            ("damage D (seed Eq. 6)", lambda s: s.fields["damage"], "magma", colors.Normalize(0, 1), None)],
    }
    if "source" in shown[0].fields:
        made["source.png"] = [("stress source", lambda s: s.fields["source"],
                               colors.ListedColormap(["grey", "tab:red", "tab:green", "tab:orange"]),
                               colors.BoundaryNorm(np.arange(-0.5, 4.5), 4), vtu.STRESS_SOURCES)]
    for name, rows in made.items():
        figures.snapshot_grid(shown, rows, out / name)
    return list(made)


def series_figures(series, out):
    t = series["t"]
    figures.time_plot(out / "front_height.png",
                      [(t, series["front"], "front (largest x) [m]", None),
                       (t, series["max_height"], "height (largest y) [m]", None)],
                      "t [s]", "position [m]")
    made = ["front_height.png"]
    if "hit_rate" in series:
        rows = slice(1, None)  # row 0 is the initial state, before any lookup
        points = series["hits"][rows] + series["misses"][rows] + series["live_cells"][rows]
        figures.time_plot(out / "hit_rate.png",
                          [(t[rows], series["hit_rate"][rows], "hit rate among lookups (series.csv hit_rate)", None),
                           (t[rows], series["hits"][rows] / np.maximum(points, 1), "fraction of points answered by a hit",
                            {"linestyle": "-."}),
                           (t[rows], series["live_cells"][rows] / np.maximum(points, 1), "fraction of points live",
                            {"linestyle": "--"})],
                          "t [s]", "fraction", title="cell library: hits and live DEM points (at each series row)")
        made.append("hit_rate.png")
    return made


def tracked_figures(run_dirs, out):
    """Damage of the tracked points over time and the bonds per sphere of their DEM cells (when live; a
    re-tiled cell has more spheres and bonds, not more per sphere)."""
    if not all((Path(d) / "tracked_points.csv").exists() for d in run_dirs):
        return []
    ends = segment_ends(run_dirs)
    per_point = tables.split_by(joined_tables([tables.read_csv(Path(d) / "tracked_points.csv") for d in run_dirs], ends),
                                "point")
    curves = [(p["t"], p["damage"], f"point {pid}", None) for pid, p in per_point.items()]
    figures.time_plot(out / "tracked_damage.png", curves, "t [s]", "damage D", title="tracked points")
    made = ["tracked_damage.png"]
    cells = {}
    for run_dir, end in zip(run_dirs, ends):
        for point, (t, n) in tracked_cell_counts(run_dir).items():
            before = cells.get(point, (np.array([]), np.array([])))
            cells[point] = (np.concatenate([before[0], t[t < end]]), np.concatenate([before[1], n[t < end]]))
    if cells:
        figures.time_plot(out / "tracked_bonds.png",
                          [(t, n, f"point {pid}", {"marker": "o"}) for pid, (t, n) in cells.items()],
                          "t [s]", "intact bonds per sphere", title="DEM cells of the tracked points")
        made.append("tracked_bonds.png")
    return made


def tracked_cell_counts(run_dir):
    """{point id → (times, intact bonds per sphere)} from the cells/*.vtk of a run."""
    times = {vtu.vtu_index(path): t for t, path in vtu.read_pvd(Path(run_dir) / "points.pvd")}
    counts = {}
    for point, files in tracked_cells.tracked_cell_files(run_dir).items():
        shown = [(times[index], path) for index, path in files if index in times]
        counts[point] = (np.array([t for t, _ in shown]), np.array([tracked_cells.bonds_per_sphere(p) for _, p in shown]))
    return counts


def segment_ends(run_dirs):
    """For each segment of a resumed run, the time from which the next segment takes over: the next one's
    start (a killed segment ran on past the checkpoint it was resumed from); infinity for the last."""
    return [start * (1 - 1e-12) for start in resumed_run.segment_starts(run_dirs)] + [np.inf]


def joined_tables(parts, ends):
    """Tables of the segments of a resumed run, one after the other, each up to its end (segment_ends), on
    the columns they share (an older segment may lack a column a newer build writes)."""
    shared = [k for k in parts[0] if all(k in p for p in parts)]
    return {k: np.concatenate([p[k][p["t"] < end] for p, end in zip(parts, ends)]) for k in shared}


def spreading_outputs(snapshots, series, out):
    """spreading.png, deposit.png and spreading.json: each side's runout, the centroid, the top corners
    and the deposit (spreading.py), with how far the run is from rest (kinetic energy over its peak)."""
    rows = spreading.spreading(snapshots)
    spreading.spreading_figure(rows, out / "spreading.png")
    spreading.deposit_figure(snapshots, rows, out / "deposit.png")
    energy = series["kinetic_energy"]
    summary = {"final": rows[-1], "kinetic_energy_peak": float(energy.max()),
               "kinetic_energy_final": float(energy[-1]),
               "kinetic_energy_over_peak": float(energy[-1] / energy.max()) if energy.max() > 0 else 0.0,
               "rows": rows}
    (out / "spreading.json").write_text(json.dumps(summary, indent=1) + "\n")
    return ["spreading.png", "deposit.png", "spreading.json"]


def all_figures(run_dirs, out, panels=5):
    """Writes every figure of a run into `out`; returns their file names. `run_dirs` is one run folder,
    or the folders of a run and its resumed segments, in order."""
    run_dirs = [Path(run_dirs)] if isinstance(run_dirs, (str, Path)) else [Path(d) for d in run_dirs]
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    ends = segment_ends(run_dirs)
    snapshots = [s for d, end in zip(run_dirs, ends) for s in vtu.read_run(d) if s.time < end]
    series = joined_tables([tables.read_csv(d / "series.csv") for d in run_dirs], ends)
    made = snapshot_figures(snapshots, out, panels)
    made += series_figures(series, out)
    made += spreading_outputs(snapshots, series, out)
    made += tracked_figures(run_dirs, out)
    return made
