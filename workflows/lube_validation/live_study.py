"""The planar column collapse of Lube et al. (2005) with live DEM cells (issue 18): every material point
answered by its own 3D periodic cell of frictional, unbonded spheres (μ_p = 0.5, the dense cell of
workflows/cell_response), at aspect ratios a = 0.5, 1 and 2, against Lube's law and against the
Drucker–Prager column made of the same material:
- its friction angle from the cell's critical-state stress ratio, sin φ = μ_s: at steady isochoric
  (critical-state) flow a Drucker–Prager cone in plane strain has τ/σ = sin φ on the planes of zero
  extension (Davis 1968), which are the shear planes of the cell's rheometer, whose μ(I) fit gives μ_s
  (cell_response/results/mu_of_i.csv);
- its elastic moduli those of the cell (cell_response/results/moduli.csv, dense, 1 kPa), its density
  the cell's, φ ρ_s.
The gate is removed later than in study.py, once the cells, prepared isotropically at P0, have settled
into the column's own weight. A second packing seed at a = 1 gives the noise floor, cells of 64 and
250 spheres the effect of the cell's size, and the a = 1 column (live and twin) on the grid of half
the cell size the effect of h. Measured at rest (kinetic energy below REST of its peak), or,
for a run that never gets there, at its end (flagged, with its kinetic energy over the peak).

  /usr/bin/python3 live_study.py [OUT] [--build BUILD] [--threads N] [--cases NAME ...] [--smoke] [--remeasure]
                                 [--channel-width W]

Writes OUT/<case>/ (cell, scene, run and result.json), OUT/live.json (every finished case), OUT/live.md,
OUT/live.png and, once the live a = 1 column is in on both grids, OUT/live_grid.json and OUT/live_grid.png
(both measured at the earlier of their ends). Cases run as separate calls into one OUT (side by side) are
collected together.
--remeasure measures the finished runs again and runs nothing. --smoke runs a two-point-wide column of
27-sphere cells for a few milliseconds past the gate (the CI test). --channel-width W puts every column
in a flume, between side walls W apart with the back wall's friction (column_scene.channel).
"""
import argparse
import csv
import functools
import json
import math
import statistics
import sys
from pathlib import Path

import column_scene
import study

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE.parent / "cell_response"))
from plotting import environment  # noqa: E402
from plotting.figures import plt, DPI  # noqa: E402
from plotting.tables import read_csv  # noqa: E402
import moduli  # noqa: E402  (the cell)
import mu_of_i  # noqa: E402  (its critical state)

CELL_RESULTS = HERE.parent / "cell_response" / "results"
PREPARATION_PRESSURE = 500  # [Pa], about the mean weight of the a = 1 column
GATE = 0.05  # [s]
H, PPC = 0.02, 1  # L0/h = 10, one point (one cell) per grid cell
GRID_PAIR = ("live_a1", "live_a1_h0.01")  # the live column on two grids


@functools.cache
def cell_mu_of_i():
    """(μ_s, μ_2, I_0) of the μ(I) fit to the committed rheometer results."""
    with (CELL_RESULTS / "mu_of_i.csv").open() as f:
        rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
    means = mu_of_i.summary(rows)
    return mu_of_i.fit([m["I"] for m in means], [m["mu"] for m in means], [m["mu_sd"] for m in means])


def critical_state_ratio():
    return cell_mu_of_i()[0]


@functools.cache
def cell_elasticity():
    """(E, ν, φ) of the dense cell at 1 kPa, seed means of the committed moduli study."""
    with (CELL_RESULTS / "moduli.csv").open() as f:
        rows = [r for r in csv.DictReader(f) if r["preparation"] == "dense" and float(r["pressure"]) == 1000
                and not r.get("refused")]  # a packing not in equilibrium has no moduli (moduli.py)
    k = statistics.mean(float(r["K"]) for r in rows)
    g = statistics.mean(float(r["G_pure_shear"]) for r in rows)
    return (*moduli.young_and_poisson(k, g), statistics.mean(float(r["phi"]) for r in rows))


