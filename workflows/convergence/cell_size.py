"""Convergence in cell size, against the packing-seed spread (issue 18, "Convergence: cell size,
packing seed"): the demo column run live with DEM cells of N spheres, for each N with several packing
seeds. The runout of a run is its front's advance; at each N the seed spread is
(max − min) / mean of the runouts of the seeds. The representative cell is the smallest N whose seed
spread at the last time is below --target (5 %).

  /usr/bin/python3 cell_size.py [OUT] [--build BUILD] [--spheres 64 125 250] [--seeds 1 2]
                                [--times 0.1 0.2 0.3] [--end 0.3] [--threads N] [--target 0.05]

Runs finished in OUT/runs/ are kept (an interrupted study resumes). Writes OUT/cell_size.csv (one row
per run and time), OUT/cell_size.md and OUT/cell_size.png (runout against N, one marker per seed).
"""
import argparse
import json
import statistics
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, tables  # noqa: E402
from plotting.figures import finish_and_save, plt  # noqa: E402
from live_demo import run, runout_at, spread  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("cell_size"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--spheres", type=int, nargs="+", default=[64, 125, 250])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--times", type=float, nargs="+", default=[0.1, 0.2, 0.3])
    parser.add_argument("--end", type=float, default=0.3)
    parser.add_argument("--threads", type=int, default=environment.threads())
    parser.add_argument("--target", type=float, default=0.05, help="seed spread of a representative cell")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    build = args.build.resolve()

    rows = []
    for spheres in args.spheres:
        for seed in args.seeds:
            series, cost = run(build, args.out, args.end, args.threads, spheres, seed)
            for t in args.times:
                rows.append({"spheres": spheres, "seed": seed, "t": t, "runout_m": runout_at(series, t),
                             "cpu_s": cost["cpu_s"], "failed": cost["failed"]})
            print(f"N = {spheres}, seed {seed}: {cost['cpu_s']:.0f} CPU-s" + (f", {cost['failed']}" if cost["failed"] else ""),
                  flush=True)
    tables.write_csv(args.out / "cell_size.csv", rows)

    header = "| N | " + " | ".join(f"runout at {t:g} s [cm] (seeds) | spread" for t in args.times) + " | CPU-s per run |"
    lines = [header, "|" + "---|" * (2 + 2 * len(args.times))]
    summary = {}
    for spheres in args.spheres:
        cells = []
        for t in args.times:
            values = [r["runout_m"] for r in rows if r["spheres"] == spheres and r["t"] == t]
            s = spread(values)
            summary[(spheres, t)] = {"mean": statistics.mean(v for v in values if v is not None) if any(
                v is not None for v in values) else None, "spread": s}
            cells.append(", ".join("–" if v is None else f"{100 * v:.1f}" for v in values) + " | "
                         + ("–" if s is None else f"{100 * s:.0f} %"))
        cpu = statistics.mean(r["cpu_s"] for r in rows if r["spheres"] == spheres)
        lines.append(f"| {spheres} | " + " | ".join(cells) + f" | {cpu:.0f} |")
    last = args.times[-1]
    representative = next((n for n in args.spheres if summary[(n, last)]["spread"] is not None
                           and summary[(n, last)]["spread"] < args.target), None)
    lines += ["", f"Representative cell (seed spread below {100 * args.target:g} % at t = {last:g} s): "
              + (f"N = {representative}" if representative else f"none of N = {', '.join(map(str, args.spheres))}")]
    text = "\n".join(lines) + "\n"
    (args.out / "cell_size.md").write_text(text)
    (args.out / "cell_size.json").write_text(json.dumps(
        {"rows": rows, "representative": representative,
         "summary": [{"spheres": n, "t": t, **v} for (n, t), v in summary.items()]}, indent=2))

    fig, ax = plt.subplots(figsize=(6, 4))
    for t, colour in zip(args.times, ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple")):
        points = [(r["spheres"], 100 * r["runout_m"]) for r in rows if r["t"] == t and r["runout_m"] is not None]
        means = [(n, 100 * summary[(n, t)]["mean"]) for n in args.spheres if summary[(n, t)]["mean"] is not None]
        if points:
            ax.plot(*zip(*points), "o", color=colour, alpha=0.6, label=f"t = {t:g} s, one seed")
            ax.plot(*zip(*means), "-", color=colour)
    ax.set_xscale("log")
    finish_and_save(fig, ax, args.out / "cell_size.png", "spheres per DEM cell N", "runout [cm]")
    print(text, end="")


if __name__ == "__main__":
    main()
