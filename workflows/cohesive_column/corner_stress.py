"""Why the two-scale column's threshold moves with the grid: the stress at its corners (issue 18).

A column's base meets its free face at the toe and the back wall at the heel. Where a face meets a
floor that holds it by friction, elasticity puts a stress concentration at the corner that a finer
grid resolves further: the toe's material point sits h/2 from it and carries more of it at every
halving of h. The gate's removal also sends a wave through the column that a finer grid keeps
sharper, so the corners' stress peaks after it grow with refinement too. A brittle cell, which fails
where its stress first reaches its strength, then fails at a lower column on a finer grid.

This script measures both on the live columns' elastic twins: live_threshold.py's scene (back wall,
floor, gate removed at 0.08 s, or with --release T let go of over T seconds from then, one point
per grid cell) with an elastic law in place of the cells, run to --end. Of each twin it reports, at
the points nearest the toe and the heel, the in-plane maximum shear stress
2τ_max = √((σ_xx − σ_yy)² + 4σ_xy²) settled (averaged from --average-from, after the transfer's blend
has damped the ringing) and its peak after the gate (tracked every 0.5 ms), and the toe's largest
principal stress σ_1, each over ρ g H0, and the bottom row's mean σ_yy against the
weight above it (a check of the column's equilibrium).

- --column H0 L0 --ratios 6 12 24 48: one column on grids of H0/h = each ratio; self-similar under
  gravity, so each figure over ρ g H0 holds for any H0 at that ratio and width over height.
- --threshold A.json [B.json ...]: the live runs of live_threshold.json files (local, one point per
  cell, the scene's transfer), each with its own twin, ranked per floor friction by two loads in
  metres of overburden, 2τ_max/(ρ g): the toe's settled stress and the larger corner peak. Where one
  critical load separates every standing run from every falling one, that load explains the
  verdicts, and the --column table predicts the threshold at each H0/h: the heights between
  standing_max / f and falling_min / f, f the twin's 2τ_max/(ρ g H0) there. Where every file gives
  its cell's unconfined strength (live_threshold.py --unconfined, since stop 82), the runs are also
  ranked by the corners' peak 2τ_max over their own cell's q_u, so that cells of other packing seeds,
  which differ in strength, are judged together; and where the runs are of several cells, each cell's
  runs are also ranked alone (whether one load separates one packing's runs across grids).

  /usr/bin/python3 corner_stress.py OUT [--column 0.3 0.2 --ratios 6 12 24 48] [--floor-friction MU]
                                    [--threshold live_threshold.json ...]
                                    [--young 1e6] [--poisson 0.3] [--end 1.0] [--average-from 0.6]
                                    [--release T]
                                    [--build BUILD] [--threads N]

Writes OUT/corner_stress.md and OUT/corner_stress.json; the twins' runs stay in OUT/twins/ and are
reused.
"""
import argparse
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, scenes, tables, vtu  # noqa: E402
from live_threshold import CELL, SCENE, column_settings, points_per_cell, regularization  # noqa: E402

G = 9.81
DENSITY = 540.0  # [kg/m³]: any; every figure is over ρ g
BASE_SCENE = json.loads(SCENE.read_text())
GATE_REMOVAL = next(o["remove_at"] for o in BASE_SCENE["obstacles"] if "remove_at" in o)  # [s]
SERIES_INTERVAL = 5e-4  # [s]: the corners' stress history, fine enough for the peaks after the gate


def corners(width):
    """The column's two corners on the floor: the heel (at the back wall) and the toe (at the face)."""
    x0, y0 = BASE_SCENE["regions"][0]["rectangle"]["min"]
    return {"heel": [x0, y0], "toe": [x0 + width, y0]}


