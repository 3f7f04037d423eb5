"""Where a heap of the column's material comes to rest: a symmetric triangular heap (half-width
W = 0.2 m, slopes θ) of the Drucker–Prager sand (φ = 30°, c = 0) on a rough base (friction 1), under
gravity ramped in over 0.1 s, run to 1.5 s. Below φ it must stand: the apex settles only
elastically, by about ρ g H² / (2E). Above φ it slumps, and the slope it stops at tells how mobile
the continuum is in flow; its change with h and with the transfer tells how much of that is the
grid's. Prints, per slope, transfer and h: the mean slope atan(H/W) (from the points' centres) at the start
and at the end, the apex's settlement and the largest speed then.

  /usr/bin/python3 heap.py [OUT] [--build BUILD] [--slopes 25 35] [--cell-sizes 0.01 0.005]
                           [--transfers apic apic_flip:5 apic_flip:500]
"""
import argparse
import math
import sys
from pathlib import Path

import column_scene
import study

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, scenes  # noqa: E402
from plotting.vtu import read_run  # noqa: E402

HALF_WIDTH, CENTRE, END, RAMP = 0.2, 0.5, 1.5, 0.1  # [m], [m], [s], [s]


def heap_scene(slope_deg, h, transfer):
    height = HALF_WIDTH * math.tan(math.radians(slope_deg))
    scene = column_scene.scene(1.0, h=h, end=END, transfer=transfer)
    base = 2 * h
    scene["grid"]["cells"] = [math.ceil((2 * CENTRE) / h), math.ceil((base + height + 3 * h) / h)]
    scene["regions"][0].pop("rectangle")
    scene["regions"][0]["polygon"] = [[CENTRE - HALF_WIDTH, base], [CENTRE + HALF_WIDTH, base], [CENTRE, base + height]]
    scene["obstacles"] = scene["obstacles"][:1]  # the base only, rough
    scene["obstacles"][0]["friction"] = 1.0
    scene["gravity"]["ramp"] = {"start": 0, "end": RAMP, "from": [0, 0]}
    scene["time"]["output_interval"] = END / 6
    return scene


def mean_slope(snapshot, base_y):
    """atan(apex height / half-width) [°], both from the points' centres."""
    x, y = snapshot.xy[:, 0], snapshot.xy[:, 1]
    return math.degrees(math.atan2(y.max() - base_y, 0.5 * (x.max() - x.min())))


def measure(run_folder):
    """Mean slope [°] at the start and at the end, the apex's settlement [m] and the largest point
    speed [m/s] at the end."""
    first, last = (read_run(run_folder)[i] for i in (0, -1))
    base_y = first.xy[:, 1].min()
    return (mean_slope(first, base_y), mean_slope(last, base_y), first.xy[:, 1].max() - last.xy[:, 1].max(),
            last.speed().max())


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("heap"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--slopes", type=float, nargs="+", default=[25, 35])
    parser.add_argument("--cell-sizes", type=float, nargs="+", default=[0.01, 0.005])
    parser.add_argument("--transfers", nargs="+", default=["apic", "apic_flip:5", "apic_flip:500"])
    args = parser.parse_args()
    print("| slope | transfer | h [m] | mean slope: start → 1.5 s | apex settled [mm] | largest speed [m/s] | CPU [s] |\n"
          "|---|---|---|---|---|---|---|")
    for slope in args.slopes:
        for text in args.transfers:
            for h in args.cell_sizes:
                folder = args.out / f"slope{slope:g}_{text.replace(':', '')}_h{h:g}"
                run = study.run_scene(folder, heap_scene(slope, h, scenes.transfer_arg(text)), args.build, 1)
                if run["failed"]:
                    sys.exit(f"heap.py: {folder}: {run['failed']}")
                start, end, settled, speed = measure(folder / "run")
                print(f"| {slope:g}° | {text} | {h:g} | {start:.1f}° → {end:.1f}° | {1e3 * settled:.3f} | {speed:.3f} | "
                      f"{run['cpu_s']:.0f} |", flush=True)


if __name__ == "__main__":
    main()
