"""Convergence in grid size (issue 18, "Convergence: mesh"): the demo column run live with its cell of
125 spheres (--spheres; packing seed 1) on grids of cell size h = factor × 0.05 m (same domain, one point
per grid cell, so four times the points at half the size). Three measures of how far the column has
gone: the runout (the front, its farthest point), the advance of its 95 % mass edge and of its
centroid. Their change between successive grids (relative to the coarser value; not reported below
1 cm) is set against the packing-seed spread of the same measure (--noise-floor: a cell-size study's
OUT, by default this OUT, whose runs at N = 125 with seeds 1, 2, … on the base grid give it), the
noise floor below which a difference means nothing. Run into the cell-size study's OUT, the two share the run at
h = 0.05 m, N = 125. With --nonlocal-length ℓ every run is regularized over ℓ (the scene's
regularization.nonlocal_length), the issue's remedy for a softening material's mesh dependence; the
noise floor is still that of the local runs of --noise-floor.

  /usr/bin/python3 mesh.py [OUT] [--build BUILD] [--grid-factors 2 1 0.5] [--times 0.1 0.2 0.3] [--end 0.3]
                           [--threads N] [--spheres 125] [--noise-floor CELL_SIZE_OUT] [--nonlocal-length ℓ]

Runs finished in OUT/runs/ are kept (an interrupted study resumes). Writes OUT/mesh.csv, OUT/mesh.md,
OUT/mesh.json and OUT/mesh.png (each measure against h).
  /usr/bin/python3 cell_size.py OUT && /usr/bin/python3 mesh.py OUT   # both studies, sharing a run
"""
import argparse
import json
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, scenes, tables  # noqa: E402
from plotting.figures import finish_and_save, plt  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402
from live_demo import MEASURES, MIN_RUNOUT, SCENE, measures_at, run, run_name, spread  # noqa: E402


def seed_spreads(floor_out, spheres, times):
    """{(measure, t): spread} over the finished runs floor_out/runs/n{spheres}_seed{S} (the cell-size
    study's runs on the base grid), each None with fewer than two seeds."""
    pattern = re.compile(rf"n{spheres}_seed\d+")
    folders = [f for f in sorted((Path(floor_out) / "runs").glob(f"n{spheres}_seed*"))
               if pattern.fullmatch(f.name) and (f / "study_run.json").exists()]
    per_run = [measures_at(f, times) for f in folders]
    return {(key, t): spread([m[t][key] for m in per_run]) for key in MEASURES for t in times}


def change_table(rows, sizes, times, key, label):
    """Markdown lines of measure `key` against h at each time, with its change from the next coarser grid
    (relative to the coarser value; none below MIN_RUNOUT), and those changes as dicts."""
    lines = ["| h [m] | " + " | ".join(f"{label} at {t:g} s [cm] | change from the coarser grid" for t in times)
             + " | CPU-s |", "|" + "---|" * (2 + 2 * len(times))]
    changes = []
    for k, h in enumerate(sizes):
        cells = []
        for t in times:
            value = next(x[key] for x in rows if x["h_m"] == h and x["t"] == t)
            coarser = next(x[key] for x in rows if x["h_m"] == sizes[k - 1] and x["t"] == t) if k else None
            change = (abs(value - coarser) / abs(coarser)
                      if value is not None and coarser is not None and abs(coarser) >= MIN_RUNOUT else None)
            changes.append({"h_m": h, "t": t, "change": change})
            cells.append(("–" if value is None else f"{100 * value:.1f}") + " | "
                         + ("–" if change is None else f"{100 * change:.0f} %"))
        cpu = next(x["cpu_s"] for x in rows if x["h_m"] == h)
        lines.append(f"| {h:g} | " + " | ".join(cells) + f" | {cpu:.0f} |")
    return lines, changes


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("mesh"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--grid-factors", type=float, nargs="+", default=[2, 1, 0.5])
    parser.add_argument("--times", type=float, nargs="+", default=[0.1, 0.2, 0.3])
    parser.add_argument("--end", type=float, default=0.3)
    parser.add_argument("--threads", type=int, default=environment.threads())
    parser.add_argument("--spheres", type=int, default=125, help="spheres per DEM cell")
    scenes.add_nonlocal_length_option(parser, "regularize every run over ℓ [m] (default: local)")
    parser.add_argument("--noise-floor", type=Path,
                        help="OUT of a cell_size.py study whose seed runs at --spheres give the spread (default: OUT)")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    build = args.build.resolve()
    base_h = json.loads(SCENE.read_text())["grid"]["cell_size"]

    rows = []
    for factor in args.grid_factors:
        _, cost = run(build, args.out, args.end, args.threads, args.spheres, 1, factor, args.nonlocal_length)
        folder = args.out / "runs" / run_name(args.spheres, 1, factor, args.nonlocal_length)
        for t, measures in measures_at(folder, args.times).items():
            rows.append({"h_m": base_h * factor, "t": t, **measures, "cpu_s": cost["cpu_s"],
                         "failed": cost["failed"]})
        print(f"h = {base_h * factor:g} m: {cost['cpu_s']:.0f} CPU-s" + (f", {cost['failed']}" if cost["failed"] else ""),
              flush=True)
    tables.write_csv(args.out / "mesh.csv", rows)

    sizes = [base_h * f for f in args.grid_factors]
    floors = seed_spreads(args.noise_floor or args.out, args.spheres, args.times)
    lines = ["Local cells (no regularization)." if args.nonlocal_length is None else
             f"Cells regularized over ℓ = {args.nonlocal_length:g} m (regularization.nonlocal_length).", ""]
    changes = []
    for key, label in MEASURES.items():
        table, measure_changes = change_table(rows, sizes, args.times, key, label)
        lines += table
        lines += [f"Seed spread at N = {args.spheres} on the base grid (the noise floor): " + ", ".join(
            f"t = {t:g} s: " + ("not measured" if floors[(key, t)] is None else f"{100 * floors[(key, t)]:.0f} %")
            for t in args.times), ""]
        changes += [{"measure": key, **c} for c in measure_changes]
    text = "\n".join(lines)
    (args.out / "mesh.md").write_text(text)
    (args.out / "mesh.json").write_text(json.dumps(
        {"nonlocal_length": args.nonlocal_length, "rows": rows, "changes": changes,
         "seed_spread": [{"measure": key, "t": t, "spread": f} for (key, t), f in floors.items()]}, indent=2))

    fig, axes = plt.subplots(1, len(MEASURES), figsize=(5 * len(MEASURES), 4))
    for ax, (key, label) in zip(axes, MEASURES.items()):
        for t in args.times:
            points = [(x["h_m"], 100 * x[key]) for x in rows if x["t"] == t and x[key] is not None]
            if points:
                ax.plot(*zip(*points), "o-", label=f"t = {t:g} s")
        ax.set_xscale("log")
        ax.set_xticks(sizes, labels=[f"{h:g}" for h in sizes])
        ax.xaxis.set_minor_formatter(NullFormatter())  # the grid sizes are the ticks
        ax.set_title(label, fontsize=9)
        ax.set_xlabel("grid cell size h [m]")
        ax.grid(alpha=0.3)
    finish_and_save(fig, axes[0], args.out / "mesh.png", "grid cell size h [m]", "advance [cm]")
    print(text, end="")


if __name__ == "__main__":
    main()
