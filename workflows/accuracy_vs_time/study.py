#!/usr/bin/python3
"""Accuracy versus time on a column collapse: the scene with `live` as reference and every knob that
trades accuracy for time (variants.py), error against wall and CPU time as a Pareto plot and a table.

  study.py [OUT] [--scene SCENE.json] [--cell CELL.json] [--spheres N] [--paths PATHS.json]
               [--variants full|reduced|enriched|creeping|smoke] [--skip RUN,RUN] [--end T] [--threads N] [--build DIR]

Defaults: OUT = $GRAINBANK_OUT/accuracy_vs_time (build/out/accuracy_vs_time); the demo's column
(workflows/demo/column.json), its soft snow cell and library paths, except for a set with inputs of
its own (variants.INPUTS: `creeping`, the former cache_vs_live comparison); `--spheres N` prepares that
cell, and so the libraries' template and every run, with N spheres (250: the demo column's representative
cell, workflows/convergence). The variant scenes are
written by `mpm_solver scene` (plotting/scenes.py). The
library (OUT/lib, template 1 = the cell) is built first and timed apart: it is a one-off cost shared
by every library run. Runs on the scene's own library (variants.py, "enriched") use OUT/lib_enriched:
the template alone, enriched by the `enriching` run (rebuilt from scratch unless that run finished).
Runs already finished in OUT/runs/ are kept (delete them to rerun).
Errors against the reference, at their common output times (plotting/run_compare.py): front, final
runout, stress field (point by point and smoothed over a point spacing), deposit profile and the
bulk's advance (95 % mass edge, centroid); the front, stress, deposit and bulk errors also over those
of the noise-floor run (variants.NOISE_FLOOR: live on a cell packed with another seed), when the set
has it.
A run that stops before the end (its error in the column `failed`) is compared up to where it stopped.
Writes OUT/results.csv, OUT/results.md, OUT/pareto.png and OUT/study.json.
"""
import argparse
import json
import math
import shutil
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, run_compare, scenes, tables, vtu  # noqa: E402  (after the path set-up)
from plotting.timing import timed  # noqa: E402
import variants  # noqa: E402

WORKFLOWS = HERE.parent
DEMO_INPUTS = {"scene": WORKFLOWS / "demo" / "column.json", "cell": WORKFLOWS / "demo" / "cell_soft_snow_250.json",
               "paths": WORKFLOWS / "demo" / "paths.json"}


def with_preparation(cell_file, preparation, out):
    """`out`: the cell of `cell_file` with the keys of `preparation` replaced in its preparation."""
    cell = json.loads(cell_file.read_text())
    cell["preparation"].update(preparation)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(cell, indent=2) + "\n")
    return out


def build_library(args, build):
    library = args.out / "lib"
    dem_sampler = build / "dem_sampler" / "dem_sampler"
    wall, cpu = timed([dem_sampler, "prepare", args.cell, "--library", library])
    if args.paths:
        w, c = timed([dem_sampler, "sample", args.paths, "--library", library, "--threads", args.threads])
        wall, cpu = wall + w, cpu + c
    return library, {"wall_s": wall, "cpu_s": cpu}


def prepare_enriched_library(args, build):
    library, enriching = args.out / "lib_enriched", args.out / "runs" / "enriching"
    if not (enriching / "study_run.json").exists():  # a library enriched by an unfinished run is no reference
        shutil.rmtree(library, ignore_errors=True)
        shutil.rmtree(enriching, ignore_errors=True)
    timed([build / "dem_sampler" / "dem_sampler", "prepare", args.cell, "--library", library])
    return library


def write_scene(name, spec, library, build, args):
    material = dict(spec.get("material", {}))
    if "preparation" in spec:
        cell_file = with_preparation(args.cell, spec["preparation"], args.out / "cells" / f"{name}.json")
        material["cell"] = str(cell_file.resolve())
    settings = dict(spec.get("settings", {}))
    if "grid_factor" in spec:
        grid = json.loads(args.scene.read_text())["grid"]
        settings["/grid/cell_size"] = grid["cell_size"] * spec["grid_factor"]
        settings["/grid/cells"] = [math.ceil(n / spec["grid_factor"]) for n in grid["cells"]]
    if "gravity_factor" in spec:
        settings.update(scenes.scaled_gravity(args.scene, spec["gravity_factor"]))
    if args.end:
        settings["/time/end"] = args.end
    scene_file = args.out / "scenes" / f"{name}.json"
    scenes.variant(build, args.scene, scene_file, spec["law"], library, material, settings)
    return scene_file


