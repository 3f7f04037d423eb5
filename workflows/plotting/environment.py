"""The environment of the workflow scripts, as workflows/env.sh sets it for the shell scripts: the
build directory (GRAINBANK_BUILD_DIR), where runs write by default (GRAINBANK_OUT, never the source
tree) and the thread count (THREADS)."""
import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _from_root(variable, default):
    path = Path(os.environ.get(variable) or default)
    return path if path.is_absolute() else ROOT / path


def build_dir():
    return _from_root("GRAINBANK_BUILD_DIR", "build")


def output_dir(name):
    """The default output folder of the workflow `name`: GRAINBANK_OUT/name, by default build/out/name."""
    return _from_root("GRAINBANK_OUT", build_dir() / "out") / name


def threads():
    return int(os.environ.get("THREADS") or os.cpu_count())