def twin_material(inertial=False, separation=False):
    """The Drucker–Prager material of the cell: φ from μ_s, moduli and density of the cell; with
    `inertial`, also the rate dependence of the cell's μ(I) fit (μ_2, I_0, its grains' mean diameter and
    density); with `separation`, sand pulled apart carries nothing until packed back, as a cell does."""
    young, poisson, solid_fraction = cell_elasticity()
    mu_s, mu_2, i_0 = cell_mu_of_i()
    rheology = {"mu_2": mu_2, "inertial_number_0": i_0, "grain_diameter": sum(moduli.DIAMETER.values()) / 2,
                "grain_density": moduli.MATERIAL["density"]} if inertial else None
    return column_scene.drucker_prager(math.degrees(math.asin(mu_s)), solid_fraction * moduli.MATERIAL["density"],
                                       young, poisson, rheology, separation)


def live_material(cell_file):
    """A cell sheared thin re-tiles, up to 1000 spheres (three doublings of 125), and beyond that is
    regenerated from the template at its stress (a cohesionless cell has no damage to carry over)."""
    return {"name": "sand", "law": "live", "cell": cell_file,
            "retiling": {"max_spheres": 1000, "beyond_cap": "regenerate"}}


def cases(smoke):
    """(name, law, aspect ratio, packing seed, spheres, h, points per cell)."""
    if smoke:
        return [("live_smoke", "live", 1.0, 1, 27, 0.1, 1)]
    out = [(f"live_a{a:g}", "live", a, 1, 125, H, PPC) for a in (0.5, 1.0, 2.0)]
    out += [("live_a1_seed2", "live", 1.0, 2, 125, H, PPC)]
    out += [(f"live_a1_n{n}", "live", 1.0, 1, n, H, PPC) for n in (64, 250)]
    out += [("live_a1_h0.01", "live", 1.0, 1, 125, H / 2, PPC)]
    out += [("live_a1_ppc2", "live", 1.0, 1, 125, H, 2)]  # the twin's points per cell (stop 74)
    out += [(f"dp_a{a:g}", "drucker_prager", a, None, None, H, PPC) for a in (0.5, 1.0, 2.0)]
    out += [(f"dp_a{a:g}_h0.01_ppc2", "drucker_prager", a, None, None, 0.01, 2) for a in (0.5, 1.0, 2.0)]
    out += [("dp_a1_h0.01", "drucker_prager", 1.0, None, None, H / 2, PPC)]
    out += [(f"dp_mu_i_a{a:g}", "drucker_prager_mu_i", a, None, None, H, PPC) for a in (0.5, 1.0, 2.0)]
    return out


def end_time(a, smoke):
    return GATE + 0.01 if smoke else GATE + 6 * math.sqrt(a * study.WIDTH / 9.81) + 0.1


def earliest_rest(a):
    """No collapse is over within 2 sqrt(H0/g) of the gate: before, a quiet row is the settled column."""
    return GATE + 2 * math.sqrt(a * study.WIDTH / 9.81)


def case_scene(folder, law, a, seed, spheres, h, ppc, smoke, channel=None):
    if law == "live":
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "cell.json").write_text(json.dumps(
            moduli.cell_spec(seed, PREPARATION_PRESSURE, spheres, "dense"), indent=2) + "\n")
        young, poisson, _ = cell_elasticity()
        material = live_material("cell.json")
    else:
        material = twin_material(inertial=law == "drucker_prager_mu_i")
        young, poisson = material["young"], material["poisson"]
    # The finer grid runs out beyond twice Lube's runout: the twin (about 20° of friction), and the live
    # column, whose front left a grid of twice that room at 0.83 s (stop 35).
    scene = column_scene.scene(a, study.WIDTH, h, ppc, end=end_time(a, smoke), material=material,
                               p_wave=column_scene.p_wave_modulus(young, poisson), gate=GATE, room=4, channel=channel)
    scene["time"]["stop_at_rest"] = {"kinetic_energy_fraction": study.REST, "not_before": earliest_rest(a)}
    return scene


