"""Does the two-scale column stand where its cell's strength says it should? (issue 18, "cohesive
column: the transition from standing to collapse", with live DEM cells).

The demo column (workflows/demo/column.json: against a back wall, gravity ramped in over 0.05 s, gate
removed at 0.08 s, one point per grid cell) at several heights H0, made --width L0 wide (default
0.15 m, wider than a vertical cut's mechanism for H0 ≤ 0.2 m) on a grid of --cell-size h (default
0.0125 m), every point answered by its own live DEM cell (default: the demo's 125-sphere soft-snow
cell). The cost of a run grows as (H0/h)² √H0: a column resolved by ten or so grid cells is the
affordable one. --nonlocal-length ℓ regularizes the cells (the scene's regularization.nonlocal_length:
each cell driven by the velocity gradient averaged over ℓ, mpm_solver/core/nonlocal_average.hpp), so
that runs at several h and one ℓ show whether the threshold converges once the material has an
internal length; runs without it are local. --floor-friction μ sets the floor's Coulomb friction
(the scene's 0.5 by default): where a face meets a floor that holds it, the toe carries a stress
concentration that a finer grid resolves further (corner_stress.py); on a frictionless floor the
settled toe does not, though the gate's release still peaks at the corners. --release T lets the gate
go over T seconds instead of at once (the obstacle's "release": its traction on the face falls
linearly to zero), so that the face unloads quasi-statically and no unloading wave peaks at the
corners (corner_stress.py --release).

The predictions come from the cell alone, each the highest vertical cut that stands in limit analysis
(Chen's log-spiral, γ H_c / c = 3.83 tan(45° + φ/2)), run on the same --cell:
- --strength, the strength.json of workflows/cell_response/strength.py: the peak Mohr–Coulomb
  envelope of DEM shear tests under a held normal stress, read two ways (τ/σ = tan φ or sin φ on the
  shear plane);
- --unconfined, the unconfined.json of workflows/cell_response/unconfined.py: the strength q_u of the
  two-scale material in unconfined plane-strain compression, the stress state of a cut's face, which
  for a Mohr–Coulomb material fixes H_c = 1.915 q_u / (ρ g) whatever its c and φ.

A run stands when its front (farthest point) has moved less than STANDING × L0 between the gate's
removal (the start of its release) and the end, the time the gate is gone plus WATCH √(H0/g) (at least
MIN_WATCH s); a run that stopped
before the end (its table row says why) has fallen if its front had moved that far, and gives no
verdict otherwise. Once a column's front has run FALLEN × L0 (twice STANDING) from where it started,
its verdict is in, and the run ends there (the scene's time.stop_at_front; "stopped once fallen" in
the table): a falling column costs the time it takes to fall, not the whole watch (runs from before
stop 89 watched to the end).

  /usr/bin/python3 live_threshold.py OUT [--strength STRENGTH.json] [--unconfined UNCONFINED.json]
                                     [--heights 0.05 0.1 0.15 0.2]
                                     [--width 0.15] [--cell-size 0.0125] [--nonlocal-length ℓ]
                                     [--points-per-cell 1] [--transfer apic|pic|RATE|apic_flip:RATE]
                                     [--floor-friction MU] [--release T]
                                     [--cell CELL.json]
                                     [--build BUILD] [--threads N] [--watch 4]

Finished runs in OUT/runs/ are kept (an interrupted study resumes), and the outputs cover every run of
the cell there, so that heights run with other widths, grids and lengths ℓ join one table (the
thresholds bracketed per ℓ, H0/h and points per cell); `--heights` with no height runs nothing and
reports those runs again, for instance against a strength measured again. Writes OUT/live_threshold.md,
OUT/live_threshold.json (with the cell's q_u and bulk density under "unconfined", when given) and
OUT/live_threshold.png (front displacement against H0, with each H_c).
"""
import argparse
import json
import math
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, flow, run_compare, scenes, tables, vtu  # noqa: E402
from plotting.figures import finish_and_save, plt  # noqa: E402
from stability import STANDING  # noqa: E402  (the Drucker–Prager columns' criterion, so the two compare)

