#!/usr/bin/env python3
"""Accuracy and cost of the cache and hybrid laws against live DEM on the cohesive column collapse.

  cache_vs_live.py scenes BASE.json OUT   writes OUT/scenes/<run>.json, variants of BASE (library OUT/lib)
  cache_vs_live.py compare OUT            prints the table of wall times, hit rates and errors against
                                          the reference run, and plots OUT/front.png when matplotlib is there

Runs (see run_comparison.sh): reference = hybrid on the empty library (every point live from its first
step: the live law to round-off, tests/mpm/hybrid_law_test.cpp) whose live responses enrich the library;
live_probe = the live law itself for the first steps (its cost per step); then hybrid, cache and
hybrid_skip (hybrid skipping negligible increments), hybrid_fine and cache_fine (finer key scales) on
the enriched library.
"""
import copy
import json
import math
import re
import struct
import sys
from pathlib import Path

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
}
COMPARED = ["reference", "hybrid", "cache", "hybrid_skip", "hybrid_fine", "cache_fine"]


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


def read_series(run):
    lines = (run / "series.csv").read_text().splitlines()
    header = lines[0].split(",")
    return [dict(zip(header, map(float, line.split(",")))) for line in lines[1:]]


def read_vtu(file):
    """id -> in-plane stress (xx, yy, xy) of a VTU written by mpm_solver (raw appended arrays)."""
    data = file.read_bytes()
    head, _, block = data.partition(b'<AppendedData encoding="raw">\n_')
    arrays = {}
    for m in re.finditer(rb'<DataArray type="(\w+)" Name="(\w+)" NumberOfComponents="(\d+)" format="appended" offset="(\d+)"', head):
        kind, name, offset = m.group(1).decode(), m.group(2).decode(), int(m.group(4))
        size = struct.unpack_from("<Q", block, offset)[0]
        fmt = {"Float64": "d", "Int64": "q", "Int32": "i", "UInt8": "B"}[kind]
        arrays[name] = struct.unpack_from(f"<{size // struct.calcsize(fmt)}{fmt}", block, offset + 8)
    stress = arrays["stress"]
    return {pid: (stress[9 * k], stress[9 * k + 4], stress[9 * k + 1]) for k, pid in enumerate(arrays["id"])}


def stress_error(ref, run):
    num = sum((a - b) ** 2 for pid, s in ref.items() for a, b in zip(s, run[pid]))
    den = sum(a ** 2 for s in ref.values() for a in s)
    return math.sqrt(num / den) if den > 0 else float("nan")


def compare(out):
    ref_series = read_series(out / "reference")
    ref_front = {round(r["t"], 9): r["front"] for r in ref_series}
    x0 = ref_series[0]["front"]
    probe = json.loads((out / "live_probe" / "summary.json").read_text())
    live_step = probe["wall_time"]["steps"] / max(probe["steps"], 1)
    rows = []
    for name in COMPARED:
        run = out / name
        summary = json.loads((run / "summary.json").read_text())
        series = read_series(run)
        last = series[-1]
        # Runout = front − initial front; its relative error against the reference, worst over time
        # once the runout exceeds 1 cm (before that the ratio is noise over a tiny number).
        worst = 0.0
        for r in series:
            t = round(r["t"], 9)
            if t in ref_front and ref_front[t] - x0 > 0.01:
                worst = max(worst, abs((r["front"] - x0) - (ref_front[t] - x0)) / (ref_front[t] - x0))
        errors = []
        for vtu in sorted(run.glob("points_*.vtu"))[1:]:
            errors.append(stress_error(read_vtu(out / "reference" / vtu.name), read_vtu(vtu)))
        lookups = sum(r["hits"] + r["misses"] for r in series[1:])  # row 0: the initial state
        rows.append({
            "run": name,
            "wall_s": summary["wall_time"]["total"],
            "steps": summary["steps"],
            "s_per_step": summary["wall_time"]["steps"] / summary["steps"],
            "hit_rate_mean": sum(r["hits"] for r in series[1:]) / lookups if lookups else 0.0,
            "live_cells_end": last["live_cells"],
            "went_live": last["went_live"],
            "skipped_point_steps": last["skipped_point_steps"],
            "runout_m": last["front"] - x0,
            "runout_rel_err_max": worst,
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
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6, 4))
    for name in COMPARED:
        s = read_series(out / name)
        ax.plot([r["t"] for r in s], [r["front"] - x0 for r in s], label=name)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("runout [m]")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "front.png", dpi=120)


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "scenes":
        make_scenes(sys.argv[2], Path(sys.argv[3]))
    elif len(sys.argv) == 3 and sys.argv[1] == "compare":
        compare(Path(sys.argv[2]))
    else:
        sys.exit(__doc__)
