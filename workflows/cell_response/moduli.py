"""Small-strain moduli of prepared frictional cells against the effective-medium (Voigt) estimate
(issue 18, "cell response against theory").

Each cell (`dem_sampler run`, prepared dense or loose, no bonds, contacts carrying the full k_n, μ_p = 0.5) is strained by
`STRAIN` slowly (a tenth of its strain per 1e-3 s, so the grains relax as it goes) and then held
still; the stress change against the same cell left alone as long (a loose packing may still creep)
gives, with tension-positive σ and Δσ = λ tr ε I
+ 2 G ε for an isotropic linear solid:
- in-plane isotropic compression ε = −e diag(1, 1, 0): λ = −Δσ_zz / (2e), G = (Δσ_zz − Δσ_xx) / (2e),
  K = λ + 2G/3;
- pure shear ε = e diag(1, −1, 0): G = (Δσ_xx − Δσ_yy) / (4e);
- simple shear γ = 2e: G = Δσ_xy / (2e).
The Voigt (affine) estimate at the cell's own φ and Z, mean radius R:
K_V = φ Z k_n / (6πR), G_V = φ Z (2 k_n + 3 k_t) / (20πR) (mpm_solver's voigt_moduli). The relaxed
moduli lie below the affine ones (relaxation can only lower the elastic energy); how far below,
especially for G, measures the non-affine softening that effective-medium theory misses (Makse et
al. 1999, PRL 83:5070; Agnolin & Roux 2007, PRE 76:061304).

With `--cells FILE ...` the cells are those files as they stand (a column's cell, bonded or not: its
own material, preparation and seed) instead of the seeds × pressures × preparations above; a bonded
cell has no Voigt estimate here (its bonds are not in it), so its K/K_V and G/G_V stay empty. Every
row also gives the isotropic solid's E and ν from K and the pure-shear G, which is what an elastic twin
of the cell carries.

  /usr/bin/python3 moduli.py [OUT] [--build BUILD] [--seeds 1 2 3 4] [--pressures 1000 10000] [--preparations dense loose]
                             [--spheres 125] [--cells FILE ...]

Writes OUT/moduli.csv (one row per cell) and OUT/moduli.md (the table, mean ± standard deviation over
seeds; one row per file with `--cells`); a cell dem_sampler refuses to prepare, its packing not in
equilibrium once left alone, is named under the table and in no mean.
"""
import argparse
import csv
import json
import math
import statistics
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from plotting import environment  # noqa: E402

MATERIAL = {"density": 920, "k_n": 2000, "k_t": 600, "restitution": 0.3, "friction": 0.5, "contact_weight": 1}
DIAMETER = {"min": 3.4e-4, "max": 4.0e-4}
STRAIN = 1e-5
LOADING, HOLD = 1e-3, 1e-3  # [s]
# Moduli are the response about an equilibrium. dem_sampler refuses a packing that is not in one (its
# preparation's equilibrium check: a loose packing that collapses once left alone, as seed 3 at 1 kPa
# did, stop 89); such a cell is named and left out of the means. The others drift by at most 1.7 %
# (loose, 1 kPa), most of it in the first 2e-4 s and the same in every run, which the rest run takes out.
NOT_IN_EQUILIBRIUM = "not in equilibrium"  # in dem_sampler's refusal
# moduli.csv's columns, whichever cells were refused (a refused cell's row leaves the moduli empty).
COLUMNS = ["preparation", "seed", "pressure", "spheres", "phi", "Z", "K", "G_compression", "G_pure_shear",
           "G_simple_shear", "K_voigt", "G_voigt", "young", "poisson", "rest_drift", "refused", "K_ratio", "G_ratio",
           "G_isotropy"]

# In-plane strain directions (unit strain); the moduli from the stress change per unit strain.
LOADS = {
    "rest": [[0, 0], [0, 0]],  # the same cell left alone: what it drifts by without strain is not a modulus
    "compression": [[-1, 0], [0, -1]],
    "pure_shear": [[1, 0], [0, -1]],
    "simple_shear": [[0, 2], [0, 0]],
}