SCENE = HERE.parent / "demo" / "column.json"
CELL = HERE.parent / "demo" / "cell_soft_snow_125.json"
G = 9.81
MIN_WATCH = 0.3  # [s] after the gate, at least
FALLEN = 2 * STANDING  # × L0: a front that has run this far has fallen beyond doubt
OUTCOME = {True: "stands", False: "falls", None: "stopped"}


def column_settings(scene, height, width, h, nonlocal_length, points_per_cell, floor_friction=None, release=None,
                    stop_past=None):
    """({JSON pointer: value} making the demo scene's column `height` × `width` on a grid of cell size
    `h`, `points_per_cell` points (cells) per grid cell and direction, with room for a runout of three
    times the larger of the two and a floor under all of it, the times the gate starts and ends letting
    go), regularized over `nonlocal_length` unless it is None, on a floor of Coulomb friction
    `floor_friction` (None: the scene's). The gate is removed at once at the scene's time, or with
    `release` [s] let go of over that long from it (its traction on the face falling linearly to zero,
    the obstacles' "release"). The grid's lines pass through the column's base and back wall, so that
    its points sit whole cells' halves off them. With `stop_past` the run ends once its front has run
    that many L0 beyond its first points after the gate has started to let go (time.stop_at_front)."""
    x0, y0 = scene["regions"][0]["rectangle"]["min"]
    gates = [k for k, o in enumerate(scene["obstacles"]) if "remove_at" in o]
    (floor,) = [k for k, o in enumerate(scene["obstacles"]) if "line" in o and all(y == y0 for _, y in o["line"])]
    face = x0 + width
    origin = [x0 - math.ceil(x0 / h - 1e-9) * h, y0 - math.ceil(y0 / h - 1e-9) * h]
    cells = [math.ceil((face + 3 * max(width, height) - origin[0]) / h), math.ceil((y0 + 1.5 * height - origin[1]) / h)]
    gate = {**scene["obstacles"][gates[0]], "line": [[face, y0], [face, y0 + 1.5 * height]]}
    start = gate["remove_at"]
    if release is not None:
        del gate["remove_at"]
        gate["release"] = {"start": start, "end": start + release}
    return {**scenes.regularization_settings(nonlocal_length)[0],
            "/grid/origin": origin, "/grid/cell_size": h, "/grid/cells": cells,
            "/regions/0/rectangle/max": [face, y0 + height], "/regions/0/points_per_cell": points_per_cell,
            f"/obstacles/{floor}/line": [[origin[0], y0], [origin[0] + cells[0] * h, y0]],
            f"/obstacles/{gates[0]}": gate,
            **({} if floor_friction is None else {f"/obstacles/{floor}/friction": floor_friction}),
            **({} if stop_past is None else
               {"/time/stop_at_front": {"x": face - h / (2 * points_per_cell) + stop_past * width,
                                        "not_before": start}}),
            "/tracked_points": []}, start, start + (release or 0)


