#!/usr/bin/python3
"""Accuracy versus time on a column collapse: the scene with `live` as reference and every knob that
trades accuracy for time (variants.py), error against wall and CPU time as a Pareto plot and a table.

  study.py [OUT] [--scene SCENE.json] [--cell CELL.json] [--paths PATHS.json]
               [--variants full|reduced|enriched|creeping|smoke] [--skip RUN,RUN] [--end T] [--threads N] [--build DIR]

Defaults: OUT = $GRAINBANK_OUT/accuracy_vs_time (build/out/accuracy_vs_time); the demo's column
(workflows/demo/column.json), its soft snow cell and library paths, except for a set with inputs of
its own (variants.INPUTS: `creeping`, the former cache_vs_live comparison). The variant scenes are
written by `mpm_solver scene` (plotting/scenes.py). The
library (OUT/lib, template 1 = the cell) is built first and timed apart: it is a one-off cost shared
by every library run. Runs on the scene's own library (variants.py, "enriched") use OUT/lib_enriched:
the template alone, enriched by the `enriching` run (rebuilt from scratch unless that run finished).
Runs already finished in OUT/runs/ are kept (delete them to rerun).
Errors against the reference, at their common output times: front = worst relative runout error
(rows with a reference runout above 1 cm), stress = mean relative L2 of the in-plane stress field
(points matched by id, by nearest position when the discretisation differs), deposit = RMS difference
of the free-surface height at the last output [m].
A run that stops before the end (its error in the column `failed`) is compared up to where it stopped.
Writes OUT/results.csv, OUT/results.md, OUT/pareto.png and OUT/study.json.
"""
import argparse
import json
import math
import shutil
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, flow, scenes, tables, vtu  # noqa: E402  (after the path set-up)
from plotting.timing import timed, timed_run  # noqa: E402
import variants  # noqa: E402

WORKFLOWS = HERE.parent
DEMO_INPUTS = {"scene": WORKFLOWS / "demo" / "column.json", "cell": WORKFLOWS / "demo" / "cell_soft_snow_125.json",
               "paths": WORKFLOWS / "demo" / "paths.json"}


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
    if "cell_spheres" in spec:
        cell = json.loads(args.cell.read_text())
        cell["preparation"]["spheres"] = spec["cell_spheres"]
        cell_file = args.out / "cells" / f"{name}.json"
        cell_file.parent.mkdir(parents=True, exist_ok=True)
        cell_file.write_text(json.dumps(cell, indent=2) + "\n")
        material["cell"] = str(cell_file.resolve())
    settings = dict(spec.get("settings", {}))
    if "grid_factor" in spec:
        grid = json.loads(args.scene.read_text())["grid"]
        settings["/grid/cell_size"] = grid["cell_size"] * spec["grid_factor"]
        settings["/grid/cells"] = [math.ceil(n / spec["grid_factor"]) for n in grid["cells"]]
    if args.end:
        settings["/time/end"] = args.end
    scene_file = args.out / "scenes" / f"{name}.json"
    scenes.variant(build, args.scene, scene_file, spec["law"], library, material, settings)
    return scene_file


def run(name, spec, library, build, args):
    folder = args.out / "runs" / name
    if (folder / "study_run.json").exists():
        return json.loads((folder / "study_run.json").read_text())
    scene_file = write_scene(name, spec, library, build, args)
    # A run that stops (e.g. a point thrown out of the grid) is a result too: its error is kept and its
    # outputs up to the stop are compared.
    wall, cpu, error = timed_run([build / "mpm_solver" / "mpm_solver", scene_file, "--out", folder, "--threads",
                                  args.threads])
    result = {"wall_s": wall, "cpu_s": cpu, "failed": error or ""}
    (folder / "study_run.json").write_text(json.dumps(result) + "\n")
    return result


def stress_error(snapshot, reference):
    if len(snapshot) == len(reference) and (snapshot.fields["id"] == reference.fields["id"]).all():
        return flow.stress_error(snapshot, reference)
    return flow.stress_error_nearest(snapshot, reference)


def errors(folder, reference_folder):
    series, ref_series = (tables.read_csv(f / "series.csv") for f in (folder, reference_folder))
    snaps = {round(s.time, 9): s for s in vtu.read_run(folder)}
    ref_snaps = {round(s.time, 9): s for s in vtu.read_run(reference_folder)}
    common = sorted(set(snaps) & set(ref_snaps))[1:]  # the initial state is the same by construction
    if not common:
        raise ValueError(f"{folder}: no output time in common with the reference {reference_folder}")
    final, ref_final = snaps[common[-1]], ref_snaps[common[-1]]
    # Columns of two reference point spacings across every x either run reaches.
    width = 2 * ref_final.spacing()
    x = np.concatenate([final.xy[:, 0], ref_final.xy[:, 0]])
    bins = np.arange(x.min(), x.max() + 2 * width, width)
    return {
        "front_rel_err": flow.front_error(series, ref_series),
        "stress_rel_l2": float(np.mean([stress_error(snaps[t], ref_snaps[t]) for t in common])),
        "deposit_rms_m": flow.profile_error(final, ref_final, bins),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("accuracy_vs_time"))
    parser.add_argument("--scene", type=Path)
    parser.add_argument("--cell", type=Path)
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
                     **errors(folder, reference), "failed": costs[name].get("failed", "")})
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
