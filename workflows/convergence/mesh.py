"""Convergence in grid size (issue 18, "Convergence: mesh"): the demo column run live with its cell of
125 spheres (--spheres; packing seed 1) on grids of cell size h = factor × 0.05 m (same domain, one point per
grid cell, so four times the points at half the size). The change of runout between successive grids
(relative to the coarser one; not reported below a runout of 1 cm) is set against the packing-seed spread of cell_size.py (--noise-floor: a finished cell-size study's
OUT, by default this OUT, whose spread at N = 125 is read), the noise floor below which a difference
means nothing. Run into the cell-size study's OUT, the two share the run at h = 0.05 m, N = 125.

  /usr/bin/python3 mesh.py [OUT] [--build BUILD] [--grid-factors 2 1 0.5] [--times 0.1 0.2 0.3] [--end 0.3]
                           [--threads N] [--spheres 125] [--noise-floor CELL_SIZE_OUT]

Runs finished in OUT/runs/ are kept (an interrupted study resumes). Writes OUT/mesh.csv, OUT/mesh.md,
OUT/mesh.json and OUT/mesh.png (runout against h).
  /usr/bin/python3 cell_size.py OUT && /usr/bin/python3 mesh.py OUT   # both studies, sharing a run
"""
import argparse
import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, tables  # noqa: E402
from plotting.figures import finish_and_save, plt  # noqa: E402
from live_demo import MIN_RUNOUT, SCENE, run, runout_at  # noqa: E402


def seed_spread(cell_size_out, spheres, t):
    """The seed spread at N = `spheres` and time t of a finished cell_size.py study; None without one."""
    if cell_size_out is None:
        return None
    summary = json.loads((Path(cell_size_out) / "cell_size.json").read_text())["summary"]
    return next((s["spread"] for s in summary if s["spheres"] == spheres and abs(s["t"] - t) < 1e-9), None)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("mesh"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--grid-factors", type=float, nargs="+", default=[2, 1, 0.5])
    parser.add_argument("--times", type=float, nargs="+", default=[0.1, 0.2, 0.3])
    parser.add_argument("--end", type=float, default=0.3)
    parser.add_argument("--threads", type=int, default=environment.threads())
    parser.add_argument("--spheres", type=int, default=125, help="spheres per DEM cell")
    parser.add_argument("--noise-floor", type=Path, help="OUT of a finished cell_size.py study (default: OUT)")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    build = args.build.resolve()
    base_h = json.loads(SCENE.read_text())["grid"]["cell_size"]

    rows = []
    for factor in args.grid_factors:
        series, cost = run(build, args.out, args.end, args.threads, args.spheres, 1, factor)
        for t in args.times:
            rows.append({"h_m": base_h * factor, "t": t, "runout_m": runout_at(series, t), "cpu_s": cost["cpu_s"],
                         "failed": cost["failed"]})
        print(f"h = {base_h * factor:g} m: {cost['cpu_s']:.0f} CPU-s" + (f", {cost['failed']}" if cost["failed"] else ""),
              flush=True)
    tables.write_csv(args.out / "mesh.csv", rows)

    sizes = [base_h * f for f in args.grid_factors]
    lines = ["| h [m] | " + " | ".join(f"runout at {t:g} s [cm] | change from the coarser grid" for t in args.times)
             + " | CPU-s |", "|" + "---|" * (2 + 2 * len(args.times))]
    changes = {}
    for k, h in enumerate(sizes):
        cells = []
        for t in args.times:
            r = next(x["runout_m"] for x in rows if x["h_m"] == h and x["t"] == t)
            coarser = next(x["runout_m"] for x in rows if x["h_m"] == sizes[k - 1] and x["t"] == t) if k else None
            change = abs(r - coarser) / coarser if r is not None and coarser is not None and coarser >= MIN_RUNOUT else None
            changes[(h, t)] = change
            cells.append(("–" if r is None else f"{100 * r:.1f}") + " | " + ("–" if change is None else f"{100 * change:.0f} %"))
        cpu = next(x["cpu_s"] for x in rows if x["h_m"] == h)
        lines.append(f"| {h:g} | " + " | ".join(cells) + f" | {cpu:.0f} |")
    floor_study = args.noise_floor or (args.out if (args.out / "cell_size.json").exists() else None)
    floors = {t: seed_spread(floor_study, args.spheres, t) for t in args.times}
    lines += ["", f"Seed spread at N = {args.spheres} (the noise floor): "
              + ", ".join(f"t = {t:g} s: " + ("not measured" if f is None else f"{100 * f:.0f} %") for t, f in floors.items())]
    text = "\n".join(lines) + "\n"
    (args.out / "mesh.md").write_text(text)
    (args.out / "mesh.json").write_text(json.dumps(
        {"rows": rows, "changes": [{"h_m": h, "t": t, "change": c} for (h, t), c in changes.items()],
         "seed_spread": [{"t": t, "spread": f} for t, f in floors.items()]}, indent=2))

    fig, ax = plt.subplots(figsize=(6, 4))
    for t in args.times:
        points = [(x["h_m"], 100 * x["runout_m"]) for x in rows if x["t"] == t and x["runout_m"] is not None]
        if points:
            ax.plot(*zip(*points), "o-", label=f"t = {t:g} s")
    ax.set_xscale("log")
    finish_and_save(fig, ax, args.out / "mesh.png", "grid cell size h [m]", "runout [cm]")
    print(text, end="")


if __name__ == "__main__":
    main()
