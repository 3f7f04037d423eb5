"""The cohesion and friction of the paper's bonded snow cell, from a DEM shear test (issue 18,
"cohesive column": "the cell's macroscopic cohesion and friction come from a DEM biaxial or shear test
of the cell"), and what they say about the paper's column.

For each packing seed the column's cell (workflows/column_collapse/cell_snow_370um.json, bonds and all)
is consolidated to the isotropic stress −P and sheared quasi-statically (I = 1e-3) under σ_yy = −P by
`dem_sampler rheometer`. Its peak shear stress τ_peak at each P gives the cell's Mohr–Coulomb envelope
τ_peak = c + P tan φ (least squares per seed); the mean stress ratio at γ = 0.1–0.15, after the bonds
near the shear have broken, gives the residual friction.

τ/P on the shear plane is tan φ when plastic flow is associated (a dilating shear band) and sin φ when
it is isochoric and coaxial (Davis 1968); the friction angle of the packing lies between the two, so
both are reported, and with them the cohesion c = intercept (tan) or intercept / cos φ (sin).

The paper's column (2.4 m high, 1.2 m wide, both gates removed) then has the cohesion number
Co = c / (ρ g H0), with ρ = ρ_s φ_s the bulk density of the consolidated cell at the column's
mid-height stress. A vertical cut stands in limit analysis when Co ≥ 1 / (3.83 tan(45° + φ/2)) (Chen's
log-spiral mechanism), the threshold workflows/cohesive_column checks the MPM against; the highest
cut of this material that stands is H_c = H0 Co / Co_c.

  /usr/bin/python3 strength.py [OUT] [--build BUILD] [--seeds 1 2 3 4] [--pressures 250 500 1000 2000 4000 8000]
                               [--cell CELL.json] [--column SCENE.json]

--cell and --column test another cell against another column (the first region's rectangle), e.g. the
demo's soft cell (workflows/demo/cell_soft_snow_250.json) against the demo's column.

Writes OUT/strength.csv (one row per seed and P), OUT/strength.md and OUT/strength.png.
"""
import argparse
import copy
import csv
import json
import math
import statistics
import subprocess
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment  # noqa: E402
from plotting.figures import finish_and_save, plt  # noqa: E402

CELL = HERE.parent / "column_collapse" / "cell_snow_370um.json"
COLUMN = HERE.parent / "column_collapse" / "column.json"
G = 9.81
CHEN_N_S = 3.83  # γ H_c / c = N_s tan(45° + φ/2), Chen (1975), a vertical cut


def shear_test(build, cell_spec, folder, seed, pressure):
    folder.mkdir(parents=True, exist_ok=True)
    cell = copy.deepcopy(cell_spec)
    cell["preparation"]["seed"] = seed
    (folder / "cell.json").write_text(json.dumps(cell))
    out = folder / f"p{pressure:g}.csv"
    done = subprocess.run([str(build / "dem_sampler" / "dem_sampler"), "rheometer", str(folder / "cell.json"),
                           "--inertial-numbers", "0.001", "--pressure", f"{pressure:g}", "--strain", "0.15",
                           "--steady-from", "0.1", "--out", str(out)], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"strength.py: {folder}: dem_sampler rheometer failed: {done.stderr.strip()}")
    with out.open() as f:
        row = next(csv.DictReader(f))
    return {"seed": seed, "P": pressure, **{k: float(v) for k, v in row.items()}}


def envelope(pressures, shear):
    """(intercept, slope) of the least-squares line shear = intercept + slope · P."""
    slope, intercept = np.polyfit(np.asarray(pressures, float), np.asarray(shear, float), 1)
    return float(intercept), float(slope)


def mohr_coulomb(intercept, slope):
    """{convention: (c [Pa], φ [°])} of a τ–σ_n envelope (module docstring)."""
    tan_phi = math.atan(slope)
    sin_phi = math.asin(min(slope, 1.0))
    return {"tan": (intercept, math.degrees(tan_phi)), "sin": (intercept / math.cos(sin_phi), math.degrees(sin_phi))}


def sd(values):
    return statistics.stdev(values) if len(values) > 1 else 0.0


def critical_cohesion_number(phi_degrees):
    return 1 / (CHEN_N_S * math.tan(math.radians(45 + phi_degrees / 2)))


def column_height(column_file):
    scene = json.loads(column_file.read_text())
    (x0, y0), (x1, y1) = scene["regions"][0]["rectangle"]["min"], scene["regions"][0]["rectangle"]["max"]
    return y1 - y0, x1 - x0


