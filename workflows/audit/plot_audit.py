"""Figures of a `celldb audit` run: reads DIR/audit.json and DIR/audit_records.csv, writes
DIR/audit_histogram.png (relative stress errors of the determinism replays, the in-index and the
leave-one-path-out answers) and DIR/audit_error_vs_distance.png (leave-one-out error against the
nearest-record distance, the binned median and p95, the target and the suggested tolerance).

Usage: /usr/bin/python3 workflows/audit/plot_audit.py DIR   (python3-matplotlib on Debian)
"""
import csv
import json
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from plotting.figures import plt, DPI, log_histogram  # noqa: E402  (after the path set-up; Agg backend chosen there)

CHECKS = [("replay", "determinism (replayed)"), ("in_index", "in-index"), ("leave_one_out", "leave-one-path-out")]


def read_records(path):
    """Rows of audit_records.csv by check: lists of (distance or None, relative error)."""
    rows = {check: [] for check, _ in CHECKS}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            distance = float(row["distance"]) if row["distance"] else None
            rows[row["check"]].append((distance, float(row["relative_error"])))
    return rows


def histogram(rows, summary, out):
    flagged = summary["determinism"]["flagged"]
    log_histogram(out, [([e for _, e in rows[check]], label, None) for check, label in CHECKS],
                  "relative stress error |σ − σ_true| / max(|σ_true|, floor)", "records",
                  f"celldb audit: {summary['determinism']['checked']} replayed ({flagged} flagged), "
                  f"{summary['leave_one_out']['count']} leave-one-out answers")


def error_vs_distance(rows, summary, out):
    points = [(d, e) for d, e in rows["leave_one_out"] if d is not None and math.isfinite(d)]
    curve = summary["error_vs_distance"]
    fig, ax = plt.subplots(figsize=(7, 4.2), layout="constrained")
    if points:
        ax.scatter([d for d, _ in points], [e for _, e in points], s=8, alpha=0.4, color="tab:gray", label="answers")
    centres = [(b["distance_min"] + b["distance_max"]) / 2 for b in curve["bins"]]
    ax.plot(centres, [b["median"] for b in curve["bins"]], "o-", color="tab:blue", label="median per bin")
    ax.plot(centres, [b["p95"] for b in curve["bins"]], "s--", color="tab:red", label="p95 per bin")
    ax.axhline(curve["target"], color="k", lw=0.8, ls=":", label=f"target {curve['target']:g}")
    if curve["at_suggested"] is not None:
        s = curve["at_suggested"]
        ax.axvline(s["tolerance"], color="tab:green", lw=1.2,
                   label=f"suggested tolerance {s['tolerance']:.3g} ({100 * s['hit_share']:.0f} % hit)")
    t = curve["at_tolerance"]
    ax.axvline(t["tolerance"], color="tab:purple", lw=1, ls="--",
               label=f"tolerance {t['tolerance']:g}: {100 * t['hit_share']:.0f} % hit, p95 {t['hits']['p95']:.2g}")
    if all(e > 0 for _, e in points) and points:
        ax.set_yscale("log")  # errors span decades between near and far states
    ax.set_xlabel("distance to the nearest other path's record [key units]")
    ax.set_ylabel("leave-one-out relative stress error")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(out, dpi=DPI)
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    directory = Path(sys.argv[1])
    try:
        summary = json.loads((directory / "audit.json").read_text())
        rows = read_records(directory / "audit_records.csv")
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"plot_audit.py: {directory}: not a celldb audit directory: {e}")
    outputs = [directory / "audit_histogram.png", directory / "audit_error_vs_distance.png"]
    histogram(rows, summary, outputs[0])
    error_vs_distance(rows, summary, outputs[1])
    print("wrote " + ", ".join(str(p) for p in outputs), file=sys.stderr)


if __name__ == "__main__":
    main()
