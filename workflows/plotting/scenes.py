"""Variants of an mpm_solver scene for the workflows: another law for its DEM-backed materials, a cell
library, material keys merged in, any scene key set. The one generator is `mpm_solver scene`
(mpm_solver/app/scene_overrides.hpp), which knows each law's keys; this only calls it.
"""
import json
import subprocess
from pathlib import Path


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