def run_height(build, out, cell, height, width, h, nonlocal_length, points_per_cell, floor_friction, transfer, watch,
               threads, release=None):
    """One live column of height `height` [m]; returns its row of the table."""
    settings, gate, let_go = column_settings(json.loads(SCENE.read_text()), height, width, h, nonlocal_length,
                                             points_per_cell, floor_friction, release, stop_past=FALLEN)
    end = let_go + max(MIN_WATCH, watch * math.sqrt(height / G))
    settings["/time/end"] = end
    transfer_setting, transfer_suffix = scenes.transfer_settings(transfer)
    settings.update(transfer_setting)
    name = (f"h{height:g}_l{width:g}_dx{h:g}" + scenes.regularization_settings(nonlocal_length)[1]
            + (f"_ppc{points_per_cell}" if points_per_cell != 1 else "")
            + ("" if floor_friction is None else f"_floor{floor_friction:g}") + transfer_suffix
            + ("" if release is None else f"_release{release:g}"))
    scene_file = out / "scenes" / f"{name}.json"
    scene_file.parent.mkdir(parents=True, exist_ok=True)
    if not (out / "runs" / name / "study_run.json").exists():  # a finished run keeps the scene it ran
        scenes.variant(build, SCENE, scene_file, "live", None, {"cell": str(cell.resolve())}, settings)
    cost = run_compare.timed_scene_run(build, scene_file, out / "runs" / name, threads)
    series = tables.read_csv(out / "runs" / name / "series.csv")
    at_gate = min(range(len(series["t"])), key=lambda k: abs(series["t"][k] - gate))
    snapshots = vtu.read_pvd(out / "runs" / name / "points.pvd")  # only the first and last are needed
    first, last = vtu.read_vtu(snapshots[0][1]).xy, vtu.read_vtu(snapshots[-1][1]).xy
    front = float(series["front"][-1] - series["front"][at_gate])
    summary_file = out / "runs" / name / "summary.json"  # a run that failed may have written none
    row = {"cell": str(cell.resolve()), "height": height, "width": width, "cell_size": h,
           "nonlocal_length": nonlocal_length, "points_per_cell": points_per_cell, "floor_friction": floor_friction,
           "transfer": transfer, "release": release, "end": float(series["t"][-1]),
           "planned_end": end, "front": front / width, "runout_m": float(flow.runout(series)[-1]),
           "top_drop": float((first[:, 1].max() - last[:, 1].max()) / height),
           # A run that stopped early (a cell too thin, a point thrown out) has fallen if its front had moved
           # by then, and is no verdict if it had not.
           "stands": False if front >= STANDING * width else (None if cost["failed"] else True),
           "front_reached": summary_file.exists() and json.loads(summary_file.read_text()).get("front_reached", False),
           "cpu_s": cost["cpu_s"],
           "failed": cost["failed"]}
    (out / "runs" / name / "threshold_row.json").write_text(json.dumps(row) + "\n")
    return row


def finished_rows(out, cell):
    """The rows of every run of `cell` in OUT/runs, whatever grid and width each was run with, by height."""
    rows = [json.loads(f.read_text()) for f in (out / "runs").glob("*/threshold_row.json")]
    return sorted((r for r in rows if r["cell"] == str(cell.resolve())), key=lambda r: (r["height"], r["cell_size"]))


def regularization(row):
    """How a run was regularized, as the tables name it: "local" or "ℓ = … m"."""
    length = row.get("nonlocal_length")  # runs from before the option are local
    return "local" if length is None else f"ℓ = {length:g} m"


def points_per_cell(row):
    return row.get("points_per_cell", 1)  # runs from before the option had one


def resolution(row):
    """A run's regularization and resolution, as the brackets name them: "local, H0/h = 12", with ", 2
    points per cell" where it had more than one."""
    label = f"{regularization(row)}, H0/h = {round(row['height'] / row['cell_size'])}"
    label += f", {points_per_cell(row)} points per cell" if points_per_cell(row) != 1 else ""
    label += f", floor friction {row['floor_friction']:g}" if row.get("floor_friction") is not None else ""
    label += f", gate let go of over {row['release']:g} s" if row.get("release") is not None else ""
    return label + (f", transfer {row['transfer']}" if row.get("transfer") else "")


def threshold_brackets(rows):
    """{resolution: (highest height that stood, lowest that fell)} over the runs of each regularization
    and resolution, a side None where no run of that group stood (fell)."""
    found = {}
    for label in sorted({resolution(r) for r in rows}):
        group = [r for r in rows if resolution(r) == label]
        found[label] = (max((r["height"] for r in group if r["stands"] is True), default=None),
                        min((r["height"] for r in group if r["stands"] is False), default=None))
    return found


def predictions(strength, unconfined):
    """{predictor: H_c [m]} from a strength.py result (its shear envelope, read two ways) and an
    unconfined.py result (Chen's bound from q_u), either may be None."""
    found = {}
    if strength:
        for reading in ("tan", "sin"):
            r = strength[reading]
            found[f"shear envelope, τ/σ = {reading} φ (c = {r['cohesion']:.0f} Pa, φ = {r['friction_angle']:.1f}°)"] = \
                r["critical_height"]
    if unconfined:
        found[f"unconfined compression (q_u = {unconfined['q_u']:.0f} Pa)"] = \
            unconfined["critical_height"]["Chen (N_s = 3.83)"]
    return found


