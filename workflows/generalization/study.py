#!/usr/bin/python3
"""Does a generic cell library answer scenes it has never seen? (issue 13, "Benchmark")

  study.py [OUT] [--paths PATHS.json] [--aspects 0.5,1,2] [--bonds 1,1.5] [--spheres N] [--tolerance PA]
           [--surrogate KEYS.json] [--error-budget PA] [--draws N] [--end T] [--gate T] [--threads N] [--build DIR] [--smoke]

The library is made from sampled paths and states only (`dem_sampler prepare` + `sample PATHS`,
default workflows/demo/paths.json; workflows/precompute/states.json adds state probes): no run of any
test scene is in it, and no run writes to it (the hybrid law runs with enrich off, the surrogate law
learns in memory only), so the runs cannot learn from one another.
Held-out scenes: the demo's cohesive column (workflows/demo/column.json, 0.4 m wide) at height/width
`--aspects` and with the demo cell's bonds (tension and shear strength) times each of `--bonds`; each
bond strength is its own template and library; `--spheres N` prepares every template with N spheres
instead of the 125 of CELL (the demo's cell until stop 38; 250, the demo's now, is its column's
representative cell, workflows/convergence). The gate
opens at `--gate` and the scene ends at `--end`.
Runs per scene: `live` (the reference), `live_seed` (live on a template prepared with another packing
seed: the noise floor), `live_perturbed` (the reference with gravity changed in its 12th digit: how far
its own trajectory moves under a change in the last bits, the part of every error that no law, however
exact, could avoid), `hybrid` (the total-strain key: tolerance 10, warm start, back after 5) and
`surrogate` (the state key, its material keys from `--surrogate`, default surrogate.json beside this
script, the demo's setting; surrogate_fast.json is the faster one of stop 55, surrogate_long.json that one
with samples of one record and catch-ups of at most 1e-5 of strain per DEM step (stop 69: for flows run
to 0.3 s); `--tolerance` replaces
its tolerance) and `surrogate_budget` (the same with an `error_budget` of `--error-budget`,
default 300 Pa: a point whose estimated errors summed since its last live spell or re-anchoring
would pass it is re-anchored), and `surrogate_budget_seed`: surrogate_budget on the other packing's
library (its template and the same sampled paths), measured against `live_seed`, the live run of its
own template: a second draw of the surrogate's error, from another library. And `--draws` − 1 more
draws of surrogate_budget (`surrogate_budget_draw_K`, default 2): the same run with its length scales
fitted on the K-th other set of probes (`fit_seed` K, database/surrogate/length_scales.hpp) and gravity
changed in its 12th digit (× 1 + 1e-12, 1 − 1e-12, 1 + 2e-12, …). A run of the surrogate is one
trajectory of a chaotic flow, and the gravity change alone moved the flowing columns' surrogate runout
by up to 4 % (stop 47); the fit is one draw of scales the library leaves undetermined, and another set
of probes moved a flowing column's CPU by 1.5× and its runout by 7 % (stop 63). One draw does not tell
the surrogate's bias from its scatter.
Per run: CPU seconds (of the child process, not wall) and their ratio to live, the share of
point-steps that ran live, the share of its stepping time spent catching cells up on their points'
motion (catch_up_share), and the errors against live of plotting/run_compare.py (worst front error,
final runout, stress field, deposit profile).
Writes OUT/summary.json (per scene: surrogate_budget's cpu_ratio_to_live and live_fraction, its
runout_rel_error as |the mean over its draws of (runout − live's) / live's| (each draw's signed change
in runout_rel_change_draws), and
noise_floor = live_seed's runout_rel_error, chaos_floor = live_perturbed's; kinetic_energy_change, the
mean over the draws of the signed relative change of the kinetic energy at the end (each draw's in
kinetic_energy_change_draws), and kinetic_energy_noise_floor, live_seed's |change|;
runout_rel_error_seed_library =
surrogate_budget_seed's against live_seed; every run's figures under "runs", each against its
reference, "reference" naming it),
OUT/table.md and OUT/generalization.png. Runs already finished in OUT/runs/ are kept.
--smoke: one scene of the tiny test column (tests/workflows), to 0.01 s, for CI.
"""
import argparse
import json
import math
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, run_compare, scenes, tables  # noqa: E402  (after the path set-up)
from plotting.timing import timed  # noqa: E402

