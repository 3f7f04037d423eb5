"""The μ(I) of a frictional cell in steady plane shear under a controlled normal stress (issue 18,
"cell response against theory"), against the published quasi-static friction of spheres with
μ_p = 0.5 (μ_s ≈ 0.35–0.40) and the shape of the μ(I) law (Jop, Forterre & Pouliquen 2006).

For each packing seed the cell of moduli.py (dense, μ_p = 0.5, no bonds) is prepared at P and sheared
by `dem_sampler rheometer` at every inertial number, from the prepared state each time, to a strain
`--strain` (steady from γ = 1). `--pressure`, `--restitution`, `--tangential-ratio` and
`--diameter-spread` change P, the contacts' restitution, their k_t/k_n and the spread of diameters
about the mean (the cell's stiffness number κ = k_n/(P d) scales as 1/P), to tell the causes of a μ_s
apart. The law μ(I) = μ_s + (μ_2 − μ_s) / (I_0 / I + 1) is fitted to the
seed means (least squares, weighted by the standard error). Jop et al.'s glass beads (μ_s = tan 20.9°,
μ_2 = tan 32.76°, I_0 = 0.279) are drawn for the shape, not as a target: their grains are not these.

  /usr/bin/python3 mu_of_i.py [OUT] [--build BUILD] [--seeds 1 2 3 4] [--inertial-numbers 0.003 0.01 0.03 0.1 0.3]
                              [--spheres 125] [--strain 6] [--pressure 1000] [--restitution 0.3]
                              [--tangential-ratio 0.3] [--diameter-spread S]

Writes OUT/mu_of_i.csv (one row per seed and I), OUT/mu_of_i.md (means, standard deviations over
seeds and the fit) and OUT/mu_of_i.png.
"""
import argparse
import csv
import json
import math
import statistics
import subprocess
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from plotting import environment  # noqa: E402
from plotting.figures import plt, DPI  # noqa: E402

import moduli  # noqa: E402  (the same cells)

JOP_BEADS = (math.tan(math.radians(20.9)), math.tan(math.radians(32.76)), 0.279)
PUBLISHED_MU_S = (0.35, 0.40)  # spheres with μ_p = 0.5, as issue 18 states it


def mu_law(i, mu_s, mu_2, i_0):
    return mu_s + (mu_2 - mu_s) / (i_0 / i + 1)


def fit(inertial_numbers, mu, error):
    """(μ_s, μ_2, I_0) by weighted least squares: linear in μ_s and μ_2 for each I_0 of a log grid."""
    i, mu, w = np.asarray(inertial_numbers), np.asarray(mu), 1 / np.maximum(np.asarray(error), 1e-4)
    best = None
    for i_0 in np.logspace(-2.5, 1, 400):
        x = 1 / (i_0 / i + 1)  # μ = μ_s (1 − x) + μ_2 x
        a = np.stack([1 - x, x], axis=1) * w[:, None]
        (mu_s, mu_2), *_ = np.linalg.lstsq(a, mu * w, rcond=None)
        residual = float(np.sum(((mu_law(i, mu_s, mu_2, i_0) - mu) * w) ** 2))
        if best is None or residual < best[0]:
            best = (residual, mu_s, mu_2, i_0)
    return best[1:]


def diameters(spread):
    """Diameters uniform within ±spread of the moduli cells' mean diameter (theirs exactly if None)."""
    if spread is None:
        return moduli.DIAMETER
    mean = (moduli.DIAMETER["min"] + moduli.DIAMETER["max"]) / 2
    return {"min": mean * (1 - spread), "max": mean * (1 + spread)}


def run_seed(build, folder, seed, spheres, inertial_numbers, strain, pressure, material, diameter):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "cell.json").write_text(json.dumps(moduli.cell_spec(seed, pressure, spheres, "dense", material, diameter)))
    out = folder / "rheometer.csv"
    done = subprocess.run([str(build / "dem_sampler" / "dem_sampler"), "rheometer", str(folder / "cell.json"),
                           "--inertial-numbers", ",".join(f"{i:g}" for i in inertial_numbers),
                           "--strain", f"{strain:g}", "--out", str(out)], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"mu_of_i.py: {folder}: dem_sampler rheometer failed: {done.stderr.strip()}")
    with out.open() as f:
        return [{"seed": seed, **{k: float(v) for k, v in row.items()}} for row in csv.DictReader(f)]


def summary(rows):
    """Per I: mean μ, its standard deviation over seeds, mean φ and Z."""
    out = []
    for i in sorted({r["I"] for r in rows}):
        group = [r for r in rows if r["I"] == i]
        mu = [r["mu"] for r in group]
        out.append({"I": i, "mu": statistics.mean(mu), "mu_sd": statistics.stdev(mu) if len(mu) > 1 else group[0]["mu_error"],
                    "phi": statistics.mean(r["phi"] for r in group), "Z": statistics.mean(r["Z"] for r in group),
                    "P": statistics.mean(r["normal_stress"] for r in group), "seeds": len(group)})
    return out