def run_case(out, build, threads, name, law, a, seed, spheres, h, ppc, smoke, channel=None):
    folder = out / name
    cost = study.run_scene(folder, case_scene(folder, law, a, seed, spheres, h, ppc, smoke, channel), build, threads)
    return record(folder, name, law, a, seed, spheres, h, ppc, cost)


def record(folder, name, law, a, seed, spheres, h, ppc, cost):
    """Measures the finished run in `folder` and writes its result.json."""
    result = study.measure(folder, a, h, ppc, earliest_rest(a), or_at_end=True)  # or where it stopped
    result = {"case": name, "law": law, "a": a, "seed": seed, "spheres": spheres, "h": h, "points_per_cell": ppc,
              **cost, **result}
    (folder / "result.json").write_text(json.dumps(result, indent=2) + "\n")
    return result


def table(results, twin):
    lines = [f"Drucker–Prager twin: φ = {twin['friction_angle']:.1f}° (sin φ = μ_s), "
             f"E = {twin['young'] / 1e6:.2f} MPa, "
             f"ν = {twin['poisson']:.3f}, ρ = {twin['density']:.0f} kg/m³\n",
             "| case | a | L0/h | ppc | measured at [s] | KE / peak | ΔL/L0 (front) | edge 5 % H0 | edge 10 % H0 | "
             "edge 15 % H0 | Lube | H∞/H0 | CPU [s] |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        when = f"{r['rest_time']:.2f}" + ("" if r["at_rest"] else " (stopped)" if r.get("failed") else
                                           " (end, not at rest)")
        lines.append(f"| {r['case']} | {r['a']:g} | {study.WIDTH / r['h']:.0f} | {r['points_per_cell']} | {when} | "
                     f"{r['kinetic_energy_fraction']:.1e} | "
                     f"{r['runout']:.2f} | " + "".join(f"{e:.2f} | " for e in r["edges"].values())
                     + f"{r['lube_runout']:.2f} | {r['final_height']:.2f} | "
                     + ("not measured |" if r["cpu_s"] is None else f"{r['cpu_s']:.0f} |"))
    return "\n".join(lines) + "\n"


def plot(results, out, file):
    """Left: the runouts against Lube's law; right: each run's front over time, from the gate's removal,
    in units of L0 and of sqrt(H0/g)."""
    fig, ax = study.lube_axes(2.0)
    styles = {("live", H, PPC): ("o", "live DEM cells"), ("live", H / 2, PPC): ("P", "live DEM cells, L0/h = 20"),
              ("drucker_prager", H, PPC): ("s", "Drucker–Prager twin"),
              ("drucker_prager", H / 2, PPC): ("X", "Drucker–Prager twin, L0/h = 20"),
              ("drucker_prager", 0.01, 2): ("^", "Drucker–Prager twin, L0/h = 20, 2 ppc"),
              ("drucker_prager_mu_i", H, PPC): ("D", "Drucker–Prager twin with the cell's μ(I)")}
    for (law, h, ppc), (marker, label) in styles.items():
        study.draw_runouts(ax, [r for r in results if (r["law"], r["h"], r["points_per_cell"]) == (law, h, ppc)
                                and not r.get("failed")], marker, label)
    ax.legend(fontsize=7)
    fig.set_size_inches(11, 4)
    ax.set_position([0.07, 0.13, 0.38, 0.8])
    fronts = fig.add_axes([0.55, 0.13, 0.42, 0.8])
    colours = {0.5: "tab:blue", 1.0: "tab:orange", 2.0: "tab:green"}
    for r in results:
        if r["h"] != H or r["a"] not in colours:
            continue
        series = read_csv(out / r["case"] / "run" / "series.csv")
        time_unit = math.sqrt(r["a"] * study.WIDTH / 9.81)
        line = {"live": "-", "drucker_prager": "--"}.get(r["law"], ":")
        fronts.plot((series["t"] - GATE) / time_unit, (series["front"] - series["front"][0]) / study.WIDTH, line,
                    color=colours[r["a"]], lw=1 if r["seed"] in (1, None) else 0.6,
                    label=f"{r['case']}" + (" (stopped)" if r.get("failed") else ""))
    fronts.set_xlim(left=0)
    fronts.set_xlabel("(t − t_gate) / sqrt(H0/g)")
    fronts.set_ylabel("front advance / L0")
    fronts.legend(fontsize=6, ncol=2)
    fronts.grid(alpha=0.3)
    fig.savefig(file, dpi=DPI)
    plt.close(fig)