WORKFLOWS = HERE.parent
ROOT = WORKFLOWS.parent
CELL = WORKFLOWS / "demo" / "cell_soft_snow_125.json"
HYBRID = scenes.hybrid(tolerance=10.0, return_after=5)
RUNS = ("live", "live_seed", "live_perturbed", "hybrid", "surrogate", "surrogate_budget", "surrogate_budget_seed")
# The live run each run is measured against: the one on its own template.
REFERENCE = {"surrogate_budget_seed": "live_seed"}
SEED_OFFSET = 1000  # the noise floor's template: the cell's packing seed plus this


def draw_factors(draws):
    """The runs that draw surrogate_budget again, each with its gravity over the scene's: 1 + 1e-12,
    1 − 1e-12, 1 + 2e-12, … ."""
    return {f"surrogate_budget_draw_{k}": factor for k, factor in enumerate(scenes.draw_gravity_factors(draws), start=1)}


def cell_file(args, bond, seed_offset):
    cell = json.loads(CELL.read_text())
    for key in ("tensile_strength", "shear_strength"):
        cell["material"]["bond"][key] *= bond
    cell["preparation"]["seed"] += seed_offset
    if args.spheres:
        cell["preparation"]["spheres"] = args.spheres
    out = args.out / "cells" / f"bond_{bond:g}{'_seed' if seed_offset else ''}.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(cell, indent=2) + "\n")
    return out


def libraries(args, build, bond):
    """The generic library of the bond strength and the other seed's: each a template and the sampled
    paths (the live law uses only the template; surrogate_budget_seed, the paths too)."""
    dem_sampler = build / "dem_sampler" / "dem_sampler"
    generic, seeded = args.out / f"lib_bond_{bond:g}", args.out / f"lib_bond_{bond:g}_seed"
    _, cpu = timed([dem_sampler, "prepare", cell_file(args, bond, 0), "--library", generic])
    _, sample_cpu = timed([dem_sampler, "sample", args.paths, "--library", generic, "--threads", args.threads])
    timed([dem_sampler, "prepare", cell_file(args, bond, SEED_OFFSET), "--library", seeded])
    timed([dem_sampler, "sample", args.paths, "--library", seeded, "--threads", args.threads])
    return {"generic": generic, "seed": seeded, "cpu_s": cpu + sample_cpu}


def column_settings(base, aspect, args):
    """The base scene's column (its first region) with height = aspect × width, its gates as tall, the
    grid tall enough for it, the gate opened at --gate and the end at --end."""
    scene = json.loads(Path(base).read_text())
    (x0, y0), (x1, _) = scene["regions"][0]["rectangle"]["min"], scene["regions"][0]["rectangle"]["max"]
    top = y0 + aspect * (x1 - x0)
    grid = scene["grid"]
    rows = math.ceil((top - grid["origin"][1]) / grid["cell_size"]) + 3  # room above the column
    settings = {"/regions/0/rectangle/max": [x1, top], "/grid/cells": [grid["cells"][0], rows],
                "/time/end": args.end, "/tracked_points": []}
    for k, obstacle in enumerate(scene["obstacles"]):
        (ax, ay), (bx, by) = obstacle["line"]
        if ax == bx:  # a gate or wall: as tall as the column
            settings[f"/obstacles/{k}/line"] = [[ax, ay], [bx, top]]
            if "remove_at" in obstacle:
                settings[f"/obstacles/{k}/remove_at"] = args.gate
    return settings


def surrogate_material(args, fail):
    """The surrogate runs' keys: --surrogate's JSON object, --tolerance replacing its tolerance;
    `fail(message)` (the parser's error) when the file is no such object."""
    try:
        material = json.loads(args.surrogate.read_text())
    except (OSError, json.JSONDecodeError) as error:
        fail(f"{args.surrogate}: --surrogate: expected a readable JSON object of surrogate keys ({error})")
    if not isinstance(material, dict):
        fail(f"{args.surrogate}: --surrogate: expected a JSON object of surrogate keys, got {type(material).__name__}")
    if args.tolerance is not None:
        material["tolerance"] = args.tolerance
    return material


