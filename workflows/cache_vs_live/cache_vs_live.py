#!/usr/bin/env python3
"""Accuracy and cost of the cache and hybrid laws against live DEM on the cohesive column collapse.

  cache_vs_live.py scenes BASE.json OUT   writes OUT/scenes/<run>.json, variants of BASE (library OUT/lib)
  cache_vs_live.py compare OUT            prints the table of wall times, hit rates and errors against
                                          the reference run, and plots OUT/front.png (python3-matplotlib)

Runs (see run_comparison.sh): reference = hybrid on the empty library (every point live from its first
step: the live law to round-off, tests/mpm/hybrid_law_test.cpp) whose live responses enrich the library;
live_probe = the live law itself for the first steps (its cost per step); then hybrid, cache and
hybrid_skip (hybrid skipping negligible increments), hybrid_fine and cache_fine (finer key scales) on
the enriched library.
"""
import copy
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from plotting import flow, tables, vtu  # noqa: E402  (after the path set-up)

RUNS = {
    "reference": {"law": "hybrid", "enrich": True},
    "live_probe": {"law": "live", "end": 0.005},
    "hybrid": {"law": "hybrid", "enrich": False},
    "cache": {"law": "cache"},
    "hybrid_skip": {"law": "hybrid", "enrich": False, "skip": 1e-6},
    # Key scales fine enough for the small strains of a creeping column (the library default, 1e-2
    # strain per key unit, calls them all one state), live points back to the cache after 10 steps.
    "hybrid_fine": {"law": "hybrid", "enrich": False, "tolerance": 1.0, "return_after": 10,
                    "scales": {"strain": 1e-4, "rate": 1.0, "damage": 0.01}},
    "cache_fine": {"law": "cache", "tolerance": 1.0, "scales": {"strain": 1e-4, "rate": 1.0, "damage": 0.01}},
    # Fine scales with a wide tolerance: a point goes live only when its state leaves the library's
    # (the gate release), and returns after 5 steps back inside.
    "hybrid_wide": {"law": "hybrid", "enrich": False, "tolerance": 10.0, "return_after": 5,
                    "scales": {"strain": 1e-4, "rate": 1.0, "damage": 0.01}},
}
COMPARED = ["reference", "hybrid", "cache", "hybrid_skip", "hybrid_fine", "cache_fine", "hybrid_wide"]


def make_scenes(base_file, out):
    base = json.loads(Path(base_file).read_text())
    (out / "scenes").mkdir(parents=True, exist_ok=True)
    for name, spec in RUNS.items():
        scene = copy.deepcopy(base)
        material = scene["materials"][0]
        material["law"] = spec["law"]
        material["library"] = "../lib"
        if spec["law"] != "live":
            material["lookup"] = {"k": 4, "tolerance": spec.get("tolerance", 0.5)}
            if "scales" in spec:
                material["lookup"]["scales"] = spec["scales"]
        if "return_after" in spec:
            material["fallback"] = {"return_after": spec["return_after"]}
        if spec["law"] == "hybrid":
            material["enrich"] = spec["enrich"]
        if "end" in spec:
            scene["time"]["end"] = spec["end"]
            scene["time"]["output_interval"] = spec["end"]
        if "skip" in spec:
            scene.setdefault("integration", {})["skip_strain_increment"] = spec["skip"]
        (out / "scenes" / f"{name}.json").write_text(json.dumps(scene, indent=2) + "\n")


def compare(out):
    reference = tables.read_csv(out / "reference" / "series.csv")
    probe = json.loads((out / "live_probe" / "summary.json").read_text())
    live_step = probe["wall_time"]["steps"] / max(probe["steps"], 1)
    rows = []
    for name in COMPARED:
        run = out / name
        summary = json.loads((run / "summary.json").read_text())
        series = tables.read_csv(run / "series.csv")
        errors = [flow.stress_error(vtu.read_vtu(file), vtu.read_vtu(out / "reference" / file.name))
                  for file in sorted(run.glob("points_*.vtu"))[1:]]
        hits, lookups = series["hits"][1:].sum(), (series["hits"][1:] + series["misses"][1:]).sum()  # row 0: t = 0
        rows.append({
            "run": name,
            "wall_s": summary["wall_time"]["total"],
            "steps": summary["steps"],
            "s_per_step": summary["wall_time"]["steps"] / summary["steps"],
            "hit_rate_mean": float(hits / lookups) if lookups else 0.0,
            "live_cells_end": series["live_cells"][-1],
            "went_live": series["went_live"][-1],
            "skipped_point_steps": series["skipped_point_steps"][-1],
            "runout_m": flow.runout(series)[-1],
            "runout_rel_err_max": flow.front_error(series, reference),
            "stress_rel_l2_mean": sum(errors) / len(errors) if errors else 0.0,
            "stress_rel_l2_max": max(errors) if errors else 0.0,
        })
    ref_step = rows[0]["s_per_step"]
    print(f"live law (probe run, {probe['steps']} steps): {live_step:.4g} s per MPM step; "
          f"reference (hybrid on the empty library, enriching): {ref_step:.4g} s per step")
    print(f"{'run':12} {'wall[s]':>9} {'s/step':>9} {'speed-up':>9} {'hit rate':>9} {'live@end':>8} "
          f"{'went live':>9} {'skipped':>8} {'runout[m]':>9} {'front err':>9} {'σ L2 mean':>9} {'σ L2 max':>9}")
    for r in rows:
        print(f"{r['run']:12} {r['wall_s']:9.1f} {r['s_per_step']:9.3g} {live_step / r['s_per_step']:9.1f} "
              f"{r['hit_rate_mean']:9.3f} {r['live_cells_end']:8.0f} {r['went_live']:9.0f} {r['skipped_point_steps']:8.0f} "
              f"{r['runout_m']:9.4f} {r['runout_rel_err_max']:9.3%} {r['stress_rel_l2_mean']:9.3%} {r['stress_rel_l2_max']:9.3%}")
    (out / "comparison.json").write_text(json.dumps({"live_seconds_per_step": live_step, "runs": rows}, indent=2) + "\n")
    from plotting import figures  # matplotlib only for the figure
    figures.time_plot(out / "front.png", [(s["t"], flow.runout(s), name, None) for name, s in
                                          ((n, tables.read_csv(out / n / "series.csv")) for n in COMPARED)],
                      "t [s]", "runout [m]")


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "scenes":
        make_scenes(sys.argv[2], Path(sys.argv[3]))
    elif len(sys.argv) == 3 and sys.argv[1] == "compare":
        compare(Path(sys.argv[2]))
    else:
        sys.exit(__doc__)
