"""Why the two-scale column's threshold moves with the grid: the stress at its toe (issue 18).

A vertical face meets a floor that holds it by friction at the column's toe, and there elasticity
puts a stress concentration that a finer grid resolves further: the toe's material point sits h/2
from the corner and carries more of it at every halving of h, while a point at a fixed place in the
body converges. A brittle cell, which fails where its stress first reaches its strength, then fails
at a lower column on a finer grid.

This script measures that concentration on the live columns' elastic twins: live_threshold.py's
scene (back wall, floor, gate removed at 0.08 s, one point per grid cell) with an elastic law in
place of the cells, run to --end and averaged from --average-from (the transfer's blend damps the
ringing that the gate's removal starts). Of each twin it reports the toe point's in-plane maximum
shear stress 2τ_max = √((σ_xx − σ_yy)² + 4σ_xy²) and its largest principal stress σ_1, both over
ρ g H0, and the bottom row's mean σ_yy against the weight above it (a check of the column's
equilibrium).

- --column H0 L0 --ratios 6 12 24 48: one column on grids of H0/h = each ratio; self-similar under
  gravity, so each figure over ρ g H0 holds for any H0 at that ratio and width over height.
- --threshold A.json [B.json ...]: the live runs of live_threshold.json files (local, one point per
  cell, the scene's transfer), each with its own twin; each run's toe load, 2τ_max/(ρ g) of its twin
  in metres of overburden, against its verdict. If one critical load separates every standing run
  from every falling one, the toe's stress concentration explains the verdicts, and the bracket
  predicts the threshold at each H0/h: the heights between standing_max / f and falling_min / f,
  f the twin's 2τ_max/(ρ g H0) there.

  /usr/bin/python3 corner_stress.py OUT [--column 0.3 0.2 --ratios 6 12 24 48]
                                    [--threshold live_threshold.json ...]
                                    [--young 1e6] [--poisson 0.3] [--end 1.0] [--average-from 0.6]
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
from plotting import environment, scenes, vtu  # noqa: E402
from live_threshold import CELL, SCENE, column_settings, points_per_cell, regularization  # noqa: E402

G = 9.81
DENSITY = 540.0  # [kg/m³]: any; every figure is over ρ g


def twin_scene(build, scene_file, height, width, h, floor_friction, young, poisson, end):
    """Writes the elastic twin of live_threshold.py's column `height` × `width` on a grid of `h`."""
    settings, _ = column_settings(json.loads(SCENE.read_text()), height, width, h, None, 1, floor_friction)
    settings.update({"/time/end": end, "/time/output_interval": 0.02})
    scene = scenes.variant(build, SCENE, scene_file, "live", None, {"cell": str(CELL)}, settings)
    scene["materials"] = [{"name": "snow", "law": "elastic", "density": DENSITY, "young": young, "poisson": poisson}]
    scene["effects"]["cohesion"] = False
    scene.pop("audit", None)  # an audit needs DEM cells
    scene_file.write_text(json.dumps(scene, indent=1) + "\n")


def measure_twin(build, out, height, width, h, floor_friction, young, poisson, end, average_from, threads):
    """The twin's toe and bottom row, its stresses averaged over the snapshots from `average_from`."""
    name = (f"h{height:g}_l{width:g}_dx{h:g}" + ("" if floor_friction is None else f"_floor{floor_friction:g}")
            + f"_E{young:g}_nu{poisson:g}_to{end:g}")
    run = out / "twins" / name
    if not (run / "points.pvd").exists():
        scene_file = out / "twins" / f"{name}.json"
        scene_file.parent.mkdir(parents=True, exist_ok=True)
        twin_scene(build, scene_file, height, width, h, floor_friction, young, poisson, end)
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
    x0, y0 = json.loads(SCENE.read_text())["regions"][0]["rectangle"]["min"]
    return twin_figures(first.by_id(first.xy), stress, x0 + width, y0, height, h)


def twin_figures(xy, stress, face, floor, height, h):
    """The toe point's (nearest the face–floor corner) 2τ_max and σ_1, over ρ g H0, and the bottom
    row's mean σ_yy over the weight above it; `xy` the points' initial positions, `stress` their
    in-plane σ_xx, σ_yy, σ_xy."""
    toe = int(np.argmin(np.hypot(xy[:, 0] - face, xy[:, 1] - floor)))
    sxx, syy, sxy = stress[toe]
    two_tau = math.hypot(sxx - syy, 2 * sxy)
    bottom = xy[:, 1] < floor + h
    weight = DENSITY * G * height
    above_bottom_row = DENSITY * G * (height - float(np.mean(xy[bottom, 1]) - floor))
    return {"toe": [float(v) for v in xy[toe]], "two_tau_max": two_tau / weight,
            "sigma_1": (0.5 * (sxx + syy) + 0.5 * two_tau) / weight,
            "bottom_row_load": -float(np.mean(stress[bottom, 1])) / above_bottom_row}