def run_scene(name, settings, libs, surrogate, build, args):
    specs = {"live": ("live", libs["generic"], None), "live_seed": ("live", libs["seed"], None),
             "live_perturbed": ("live", libs["generic"], None),
             "hybrid": ("hybrid", libs["generic"], HYBRID), "surrogate": ("surrogate", libs["generic"], surrogate),
             "surrogate_budget": ("surrogate", libs["generic"], {**surrogate, "error_budget": args.error_budget}),
             "surrogate_budget_seed": ("surrogate", libs["seed"], {**surrogate, "error_budget": args.error_budget})}
    draws = draw_factors(args.draws)
    gravity_factors = {"live_perturbed": 1 + scenes.GRAVITY_PERTURBATION, **draws}
    law, library, material = specs["surrogate_budget"]
    specs.update({run: (law, library, scenes.drawn_material(material, k)) for k, run in enumerate(draws, start=1)})
    # The scene with live cells and no key of any other law, so that each run's keys are its own.
    folder = args.out / "scenes"
    folder.mkdir(parents=True, exist_ok=True)
    bare = folder / f"{name}.json"
    scenes.variant(build, args.scene, bare, "live", None, None, settings)
    costs = {}
    for run in specs:
        law, library, material = specs[run]
        scene_file = folder / f"{name}_{run}.json"
        scenes.variant(build, bare, scene_file, law, library, material,
                       scenes.scaled_gravity(bare, gravity_factors[run]) if run in gravity_factors else None)
        costs[run] = run_compare.timed_scene_run(build, scene_file, args.out / "runs" / name / run, args.threads)
        print(f"{name} {run}: {costs[run]['cpu_s']:.1f} s CPU{' (' + costs[run]['failed'] + ')' if costs[run]['failed'] else ''}",
              flush=True)
    return costs


def live_fraction(folder, law):
    if law == "live":
        return 1.0
    coupling = json.loads((folder / "summary.json").read_text())["coupling"]
    return sum(law["live_point_steps"] for law in coupling["laws"]) / coupling["point_steps"]


def catch_up_share(folder, threads):
    """The share of a run's stepping time its cells spent catching up on their points' motion: what
    keeping each point's cell in step with its motion costs, beside its live steps. The catch-ups'
    time (warm_start_seconds) is summed over the points, so it is measured against the stepping wall
    time of all `threads`."""
    summary = json.loads((folder / "summary.json").read_text())
    caught_up = sum(law.get("warm_start_seconds", 0.0) for law in summary["coupling"]["laws"])
    stepping = summary["wall_time"]["steps"] * threads
    return caught_up / stepping if stepping > 0 else 0.0


def measure(name, costs, args):
    runs = {}
    for run in costs:
        folder, reference = (args.out / "runs" / name / r for r in (run, REFERENCE.get(run, "live")))
        runs[run] = {"reference": reference.name, "cpu_s": costs[run]["cpu_s"],
                     "cpu_ratio_to_live": costs[run]["cpu_s"] / costs[reference.name]["cpu_s"],
                     "live_fraction": live_fraction(folder, "live" if run.startswith("live") else run),
                     "catch_up_share": catch_up_share(folder, args.threads),
                     **run_compare.errors(folder, reference), "failed": costs[run]["failed"]}
    s = runs["surrogate_budget"]  # the demo's setting, the one that lets no column stand that falls live
    draws = [run_compare.final_runout_change(*(tables.read_csv(args.out / "runs" / name / r / "series.csv")
                                               for r in (run, "live")))
             for run in ["surrogate_budget", *draw_factors(args.draws)]]
    measured = [change for change in draws if change is not None]  # None: the live column ran out < 1 cm
    energies = [runs[run]["kinetic_energy_change"] for run in ["surrogate_budget", *draw_factors(args.draws)]]
    moving = [change for change in energies if change is not None]  # None: the live column is at rest
    return {"cpu_ratio_to_live": s["cpu_ratio_to_live"], "live_fraction": s["live_fraction"],
            "runout_rel_error": abs(sum(measured) / len(measured)) if measured else None,
            "runout_rel_change_draws": draws,
            "noise_floor": runs["live_seed"]["runout_rel_err"],
            "damage_change": s["damage_change"], "damage_noise_floor": abs(runs["live_seed"]["damage_change"]),
            "kinetic_energy_change": sum(moving) / len(moving) if moving else None,
            "kinetic_energy_change_draws": energies,
            "kinetic_energy_noise_floor": (None if runs["live_seed"]["kinetic_energy_change"] is None
                                           else abs(runs["live_seed"]["kinetic_energy_change"])),
            "chaos_floor": runs["live_perturbed"]["runout_rel_err"],
            "runout_rel_error_seed_library": runs["surrogate_budget_seed"]["runout_rel_err"], "runs": runs}


