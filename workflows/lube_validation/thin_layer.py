"""How a thin Drucker–Prager layer spreads as the grid resolves it: the column's material (φ = 30°,
c = 0) as a layer of thickness T and length 10 T on the column's base (friction 0.5), released at
rest, so its two free ends slump; the ends' spread is printed for T / h = 2, 4, 8 (or --cells) and
each transfer. The column's deposit tail is such a layer, which is why its front does not converge
in h (see deposit.py). Lube et al.'s planar law at small aspect ratio, ΔL = 1.2 H0, gives the scale:
1.2 T.

With --velocity V0 the layer is launched along the base at V0 instead (on a base of --base-friction
μ), as the column's sheet slides out: the printout adds how far its centre of mass went, against a
rigid block's v0²/(2 μ g) (on a base weaker in shear than the material, the base's friction sets
the slide: the base contact checked on a layer as thin as the grid), and how far its front and rear
went.

  /usr/bin/python3 thin_layer.py [OUT] [--build BUILD] [--thickness T] [--transfers apic apic_flip:5 ...]
                                 [--cells 2 4 8] [--velocity V0] [--base-friction MU]
"""
import argparse
import json
import math
import subprocess
import sys
from pathlib import Path

import column_scene

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, flow, scenes  # noqa: E402
from plotting.vtu import read_run  # noqa: E402

# [s] after a layer at rest is released (or has slid to rest): its ends have about stopped by then
# (kinetic energy below 1 % of its peak at T/h = 4, 8).
END = 0.3


def rigid_slide(velocity, base_friction):
    """How far a rigid block launched at `velocity` slides on a Coulomb base [m]: v0² / (2 μ g)."""
    return velocity**2 / (2 * base_friction * column_scene.GRAVITY)


def layer_scene(thickness, h, transfer, velocity=0.0, base_friction=column_scene.BASE_FRICTION):
    length, margin = 10 * thickness, 4 * thickness
    # A launched layer slides for v0/(μ g) and then rests; its front may go several slides out.
    end = END + velocity / (base_friction * column_scene.GRAVITY)
    ahead = 3 * rigid_slide(velocity, base_friction)
    scene = column_scene.scene(1.0, h=h, end=end, transfer=transfer)
    base = 2 * h
    scene["grid"]["cells"] = [math.ceil((length + 2 * margin + ahead) / h), math.ceil((base + thickness + 3 * h) / h)]
    scene["regions"][0]["rectangle"] = {"min": [margin, base], "max": [margin + length, base + thickness]}
    if velocity:
        scene["regions"][0]["velocity"] = [velocity, 0.0]
    scene["obstacles"] = scene["obstacles"][:1]  # the base only
    scene["obstacles"][0]["friction"] = base_friction
    scene["time"]["output_interval"] = end
    return scene


def displacements(run_folder):
    """How far the layer's front, rear and centre of mass [m] moved between the first and the last
    snapshot (points of one layer carry equal masses)."""
    snapshots = read_run(run_folder)
    first, last = snapshots[0].xy[:, 0], snapshots[-1].xy[:, 0]
    _, centre = flow.bulk_advance(snapshots[-1], snapshots[0])
    return {"front": last.max() - first.max(), "rear": last.min() - first.min(), "centre": centre}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("thin_layer"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--thickness", type=float, default=0.02)
    parser.add_argument("--transfers", nargs="+", default=["apic", "apic_flip:5"])
    parser.add_argument("--cells", type=int, nargs="+", default=[2, 4, 8], help="T / h of each run")
    parser.add_argument("--velocity", type=float, default=0.0, help="launch speed along the base [m/s] (0: at rest)")
    parser.add_argument("--base-friction", type=float, default=column_scene.BASE_FRICTION)
    args = parser.parse_args()
    if not (math.isfinite(args.thickness) and args.thickness > 0):
        parser.error(f"--thickness: expected a positive length [m], got {args.thickness}")
    if min(args.cells) < 1:
        parser.error(f"--cells: expected whole numbers of grid cells >= 1, got {min(args.cells)}")
    if not (math.isfinite(args.velocity) and args.velocity >= 0):
        parser.error(f"--velocity: expected a speed >= 0 [m/s], got {args.velocity}")
    if not (math.isfinite(args.base_friction) and args.base_friction > 0):
        parser.error(f"--base-friction: expected a positive friction coefficient, got {args.base_friction}")
    sliding = args.velocity > 0
    if sliding:
        print(f"| transfer | T/h | centre moved [mm] (rigid block: {1000 * rigid_slide(args.velocity, args.base_friction):.1f})"
              " | front moved [mm] | rear moved [mm] | spread of each end / T |\n|---|---|---|---|---|---|")
    else:
        print("| transfer | T/h | spread of each end / T |  (Lube, small a: 1.2)\n|---|---|---|")
    for text in args.transfers:
        for cells in args.cells:
            h = args.thickness / cells
            folder = args.out / f"{text.replace(':', '')}_T{cells}h"
            folder.mkdir(parents=True, exist_ok=True)
            scene = layer_scene(args.thickness, h, scenes.transfer_arg(text), args.velocity, args.base_friction)
            (folder / "scene.json").write_text(json.dumps(scene))
            done = subprocess.run([str(args.build.resolve() / "mpm_solver" / "mpm_solver"), str(folder / "scene.json"),
                                   "--out", str(folder / "run"), "--threads", "1"], capture_output=True, text=True)
            if done.returncode != 0:
                sys.exit(f"thin_layer.py: {folder}: mpm_solver failed: {done.stderr.strip().splitlines()[-1]}")
            moved = displacements(folder / "run")
            end_spread = 0.5 * (moved["front"] - moved["rear"]) / args.thickness
            if sliding:
                print(f"| {text} | {cells} | {1000 * moved['centre']:.1f} | {1000 * moved['front']:.1f} | "
                      f"{1000 * moved['rear']:.1f} | {end_spread:.2f} |", flush=True)
            else:
                print(f"| {text} | {cells} | {end_spread:.2f} |", flush=True)


if __name__ == "__main__":
    main()