def twin_scene(build, scene_file, height, width, h, floor_friction, young, poisson, end, release):
    """Writes the elastic twin of live_threshold.py's column `height` × `width` on a grid of `h`, its
    corners' points tracked, the gate removed at once or let go of over `release` [s]."""
    settings, _, _ = column_settings(BASE_SCENE, height, width, h, None, 1, floor_friction, release)
    settings.update({"/time/end": end, "/time/output_interval": 0.02, "/time/series_interval": SERIES_INTERVAL})
    scene = scenes.variant(build, SCENE, scene_file, "live", None, {"cell": str(CELL)}, settings)
    scene["materials"] = [{"name": "snow", "law": "elastic", "density": DENSITY, "young": young, "poisson": poisson}]
    scene["effects"]["cohesion"] = False
    scene["tracked_points"] = list(corners(width).values())
    scene.pop("audit", None)  # an audit needs DEM cells
    scene_file.write_text(json.dumps(scene, indent=1) + "\n")


def finished(run):
    """Whether the twin in folder `run` ran to its end (an interrupted one says so in its summary)."""
    try:
        return json.loads((run / "summary.json").read_text())["interrupted"] is False
    except (OSError, ValueError, KeyError):
        return False


def measure_twin(build, out, height, width, h, floor_friction, young, poisson, end, average_from, threads,
                 release=None):
    """The twin's corners and bottom row: their stresses averaged over the snapshots from
    `average_from`, and the corners' peaks after the gate's removal."""
    name = (f"h{height:g}_l{width:g}_dx{h:g}" + ("" if floor_friction is None else f"_floor{floor_friction:g}")
            + f"_E{young:g}_nu{poisson:g}_to{end:g}" + ("" if release is None else f"_release{release:g}"))
    run = out / "twins" / name
    if not finished(run):  # a finished twin is reused as it is
        scene_file = out / "twins" / f"{name}.json"
        scene_file.parent.mkdir(parents=True, exist_ok=True)
        twin_scene(build, scene_file, height, width, h, floor_friction, young, poisson, end, release)
        done = subprocess.run([str(build / "mpm_solver" / "mpm_solver"), str(scene_file), "--out", str(run),
                               "--threads", str(threads)], capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"the elastic twin {scene_file} failed:\n{done.stderr}")
    snapshots = vtu.read_pvd(run / "points.pvd")
    first = vtu.read_vtu(snapshots[0][1])
    late = [vtu.read_vtu(file) for t, file in snapshots if t >= average_from - 1e-9]
    if not late:
        raise ValueError(f"{run}: no snapshot at or after --average-from {average_from} s")
    stress = np.mean([snap.by_id(snap.in_plane_stress()) for snap in late], axis=0)
    tracked = tables.split_by(tables.read_csv(run / "tracked_points.csv"), "point")
    weight = DENSITY * G * height
    figures = twin_figures(first.by_id(first.xy), stress, corners(width), height, h)
    for figure in figures["corners"].values():
        history = tracked[figure["id"]]  # the scene tracks the point nearest each corner, as twin_figures finds it
        after = history["t"] >= GATE_REMOVAL
        two_tau = np.hypot(history["sxx"] - history["syy"], 2 * history["sxy"])[after]
        figure["peak_two_tau_max"] = float(two_tau.max()) / weight
        figure["peak_time"] = float(history["t"][after][np.argmax(two_tau)])
    return figures


def twin_figures(xy, stress, corners, height, h):
    """Each corner's point (the nearest to it) with its 2τ_max and σ_1 over ρ g H0, and the bottom
    row's mean σ_yy over the weight above it; `xy` the points' initial positions, `stress` their
    in-plane σ_xx, σ_yy, σ_xy."""
    weight = DENSITY * G * height
    found = {}
    for corner, (x, y) in corners.items():
        point = int(np.argmin(np.hypot(xy[:, 0] - x, xy[:, 1] - y)))
        sxx, syy, sxy = stress[point]
        two_tau = math.hypot(sxx - syy, 2 * sxy)
        found[corner] = {"id": point, "point": [float(v) for v in xy[point]], "two_tau_max": two_tau / weight,
                         "sigma_1": (0.5 * (sxx + syy) + 0.5 * two_tau) / weight}
    floor = min(y for _, y in corners.values())
    bottom = xy[:, 1] < floor + h
    above_bottom_row = DENSITY * G * (height - float(np.mean(xy[bottom, 1]) - floor))
    return {"corners": found, "bottom_row_load": -float(np.mean(stress[bottom, 1])) / above_bottom_row}


