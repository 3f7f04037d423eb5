#!/usr/bin/python3
"""Run time of the full column collapse per law, EXTRAPOLATED from a short probe run of a few steps:
estimate_time.py [OUT] [--laws live,hybrid,cache] [--probe-time T] [--threads N] [--build DIR]

Each probe runs column.json to t = T (default 1e-3 s, ~6 MPM steps) and the estimate is
setup + (seconds per step) × (scene end time / mean probe step). The probe covers the first steps of
the settling phase only: later the flow shortens the step (seed Eq. 4) and, for hybrid, more points
miss and turn live, so hybrid's figure is a lower bound and live's is its upper bound. The hybrid and
cache probes use a two-path library (paths_probe.json): they time the lookups, not a useful library.
Writes OUT/estimate.json and OUT/estimate.md (OUT default: $GRAINBANK_OUT/column_estimate, i.e.
build/out/column_estimate).
"""
import argparse
import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, scenes, tables  # noqa: E402  (after the path set-up)
from plotting.timing import timed  # noqa: E402


def run_probe(build, scene_file, out, threads):
    _, cpu = timed([build / "mpm_solver" / "mpm_solver", scene_file, "--out", out, "--threads", threads])
    return json.loads((out / "summary.json").read_text()), cpu


def estimate(law, summary, cpu, end_time, threads):
    steps = summary["steps"]
    wall = summary["wall_time"]
    per_step = wall["steps"] / steps
    full_steps = end_time / (summary["final_time"] / steps)
    # CPU of the stepping part: the run's CPU in the proportion of its stepping wall time.
    cpu_per_step = cpu * wall["steps"] / wall["total"] / steps
    return {"law": law, "points": summary["points"], "probe_steps": steps, "probe_dt_s": summary["final_time"] / steps,
            "setup_s": wall["setup"], "wall_s_per_step": per_step, "cpu_s_per_step": cpu_per_step,
            "extrapolated_steps": round(full_steps), "threads": threads,
            "extrapolated_wall_h": (wall["setup"] + per_step * full_steps) / 3600,
            "extrapolated_cpu_h_per_core": cpu_per_step * full_steps / 3600 / threads}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("column_estimate"))
    parser.add_argument("--laws", default="live,hybrid,cache")
    parser.add_argument("--probe-time", type=float, default=1e-3)
    parser.add_argument("--threads", type=int, default=environment.threads())
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    args = parser.parse_args()
    build = args.build.resolve()
    args.out.mkdir(parents=True, exist_ok=True)
    end_time = json.loads((HERE / "column.json").read_text())["time"]["end"]
    rows = []
    for law in args.laws.split(","):
        library = None
        if law != "live":
            library = args.out / "lib"
            dem_sampler = build / "dem_sampler" / "dem_sampler"
            timed([dem_sampler, "prepare", HERE / "cell_snow_370um.json", "--library", library])
            timed([dem_sampler, "sample", HERE / "paths_probe.json", "--library", library, "--threads", args.threads])
        material = json.loads((HERE / "hybrid.json").read_text()) if law == "hybrid" else None
        settings = {"/time/end": args.probe_time, "/time/output_interval": args.probe_time}
        scene_file = args.out / f"probe_{law}.json"
        scenes.variant(build, HERE / "column.json", scene_file, law, library, material, settings)
        summary, cpu = run_probe(build, scene_file, args.out / f"probe_{law}", args.threads)
        rows.append(estimate(law, summary, cpu, end_time, args.threads))
        print(f"{law}: {rows[-1]['wall_s_per_step']:.3g} s per step -> extrapolated {rows[-1]['extrapolated_wall_h']:.3g} h "
              f"for t = {end_time} s ({rows[-1]['extrapolated_steps']} steps, {args.threads} thread(s))")
    (args.out / "estimate.json").write_text(json.dumps({"end_time_s": end_time, "probe_time_s": args.probe_time,
                                                        "extrapolation": True, "laws": rows}, indent=2) + "\n")
    tables.write_markdown(args.out / "estimate.md", rows)


if __name__ == "__main__":
    main()