def plot(rows, fits, out):
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot([r["P"] for r in rows], [r["peak_shear"] for r in rows], "o", color="tab:blue", alpha=0.6,
            label="peak τ, one seed")
    ax.plot([r["P"] for r in rows], [r["mu"] * r["normal_stress"] for r in rows], "s", color="tab:orange", alpha=0.6,
            label="residual τ (γ = 0.1–0.15)")
    grid = np.linspace(0, max(r["P"] for r in rows), 50)
    intercept, slope = fits["peak"]
    ax.plot(grid, intercept + slope * grid, color="tab:blue", label=f"peak: {intercept:.0f} Pa + {slope:.2f} P")
    ax.plot(grid, fits["residual"][1] * grid, color="tab:orange", label=f"residual: {fits['residual'][1]:.2f} P")
    finish_and_save(fig, ax, out, "normal stress P [Pa]", "shear stress τ [Pa]")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("strength"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4])
    parser.add_argument("--pressures", type=float, nargs="+", default=[250, 500, 1000, 2000, 4000, 8000])
    parser.add_argument("--cell", type=Path, default=CELL,
                        help="the cell JSON to test (default: the paper's snow cell)")
    parser.add_argument("--column", type=Path, default=COLUMN, help="the column scene whose Co is stated")
    args = parser.parse_args()
    build = args.build.resolve()
    cell_spec = json.loads(args.cell.read_text())
    rows = [shear_test(build, cell_spec, args.out / f"seed{seed}", seed, p)
            for seed in args.seeds for p in args.pressures]
    with (args.out / "strength.csv").open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)

    per_seed = {seed: envelope([r["P"] for r in rows if r["seed"] == seed], [r["peak_shear"] for r in rows if r["seed"] == seed])
                for seed in args.seeds}
    fits = {"peak": envelope([r["P"] for r in rows], [r["peak_shear"] for r in rows]),
            # through the origin: the broken packing keeps no cohesion worth fitting
            "residual": (0.0, float(np.sum([r["mu"] * r["normal_stress"] * r["P"] for r in rows])
                                    / np.sum([r["P"] ** 2 for r in rows])))}
    height, width = column_height(args.column)
    grain_density = cell_spec["material"]["density"]
    mean_phi_s = statistics.mean(r["phi_consolidated"] for r in rows)
    mid_stress = min(args.pressures, key=lambda p: abs(p - grain_density * mean_phi_s * G * height / 2))
    density = grain_density * statistics.mean(r["phi_consolidated"] for r in rows if r["P"] == mid_stress)

    lines = ["| P [Pa] | peak τ [Pa] (mean ± sd over seeds) | at γ | residual τ/P | φ_s consolidated |",
             "|---|---|---|---|---|"]
    for p in args.pressures:
        group = [r for r in rows if r["P"] == p]
        peak = [r["peak_shear"] for r in group]
        lines.append(f"| {p:g} | {statistics.mean(peak):.0f} ± {sd(peak):.0f} | "
                     f"{statistics.mean(r['peak_strain'] for r in group):.3f} | "
                     f"{statistics.mean(r['mu'] for r in group):.3f} | "
                     f"{statistics.mean(r['phi_consolidated'] for r in group):.3f} |")
    lines += ["", "Peak envelope τ = intercept + slope · P per seed: "
              + ", ".join(f"seed {s}: {i:.0f} Pa + {k:.3f} P" for s, (i, k) in per_seed.items()),
              f"All seeds: {fits['peak'][0]:.0f} Pa + {fits['peak'][1]:.3f} P; residual: {fits['residual'][1]:.3f} P", "",
              f"The column ({args.column.name}): H0 = {height:g} m, L0 = {width:g} m, "
              f"ρ = ρ_s φ_s = {density:.0f} kg/m³ (φ_s at P = {mid_stress:g} Pa, nearest its mid-height stress)", "",
              "| convention | c [Pa] (seed sd) | φ [°] (seed sd) | Co = c/(ρ g H0) | Co_c, vertical cut (Chen) | stands? | "
              "highest standing cut H_c [m] |", "|---|---|---|---|---|---|---|"]
    result = {"cell": str(args.cell), "cell_json": cell_spec, "rows": rows,
              "per_seed": per_seed, "fits": fits,
              "column": {"scene": str(args.column), "height": height, "width": width, "density": density}}
    for convention in ("tan", "sin"):
        seeds = [mohr_coulomb(*f)[convention] for f in per_seed.values()]
        c, phi = mohr_coulomb(*fits["peak"])[convention]
        co, co_c = c / (density * G * height), critical_cohesion_number(phi)
        lines.append(f"| τ/σ = {convention} φ | {c:.0f} ({sd([s[0] for s in seeds]):.0f}) | "
                     f"{phi:.1f} ({sd([s[1] for s in seeds]):.1f}) | {co:.3f} | {co_c:.3f} | {'yes' if co >= co_c else 'no'} | "
                     f"{height * co / co_c:.2f} |")
        result[convention] = {"cohesion": c, "friction_angle": phi, "cohesion_number": co, "critical": co_c,
                              "critical_height": height * co / co_c}
    text = "\n".join(lines) + "\n"
    (args.out / "strength.md").write_text(text)
    (args.out / "strength.json").write_text(json.dumps(result, indent=2))
    plot(rows, fits, args.out / "strength.png")
    print(text, end="")


if __name__ == "__main__":
    main()