def threshold_rows(files, release=None):
    """The local, one-point-per-cell runs of the scene's transfer and the gate's `release` in
    live_threshold.json `files`; raises ValueError naming a file that is not one."""
    rows = []
    for file in files:
        try:
            result = json.loads(Path(file).read_text())
            runs = result["runs"]
            if not isinstance(runs, list):
                raise TypeError
        except (OSError, ValueError, KeyError, TypeError) as error:
            raise ValueError(f"{file}: expected a live_threshold.json with a list 'runs' ({error!r})") from None
        strength = result.get("unconfined")  # absent before stop 82
        rows += [{**r, "source": str(file), "strength": strength} for r in runs
                 if regularization(r) == "local" and points_per_cell(r) == 1 and r.get("transfer") is None
                 and r.get("release") == release and r["stands"] is not None]
    return rows


def critical_load(rows, load):
    """The highest standing `load` and the lowest falling one over `rows` (None where no run stood or
    fell), and whether the first is below the second."""
    standing = [r[load] for r in rows if r["stands"]]
    falling = [r[load] for r in rows if not r["stands"]]
    high, low = (max(standing) if standing else None), (min(falling) if falling else None)
    return {"highest_standing": high, "lowest_falling": low, "separates_every_run": high is None or low is None or high < low}


# The two loads a run is ranked by, in metres of overburden (2τ_max / (ρ g)): the toe's settled stress,
# and the larger of the two corners' peaks after the gate's removal.
LOADS = {"toe_load": "the toe's settled 2τ_max", "peak_load": "the corners' peak 2τ_max after the gate"}
# And, where the run's file gives its cell's unconfined strength q_u and bulk density ρ, that peak over
# q_u: cells of other packings differ in strength, and this ranks their runs together.
STRENGTH_RATIO = {"peak_over_strength": "the corners' peak 2τ_max after the gate over the cell's q_u"}


def critical_loads(runs):
    """Per floor, each load's critical_load over `runs` (ranked runs: their loads set); and where the
    runs are of several cells, per floor and cell the same over that cell's runs alone. One critical
    load per floor: a frictional floor confines the toe, a frictionless one leaves the base in
    uniaxial compression, and the cell's strength differs between the two. Per cell: whether one load
    separates the runs of one packing, whatever the grid, where no load over q_u separates them all."""
    critical, per_cell = {}, {}
    for friction in sorted({r.get("floor_friction") for r in runs}, key=lambda f: -1 if f is None else f):
        group = [r for r in runs if r.get("floor_friction") == friction]
        ranked = dict(LOADS, **(STRENGTH_RATIO if all(r["peak_over_strength"] is not None for r in group) else {}))
        critical[floor_name(friction)] = {load: critical_load(group, load) for load in ranked}
        by_cell = {}
        for r in group:
            by_cell.setdefault(Path(r["cell"]).name, []).append(r)
        if len(by_cell) > 1:
            per_cell[floor_name(friction)] = {cell: {load: critical_load(cell_runs, load) for load in ranked}
                                              for cell, cell_runs in sorted(by_cell.items())}
    return critical, per_cell


def loads(twin, height):
    return {"toe_load": twin["corners"]["toe"]["two_tau_max"] * height,
            "peak_load": max(c["peak_two_tau_max"] for c in twin["corners"].values()) * height}