# Compressed without friction the packing is dense and well connected; with the grains' own friction
# it jams looser, with fewer contacts, nearer the isostatic Z = 4 of frictional spheres.
PREPARATIONS = {"dense": 0.0, "loose": 0.5}  # friction while compressing


def cell_spec(seed, pressure, spheres, preparation, material=MATERIAL, diameter=DIAMETER):
    return {"material": material, "preparation": {"spheres": spheres, "diameter": diameter, "pressure": pressure,
                                                  "seed": seed, "compression_friction": PREPARATIONS[preparation]}}


def path_spec(direction):
    rate = [[STRAIN / LOADING * v for v in row] for row in direction]
    return {"segments": [{"L": rate, "duration": LOADING}, {"L": [[0, 0], [0, 0]], "duration": HOLD}],
            "record_interval": 1e-4}


def stress_change(table):
    """Tension-positive stress change (xx, yy, zz, xy) from the first record to the last."""
    first, last = table[0], table[-1]
    return {k: float(last[f"sigma_{k}"]) - float(first[f"sigma_{k}"]) for k in ("xx", "yy", "zz", "xy")}, first


def strained_minus_rest(changes, name):
    return {k: changes[name][k] - changes["rest"][k] for k in changes[name]}


def voigt(phi, z, radius, material):
    scale = phi * z / (math.pi * radius)
    return scale * material["k_n"] / 6, scale * (2 * material["k_n"] + 3 * material["k_t"]) / 20


def young_and_poisson(bulk, shear):
    """E and ν of the isotropic linear solid with bulk modulus K and shear modulus G."""
    return 9 * bulk * shear / (3 * bulk + shear), (3 * bulk - 2 * shear) / (2 * (3 * bulk + shear))


