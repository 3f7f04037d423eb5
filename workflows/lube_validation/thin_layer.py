"""How a thin Drucker–Prager layer spreads as the grid resolves it: the column's material (φ = 30°,
c = 0) as a layer of thickness T and length 10 T on the column's base (friction 0.5), released at
rest, so its two free ends slump; the ends' spread is printed for T / h = 2, 4, 8 and each transfer.
The column's deposit tail is such a layer, which is why its front does not converge in h (see
deposit.py). Lube et al.'s planar law at small aspect ratio, ΔL = 1.2 H0, gives the scale: 1.2 T.

  /usr/bin/python3 thin_layer.py [OUT] [--build BUILD] [--thickness T] [--transfers apic apic_flip:5 ...]
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
from plotting import environment  # noqa: E402
from plotting.vtu import read_run  # noqa: E402

END = 0.3  # [s]: the ends have about stopped by then (kinetic energy below 1 % of its peak at T/h = 4, 8)


def layer_scene(thickness, h, transfer):
    length, margin = 10 * thickness, 4 * thickness
    scene = column_scene.scene(1.0, h=h, end=END, transfer=transfer)
    base = 2 * h
    scene["grid"]["cells"] = [math.ceil((length + 2 * margin) / h), math.ceil((base + thickness + 3 * h) / h)]
    scene["regions"][0]["rectangle"] = {"min": [margin, base], "max": [margin + length, base + thickness]}
    scene["obstacles"] = scene["obstacles"][:1]  # the base only
    scene["time"]["output_interval"] = END
    return scene


def spread(run_folder):
    """Mean outward spread of the two ends [m] between the first and the last snapshot."""
    first, last = (s.xy[:, 0] for s in (read_run(run_folder)[i] for i in (0, -1)))
    return 0.5 * ((last.max() - first.max()) + (first.min() - last.min()))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("thin_layer"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--thickness", type=float, default=0.02)
    parser.add_argument("--transfers", nargs="+", default=["apic", "apic_flip:5"])
    args = parser.parse_args()
    print("| transfer | T/h | spread of each end / T |  (Lube, small a: 1.2)\n|---|---|---|")
    for text in args.transfers:
        for cells in (2, 4, 8):
            h = args.thickness / cells
            folder = args.out / f"{text.replace(':', '')}_T{cells}h"
            folder.mkdir(parents=True, exist_ok=True)
            (folder / "scene.json").write_text(json.dumps(layer_scene(args.thickness, h, column_scene.transfer_arg(text))))
            done = subprocess.run([str(args.build.resolve() / "mpm_solver" / "mpm_solver"), str(folder / "scene.json"),
                                   "--out", str(folder / "run"), "--threads", "1"], capture_output=True, text=True)
            if done.returncode != 0:
                sys.exit(f"thin_layer.py: {folder}: mpm_solver failed: {done.stderr.strip().splitlines()[-1]}")
            print(f"| {text} | {cells} | {spread(folder / 'run') / args.thickness:.2f} |", flush=True)


if __name__ == "__main__":
    main()