def peak_over_strength(run):
    """The corners' peak 2τ_max of `run`'s twin over its cell's q_u, or None when its file has no q_u."""
    strength = run.get("strength")
    return None if not strength else run["peak_load"] * strength["density"] * G / strength["q_u"]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path)
    parser.add_argument("--column", type=float, nargs=2, metavar=("H0", "L0"), help="a column to refine [m]")
    parser.add_argument("--ratios", type=int, nargs="+", default=[6, 12, 24, 48], help="H0/h of --column's grids")
    parser.add_argument("--floor-friction", type=scenes.friction_coefficient,
                        help="--column's floor friction (default: the scene's, 0.5)")
    parser.add_argument("--threshold", type=Path, nargs="+", default=[], help="live_threshold.json files")
    parser.add_argument("--young", type=float, default=1e6, help="the twin's Young's modulus [Pa]")
    parser.add_argument("--poisson", type=float, default=0.3, help="the twin's Poisson's ratio")
    parser.add_argument("--release", type=float, help="let the gate go over this long [s] (default: at once), in the "
                        "twins and the --threshold runs taken")
    parser.add_argument("--end", type=float, default=1.0, help="the twin's end [s]")
    parser.add_argument("--average-from", type=float, default=0.6, help="stresses averaged from this time [s]")
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--threads", type=int, default=environment.threads())
    args = parser.parse_args()
    if not args.column and not args.threshold:
        parser.error("give --column H0 L0, --threshold FILES or both")
    if not 0 <= args.average_from < args.end:
        parser.error(f"--average-from: expected a time in [0, --end = {args.end}), got {args.average_from}")
    if not args.young > 0 or not 0 <= args.poisson < 0.5:
        parser.error(f"--young {args.young:g} --poisson {args.poisson:g}: expected E > 0 and 0 <= ν < 0.5")
    if min(args.ratios) < 1:
        parser.error(f"--ratios: expected H0/h >= 1, got {min(args.ratios)}")
    try:
        runs = threshold_rows(args.threshold, args.release)
    except ValueError as error:
        parser.error(f"--threshold {error}")
    build = args.build.resolve()
    args.out.mkdir(parents=True, exist_ok=True)

    def twin(height, width, h, floor_friction):
        return measure_twin(build, args.out, height, width, h, floor_friction, args.young, args.poisson, args.end,
                            args.average_from, args.threads, args.release)

    refinement = []
    if args.column:
        height, width = args.column
        refinement = [{"ratio": ratio, **twin(height, width, height / ratio, args.floor_friction)}
                      for ratio in args.ratios]
    for r in runs:
        r["twin"] = twin(r["height"], r["width"], r["cell_size"], r.get("floor_friction"))
        r.update(loads(r["twin"], r["height"]))
        r["peak_over_strength"] = peak_over_strength(r)
    critical, critical_per_cell = critical_loads(runs)
    own = critical.get(floor_name(args.floor_friction), {})
    for r in refinement:  # a column of this shape and H0/h stands below high / f and falls above low / f
        per_height = loads(r, 1.0)
        r["predicted_threshold"] = {
            load: [None if load not in own or not own[load]["separates_every_run"] or own[load][side] is None
                   else own[load][side] / per_height[load] for side in ("highest_standing", "lowest_falling")]
            for load in LOADS}
    result = {"young": args.young, "poisson": args.poisson, "end": args.end, "average_from": args.average_from,
              "release": args.release,
              "column": args.column, "floor_friction": args.floor_friction, "refinement": refinement,
              "runs": [{k: r.get(k) for k in ("source", "cell", "strength", "height", "width", "cell_size", "floor_friction",
                                              "stands", "front",
                                              "twin", *LOADS, *STRENGTH_RATIO)}
                       for r in runs],
              "critical": critical, "critical_per_cell": critical_per_cell}
    (args.out / "corner_stress.json").write_text(json.dumps(result, indent=1) + "\n")
    (args.out / "corner_stress.md").write_text(report(result))
    print(report(result), end="")


