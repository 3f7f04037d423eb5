"""Variants of an mpm_solver scene for the workflows: another law for its DEM-backed materials, a cell
library, material keys merged in, any scene key set. The one generator is `mpm_solver scene`
(mpm_solver/app/scene_overrides.hpp), which knows each law's keys; this only calls it.
"""
import argparse
import json
import math
import subprocess
from pathlib import Path


# A relative change of gravity in its 12th digit: a run's last bits. The studies' chaos floor is the
# reference run so changed, and their further draws of a run are changed by multiples of it.
GRAVITY_PERTURBATION = 1e-12


def draw_gravity_factors(draws):
    """The gravity factors of a run's further draws, after the first on the scene's own gravity:
    1 + 1e-12, 1 − 1e-12, 1 + 2e-12, … (`draws` − 1 of them)."""
    return [1 + (1 if k % 2 else -1) * ((k + 1) // 2) * GRAVITY_PERTURBATION for k in range(1, draws)]


def drawn_material(material, k):
    """The surrogate material keys of a run's K-th further draw: its length scales fitted on the K-th
    other set of probes (fit_seed K; database/surrogate/length_scales.hpp), the largest source of the
    surrogate's scatter found (stop 63)."""
    return {**material, "fit_seed": k}


# The material keys of the library laws, as the studies run them. `lookup` is the total-strain key of
# `cache` and `hybrid`; `hybrid` adds its live fallback; `surrogate` is the state key.
LOOKUP = {"k": 4, "tolerance": 1.0, "scales": {"strain": 1e-4, "rate": 1.0, "damage": 0.01}}


def lookup(**keys):
    return {"lookup": {**LOOKUP, **keys}}


def hybrid(start="warm_start", return_after=10, **lookup_keys):
    """The total-strain key, with a live fallback (`mpm_solver scene --law hybrid` drops a base
    surrogate's fallback keys that the hybrid does not take)."""
    return {**lookup(**lookup_keys), "fallback": {"start": start, "return_after": return_after}, "enrich": False}


def surrogate(tolerance_pa=50.0, return_after=5, error_budget_pa=None):
    """The state-keyed surrogate, back after 5 steps within its tolerance as in the demo; a base scene's
    error budget is removed (null) unless one is given."""
    return {"tolerance": tolerance_pa, "error_budget": error_budget_pa, "fallback": {"return_after": return_after}}


def scaled_gravity(scene_file, factor):
    """The setting {JSON pointer: value} of the gravity of `scene_file` times `factor`, for variant()."""
    return {"/gravity/g": [g * factor for g in json.loads(Path(scene_file).read_text())["gravity"]["g"]]}


def add_nonlocal_length_option(parser, help_text):
    """Adds --nonlocal-length ℓ [m] to `parser`: a positive length, or None (local cells) when absent."""
    def positive_length(text):
        value = float(text)
        if not value > 0:
            raise argparse.ArgumentTypeError(f"expected a positive length [m], got {text}")
        return value
    parser.add_argument("--nonlocal-length", type=positive_length, help=help_text)


def add_points_per_cell_option(parser, default, help_text):
    """Adds --points-per-cell N to `parser`: material points per grid cell and direction, an integer >= 1,
    or `default` when absent."""
    def at_least_one(text):
        if not text.strip().lstrip("+-").isdigit() or int(text) < 1:
            raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {text}")
        return int(text)
    parser.add_argument("--points-per-cell", type=at_least_one, default=default, help=help_text)


def friction_coefficient(text):
    """An argparse type: a Coulomb friction coefficient, a number >= 0."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not value >= 0:
        raise argparse.ArgumentTypeError(f"expected a friction coefficient >= 0, got {text}")
    return value


def transfer_arg(text):
    """The scene's integration.transfer named by `text`: "apic", "pic", "apic_flip:RATE" (APIC-FLIP with
    RATE PIC per second) or RATE alone (the FLIP/PIC blend)."""
    if text in ("apic", "pic"):
        return text
    try:
        if text.startswith("apic_flip:"):
            return {"apic_flip": {"pic_rate": float(text.split(":", 1)[1])}}
        return {"flip_pic": {"pic_rate": float(text)}}
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected apic, pic, RATE or apic_flip:RATE, got {text}") from None


def transfer_name(text):
    """`text` itself once transfer_arg accepts it: an argparse type for options that keep the name."""
    transfer_arg(text)
    return text


def transfer_settings(text):
    """({JSON pointer: value} setting the transfer `text` names (transfer_arg), the suffix naming such a
    run); ({}, "") for None, the scene's own transfer."""
    if text is None:
        return {}, ""
    return {"/integration/transfer": transfer_arg(text)}, "_" + text.replace(":", "")


def regularization_settings(nonlocal_length):
    """({JSON pointer: value} regularizing a scene over `nonlocal_length` [m] (the scene's
    regularization.nonlocal_length), the suffix naming such a run); ({}, "") for None, a local run."""
    if nonlocal_length is None:
        return {}, ""
    return {"/regularization": {"nonlocal_length": nonlocal_length}}, f"_nl{nonlocal_length:g}"


def require_whole_cells(parser, cell_size, lengths):
    """Stops `parser` with an error naming the option unless each of `lengths` ((option, length [m])
    pairs) is a whole number of grid cells of `cell_size`: scenes seed their points half a cell off a region's
    edges, so an edge inside a cell would put a point into the wall or platen standing on it."""
    for name, length in lengths:
        cells = length / cell_size
        if round(cells) < 1 or abs(cells - round(cells)) > 1e-6:
            parser.error(f"{name} {length:g}: expected a whole number of grid cells of {cell_size:g} m")


def variant(build, base, out, law=None, library=None, material=None, settings=None):
    """Writes `out`: the scene file `base` with `law` and `library` for every DEM-backed material (a
    library replaces `cell`), the `material` keys merged into them (a `cell` there replaces the
    library), then each {JSON pointer: value} of `settings` set (e.g. {"/time/end": 0.05}). Its cell
    and library paths are absolute. `build` is the build directory holding mpm_solver."""
    command = [Path(build) / "mpm_solver" / "mpm_solver", "scene", base, "--out", out]
    if law:
        command += ["--law", law]
    if library:
        command += ["--library", Path(library).resolve()]
    if material:
        command += ["--material", json.dumps(material)]
    for pointer, value in (settings or {}).items():
        command += ["--set", f"{pointer}={json.dumps(value)}"]
    done = subprocess.run([str(c) for c in command], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"mpm_solver scene {base} -> {out} failed:\n{done.stderr}")
    return json.loads(Path(out).read_text())