def read_prediction(file, cell, producer):
    """The JSON `file` of `producer` run on `cell`; exits naming the file and field otherwise."""
    if file is None:
        return None
    result = json.loads(file.read_text())
    # By content, so that a result made in another checkout, or before the cell file was edited, is judged
    # by the cell it measured.
    if result.get("cell_json") != json.loads(cell.read_text()):
        sys.exit(f"live_threshold.py: {file}: field 'cell_json' (the cell measured, from {result.get('cell')!r}) is "
                 f"not the cell the columns run, {cell}: run {producer} --cell {cell}")
    return result


def verdicts_of(rows, critical):
    """{predictor: the heights that contradict its H_c (stood above it), and per resolution H0/h the
    highest standing and lowest falling height over H_c}."""
    brackets = threshold_brackets(rows)
    return {name: {"critical_height": value,
                   "contradicted_by": [r["height"] for r in rows if r["stands"] is True and r["height"] > value],
                   "threshold_over_critical": {group: [None if h is None else h / value for h in pair]
                                               for group, pair in brackets.items()}}
            for name, value in critical.items()}


def outcome(row):
    return OUTCOME[row["stands"]] + (" (stopped once fallen)" if row.get("front_reached") else "")


def report(rows, critical, verdicts, cell):
    """live_threshold.md: the runs against each prediction, then each prediction's verdict."""
    lines = [f"Cell {cell.name}. Critical heights (Chen's kinematic bound: above it a cut must fall, below it "
             "it may stand): " + "; ".join(f"{name}: {value:.3f} m" for name, value in critical.items()), "",
             "| H0 [m] | L0 [m] | h [m] | points per cell | regularization | watched to t [s] | front after the gate / L0 | "
             "top drop / H0 | outcome | "
             + " | ".join(f"H_c = {value:.3f} m" for value in critical.values()) + " | CPU-s |",
             "|---|---|---|---|---|---|---|---|---|" + "---|" * len(critical) + "---|"]
    lines += [f"| {r['height']:g} | {r['width']:g} | {r['cell_size']:g} | {points_per_cell(r)} | {regularization(r)} | {r['end']:.3f} | "
              f"{r['front']:.3f} | {r['top_drop']:.3f} | {outcome(r)} | " + " | ".join(r["predicted"].values())
              + f" | {r['cpu_s']:.0f} |" + (f" stopped: {r['failed']}" if r["failed"] else "") for r in rows]
    lines.append("")
    for name, v in verdicts.items():
        contradicted = (f"contradicted: columns of H0 = {', '.join(f'{h:g}' for h in v['contradicted_by'])} m stood "
                        "above H_c" if v["contradicted_by"] else "not contradicted")
        thresholds = [f"{group}: " + ", ".join(
            f"{label} {ratio:.2f} H_c" for label, ratio in zip(("highest standing", "lowest falling"), pair)
            if ratio is not None) for group, pair in v["threshold_over_critical"].items()]
        lines.append(f"{name}: {contradicted}; " + "; ".join(thresholds))
    return "\n".join(lines) + "\n"