def floor_name(friction):
    return "the scene's" if friction is None else f"{friction:g}"


def bracket(pair):
    low, high = pair
    if low is None and high is None:
        return "–"
    return f"({'–' if low is None else f'{low:.3f}'}, {'–' if high is None else f'{high:.3f}'}]"


def load_text(load, name):
    if load is None:
        return "–"
    return f"{load:.4f}" if name in STRENGTH_RATIO else f"{load:.4f} m"


def ratio_text(ratio):
    return "–" if ratio is None else f"{ratio:.3f}"


def report(result):
    release = result.get("release")
    lines = [f"Elastic twins (E = {result['young']:g} Pa, ν = {result['poisson']:g}), settled stresses averaged from "
             f"{result['average_from']:g} s to {result['end']:g} s; peaks after the gate's "
             + ("removal." if release is None else f"release began (let go of over {release:g} s)."), ""]
    if result["refinement"]:
        height, width = result["column"]
        lines += [f"Column H0 = {height:g} m, L0 = {width:g} m, floor friction {floor_name(result['floor_friction'])} "
                  "(2τ_max over ρgH0; thresholds predicted by the runs' critical loads, H0 [m]):", "",
                  "| H0/h | toe, settled | toe σ_1, settled | toe, peak (t [s]) | heel, settled | heel, peak (t [s]) "
                  "| bottom row's load / weight above it | threshold by the settled toe | by the peaks |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for r in result["refinement"]:
            toe, heel = r["corners"]["toe"], r["corners"]["heel"]
            lines.append(f"| {r['ratio']} | {toe['two_tau_max']:.3f} | {toe['sigma_1']:.3f} | {toe['peak_two_tau_max']:.3f} "
                         f"({toe['peak_time']:.4f}) | {heel['two_tau_max']:.3f} | {heel['peak_two_tau_max']:.3f} "
                         f"({heel['peak_time']:.4f}) | {r['bottom_row_load']:.3f} | "
                         f"{bracket(r['predicted_threshold']['toe_load'])} | {bracket(r['predicted_threshold']['peak_load'])} |")
        lines.append("")
    if result["runs"]:
        lines += ["| H0 [m] | L0 [m] | h [m] | H0/h | floor friction | cell | live outcome | front / L0 "
                  "| toe load, settled [m] | peak load [m] | peak 2τ_max / q_u |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in sorted(result["runs"], key=lambda r: (r["floor_friction"] is not None, r["peak_over_strength"] or 0,
                                                       r["peak_load"])):
            lines.append(f"| {r['height']:g} | {r['width']:g} | {r['cell_size']:g} | {r['height'] / r['cell_size']:.0f} | "
                         f"{floor_name(r['floor_friction'])} | {Path(r['cell']).name} | "
                         f"{'stands' if r['stands'] else 'falls'} | {r['front']:.3f} | "
                         f"{r['toe_load']:.4f} | {r['peak_load']:.4f} | {ratio_text(r['peak_over_strength'])} |")
        lines.append("")
        for floor, per_load in result["critical"].items():
            lines += [critical_text(f"Floor friction {floor}", load, c) for load, c in per_load.items()]
        for floor, per_cell in result.get("critical_per_cell", {}).items():
            lines += ["", f"Each cell's runs alone, floor friction {floor}:"]
            lines += [critical_text(f"- {cell}", load, c) for cell, per_load in per_cell.items()
                      for load, c in per_load.items()]
    return "\n".join(lines) + "\n"


def critical_text(whose, load, c):
    return (f"{whose}, {dict(LOADS, **STRENGTH_RATIO)[load]}: highest standing {load_text(c['highest_standing'], load)}, "
            f"lowest falling {load_text(c['lowest_falling'], load)}: "
            + ("one critical load separates every standing run from every falling one."
               if c["separates_every_run"] else "no single critical load separates the verdicts."))


if __name__ == "__main__":
    main()