def threshold_rows(files):
    """The local, one-point-per-cell runs of the scene's transfer in live_threshold.json `files`; raises
    ValueError naming a file that is not one."""
    rows = []
    for file in files:
        try:
            runs = json.loads(Path(file).read_text())["runs"]
            if not isinstance(runs, list):
                raise TypeError
        except (OSError, ValueError, KeyError, TypeError) as error:
            raise ValueError(f"{file}: expected a live_threshold.json with a list 'runs' ({error!r})") from None
        rows += [{**r, "source": str(file)} for r in runs
                 if regularization(r) == "local" and points_per_cell(r) == 1 and r.get("transfer") is None
                 and r["stands"] is not None]
    return rows


def critical_load(rows):
    """(highest standing toe load, lowest falling toe load, whether the first is below the second) over
    `rows` that carry `toe_load`; None where no run stood or fell."""
    standing = [r["toe_load"] for r in rows if r["stands"]]
    falling = [r["toe_load"] for r in rows if not r["stands"]]
    high, low = (max(standing) if standing else None), (min(falling) if falling else None)
    return high, low, high is None or low is None or high < low


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
        runs = threshold_rows(args.threshold)
    except ValueError as error:
        parser.error(f"--threshold {error}")
    build = args.build.resolve()
    args.out.mkdir(parents=True, exist_ok=True)

    def twin(height, width, h, floor_friction):
        return measure_twin(build, args.out, height, width, h, floor_friction, args.young, args.poisson, args.end,
                            args.average_from, args.threads)

    refinement = []
    if args.column:
        height, width = args.column
        refinement = [{"ratio": ratio, **twin(height, width, height / ratio, args.floor_friction)}
                      for ratio in args.ratios]
    for r in runs:
        r["twin"] = twin(r["height"], r["width"], r["cell_size"], r.get("floor_friction"))
        r["toe_load"] = r["twin"]["two_tau_max"] * r["height"]  # 2τ_max / (ρ g) [m]
    # One critical load per floor: a frictional floor confines the toe, a frictionless one leaves it
    # in uniaxial compression, and the cell's strength differs between the two.
    critical = {}
    for friction in sorted({r.get("floor_friction") for r in runs}, key=lambda f: -1 if f is None else f):
        high, low, separated = critical_load([r for r in runs if r.get("floor_friction") == friction])
        critical[floor_name(friction)] = {"highest_standing": high, "lowest_falling": low,
                                          "separates_every_run": separated}
    own = critical.get(floor_name(args.floor_friction))
    for r in refinement:  # a column of this shape and H0/h stands below high / f and falls above low / f
        r["predicted_threshold"] = [None if not own or not own["separates_every_run"] or load is None
                                    else load / r["two_tau_max"] for load in (own["highest_standing"] if own else None,
                                                                              own["lowest_falling"] if own else None)]
    result = {"young": args.young, "poisson": args.poisson, "end": args.end, "average_from": args.average_from,
              "column": args.column, "floor_friction": args.floor_friction, "refinement": refinement,
              "runs": [{k: r.get(k) for k in ("source", "height", "width", "cell_size", "floor_friction", "stands", "front",
                                              "twin", "toe_load")}
                       for r in runs],
              "critical_toe_load": critical}
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


def load_text(load):
    return "–" if load is None else f"{load:.4f} m"


def report(result):
    lines = [f"Elastic twins (E = {result['young']:g} Pa, ν = {result['poisson']:g}), stresses averaged from "
             f"{result['average_from']:g} s to {result['end']:g} s.", ""]
    if result["refinement"]:
        height, width = result["column"]
        lines += [f"Column H0 = {height:g} m, L0 = {width:g} m, floor friction {floor_name(result['floor_friction'])}:", "",
                  "| H0/h | toe point (x, y) [m] | toe 2τ_max / ρgH0 | toe σ_1 / ρgH0 | bottom row's mean −σ_yy / weight above it "
                  "| threshold predicted by the runs' critical toe load, H0 [m] |",
                  "|---|---|---|---|---|---|"]
        lines += [f"| {r['ratio']} | ({r['toe'][0]:.5f}, {r['toe'][1]:.5f}) | {r['two_tau_max']:.3f} | {r['sigma_1']:.3f} | "
                  f"{r['bottom_row_load']:.3f} | {bracket(r['predicted_threshold'])} |" for r in result["refinement"]]
        lines.append("")
    if result["runs"]:
        lines += ["| H0 [m] | L0 [m] | h [m] | H0/h | floor friction | live outcome | front / L0 | twin's toe 2τ_max / ρgH0 "
                  "| toe load 2τ_max/(ρg) [m] |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for r in sorted(result["runs"], key=lambda r: r["toe_load"]):
            lines.append(f"| {r['height']:g} | {r['width']:g} | {r['cell_size']:g} | {r['height'] / r['cell_size']:.0f} | "
                         f"{floor_name(r['floor_friction'])} | "
                         f"{'stands' if r['stands'] else 'falls'} | {r['front']:.3f} | {r['twin']['two_tau_max']:.3f} | "
                         f"{r['toe_load']:.4f} |")
        lines.append("")
        for floor, c in result["critical_toe_load"].items():
            lines.append(f"Floor friction {floor}: highest standing toe load {load_text(c['highest_standing'])}, lowest "
                         f"falling {load_text(c['lowest_falling'])}: "
                         + ("one critical toe load separates every standing run from every falling one."
                            if c["separates_every_run"] else "no single critical toe load separates the verdicts."))
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
