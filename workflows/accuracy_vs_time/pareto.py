"""The Pareto plot of the study: each error measure against CPU time, one panel per measure, the
reference and the noise floor marked, the non-dominated runs joined."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from plotting.figures import plt, DPI  # noqa: E402  (after the path set-up; Agg backend chosen there)
from matplotlib.ticker import NullFormatter  # noqa: E402
from variants import NOISE_FLOOR  # noqa: E402

MEASURES = [("front_rel_err", "front: worst relative runout error"), ("stress_rel_l2", "stress field: mean rel. L2"),
            ("deposit_rms_m", "deposit profile: RMS height error [m]"),
            ("mass_edge_rel_err", "bulk: 95 % mass edge, relative error")]


def pareto_front(points):
    """Indices of the points (cost, error) that no other point beats in both, by increasing cost."""
    front, best = [], float("inf")
    for i in sorted(range(len(points)), key=lambda i: points[i]):
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def plot(rows, out):
    fig, axes = plt.subplots(1, len(MEASURES), figsize=(4.5 * len(MEASURES), 4.2), layout="constrained", sharex=True)
    for ax, (key, label) in zip(axes, MEASURES):
        measured = [r for r in rows if r[key] is not None]  # None: the reference's bulk moved < 1 cm
        # A run that stopped early is drawn (x, "stopped") but is not a candidate of the front: its
        # errors cover only the time before it stopped.
        for r in (r for r in measured if r.get("failed")):
            ax.scatter(r["cpu_s"], r[key], marker="x", color="k")
            ax.annotate(r["run"] + " (stopped)", (r["cpu_s"], r[key]), fontsize=7, xytext=(3, 3),
                        textcoords="offset points")
        others = [r for r in measured if r["run"] != "live" and not r.get("failed")]
        for r in others:
            ax.scatter(r["cpu_s"], r[key], marker="s" if r["law"] == "live" else "o")
            ax.annotate(r["run"], (r["cpu_s"], r[key]), fontsize=7, xytext=(3, 3), textcoords="offset points")
        front = pareto_front([(r["cpu_s"], r[key]) for r in others])
        ax.plot([others[i]["cpu_s"] for i in front], [others[i][key] for i in front], "k--", lw=0.8, label="Pareto front")
        reference = next(r for r in rows if r["run"] == "live")
        ax.axvline(reference["cpu_s"], color="tab:red", lw=1, label="live reference (error 0)")
        noise = next((r for r in measured if r["run"] == NOISE_FLOOR), None)
        if noise:
            ax.axhline(noise[key], color="tab:gray", lw=1, ls=":", label="noise floor (other packing seed)")
        ax.set_xscale("log")
        ax.xaxis.set_minor_formatter(NullFormatter())  # labelled minor ticks overlap on a short range
        ax.set_xlabel("CPU time [s]")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("accuracy versus time against the live reference (squares: live variants, circles: library, "
                 "x: stopped early)",
                 fontsize=10)
    fig.savefig(out, dpi=DPI)
    plt.close(fig)
