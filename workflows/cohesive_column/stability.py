"""When does a cohesive column stand? (issue 18, "cohesive column: the transition from standing to
collapse"). The Drucker–Prager column of workflows/lube_validation (φ = 30°, aspect ratio a = H0/L0,
gate removed at 0.02 s) given a cohesion c, with no tension cut-off below the cone's apex, for a
sweep of the cohesion number Co = c / (ρ g H0), at two grid sizes.

The reference is limit analysis of a vertical cut in a Mohr–Coulomb material (which this cone is in
steady plane strain, see drucker_prager_law.hpp), γ H_c / c = N_s tan(45° + φ/2):
- N_s = 4, Culmann's planar wedge through the toe, an upper bound on H_c (Co_c ≥ 0.144 at φ = 30°);
- N_s = 3.83, the log-spiral mechanism of Chen (1975, Limit analysis and soil plasticity), the least
  upper bound (Co_c ≥ 0.151).
Those theorems hold for an associated flow rule, the cone with `--dilatancy-angle` 30 (= φ). The
study's sand flows without dilatancy (ψ = 0, the default), and such a material collapses at lower
loads, between those of two associated materials (`references`): it falls below Chen's 0.151 and
stands above about 0.186; along Culmann's wedge it fails at 0.178.
A column released suddenly may fail a little above the static threshold (the gate's removal is an
impact, not a quasi-static unloading), and the back wall sits at L0 from the face, beyond the wedge
(0.577 H0 at φ = 30°) only for a < 1.73.

A run stands when its front has moved less than STANDING × L0 by the end (8 √(H0/g) + 0.3 s).

  /usr/bin/python3 stability.py [OUT] [--build BUILD] [--aspect-ratio 1] [--cohesion-numbers 0.10 0.11 ... 0.20]
                                [--cells 10 20 40] [--dilatancy-angle 0]

Writes OUT/stability.md, OUT/stability.json and OUT/stability.png (front displacement against Co).
"""
import argparse
import json
import math
import resource
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE.parent / "lube_validation"))
import column_scene  # noqa: E402
from plotting import environment  # noqa: E402
from plotting.figures import finish_and_save, plt  # noqa: E402
from plotting.vtu import read_run  # noqa: E402

WIDTH = 0.2  # L0 [m]
STANDING = 0.02  # front displacement / L0 below which the column stands
PHI = math.radians(column_scene.FRICTION_ANGLE)


def references(dilatancy_angle):
    """{name: critical cohesion number Co_c = c / (ρ g H_c)} for a cone of dilatancy `dilatancy_angle`
    [°], each from γ H_c / c = N_s tan(45° + φ/2) on a material (c, φ). The limit theorems hold for the
    associated material (ψ = φ): Culmann's wedge and Chen's log-spiral bound it, a column below either
    must fall. A non-associated one (ψ < φ) collapses between two associated materials (Radenkovic's
    theorems): the one of the same (c, φ), which it cannot outlast (it falls below Chen's 0.151), and
    the one of c* = c cos φ, tan φ* = sin φ, which it outlasts; Chen's mechanism on that one gives
    0.186 at φ = 30°, about where such a column must stand. Along a translational mechanism it behaves
    as the associated material of c* = k c, tan φ* = k tan φ, k = cos ψ cos φ / (1 − sin ψ sin φ)
    (Davis 1968; Drescher & Detournay 1993, Géotechnique 43:443): Culmann's wedge on it, 0.178 at
    ψ = 0."""
    def co(n_s, k):
        return 1 / (n_s * k * math.tan(math.pi / 4 + math.atan(k * math.tan(PHI)) / 2))

    if dilatancy_angle == column_scene.FRICTION_ANGLE:
        return {"Culmann wedge (N_s = 4)": co(4, 1), "Chen log-spiral (N_s = 3.83)": co(3.83, 1)}
    psi = math.radians(dilatancy_angle)
    davis = math.cos(psi) * math.cos(PHI) / (1 - math.sin(psi) * math.sin(PHI))
    return {"Chen, associated: falls below": co(3.83, 1),
            f"Culmann wedge, Davis-reduced for ψ = {dilatancy_angle:g}°": co(4, davis),
            "Chen, reduced by cos φ: stands above": co(3.83, math.cos(PHI))}



def cohesive_scene(a, cohesion_number, h, dilatancy_angle=0.0):
    scene = column_scene.scene(a, width=WIDTH, h=h)
    cohesion = cohesion_number * column_scene.DENSITY * 9.81 * a * WIDTH
    sand = scene["materials"][0]
    sand["cohesion"] = cohesion
    if dilatancy_angle:
        sand["dilatancy_angle"] = dilatancy_angle
    # The cone's apex ξ c / η: tension up to it, so the yield surface is Mohr–Coulomb's alone.
    sand["tensile_strength"] = cohesion * math.cos(PHI) / math.sin(PHI) * (1 - 1e-9)
    return scene


