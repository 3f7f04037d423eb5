#!/usr/bin/python3
"""Steady shear flow under a held normal stress: the friction and dilatancy a law flows with, against
live cells. One material point, from the library's template, in simple shear at the rate γ̇ while
σ_yy is servoed to −P (the scene key integration.homogeneous_drive.normal_stress), to a shear strain
`strain`, run by three laws: live cells of the template's own packing (the reference), of another
packing seed (the noise floor), and the law under test. This is how a point in a flowing column is
loaded (its pressure set by the weight above it, its volume free), where the kinematic element tests
(element_tests.py) hold the volume, so that a dense cell builds pressure and no steady flow is
reached.

  held_shear.py OUT --library LIB --floor-cell CELL.json [--template 1] [--law surrogate]
                [--material JSON] [--pressures 300 1000] [--rates 1 3] [--strain 1] [--build DIR]

Per run, over the second half of the strain (from the snapshots, one per 0.02 of strain): the friction
μ = mean |σ_xy| / mean(−σ_yy), the mean −σ_yy (how well the servo held P), the normal stresses
σ_xx/σ_yy and σ_zz/σ_yy, the volumetric strain −ln(ρ/ρ0) at the end (dilation positive), the damage at
the end, the share of live point-steps and the CPU time. Per condition, the law's friction error
against the reference over the floor's. Writes OUT/held_shear.md, OUT/held_shear.json and
OUT/held_shear.png (friction and dilation against strain, per condition); the runs stay in OUT/runs/.
"""
import argparse
import json
import resource
import subprocess
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from plotting import environment, tables, vtu  # noqa: E402  (after the path set-up)
from plotting.figures import plt, DPI  # noqa: E402

import element_tests  # noqa: E402  (the demo material's settings, as the element tests take them)

SNAPSHOT_STRAIN = 0.02


def material(args, law):
    """The material block of `law`: "reference" and "floor" are live cells of the two packings."""
    live = element_tests.material_settings(argparse.Namespace(law="live", material={}))
    if law == "reference":
        return {"law": "live", "library": str(args.library.resolve()), "template": args.template, **live}
    if law == "floor":
        return {"law": "live", "cell": str(args.floor_cell.resolve()), **live}
    return element_tests.law_block(args)


def scene(block, pressure, rate, strain):
    """Simple shear at `rate` under σ_yy = −pressure, to `strain`, one snapshot per SNAPSHOT_STRAIN."""
    return element_tests.one_point_scene(
        block, {"L": [[0, rate], [0, 0]], "normal_stress": {"stress": pressure}}, strain / rate,
        SNAPSHOT_STRAIN / rate)


def history(run_folder):
    """Per snapshot: shear strain, the stress (9 components, tension positive) and the dilation −ln(ρ/ρ0)."""
    snapshots = vtu.read_run(run_folder)
    stress = np.array([s.fields["stress"][0] for s in snapshots])
    density = np.array([s.fields["density"][0] for s in snapshots])
    return np.arange(len(snapshots)) * SNAPSHOT_STRAIN, stress, np.log(density[0] / density), snapshots[-1]


def steady_flow(run_folder):
    """The run's steady-flow measures (module docstring) from its snapshots and summary."""
    _, stress, dilation, last = history(run_folder)
    steady = stress[len(stress) // 2:]
    normal = -steady[:, 4]
    summary = json.loads((run_folder / "summary.json").read_text())
    law = summary["coupling"]["laws"][0]
    return {"friction": float(np.mean(np.abs(steady[:, 1])) / np.mean(normal)),
            "normal_stress_Pa": float(np.mean(normal)),
            "sxx_over_syy": float(np.mean(steady[:, 0]) / np.mean(steady[:, 4])),
            "szz_over_syy": float(np.mean(steady[:, 8]) / np.mean(steady[:, 4])),
            "dilation": float(dilation[-1]),
            "damage": float(last.fields["damage"][0]),
            "live_share": (1.0 if law["law"] == "live" else law["live_point_steps"] / summary["coupling"]["point_steps"])}


def plot(folders, out):
    """folders: {(P, rate): {run name: run folder}}, one column of panels per condition."""
    fig, axes = plt.subplots(2, len(folders), figsize=(3.2 * len(folders), 5.2), squeeze=False, sharex=True)
    for column, ((pressure, rate), runs) in enumerate(folders.items()):
        for name, folder in runs.items():
            strain, stress, dilation, _ = history(folder)
            axes[0][column].plot(strain[1:], np.abs(stress[1:, 1]) / -stress[1:, 4], label=name)
            axes[1][column].plot(strain, dilation, label=name)
        axes[0][column].set_title(f"P = {pressure:g} Pa, γ̇ = {rate:g} /s", fontsize=9)
        axes[0][column].set_ylim(0, 1.2)
        axes[1][column].set_xlabel("shear strain")
    axes[0][0].set_ylabel("|σ_xy| / (−σ_yy)")
    axes[1][0].set_ylabel("dilation −ln(ρ/ρ₀)")
    axes[0][0].legend(fontsize=7)
    for ax in axes.flat:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=DPI)
    plt.close(fig)


def run(mpm_solver, folder, scene_dict):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "scene.json").write_text(json.dumps(scene_dict, indent=2) + "\n")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([mpm_solver, folder / "scene.json", "--out", folder / "run", "--threads", "1"], check=True,
                   stdout=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return {**steady_flow(folder / "run"),
            "cpu_s": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    element_tests.add_law_arguments(parser)
    parser.add_argument("--pressures", type=float, nargs="+", default=[300.0, 1000.0], help="P [Pa]")
    parser.add_argument("--rates", type=float, nargs="+", default=[1.0, 3.0], help="γ̇ [1/s]")
    parser.add_argument("--strain", type=float, default=1.0)
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    args = parser.parse_args()
    if not (all(p > 0 for p in args.pressures) and all(r > 0 for r in args.rates) and args.strain > 0):
        parser.error("--pressures, --rates and --strain: expected positive numbers")
    mpm_solver = args.build.resolve() / "mpm_solver" / "mpm_solver"
    rows, folders = [], {}
    for pressure in args.pressures:
        for rate in args.rates:
            results = {}
            for who in ("reference", "floor", "law"):
                folder = args.out / "runs" / f"P{pressure:g}_rate{rate:g}_{who}"
                results[who] = run(mpm_solver, folder, scene(material(args, who), pressure, rate, args.strain))
                name = args.law if who == "law" else who
                folders.setdefault((pressure, rate), {})[name] = folder / "run"
                rows.append({"P_Pa": pressure, "rate": rate, "run": name,
                             **{k: round(v, 4) for k, v in results[who].items()}, "friction_error_over_floor": None})
            floor = abs(results["floor"]["friction"] - results["reference"]["friction"])
            error = abs(results["law"]["friction"] - results["reference"]["friction"])
            rows[-1]["friction_error_over_floor"] = round(error / floor, 2) if floor > 0 else None
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "held_shear.json").write_text(json.dumps(
        {"library": str(args.library.resolve()), "template": args.template, "law": args.law,
         "material": element_tests.material_settings(args), "floor_cell": str(args.floor_cell.resolve()),
         "strain": args.strain, "runs": rows}, indent=2) + "\n")
    tables.write_markdown(args.out / "held_shear.md", rows)
    plot(folders, args.out / "held_shear.png")
    print((args.out / "held_shear.md").read_text(), end="")


if __name__ == "__main__":
    main()
