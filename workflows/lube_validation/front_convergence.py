"""How the cohesionless column's front converges with the grid: the study's a = 1 column (column_scene.py)
at several cell sizes h, each run to a common end time, and its front followed in time. Per grid: the
front ΔL/L0 at the end and at given times, its peak speed, and the deposit's edges where it thins to
1, 2.5, 5 and 10 % of H0 (deposit.py says why the front alone cannot converge). A finished run that
reaches the end time is measured again, not re-run, so grids can be added one at a time.

`--material live_twin` runs instead the Drucker–Prager twin of the live study's cell (live_study.py: its
φ, moduli and density, one point per grid cell, the gate at 0.05 s), so that its fronts can be set
beside the live column's; `--points-per-cell 2` runs it at the sand's two points per cell and
direction, to tell what one point per cell does to the front from what the material does.

  /usr/bin/python3 front_convergence.py [OUT] [--build BUILD] [--threads N] [--cell-sizes H ...]
                                        [--aspect-ratio A] [--end T] [--times T ...] [--separation]
                                        [--material {sand,live_twin}] [--points-per-cell N]

Writes OUT/h<H>/ (scene, run, cost.json) and OUT/fronts.{json,md,png}.
"""
import argparse
import json
import sys
from pathlib import Path

import numpy as np

import column_scene
import deposit
import live_study
import study

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, scenes  # noqa: E402
from plotting.tables import read_csv  # noqa: E402

EDGES = (0.01, 0.025, 0.05, 0.10)  # deposit thickness / H0
SPEED_WINDOW = 0.02  # [s]: the front's speed is its advance over this window


def finished(folder, end):
    summary = folder / "run" / "summary.json"
    return summary.exists() and json.loads(summary.read_text())["final_time"] >= end - 1e-9


def run_grid(out, args, h):
    folder = out / f"h{h:g}"
    if not finished(folder, args.end):
        cost = study.run_scene(folder, grid_scene(args, h), args.build, args.threads)
        if cost.pop("failed"):
            sys.exit(f"front_convergence.py: h = {h:g}: mpm_solver failed, see {folder / 'run'}")
        (folder / "cost.json").write_text(json.dumps(cost) + "\n")
    return measure(folder, args, h)


def points_per_cell(args):
    """Per grid cell and direction: --points-per-cell, or the material's own: the study's sand 2, the live
    study's twin 1 (one cell per grid cell)."""
    if args.points_per_cell:
        return args.points_per_cell
    return live_study.PPC if args.material == "live_twin" else 2


def grid_scene(args, h):
    ppc = points_per_cell(args)
    if args.material == "live_twin":
        twin = live_study.twin_material(separation=args.separation)
        return column_scene.scene(args.aspect_ratio, study.WIDTH, h, ppc, end=args.end, material=twin,
                                  p_wave=column_scene.p_wave_modulus(twin["young"], twin["poisson"]),
                                  gate=live_study.GATE, room=4)
    return column_scene.scene(args.aspect_ratio, study.WIDTH, h, ppc, end=args.end,
                              material=column_scene.drucker_prager(separation=args.separation))


def measure(folder, args, h):
    g = column_scene.geometry(args.aspect_ratio, study.WIDTH, h, points_per_cell(args))
    series = read_csv(folder / "run" / "series.csv")
    kept = series["t"] <= args.end + 1e-9
    t, front = series["t"][kept], (series["front"][kept] + g["radius"] - g["wall"] - g["L0"]) / g["L0"]
    window = t >= t[0] + SPEED_WINDOW
    speed = (front[window] - np.interp(t[window] - SPEED_WINDOW, t, front)) * g["L0"] / SPEED_WINDOW
    x, height, snapshot_time = deposit.profile(folder / "run", g, h, args.end)
    cost_file = folder / "cost.json"
    return {"h": h, "L0_over_h": study.WIDTH / h, "end": args.end, "front": float(front[-1]),
            "front_at": {f"{s:g}": float(np.interp(s, t, front)) for s in args.times},
            "peak_speed": float(speed.max()), "peak_speed_time": float(t[window][speed.argmax()]),
            "edges": {f"{e:g}": deposit.edge(x, height, e) for e in EDGES}, "edges_time": snapshot_time,
            "cpu_s": json.loads(cost_file.read_text())["cpu_s"] if cost_file.exists() else None,
            "steps": int(series["step"][kept][-1]), "series": {"t": t.tolist(), "front": front.tolist()}}


def table(results, times):
    head = ["L0/h", "front ΔL/L0 at the end"] + [f"front at {s:g} s" for s in times] + \
        ["peak front speed [m/s] (at t [s])"] + [f"edge {100 * e:g} % H0" for e in EDGES] + ["steps", "CPU-s"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in results:
        cells = [f"{r['L0_over_h']:g}", f"{r['front']:.3f}"] + [f"{v:.3f}" for v in r["front_at"].values()] + \
            [f"{r['peak_speed']:.2f} ({r['peak_speed_time']:.2f})"] + [f"{v:.3f}" for v in r["edges"].values()] + \
            [str(r["steps"]), "" if r["cpu_s"] is None else f"{r['cpu_s']:.0f}"]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def plot(results, file):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    for r in results:
        left.plot(r["series"]["t"], r["series"]["front"], label=f"L0/h = {r['L0_over_h']:g}")
    left.set_xlabel("t [s]")
    left.set_ylabel("front ΔL/L0")
    left.legend()
    n = [r["L0_over_h"] for r in results]
    right.plot(n, [r["front"] for r in results], "ko-", label="front")
    for e in EDGES:
        right.plot(n, [r["edges"][f"{e:g}"] for r in results], "o--", label=f"edge {100 * e:g} % H0")
    right.set_xscale("log", base=2)
    right.set_xlabel("L0/h")
    right.set_ylabel("ΔL/L0 at the end")
    right.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(file, dpi=120)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("front_convergence"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--cell-sizes", type=float, nargs="+", default=[0.02, 0.01, 0.005, 0.0025])
    parser.add_argument("--aspect-ratio", type=float, default=1.0)
    parser.add_argument("--end", type=float, default=0.75, help="[s]; the a = 1 front stops by 0.7 s")
    parser.add_argument("--times", type=float, nargs="*", default=[0.3, 0.5])
    parser.add_argument("--separation", action="store_true",
                        help="sand pulled apart carries nothing until packed back (drucker_prager_law.hpp)")
    parser.add_argument("--material", choices=["sand", "live_twin"], default="sand",
                        help="the study's sand (φ = 30°), or the Drucker–Prager twin of the live study's cell")
    scenes.add_points_per_cell_option(parser, None,
                                      "material points per grid cell and direction (default: the sand's 2, the twin's 1)")
    args = parser.parse_args()
    if not all(h > 0 for h in args.cell_sizes):
        parser.error(f"--cell-sizes: expected sizes > 0 [m], got {args.cell_sizes}")
    if not all(0 < s <= args.end for s in args.times):
        parser.error(f"--times: expected times in (0, --end = {args.end:g}] [s], got {args.times}")
    args.out.mkdir(parents=True, exist_ok=True)
    args.build = args.build.resolve()
    results = []
    for h in sorted(args.cell_sizes, reverse=True):
        results.append(run_grid(args.out, args, h))
        print(json.dumps({k: v for k, v in results[-1].items() if k != "series"}), flush=True)
    (args.out / "fronts.json").write_text(json.dumps(results, indent=1) + "\n")
    (args.out / "fronts.md").write_text(table(results, args.times))
    plot(results, args.out / "fronts.png")


if __name__ == "__main__":
    main()