def plot(rows, means, law, out):
    fig, (ax_mu, ax_phi) = plt.subplots(1, 2, figsize=(9, 3.8))
    i = np.array([m["I"] for m in means])
    grid = np.logspace(math.log10(i.min()) - 0.3, math.log10(i.max()) + 0.3, 100)
    ax_mu.plot([r["I"] for r in rows], [r["mu"] for r in rows], ".", color="grey", alpha=0.6, label="one seed")
    ax_mu.errorbar(i, [m["mu"] for m in means], yerr=[m["mu_sd"] for m in means], fmt="o", color="tab:blue",
                   label="mean ± sd over seeds")
    ax_mu.plot(grid, mu_law(grid, *law), color="tab:blue", label="μ(I) fit")
    ax_mu.plot(grid, mu_law(grid, *JOP_BEADS), "--", color="tab:orange", label="Jop et al. 2006, glass beads")
    ax_mu.axhspan(*PUBLISHED_MU_S, color="tab:green", alpha=0.15, label="published μ_s, μ_p = 0.5")
    ax_mu.set_xscale("log")
    ax_mu.set_xlabel("inertial number I")
    ax_mu.set_ylabel("μ = σ_xy / (−σ_yy)")
    ax_mu.legend(fontsize=7)
    ax_phi.plot(i, [m["phi"] for m in means], "o-")
    ax_phi.set_xscale("log")
    ax_phi.set_xlabel("inertial number I")
    ax_phi.set_ylabel("solid fraction φ")
    for ax in (ax_mu, ax_phi):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=DPI)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("mu_of_i"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4])
    parser.add_argument("--inertial-numbers", type=float, nargs="+", default=[0.003, 0.01, 0.03, 0.1, 0.3])
    parser.add_argument("--spheres", type=int, default=125)
    parser.add_argument("--strain", type=float, default=6)
    parser.add_argument("--pressure", type=float, default=1000.0, help="normal stress P [Pa]")
    parser.add_argument("--restitution", type=float, default=moduli.MATERIAL["restitution"],
                        help="the contacts' coefficient of restitution")
    parser.add_argument("--tangential-ratio", type=float, default=moduli.MATERIAL["k_t"] / moduli.MATERIAL["k_n"],
                        help="the contacts' k_t / k_n")
    parser.add_argument("--diameter-spread", type=float,
                        help="diameters uniform within ± this fraction of the mean 0.37 mm (default: 0.34–0.40 mm, ±0.081)")
    args = parser.parse_args()
    if not args.pressure > 0:
        parser.error(f"--pressure: expected a positive normal stress [Pa], got {args.pressure:g}")
    if not 0 < args.restitution <= 1:
        parser.error(f"--restitution: expected a coefficient in (0, 1], got {args.restitution:g}")
    if not 0 < args.tangential_ratio <= 1:
        parser.error(f"--tangential-ratio: expected k_t/k_n in (0, 1], got {args.tangential_ratio:g}")
    if args.diameter_spread is not None and not 0 <= args.diameter_spread < 1:
        parser.error(f"--diameter-spread: expected a fraction in [0, 1), got {args.diameter_spread:g}")
    material = {**moduli.MATERIAL, "restitution": args.restitution,
                "k_t": args.tangential_ratio * moduli.MATERIAL["k_n"]}
    rows = [r for seed in args.seeds
            for r in run_seed(args.build.resolve(), args.out / f"seed{seed}", seed, args.spheres, args.inertial_numbers,
                              args.strain, args.pressure, material, diameters(args.diameter_spread))]
    means = summary(rows)
    law = fit([m["I"] for m in means], [m["mu"] for m in means], [m["mu_sd"] for m in means])
    with (args.out / "mu_of_i.csv").open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    lines = ["| I | seeds | μ | sd | φ | Z | ⟨−σ_yy⟩ [Pa] | Jop beads μ |", "|---|---|---|---|---|---|---|---|"]
    lines += [f"| {m['I']:g} | {m['seeds']} | {m['mu']:.3f} | {m['mu_sd']:.3f} | {m['phi']:.4f} | {m['Z']:.2f} | "
              f"{m['P']:.1f} | {mu_law(m['I'], *JOP_BEADS):.3f} |" for m in means]
    lines.append(f"\nFit: μ_s = {law[0]:.3f}, μ_2 = {law[1]:.3f}, I_0 = {law[2]:.3g} "
                 f"(published μ_s for μ_p = 0.5: {PUBLISHED_MU_S[0]}–{PUBLISHED_MU_S[1]})")
    lines.append(f"Cells: {args.spheres} spheres, P = {args.pressure:g} Pa, restitution {args.restitution:g}, "
                 f"k_t/k_n {args.tangential_ratio:g}, diameters {diameters(args.diameter_spread)['min'] * 1e3:.3g}–"
                 f"{diameters(args.diameter_spread)['max'] * 1e3:.3g} mm")
    text = "\n".join(lines) + "\n"
    (args.out / "mu_of_i.md").write_text(text)
    plot(rows, means, law, args.out / "mu_of_i.png")
    print(text, end="")


if __name__ == "__main__":
    main()