def measure(build, folder, spec, preparation):
    """The moduli of the cell `spec` (a cell JSON as dem_sampler reads it), in `folder`; the row is
    labelled `preparation`."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "cell.json").write_text(json.dumps(spec))
    made = spec["preparation"]
    changes = {}
    for name, direction in LOADS.items():
        (folder / f"{name}.json").write_text(json.dumps(path_spec(direction)))
        out = folder / f"{name}.csv"
        done = subprocess.run([str(build / "dem_sampler" / "dem_sampler"), "run", str(folder / "cell.json"),
                               "--path", str(folder / f"{name}.json"), "--out", str(out)], capture_output=True, text=True)
        if done.returncode != 0 and NOT_IN_EQUILIBRIUM in done.stderr:
            return {"preparation": preparation, "seed": made["seed"], "pressure": made["pressure"],
                    "spheres": made["spheres"], "refused": done.stderr.strip().splitlines()[-1]}
        if done.returncode != 0:
            sys.exit(f"moduli.py: {folder}: dem_sampler run failed: {done.stderr.strip()}")
        with out.open() as f:
            changes[name], initial = stress_change(list(csv.DictReader(f)))
    e = STRAIN
    c = strained_minus_rest(changes, "compression")
    pure, simple = strained_minus_rest(changes, "pure_shear"), strained_minus_rest(changes, "simple_shear")
    lam, g_compression = -c["zz"] / (2 * e), (c["zz"] - c["xx"]) / (2 * e)
    phi, z = float(initial["phi"]), float(initial["Z"])
    diameter = made["diameter"]
    k_v, g_v = (("", "") if "bond" in spec["material"]  # a bonded cell's bonds are not in the estimate
                else voigt(phi, z, (diameter["min"] + diameter["max"]) / 4, spec["material"]))
    bulk, g_pure = lam + 2 * g_compression / 3, (pure["xx"] - pure["yy"]) / (4 * e)
    drift = max(abs(v) for v in changes["rest"].values())
    young, poisson = young_and_poisson(bulk, g_pure)
    return {"preparation": preparation, "seed": made["seed"], "pressure": made["pressure"], "spheres": made["spheres"],
            "phi": phi, "Z": z, "K": bulk, "G_compression": g_compression, "G_pure_shear": g_pure,
            "G_simple_shear": simple["xy"] / (2 * e), "K_voigt": k_v, "G_voigt": g_v, "young": young,
            "poisson": poisson, "rest_drift": drift, "refused": ""}


def read_cell(file):
    try:
        return json.loads(file.read_text())
    except (OSError, json.JSONDecodeError) as err:
        sys.exit(f"moduli.py: {file}: expected a cell JSON file: {err}")


def table(rows):
    """The table of means ± standard deviations over each preparation and pressure's cells ("cells": how
    many, "n of m" where some were refused), then a line per cell left out."""
    def stat(key, group, scale=1.0):
        if not group or any(r[key] == "" for r in group):
            return "–"
        values = [r[key] / scale for r in group]
        spread = statistics.stdev(values) if len(values) > 1 else 0.0
        return f"{statistics.mean(values):.3g} ± {spread:.2g}"

    lines = ["| preparation | p0 [Pa] | cells | φ | Z | K [MPa] | K/K_V | G [MPa] (pure shear) | G/G_V | G simple shear / pure shear | E [MPa] | ν |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for preparation, pressure in dict.fromkeys((r["preparation"], r["pressure"]) for r in rows):
        every = [r for r in rows if (r["preparation"], r["pressure"]) == (preparation, pressure)]
        group = [r for r in every if not r["refused"]]
        cells = f"{len(group)}" if len(group) == len(every) else f"{len(group)} of {len(every)}"
        for r in group:
            has_voigt = r["K_voigt"] != ""
            r["K_ratio"] = r["K"] / r["K_voigt"] if has_voigt else ""
            r["G_ratio"] = r["G_pure_shear"] / r["G_voigt"] if has_voigt else ""
            r["G_isotropy"] = r["G_simple_shear"] / r["G_pure_shear"]
        lines.append(f"| {preparation} | {pressure:g} | {cells} | {stat('phi', group)} | {stat('Z', group)} | {stat('K', group, 1e6)} | "
                     f"{stat('K_ratio', group)} | {stat('G_pure_shear', group, 1e6)} | {stat('G_ratio', group)} | "
                     f"{stat('G_isotropy', group)} | {stat('young', group, 1e6)} | {stat('poisson', group)} |")
    left_out = [r for r in rows if r["refused"]]
    if left_out:
        lines.append("")
    lines += [f"Left out: {r['preparation']}, p0 = {r['pressure']:g} Pa, seed {r['seed']}: {r['refused']}"
              for r in left_out]
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("cell_moduli"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4])
    parser.add_argument("--pressures", type=float, nargs="+", default=[1000, 10000])
    parser.add_argument("--preparations", nargs="+", choices=list(PREPARATIONS), default=list(PREPARATIONS))
    parser.add_argument("--spheres", type=int, default=125)
    parser.add_argument("--cells", type=Path, nargs="+", help="cell JSON files to measure as they stand")
    args = parser.parse_args()
    build = args.build.resolve()
    if args.cells:
        rows = [measure(build, args.out / file.stem, read_cell(file), file.stem) for file in args.cells]
    else:
        rows = [measure(build, args.out / f"{preparation}_p{pressure:g}_seed{seed}",
                        cell_spec(seed, pressure, args.spheres, preparation), preparation)
                for preparation in args.preparations for pressure in args.pressures for seed in args.seeds]
    text = table(rows)
    with (args.out / "moduli.csv").open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS, restval="")
        writer.writeheader()
        writer.writerows(rows)
    (args.out / "moduli.md").write_text(text)
    print(text, end="")


if __name__ == "__main__":
    main()