def grid_pair(out):
    """The a = 1 live column on both grids (live_a1 and live_a1_h0.01 in `out`) measured at one time, the
    earlier of the two runs' ends, so that a run stopped early is compared where it stopped; [] unless
    both runs are there."""
    pair = [c for c in cases(False) if c[0] in GRID_PAIR]
    if not all((out / name / "run" / "series.csv").exists() for name, *_ in pair):
        return []
    until = float(min(read_csv(out / name / "run" / "series.csv")["t"][-1] for name, *_ in pair))
    return [{"case": name, "h": h, "until": until,
             **study.measure(out / name, a, h, ppc, earliest_rest(a), or_at_end=True, until=until)}
            for name, _, a, _, _, h, ppc in pair]


def plot_grid(pair, file):
    """The deposits of the grid pair at their common time, with Lube's runout."""
    fig, ax = plt.subplots(figsize=(6, 3))
    for r, style in zip(pair, ("-", "--")):
        ax.step(r["profile"]["x"], r["profile"]["height"], where="pre", ls=style,
                label=f"L0/h = {study.WIDTH / r['h']:.0f}, t = {r['profile_time']:.2f} s (front at {r['rest_time']:.2f} s)")
    ax.axvline(column_scene.lube_runout(1.0), color="k", ls=":", lw=0.8, label="Lube et al. 2005 (at rest)")
    ax.set_xlabel("(x − L0) / L0")
    ax.set_ylabel("deposit height / H0")
    ax.set_title("live DEM cells, a = 1", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(file, dpi=DPI)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("lube_live"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--cases", nargs="+", help="run only these cases (names as in the table)")
    parser.add_argument("--smoke", action="store_true")
    parser.add_argument("--remeasure", action="store_true", help="measure the finished runs again, run nothing")
    parser.add_argument("--channel-width", type=float, help="side walls this far apart [m] (default: none)")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    chosen = [c for c in cases(args.smoke) if not args.cases or c[0] in args.cases]
    if not chosen:
        sys.exit(f"live_study.py: --cases: expected names among {[c[0] for c in cases(args.smoke)]}")
    if args.remeasure:
        for case in chosen:
            if (done := args.out / case[0] / "result.json").exists():
                cost = {k: v for k, v in json.loads(done.read_text()).items() if k in ("cpu_s", "wall_s", "failed")}
                record(args.out / case[0], *case, cost)
        chosen = []
    for case in chosen:
        result = run_case(args.out, args.build.resolve(), args.threads, *case, args.smoke,
                          column_scene.channel(args.channel_width))
        print(json.dumps({k: v for k, v in result.items() if k != "profile"}), flush=True)
    # Every finished case, this call's and earlier ones' (the cases may run as separate calls side by side).
    results = [json.loads(f.read_text()) for c in cases(args.smoke) if (f := args.out / c[0] / "result.json").exists()]
    (args.out / "live.json").write_text(json.dumps(results, indent=2) + "\n")
    twin = twin_material()
    (args.out / "live.md").write_text(table(results, twin))
    plot(results, args.out, args.out / "live.png")
    if pair := grid_pair(args.out):
        (args.out / "live_grid.json").write_text(json.dumps(pair, indent=2) + "\n")
        plot_grid(pair, args.out / "live_grid.png")
    print(table(results, twin), end="")


if __name__ == "__main__":
    main()