def plot(summary, out):
    from plotting.figures import DPI, plt  # matplotlib only for the figure
    names = list(summary["scenes"])
    panels = [("cpu_ratio_to_live", "CPU relative to live", True), ("runout_rel_err", "final runout error vs live", False),
              ("stress_rel_l2", "stress field error vs live", False)]
    # A last, empty column holds the legend: the bars fill every panel.
    fig, axes = plt.subplots(1, len(panels) + 1, figsize=(5 * len(panels) + 2.5, 4.2), layout="constrained",
                             gridspec_kw={"width_ratios": [1] * len(panels) + [0.5]})
    width = 0.8 / len(RUNS)
    for ax, (key, label, log) in zip(axes, panels):
        for i, run in enumerate(RUNS):
            values = [summary["scenes"][n]["runs"][run][key] or 0.0 for n in names]  # None: not measured
            ax.bar([k + (i - (len(RUNS) - 1) / 2) * width for k in range(len(names))], values, width, label=run)
        ax.set_xticks(range(len(names)), names, rotation=30, ha="right")
        ax.set_title(label)
        if log:
            ax.set_yscale("log")
    # Every draw of surrogate_budget over its bar: the bar is one draw, the dots its scatter.
    at = (RUNS.index("surrogate_budget") - (len(RUNS) - 1) / 2) * width
    draws = [(k + at, abs(change)) for k, n in enumerate(names)
             for change in summary["scenes"][n]["runout_rel_change_draws"] if change is not None]
    if draws:
        axes[1].plot(*zip(*draws), "k.", label="surrogate_budget, each draw")
    axes[-1].axis("off")
    axes[-1].legend(*axes[1].get_legend_handles_labels(), loc="center left")
    fig.savefig(out, dpi=DPI)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("generalization"))
    parser.add_argument("--paths", type=Path, default=WORKFLOWS / "demo" / "paths.json")
    parser.add_argument("--aspects", default="0.5,1,2")
    parser.add_argument("--bonds", default="1,1.5")
    parser.add_argument("--spheres", type=int, help="spheres per cell instead of the 125 of CELL")
    parser.add_argument("--surrogate", type=Path, default=HERE / "surrogate.json",
                        help="the surrogate runs' material keys (JSON object)")
    parser.add_argument("--tolerance", type=float, help="the surrogate's tolerance [Pa] instead of --surrogate's")
    parser.add_argument("--error-budget", type=float, default=300.0,
                        help="the surrogate_budget run's error_budget [Pa]")
    parser.add_argument("--draws", type=int, default=3, help="runs of surrogate_budget, each with another length-scale fit and gravity changed in its 12th digit")
    parser.add_argument("--end", type=float, default=0.15)
    parser.add_argument("--gate", type=float, default=0.05)
    parser.add_argument("--threads", type=int, default=environment.threads())
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--smoke", action="store_true")
    args = parser.parse_args()
    if args.draws < 1:
        parser.error(f"--draws: expected a whole number >= 1, got {args.draws}")
    args.scene = WORKFLOWS / "demo" / "column.json"
    aspects, bonds = [float(a) for a in args.aspects.split(",")], [float(b) for b in args.bonds.split(",")]
    if args.smoke:
        args.scene, args.paths = ROOT / "tests" / "workflows" / "tiny_column.json", ROOT / "tests" / "workflows" / "tiny_paths.json"
        aspects, bonds, args.end, args.gate = [1.0], [1.0], 0.01, 0.002
    surrogate = surrogate_material(args, parser.error)
    args.out.mkdir(parents=True, exist_ok=True)
    build = args.build.resolve()
    spheres = args.spheres or json.loads(CELL.read_text())["preparation"]["spheres"]
    summary = {"paths": str(args.paths), "surrogate": surrogate, "error_budget": args.error_budget, "draws": args.draws,
               "spheres": spheres,
               "end_s": args.end, "gate_s": args.gate, "threads": args.threads, "libraries_cpu_s": {}, "scenes": {}}
    for bond in bonds:
        libs = libraries(args, build, bond)
        summary["libraries_cpu_s"][f"{bond:g}"] = libs["cpu_s"]
        for aspect in aspects:
            name = f"aspect_{aspect:g}_bond_{bond:g}"
            costs = run_scene(name, column_settings(args.scene, aspect, args), libs, surrogate, build, args)
            summary["scenes"][name] = measure(name, costs, args)
    (args.out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    rows = [{"scene": name, "run": run, **{k: v for k, v in s["runs"][run].items()}}
            for name, s in summary["scenes"].items() for run in s["runs"]]
    tables.write_markdown(args.out / "table.md", rows)
    plot(summary, args.out / "generalization.png")
    print((args.out / "table.md").read_text(), end="")


if __name__ == "__main__":
    main()
