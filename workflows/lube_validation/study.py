"""Validation of the cohesionless column collapse against the planar experiments of Lube et al.
(2005): runout ΔL/L0 and final height H∞/H0 at aspect ratios a = 0.5, 1, 2, 3, measured at rest
(kinetic energy below 1e-4 of its peak), and their convergence with the grid size h, the points per
cell and the time step. Beside the front (the farthest material point), the deposit's edges where it
is 5, 10 and 15 % of H0 thick and its profile (deposit.py says why). The a = 1 h-series is run
again with μ(I) friction (column_scene.JOP_RHEOLOGY), the rate dependence a constant-friction cone
lacks. Runs mpm_solver on scenes from column_scene.py, one after another. With --channel-width W the
columns stand in a flume, between side walls W apart whose friction (--wall-friction) acts on the
out-of-plane stress, and the study runs the a-series and the h-series only.

  /usr/bin/python3 study.py [OUT] [--build BUILD] [--threads N] [--quick] [--channel-width W [--wall-friction MU]]

Writes (OUT default: $GRAINBANK_OUT/lube_validation, i.e. build/out/lube_validation) OUT/<case>/
(scene and run), OUT/results.json, OUT/results.md, OUT/runout.png and OUT/deposit.png (the a = 1
deposit profiles at every h). --quick runs only the coarse a = 1 case (a smoke test of the
workflow).
"""
import argparse
import json
import sys
from pathlib import Path

import column_scene
import deposit

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment  # noqa: E402
from plotting.tables import read_csv  # noqa: E402
from plotting.timing import timed_run  # noqa: E402

REST = 1e-4  # kinetic energy / its peak
WIDTH = 0.2  # L0 [m]


def cases(quick, channel=False):
    """(name, aspect ratio, h, points per cell, CFL, μ(I)) of the study (in a channel: the a- and h-series)."""
    if quick:
        return [("a1_h0.02_ppc2", 1.0, 0.02, 2, 0.3, False)]
    out = [(f"a{a:g}_h0.01_ppc2", a, 0.01, 2, 0.3, False) for a in (0.5, 1.0, 2.0, 3.0)]
    out += [(f"a{a:g}_h{h:g}_ppc2", a, h, 2, 0.3, False) for a in (1.0, 2.0) for h in (0.02, 0.005)]
    if channel:
        return out
    out += [(f"a1_h0.01_ppc{n}", 1.0, 0.01, n, 0.3, False) for n in (1, 3)]
    out += [(f"a1_h0.01_ppc2_cfl{c:g}", 1.0, 0.01, 2, c, False) for c in (0.15, 0.5)]
    out += [(f"a1_h{h:g}_ppc2_mu_i", 1.0, h, 2, 0.3, True) for h in (0.02, 0.01, 0.005)]
    return out


def at_rest(series, gate):
    """Index of the first row after the gate's removal whose kinetic energy is below REST of the peak
    so far; None when the run never gets there."""
    peak = 0.0
    for k, (t, e) in enumerate(zip(series["t"], series["kinetic_energy"])):
        peak = max(peak, e)
        if t > gate and e < REST * peak:
            return k
    return None


def run_scene(folder, scene, build, threads):
    """Runs mpm_solver on `scene` in `folder`: {cpu_s, wall_s, failed} (failed: "" or the solver's
    message; what the run wrote until then is kept)."""
    folder.mkdir(parents=True, exist_ok=True)
    scene_file = folder / "scene.json"
    scene_file.write_text(json.dumps(scene, indent=2) + "\n")
    wall, cpu, error = timed_run([build / "mpm_solver" / "mpm_solver", scene_file, "--out", folder / "run",
                                  "--threads", threads])
    return {"cpu_s": cpu, "wall_s": wall, "failed": error or ""}


def measure(folder, a, h, ppc, gate=column_scene.GATE_REMOVAL, or_at_end=False, until=float("inf")):
    """Runout, final height and deposit of the run in `folder`, at rest; a run that never gets there
    is measured at its last row when `or_at_end` (with at_rest False), else not at all. `until` [s]
    measures the run as if it had ended then: its rows and snapshots up to that time."""
    series = read_csv(folder / "run" / "series.csv")
    kept = series["t"] <= until
    series = {name: column[kept] for name, column in series.items()}
    g = column_scene.geometry(a, WIDTH, h, ppc)
    k = at_rest(series, gate)
    settled = k is not None
    if not settled and or_at_end:
        k = len(series["t"]) - 1
    result = {"steps": int(series["step"][-1]), "lube_runout": column_scene.lube_runout(a)}
    if k is None:
        return {**result, "at_rest": False, "rest_time": None, "runout": None, "final_height": None}
    front = series["front"][k] + g["radius"]
    height = series["max_height"][k] + g["radius"]
    runout = (front - g["wall"] - g["L0"]) / g["L0"]
    x, profile, profile_time = deposit.profile(folder / "run", g, h, until)
    energy = series["kinetic_energy"]
    return {**result, "at_rest": settled, "rest_time": float(series["t"][k]), "runout": float(runout),
            "kinetic_energy_fraction": float(energy[k] / max(energy[:k + 1])),
            "final_height": float((height - g["base"]) / g["H0"]),
            "runout_error": float(runout / column_scene.lube_runout(a) - 1),
            "edges": deposit.edges(x, profile), "profile": {"x": x.tolist(), "height": profile.tolist()},
            "profile_time": profile_time}


