"""Readers of the DEM cells of tracked points (mpm_solver/io/tracked_cells.hpp): cells/point_<id>_<NNNNNN>.vtk
(intact bonds as LINES) and .csv (cell matrix h in the first three data rows)."""
import re
from pathlib import Path

import numpy as np

_NAME = re.compile(r"point_(\d+)_(\d+)\.vtk$")


def bond_count(vtk_file):
    """Number of intact bonds of a cell VTK file (its LINES section)."""
    for line in Path(vtk_file).read_text().splitlines():
        if line.startswith("LINES "):
            return int(line.split()[1])
    raise ValueError(f"{vtk_file}: no LINES section")


def bonds_per_sphere(vtk_file):
    """Intact bonds per sphere of a cell VTK file: LINES over VERTICES, unchanged when a cell re-tiles."""
    spheres = None
    for line in Path(vtk_file).read_text().splitlines():
        if line.startswith("VERTICES "):
            spheres = int(line.split()[1])
            break
    if not spheres:
        raise ValueError(f"{vtk_file}: no VERTICES section")
    return bond_count(vtk_file) / spheres


def cell_matrix(csv_file):
    """The 3 × 3 cell matrix h of a packing CSV (columns are the cell vectors) [m]."""
    rows = [line for line in Path(csv_file).read_text().splitlines() if line.strip() and not line.startswith("#")]
    return np.array([[float(v) for v in re.split(r"[,\s]+", row.strip())] for row in rows[:3]])


def tracked_cell_files(run_dir):
    """{point id → [(output index, vtk path)]} of a run's cells/ folder, in output order."""
    files = {}
    for path in sorted(Path(run_dir, "cells").glob("point_*.vtk")):
        point, index = map(int, _NAME.search(path.name).groups())
        files.setdefault(point, []).append((index, path))
    return files
