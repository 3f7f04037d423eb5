#!/usr/bin/python3
"""Figures and the text report of the demo (run_demo.sh): report.py OUT [--timestamps START LIB RUN AUDIT].

Reads OUT/run (the mpm_solver output and its audit, run/audit/run_audit.json), OUT/library.json (celldb
info --json) and writes OUT/figures/*.png, OUT/report.txt and OUT/report.json.
"""
import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from plotting import collapse_figures, tables  # noqa: E402  (after the path set-up)

EPS_Q_NOTE = ("ε̇_q is the VTU field strain_rate_q written by mpm_solver, seed Eq. 5: "
              "sqrt((L_xx − L_yy)² + (L_xy + L_yx)²) of the point's velocity gradient L. For an isochoric "
              "in-plane flow it equals √3 · sqrt(2/3 e:e) of the deviatoric strain rate e.")


def summarise(out, timestamps):
    run = out / "run"
    summary = json.loads((run / "summary.json").read_text())
    library = json.loads((out / "library.json").read_text())
    series = tables.read_csv(run / "series.csv")
    rows = slice(1, None)  # row 0: the initial state, before any lookup
    lookups = series["hits"][rows].sum() + series["misses"][rows].sum()
    point_rows = lookups + series["live_cells"][rows].sum()
    laws = summary.get("coupling", {}).get("laws", [])
    report = {
        "law": laws[0]["law"] if laws else "live",
        "points": summary["points"],
        "steps": summary["steps"],
        "final_time_s": summary["final_time"],
        "threads": summary["threads"],
        "wall_time_s": {"run": summary["wall_time"]["total"], "steps": summary["wall_time"]["steps"]},
        "library": {"templates": library["counts"]["templates"], "paths": library["counts"]["paths"],
                    "records": library["committed_records"]},
        "hit_rate_of_lookups": float(series["hits"][rows].sum() / lookups) if lookups else 0.0,
        "fraction_answered_by_hits": float(series["hits"][rows].sum() / point_rows) if point_rows else 0.0,
        "went_live": int(series["went_live"][-1]),
        # Surrogate points whose spent error budget re-anchored them on a servoed cell (no live step).
        "reanchored": int(sum(law.get("reanchored", 0) for law in laws)),
        "live_cells_at_end": int(series["live_cells"][-1]),
        "runout_m": float(series["front"][-1] - series["front"][0]),
        "front_m": {"initial": float(series["front"][0]), "final": float(series["front"][-1])},
        "height_m": {"initial": float(series["max_height"][0]), "final": float(series["max_height"][-1])},
        "max_velocity_m_s": float(series["max_velocity"].max()),
    }
    audit = run / "audit" / "run_audit.json"
    if audit.exists():
        a = json.loads(audit.read_text())
        report["audit"] = {"points": len(a["points"]), "steps_compared": a["steps_compared"],
                           "cached": a["cached"], "live": a["by_source"]["live"]}
        if "noise_floor" in a:
            report["audit"]["noise_floor"] = {"cached": a["noise_floor"]["cached"],
                                              "live": a["noise_floor"]["by_source"]["live"]}
    if timestamps:
        start, library_done, run_done, audit_done = timestamps
        report["wall_time_s"].update({"library": library_done - start, "run_total": run_done - library_done,
                                      "audit": audit_done - run_done, "figures": time.time() - audit_done})
    return report


def audit_lines(audit):
    if not audit:
        return []
    c, live = audit["cached"], audit["live"]
    lines = [f"  audit (mpm_solver audit run): {audit['points']} points re-run by live cells; relative stress error "
             f"of the {c['count']} cached point-steps: median {c['median']:.3g}, p95 {c['p95']:.3g}, max {c['max']:.3g}; "
             f"of the {live['count']} live point-steps (warm-started cells): median {live['median']:.3g}"]
    if "noise_floor" in audit:
        fc, fl = audit["noise_floor"]["cached"], audit["noise_floor"]["live"]
        lines.append(f"  noise floor (the same histories re-run by a cell of another packing seed): median "
                     f"{fc['median']:.3g}, p95 {fc['p95']:.3g} on the cached point-steps; median {fl['median']:.3g} "
                     "on the live ones")
    return lines


def text(report, figures):
    w = report["wall_time_s"]
    lib = report["library"]
    lines = [
        f"grainbank demo: cohesive column collapse, law {report['law']} (cell library; live DEM cells where "
        "it is not trusted)",
        f"  material points {report['points']}, {report['steps']} MPM steps to t = {report['final_time_s']:.3g} s "
        f"on {report['threads']} thread(s)",
        f"  library: {lib['templates']} template(s), {lib['paths']} paths, {lib['records']} records",
        f"  hit rate among lookups {report['hit_rate_of_lookups']:.3f}; point-steps answered by a hit "
        f"{report['fraction_answered_by_hits']:.3f}; points that went live {report['went_live']}, "
        f"re-anchored {report['reanchored']}, live at the end {report['live_cells_at_end']}",
        f"  front {report['front_m']['initial']:.3f} -> {report['front_m']['final']:.3f} m "
        f"(runout {report['runout_m']:.3f} m), height {report['height_m']['initial']:.3f} -> "
        f"{report['height_m']['final']:.3f} m, largest speed {report['max_velocity_m_s']:.3g} m/s",
        *audit_lines(report.get("audit")),
        "  wall time [s]: " + ", ".join(f"{k} {v:.1f}" for k, v in w.items()),
        "  " + EPS_Q_NOTE,
        "  figures: " + ", ".join(f"figures/{f}" for f in figures),
        "  ParaView: open run/points.pvd",
    ]
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path)
    parser.add_argument("--timestamps", type=float, nargs=4, metavar=("START", "LIBRARY", "RUN", "AUDIT"))
    args = parser.parse_args()
    figures = collapse_figures.all_figures(args.out / "run", args.out / "figures")
    figures += sorted(p.name for p in (args.out / "figures").glob("run_audit_*.png"))
    report = summarise(args.out, args.timestamps)
    report["figures"] = figures
    (args.out / "report.json").write_text(json.dumps(report, indent=2) + "\n")
    (args.out / "report.txt").write_text(text(report, figures))
    print(text(report, figures), end="")


if __name__ == "__main__":
    main()