def plot(rows, critical, out):
    fig, ax = plt.subplots(figsize=(6.5, 3.8))
    for stopped, label in ((False, "live DEM cells (a front below 1e-4 L0 drawn at 1e-4)"),
                           (True, f"the same, stopped once fallen ({FALLEN:g} L0)")):
        group = [r for r in rows if bool(r.get("front_reached")) == stopped]
        if group:
            ax.semilogy([r["height"] for r in group], [max(r["front"], 1e-4) for r in group], "o",
                        fillstyle="none" if stopped else "full", label=label)
    for (name, value), style in zip(critical.items(), ("--", ":", "-.")):
        ax.axvline(value, color="grey", linestyle=style, label=f"H_c, {name}")
    ax.axhline(STANDING, color="k", linewidth=0.6)
    ax.set_ylim(1e-5, 1e3)  # room above the falling columns for the legend
    finish_and_save(fig, ax, out, "column height H0 [m]", "front displacement after the gate / L0")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path)
    parser.add_argument("--strength", type=Path, help="strength.json of cell_response/strength.py on the same cell")
    parser.add_argument("--unconfined", type=Path,
                        help="unconfined.json of cell_response/unconfined.py on the same cell")
    parser.add_argument("--heights", type=float, nargs="*", default=[0.05, 0.1, 0.15, 0.2],
                        help="H0 [m]; none: only report the runs already in OUT, against the predictions given")
    parser.add_argument("--width", type=float, default=0.15, help="L0 [m]")
    parser.add_argument("--cell-size", type=float, default=0.0125, help="grid cell size h [m]")
    scenes.add_nonlocal_length_option(parser, "regularize over this length ℓ [m] (default: local)")
    parser.add_argument("--cell", type=Path, default=CELL)
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--threads", type=int, default=environment.threads())
    parser.add_argument("--transfer", type=scenes.transfer_name, help="apic, pic, RATE or apic_flip:RATE (default: the scene's, APIC-FLIP at "
                        "5 PIC per second)")
    parser.add_argument("--watch", type=float, default=4.0, help="watched time after the gate, in √(H0/g)")
    parser.add_argument("--release", type=float, help="let the gate go over this long [s] instead of removing it at "
                        "once: its traction on the face falls linearly to zero (default: at once)")
    parser.add_argument("--floor-friction", type=scenes.friction_coefficient,
                        help="the floor's Coulomb friction (default: the scene's, 0.5)")
    scenes.add_points_per_cell_option(parser, 1,
                                      "material points, each with its own cell, per grid cell and direction (default 1)")
    args = parser.parse_args()
    scenes.require_whole_cells(parser, args.cell_size,
                               [("--width", args.width)] + [("--heights", height) for height in args.heights])
    if not (args.strength or args.unconfined):
        parser.error("give --strength, --unconfined or both: what predicts the critical height")
    unconfined = read_prediction(args.unconfined, args.cell, "unconfined.py")
    if unconfined and not unconfined["peak_reached"]:
        sys.exit(f"live_threshold.py: {args.unconfined}: field 'peak_reached' is false, expected true: the test never "
                 "peaked, so its q_u is only a lower bound; run unconfined.py again with a larger --strain")
    critical = predictions(read_prediction(args.strength, args.cell, "strength.py"), unconfined)
    args.out.mkdir(parents=True, exist_ok=True)
    for height in args.heights:
        row = run_height(args.build.resolve(), args.out, args.cell, height, args.width, args.cell_size,
                         args.nonlocal_length, args.points_per_cell, args.floor_friction, args.transfer, args.watch,
                         args.threads, args.release)
        print(f"H0 = {height:g} m: front {row['front']:.3f} L0, {outcome(row)}, "
              f"{row['cpu_s']:.0f} CPU-s", flush=True)
    rows = finished_rows(args.out, args.cell)
    for row in rows:
        row["predicted"] = {name: "must fall" if row["height"] > value else "may stand"
                            for name, value in critical.items()}
    verdicts = verdicts_of(rows, critical)
    text = report(rows, critical, verdicts, args.cell)
    (args.out / "live_threshold.md").write_text(text)
    # The cell's strength and bulk density, so that runs of cells of other strengths (other packing seeds)
    # can be compared by their stress over their own q_u (corner_stress.py --threshold).
    strength = {"q_u": unconfined["q_u"], "density": unconfined["density"]} if unconfined else None
    (args.out / "live_threshold.json").write_text(json.dumps(
        {"cell": str(args.cell), "critical_height": critical, "unconfined": strength,
         "standing": STANDING, "runs": rows, "verdicts": verdicts}, indent=2))
    plot(rows, critical, args.out / "live_threshold.png")
    print(text, end="")


if __name__ == "__main__":
    main()