# The errors stated against the noise floor: each divided by the same error of the live run on a cell
# packed with another seed, so that 1 means "as far from live as another equally good live run".
ERRORS_AGAINST_NOISE = ("front_rel_err", "stress_rel_l2", "stress_smoothed_rel_l2", "deposit_rms_m",
                        "mass_edge_rel_err", "centroid_rel_err")


def over_noise_floor(row, noise_row):
    """{error}_over_noise for each of ERRORS_AGAINST_NOISE; None without the noise-floor run, or where it
    has no such error (a front that moved by nothing)."""
    def ratio(key):
        return row[key] / noise_row[key] if noise_row and noise_row[key] and row[key] is not None else None
    return {f"{key}_over_noise": ratio(key) for key in ERRORS_AGAINST_NOISE}


def run(name, spec, library, build, args):
    folder = args.out / "runs" / name
    scene_file = write_scene(name, spec, library, build, args)
    return run_compare.timed_scene_run(build, scene_file, folder, args.threads)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("accuracy_vs_time"))
    parser.add_argument("--scene", type=Path)
    parser.add_argument("--cell", type=Path)
    parser.add_argument("--spheres", type=int, help="spheres per cell instead of the cell file's")
    parser.add_argument("--paths", type=Path)
    parser.add_argument("--variants", choices=sorted(variants.SETS), default="full")
    parser.add_argument("--skip", default="", help="runs of the set to leave out, comma-separated (e.g. grid_x0.5)")
    parser.add_argument("--end", type=float, help="end time [s] instead of the scene's")
    parser.add_argument("--threads", type=int, default=environment.threads())
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    args = parser.parse_args()
    inputs = variants.INPUTS.get(args.variants, DEMO_INPUTS)
    for key in ("scene", "cell", "paths"):
        if getattr(args, key) is None:
            setattr(args, key, inputs[key])
    chosen = variants.SETS[args.variants]
    skipped = [name for name in args.skip.split(",") if name]
    unknown = [name for name in skipped if name not in chosen or name == "live"]
    if unknown:
        parser.error(f"--skip: expected runs of the set other than the reference live, got {', '.join(unknown)}")
    chosen = {name: spec for name, spec in chosen.items() if name not in skipped}
    on_enriched = any(spec.get("library") == "enriched" for spec in chosen.values())
    if on_enriched and "enriching" not in chosen:
        parser.error("--skip: the runs on the enriched library need the run enriching, which builds it")
    args.out.mkdir(parents=True, exist_ok=True)
    if args.spheres:
        args.cell = with_preparation(args.cell, {"spheres": args.spheres}, args.out / "cells" / "template.json")
    build = args.build.resolve()
    library, library_cost = build_library(args, build)
    libraries = {"generic": library}
    if on_enriched:
        libraries["enriched"] = prepare_enriched_library(args, build)
    costs = {}
    for name, spec in chosen.items():
        costs[name] = run(name, spec, libraries[spec.get("library", "generic")], build, args)
        print(f"{name}: {costs[name]['wall_s']:.1f} s wall, {costs[name]['cpu_s']:.1f} s CPU", flush=True)
    reference = args.out / "runs" / "live"
    rows = []
    for name, spec in chosen.items():
        folder = args.out / "runs" / name
        series = tables.read_csv(folder / "series.csv")
        rows.append({"run": name, "knob": spec["knob"], "value": spec["value"], "law": spec["law"],
                     "points": len(vtu.read_vtu(vtu.read_pvd(folder / "points.pvd")[0][1])),
                     "steps": int(series["step"][-1]),
                     "wall_s": costs[name]["wall_s"], "cpu_s": costs[name]["cpu_s"],
                     **run_compare.errors(folder, reference), "failed": costs[name].get("failed", "")})
    noise_row = next((row for row in rows if row["run"] == variants.NOISE_FLOOR), None)
    for row in rows:
        failed = row.pop("failed")
        row.update(over_noise_floor(row, noise_row), failed=failed)
    tables.write_csv(args.out / "results.csv", rows)
    tables.write_markdown(args.out / "results.md", rows)
    (args.out / "study.json").write_text(json.dumps({"variants": args.variants, "scene": str(args.scene),
                                                     "library_cost": library_cost, "threads": args.threads,
                                                     "runs": rows}, indent=2) + "\n")
    import pareto  # matplotlib only for the figure
    pareto.plot(rows, args.out / "pareto.png")
    print((args.out / "results.md").read_text(), end="")


if __name__ == "__main__":
    main()