def run_case(out, build, threads, name, a, h, ppc, cfl, mu_i, channel=None):
    folder = out / name
    scene = column_scene.scene(a, WIDTH, h, ppc, cfl, rheology=column_scene.JOP_RHEOLOGY if mu_i else None,
                               channel=channel)
    cost = run_scene(folder, scene, build, threads)
    failed = cost.pop("failed")
    if failed:
        sys.exit(f"study.py: {name}: mpm_solver failed: {failed}")
    return {"case": name, "a": a, "h": h, "points_per_cell": ppc, "cfl": cfl, "inertial_rheology": mu_i,
            "channel": channel, **cost, **measure(folder, a, h, ppc)}


def table(results):
    thick = " | ".join(f"edge {float(f):.0%} H0" for f in deposit.EDGE_FRACTIONS)
    lines = [f"| case | a | h [m] | ppc | CFL | at rest [s] | ΔL/L0 (front) | {thick} | Lube | error | H∞/H0 | CPU [s] |",
             "|---|---|---|---|---|---|---|" + "---|" * len(deposit.EDGE_FRACTIONS) + "---|---|---|---|"]
    blank = " |" * len(deposit.EDGE_FRACTIONS)
    for r in results:
        if r["at_rest"]:
            lines.append(f"| {r['case']} | {r['a']:g} | {r['h']:g} | {r['points_per_cell']} | {r['cfl']:g} | "
                         f"{r['rest_time']:.2f} | {r['runout']:.3f} | "
                         + "".join(f"{e:.2f} | " for e in r["edges"].values()) + f"{r['lube_runout']:.2f} | "
                         f"{100 * r['runout_error']:+.1f} % | {r['final_height']:.3f} | {r['cpu_s']:.0f} |")
        else:
            lines.append(f"| {r['case']} | {r['a']:g} | {r['h']:g} | {r['points_per_cell']} | {r['cfl']:g} | "
                         f"not at rest | |{blank} {r['lube_runout']:.2f} | | | {r['cpu_s']:.0f} |")
    return "\n".join(lines) + "\n"


def lube_axes(largest_a):
    """A runout figure with Lube's law and its ±30 % band drawn, up to a = largest_a."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    a = np.linspace(0.3, largest_a + 0.3, 200)
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot(a, [column_scene.lube_runout(x) for x in a], "k-", label="Lube et al. 2005")
    ax.fill_between(a, [0.7 * column_scene.lube_runout(x) for x in a], [1.3 * column_scene.lube_runout(x) for x in a],
                    color="0.85", label="±30 %")
    ax.set_xlabel("aspect ratio a = H0/L0")
    ax.set_ylabel("runout ΔL/L0")
    return fig, ax


def draw_runouts(ax, runs, marker, label):
    """The runs' fronts (filled) and deposit edges at 10 % of H0 (open) against their aspect ratios."""
    if runs:
        ax.plot([r["a"] for r in runs], [r["runout"] for r in runs], marker, label=f"front, {label}")
        ax.plot([r["a"] for r in runs], [r["edges"]["0.1"] for r in runs], marker, mfc="none",
                label=f"edge at 10 % of H0, {label}")


def plot(results, file):
    fig, ax = lube_axes(3.0)
    for h, marker in ((0.02, "s"), (0.01, "o"), (0.005, "^")):
        draw_runouts(ax, [r for r in results if r["at_rest"] and r["h"] == h and r["points_per_cell"] == 2
                          and r["cfl"] == 0.3 and not r["inertial_rheology"]], marker,
                     f"h = {h:g} m (L0/h = {WIDTH / h:.0f})")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(file, dpi=120)


def plot_deposits(results, file):
    """The a = 1 deposit profiles at every h (2 points per cell, CFL 0.3; constant and μ(I) friction), with
    Lube's runout."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 3))
    for r in results:
        if r["at_rest"] and r["a"] == 1.0 and r["points_per_cell"] == 2 and r["cfl"] == 0.3:
            ax.step(r["profile"]["x"], r["profile"]["height"], where="pre", ls=":" if r["inertial_rheology"] else "-",
                    label=f"h = {r['h']:g} m" + (", μ(I)" if r["inertial_rheology"] else ""))
    ax.axvline(column_scene.lube_runout(1.0), color="k", ls="--", lw=0.8, label="Lube et al. 2005")
    ax.set_xlabel("(x − L0) / L0")
    ax.set_ylabel("deposit height / H0")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(file, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, nargs="?", default=environment.output_dir("lube_validation"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--channel-width", type=float, help="side walls this far apart [m] (default: none)")
    parser.add_argument("--wall-friction", type=float, default=column_scene.WALL_FRICTION)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    channel = column_scene.channel(args.channel_width, args.wall_friction)
    results = []
    for case in cases(args.quick, channel is not None):
        results.append(run_case(args.out, args.build.resolve(), args.threads, *case, channel=channel))
        print(json.dumps(results[-1]), flush=True)
        (args.out / "results.json").write_text(json.dumps(results, indent=2) + "\n")
        (args.out / "results.md").write_text(table(results))
    plot(results, args.out / "runout.png")
    plot_deposits(results, args.out / "deposit.png")


if __name__ == "__main__":
    main()
