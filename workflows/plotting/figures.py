"""PNG figures of mpm_solver runs (matplotlib, Agg backend: no display needed)."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.colors as colors  # noqa: E402  (the backend must be chosen first)
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

DPI = 110


def snapshot_grid(snapshots, rows, out, title=None):
    """One panel per snapshot (columns) and per field (rows), each point a square of its spacing.

    rows: list of (label, values(snapshot) → array, colormap, norm or None, tick labels or None); a row
    without a norm gets a linear one over its range across all its panels, so colours compare across
    times; tick labels name the integer values of a categorical field.
    """
    spacing = snapshots[0].spacing() or 0.01
    xy = np.vstack([s.xy for s in snapshots])
    lo, hi = xy.min(axis=0) - spacing, xy.max(axis=0) + spacing
    panel = 2.2  # panel width [inches]
    panel_height = panel * (hi[1] - lo[1]) / (hi[0] - lo[0])
    fig, axes = plt.subplots(len(rows), len(snapshots), squeeze=False, sharex=True, sharey=True, layout="constrained",
                             figsize=(panel * len(snapshots) + 1.6, len(rows) * (panel_height + 0.5) + 0.5))
    marker_area = (spacing * panel * 72 / (hi[0] - lo[0])) ** 2  # points² of a square of side `spacing`
    for r, (label, values, cmap, norm, ticks) in enumerate(rows):
        data = [values(s) for s in snapshots]
        if norm is None:
            top = max(float(np.max(v)) for v in data)
            norm = colors.Normalize(min(float(np.min(v)) for v in data), top if top > 0 else 1.0)
        for c, (s, v) in enumerate(zip(snapshots, data)):
            ax = axes[r][c]
            mappable = ax.scatter(s.xy[:, 0], s.xy[:, 1], c=v, cmap=cmap, norm=norm, marker="s", linewidths=0,
                                  s=marker_area)
            ax.set_xlim(lo[0], hi[0])
            ax.set_ylim(lo[1], hi[1])
            ax.set_aspect("equal")
            if r == 0:
                ax.set_title(f"t = {s.time:.3g} s", fontsize=9)
            if c == 0:
                ax.set_ylabel("y [m]")
            if r == len(rows) - 1:
                ax.set_xlabel("x [m]")
        bar = fig.colorbar(mappable, ax=list(axes[r]), label=label, shrink=0.9)
        if ticks:
            bar.set_ticks(range(len(ticks)), labels=ticks)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.savefig(out, dpi=DPI)
    plt.close(fig)


def log_norm(snapshots, values, floor_fraction=1e-3):
    """Logarithmic colour scale from `floor_fraction` of the largest value to it (strain rates span
    decades; zeros are drawn at the floor)."""
    top = max(float(np.max(values(s))) for s in snapshots)
    top = top if top > 0 else 1.0
    return colors.LogNorm(top * floor_fraction, top, clip=True)


def finish_and_save(fig, axes, out, xlabel, ylabel):
    """The finish of a study's one-panel plot: axis labels, a small legend and a light grid on `axes`,
    then `fig` written to `out` and closed."""
    axes.set_xlabel(xlabel)
    axes.set_ylabel(ylabel)
    axes.legend(fontsize=7)
    axes.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=DPI)
    plt.close(fig)


def time_plot(out, curves, xlabel, ylabel, title=None, log_y=False):
    """curves: list of (x array, y array, label, style dict or None)."""
    fig, ax = plt.subplots(figsize=(6, 3.8))
    for x, y, label, style in curves:
        ax.plot(x, y, label=label, **(style or {}))
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if log_y:
        ax.set_yscale("log")
    if title:
        ax.set_title(title, fontsize=10)
    if any(label for _, _, label, _ in curves):
        ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=DPI)
    plt.close(fig)



def log_histogram(out, groups, xlabel, ylabel, title=None):
    """Overlaid histograms of positive errors on a log axis. groups: list of (values, label, colour or
    None); the label gets the count and how many values are exactly 0, which are drawn at the floor
    (a tenth of the smallest positive value)."""
    positive = [v for values, _, _ in groups for v in values if v > 0]
    floor = min(positive) / 10 if positive else 1e-16
    top = max(positive) * 10 if positive else 1.0
    bins = [floor * (top / floor) ** (i / 40) for i in range(41)]
    fig, ax = plt.subplots(figsize=(7, 4.2), layout="constrained")
    for values, label, colour in groups:
        if values:
            exact = sum(1 for v in values if v == 0)
            ax.hist([max(v, floor) for v in values], bins=bins, alpha=0.6, color=colour,
                    label=f"{label}: {len(values)} ({exact} exact)")
    ax.set_xscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(out, dpi=DPI)
    plt.close(fig)
