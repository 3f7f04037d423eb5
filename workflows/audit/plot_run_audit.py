"""Figures of an `mpm_solver audit RUN`: reads RUN/audit/run_audit.json and run_audit_steps.csv, writes
(into RUN/audit, or FIGURES when given) run_audit_error_vs_time.png (the relative stress error of every audited point over time, marked by what
answered the run: library hit, miss, live cell) and run_audit_histogram.png (the errors per source). An
audit run with --floor-cell adds its noise floor: the median error of the other packing's cell over
time, its histogram, and run_audit_by_time.csv (in 6 equal time windows: the cached point-steps'
median error and the floor's median on the same steps).

Usage: /usr/bin/python3 workflows/audit/plot_run_audit.py RUN/audit [FIGURES]   (python3-matplotlib on Debian)
"""
import csv
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from plotting.figures import plt, DPI, log_histogram  # noqa: E402  (after the path set-up; Agg backend chosen there)

SOURCES = [("hit", "library hit", "tab:blue"), ("miss", "library miss", "tab:red"),
           ("live", "live cell (hybrid)", "tab:green")]


def read_steps(path):
    """point id → list of (time, source, relative error); and the noise floor's (time, source, error), if any."""
    points, noise = {}, []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            points.setdefault(int(row["point"]), []).append(
                (float(row["time"]), row["source"], float(row["relative_error"])))
            if row.get("noise_floor_relative_error"):
                noise.append((float(row["time"]), row["source"], float(row["noise_floor_relative_error"])))
    return points, noise


def median(values):
    return sorted(values)[len(values) // 2]


def binned(samples, t0, t1, bins):
    """The errors of (time, error) `samples` in `bins` equal windows of [t0, t1]: window → errors, and
    the window width."""
    width = (t1 - t0) / bins or 1.0
    windows = {}
    for t, e in samples:
        windows.setdefault(min(int((t - t0) / width), bins - 1), []).append(e)
    return windows, width


def by_time(points, noise, out, windows=6):
    """The cached point-steps' median error and the floor's on the same steps, per time window."""
    cached = [(t, e) for steps in points.values() for t, s, e in steps if s in ("hit", "miss")]
    floor = [(t, e) for t, s, e in noise if s in ("hit", "miss")]
    if not cached:
        return
    t0 = min(t for steps in points.values() for t, _, _ in steps)
    t1 = max(t for steps in points.values() for t, _, _ in steps)
    run, width = binned(cached, t0, t1, windows)
    ref, _ = binned(floor, t0, t1, windows)  # the same steps: every window of `run` is in `ref`
    with open(out, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["t_start", "t_end", "cached_steps", "cached_median", "floor_median", "cached_over_floor"])
        for k in sorted(run):
            run_median, floor_median = median(run[k]), median(ref[k])
            writer.writerow([f"{t0 + k * width:.4g}", f"{t0 + (k + 1) * width:.4g}", len(run[k]), f"{run_median:.3g}",
                             f"{floor_median:.3g}", f"{run_median / floor_median:.3g}" if floor_median > 0 else ""])


def median_over_time(samples, bins=30):
    """(bin centre, median error) of `samples` in equal time bins."""
    t0, t1 = min(t for t, _ in samples), max(t for t, _ in samples)
    windows, width = binned(samples, t0, t1, bins)
    return [(t0 + (k + 0.5) * width, median(v)) for k, v in sorted(windows.items())]


def floor_of(points):
    """Where exact answers (error 0) are drawn on the log axes."""
    errors = [e for steps in points.values() for _, _, e in steps if e > 0]
    return min(errors) / 10 if errors else 1e-16


def error_vs_time(points, noise, summary, out):
    floor = floor_of(points)
    fig, ax = plt.subplots(figsize=(7, 4.2), layout="constrained")
    for steps in points.values():
        ax.plot([t for t, _, _ in steps], [max(e, floor) for _, _, e in steps], color="0.75", lw=0.6, zorder=1)
    for source, label, colour in SOURCES:
        xy = [(t, max(e, floor)) for steps in points.values() for t, s, e in steps if s == source]
        if xy:
            ax.scatter(*zip(*xy), s=4, color=colour, label=f"{label}: {len(xy)} point-steps", zorder=2)
    if noise:
        line = median_over_time([(t, e) for t, _, e in noise])
        ax.plot([t for t, _ in line], [max(e, floor) for _, e in line], color="black", lw=1.5, zorder=3,
                label="noise floor (cell of another packing seed), median")
    ax.set_yscale("log")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("relative stress error vs live cell")
    cached = summary["cached"]
    ax.set_title(f"mpm_solver audit: {len(points)} points; cached point-steps: median {cached['median']:.2g}, "
                 f"p95 {cached['p95']:.2g}", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(out, dpi=DPI)
    plt.close(fig)


def histogram(points, noise, out):
    series = [([e for steps in points.values() for _, s, e in steps if s == source], label, colour)
              for source, label, colour in SOURCES]
    if noise:
        series.append(([e for _, _, e in noise], "noise floor (another packing)", "black"))
    log_histogram(out, series, "relative stress error |σ_run − σ_live| / max(|σ_live|, floor)", "point-steps")


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    directory = Path(sys.argv[1])
    figures = Path(sys.argv[2]) if len(sys.argv) == 3 else directory
    figures.mkdir(parents=True, exist_ok=True)
    try:
        summary = json.loads((directory / "run_audit.json").read_text())
        points, noise = read_steps(directory / "run_audit_steps.csv")
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"plot_run_audit.py: {directory}: not an mpm_solver audit directory: {e}")
    outputs = [figures / "run_audit_error_vs_time.png", figures / "run_audit_histogram.png"]
    error_vs_time(points, noise, summary, outputs[0])
    histogram(points, noise, outputs[1])
    if noise:
        outputs.append(figures / "run_audit_by_time.csv")
        by_time(points, noise, outputs[-1])
    print("wrote " + ", ".join(str(p) for p in outputs), file=sys.stderr)


if __name__ == "__main__":
    main()
