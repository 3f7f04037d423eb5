"""Scene of the planar cohesionless column collapse of Lube et al. (2005) for mpm_solver: a
Drucker–Prager column (φ = 30°, c = 0, ρ = 1500 kg/m³, E = 5 MPa, ν = 0.3) of width L0 and height
a L0 against a back wall, on a base with friction 0.5 (walls 0.3, as the example scenes), held by a
gate removed at t = 0.02 s. The same setup as tests/mpm/granular_column.hpp (the CI test). With
--channel-width, the column stands in a flume: two side walls W apart, parallel to the plane, whose
friction (--wall-friction, default that of the back wall and the gate) acts on the out-of-plane stress
(mpm_solver/core/channel_walls.hpp).

  python3 column_scene.py OUT.json --aspect-ratio A [--width L0] [--cell-size H] [--points-per-cell N]
                          [--cfl C] [--end T] [--transfer apic|pic|RATE|apic_flip:RATE]
                          [--inertial-rheology] [--separation] [--channel-width W [--wall-friction MU]]
"""
import argparse
import json
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from plotting import scenes  # noqa: E402

GATE_REMOVAL = 0.02  # [s]
GRAVITY = 9.81  # [m/s²], downwards
DENSITY, YOUNG, POISSON, FRICTION_ANGLE = 1500.0, 5e6, 0.3, 30.0
BASE_FRICTION, WALL_FRICTION = 0.5, 0.3


def lube_runout(a):
    """ΔL/L0 of Lube et al. 2005 (planar): 1.2 a for a ≲ 1.8, 1.9 a^(2/3) above."""
    return 1.2 * a if a <= 1.8 else 1.9 * a ** (2.0 / 3.0)


def p_wave_modulus(young=YOUNG, poisson=POISSON):
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    return lam + young / (1 + poisson)


def drucker_prager(friction_angle=FRICTION_ANGLE, density=DENSITY, young=YOUNG, poisson=POISSON, rheology=None,
                   separation=False):
    """The column's material: a cohesionless Drucker–Prager cone (the study's sand by default);
    `separation`: sand pulled apart carries nothing until packed back (drucker_prager_law.hpp)."""
    out = {"name": "sand", "law": "drucker_prager", "density": density, "young": young, "poisson": poisson,
           "friction_angle": friction_angle}
    if rheology:
        out["inertial_rheology"] = rheology
    if separation:
        out["separation"] = True
    return out


DEFAULT_TRANSFER = {"apic_flip": {"pic_rate": 5.0}}  # the solver's default
# μ(I) on the column's static friction sin φ: the rate dependence (μ_2 − μ_s = 0.26, I_0 = 0.279) of
# the glass beads of Jop, Forterre & Pouliquen (2005, J. Fluid Mech. 541:167; d = 0.53 mm, ρ_s = 2450).
JOP_RHEOLOGY = {"mu_2": math.sin(math.radians(FRICTION_ANGLE)) + 0.26, "inertial_number_0": 0.279,
                "grain_diameter": 0.53e-3, "grain_density": 2450.0}


def scene(a, width=0.2, h=0.02, ppc=2, cfl=0.3, end=None, transfer=DEFAULT_TRANSFER, rheology=None,
          material=None, p_wave=None, gate=GATE_REMOVAL, room=2, channel=None):
    """The column scene; `material` (named "sand") replaces the Drucker–Prager sand, and `p_wave`, its
    P-wave modulus, sets the stiffness of base and walls. The grid reaches `room` times Lube's runout
    beyond the column. `channel` ({"width": W, "friction": μ_w}) puts it between side walls."""
    L0, H0 = width, a * width
    base = wall = 2 * h
    cells_x = math.ceil((wall + L0 * (1 + room * lube_runout(a)) + 2 * h) / h)
    cells_y = math.ceil((base + H0 + 2 * h) / h)
    # Base and walls as stiff as the material over one cell: sqrt(k_n / m_p) = c_p / h.
    k_n = (p_wave or p_wave_modulus()) / ppc**2
    top = base + H0 + h
    contact = lambda mu: {"k_n": k_n, "k_t": k_n, "friction": mu, "damping": 0.5}
    end = end or 8 * math.sqrt(H0 / GRAVITY) + 0.3  # at rest after about 4 to 5 sqrt(H0 / g)
    sand = material or drucker_prager(rheology=rheology)
    out = {
        "grid": {"origin": [0, 0], "cell_size": h, "cells": [cells_x, cells_y]},
        "time": {"end": end, "output_interval": end / 10, "series_interval": 2e-3, "cfl": cfl, "contact_factor": cfl},
        "integration": {"transfer": transfer},
        "effects": {"gravity": True, "boundary_friction": True},
        "gravity": {"g": [0, -GRAVITY]},
        "materials": [sand],
        "regions": [{"material": "sand", "rectangle": {"min": [wall, base], "max": [wall + L0, base + H0]},
                     "points_per_cell": ppc}],
        "obstacles": [
            {"line": [[-1, base], [cells_x * h + 1, base]], **contact(BASE_FRICTION)},
            {"line": [[wall, base], [wall, top]], **contact(WALL_FRICTION)},
            {"line": [[wall + L0, base], [wall + L0, top]], **contact(WALL_FRICTION), "remove_at": gate},
        ],
    }
    if channel:
        out["effects"]["channel_walls"] = True
        out["channel_walls"] = channel
    return out


def channel(width, friction=WALL_FRICTION):
    """Side walls `width` apart for scene(), or None when width is None."""
    return None if width is None else {"width": width, "friction": friction}


def geometry(a, width=0.2, h=0.02, ppc=2):
    """Where the column starts: wall x, base y, L0, H0 and the point radius (to turn point centres
    into the material's edge)."""
    return {"wall": 2 * h, "base": 2 * h, "L0": width, "H0": a * width, "radius": h / (2 * ppc)}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path)
    parser.add_argument("--aspect-ratio", type=float, required=True)
    parser.add_argument("--width", type=float, default=0.2)
    parser.add_argument("--cell-size", type=float, default=0.02)
    parser.add_argument("--points-per-cell", type=int, default=2)
    parser.add_argument("--cfl", type=float, default=0.3)
    parser.add_argument("--end", type=float)
    parser.add_argument("--transfer", type=scenes.transfer_arg, default=DEFAULT_TRANSFER,
                        help="apic, pic, a FLIP/PIC rate [1/s] or apic_flip:RATE (default apic_flip:5)")
    parser.add_argument("--inertial-rheology", action="store_true",
                        help="μ(I) with the rate dependence of Jop et al.'s glass beads (JOP_RHEOLOGY)")
    parser.add_argument("--separation", action="store_true",
                        help="sand pulled apart carries nothing until packed back (Dunatunga & Kamrin 2015)")
    parser.add_argument("--channel-width", type=float, help="side walls this far apart [m] (default: none)")
    parser.add_argument("--wall-friction", type=float, default=WALL_FRICTION)
    args = parser.parse_args()
    rheology = JOP_RHEOLOGY if args.inertial_rheology else None
    s = scene(args.aspect_ratio, args.width, args.cell_size, args.points_per_cell, args.cfl, args.end, args.transfer,
              rheology, material=drucker_prager(rheology=rheology, separation=args.separation),
              channel=channel(args.channel_width, args.wall_friction))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(s, indent=2) + "\n")


if __name__ == "__main__":
    main()