def run(out, build, a, cohesion_number, cells, dilatancy_angle=0.0):
    """One column; an interrupted study resumes: a run whose result.json is there for the same scene is
    not run again."""
    h = WIDTH / cells
    folder = out / f"a{a:g}_co{cohesion_number:g}_n{cells}"
    folder.mkdir(parents=True, exist_ok=True)
    scene = json.dumps(cohesive_scene(a, cohesion_number, h, dilatancy_angle))
    result = folder / "result.json"
    if result.exists() and (folder / "scene.json").read_text() == scene:
        return json.loads(result.read_text())
    (folder / "scene.json").write_text(scene)
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    done = subprocess.run([str(build / "mpm_solver" / "mpm_solver"), str(folder / "scene.json"), "--out",
                           str(folder / "run"), "--threads", "1"], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"stability.py: {folder}: mpm_solver failed: {done.stderr.strip().splitlines()[-1]}")
    snapshots = read_run(folder / "run")
    first, last = snapshots[0].xy, snapshots[-1].xy
    row = {"a": a, "cohesion_number": cohesion_number, "cells": cells,
           "front": float((last[:, 0].max() - first[:, 0].max()) / WIDTH),
           "top_drop": float((first[:, 1].max() - last[:, 1].max()) / (a * WIDTH)),
           "cpu_s": resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - before}
    result.write_text(json.dumps(row))
    return row


def threshold(rows):
    """(largest Co that fell, smallest Co that stood) of one sweep; None where there is none."""
    fell = [r["cohesion_number"] for r in rows if r["front"] >= STANDING]
    stood = [r["cohesion_number"] for r in rows if r["front"] < STANDING]
    return (max(fell) if fell else None, min(stood) if stood else None)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("cohesive_column"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--aspect-ratio", type=float, default=1.0)
    parser.add_argument("--cohesion-numbers", type=float, nargs="+",
                        default=[round(0.10 + 0.01 * k, 2) for k in range(11)])
    parser.add_argument("--cells", type=int, nargs="+", default=[10, 20, 40], help="L0 / h")
    parser.add_argument("--dilatancy-angle", type=float, default=0.0,
                        help="ψ [degrees] of the cone's flow rule; = φ (30) is associated, the material of the limit theorems")
    args = parser.parse_args()
    rows = [run(args.out, args.build.resolve(), args.aspect_ratio, co, n, args.dilatancy_angle)
            for n in args.cells for co in args.cohesion_numbers]

    bounds = references(args.dilatancy_angle)
    lines = [f"a = {args.aspect_ratio:g}, φ = {column_scene.FRICTION_ANGLE:g}°, ψ = {args.dilatancy_angle:g}°; "
             "limit analysis: " + ", ".join(f"{k}: Co_c ≥ {v:.3f}" for k, v in bounds.items()), "",
             "| L0/h | Co | front ΔL/L0 | top drop / H0 | stands | CPU-s |", "|---|---|---|---|---|---|"]
    lines += [f"| {r['cells']} | {r['cohesion_number']:g} | {r['front']:.3f} | {r['top_drop']:.3f} | "
              f"{'yes' if r['front'] < STANDING else 'no'} | {r['cpu_s']:.0f} |" for r in rows]
    lines.append("")
    thresholds = {}
    for n in args.cells:
        fell, stood = threshold([r for r in rows if r["cells"] == n])
        thresholds[n] = {"fell_at": fell, "stood_at": stood}
        lines.append(f"L0/h = {n}: the threshold lies between Co = {fell} (falls) and {stood} (stands)")
    text = "\n".join(lines) + "\n"
    (args.out / "stability.md").write_text(text)
    (args.out / "stability.json").write_text(json.dumps({"runs": rows, "thresholds": thresholds,
                                                         "bounds": bounds, "standing": STANDING,
                                                         "dilatancy_angle": args.dilatancy_angle}, indent=2))
    fig, ax = plt.subplots(figsize=(6, 3.8))
    for n in args.cells:
        sweep = [r for r in rows if r["cells"] == n]
        ax.semilogy([r["cohesion_number"] for r in sweep], [max(r["front"], 1e-4) for r in sweep], "o-",
                    label=f"L0/h = {n}")
    for (name, value), style in zip(bounds.items(), ("--", ":", "-.")):
        ax.axvline(value, color="grey", linestyle=style, label=name)
    ax.axhline(STANDING, color="k", linewidth=0.6)
    finish_and_save(fig, ax, args.out / "stability.png", "cohesion number Co = c / (ρ g H0)",
                    "front displacement ΔL / L0")
    print(text, end="")


if __name__ == "__main__":
    main()
