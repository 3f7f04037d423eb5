"""Readers of the VTU/PVD files that mpm_solver writes (mpm_solver/io/vtu_writer.cpp).

The VTU files are UnstructuredGrid with raw appended binary arrays (UInt64 size headers, little
endian), one vertex per material point; the time is in the FieldData `TimeValue`.
"""
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

_TYPES = {"Float64": "<f8", "Float32": "<f4", "Int64": "<i8", "Int32": "<i4", "UInt8": "u1"}
_APPENDED = b'<AppendedData encoding="raw">'
# The names of the codes 0–3 of the field `source` (mpm_solver/core/coupling_status.hpp: StressSource).
STRESS_SOURCES = ["analytic", "live", "hit", "miss"]


@dataclass
class Snapshot:
    """One output step: `time`, `xy` (n × 2 positions) and `fields` (name → n or n × c array)."""
    time: float
    xy: np.ndarray
    fields: dict

    def __len__(self):
        return len(self.xy)

    def spacing(self):
        """Median distance from a material point to its nearest neighbour [m]."""
        if len(self.xy) < 2:
            return 0.0
        d = np.hypot(*(self.xy[:, None, k] - self.xy[None, :, k] for k in (0, 1)))
        np.fill_diagonal(d, np.inf)
        return float(np.median(d.min(axis=1)))

    def speed(self):
        return np.hypot(self.fields["velocity"][:, 0], self.fields["velocity"][:, 1])

    def in_plane_stress(self):
        """n × 3 array of σ_xx, σ_yy, σ_xy [Pa] (tension positive)."""
        s = self.fields["stress"]
        return np.column_stack([s[:, 0], s[:, 4], s[:, 1]])

    def by_id(self, values):
        """values reordered by material point id (ids are 0 … n−1 for a seeded scene)."""
        return values[np.argsort(self.fields["id"])]


def read_vtu(file):
    """Parses a VTU of mpm_solver; raises ValueError naming the file when it is malformed."""
    file = Path(file)
    data = file.read_bytes()
    head, marker, tail = data.partition(_APPENDED)
    start = tail.find(b"_")
    if not marker or start < 0:
        raise ValueError(f"{file}: no raw appended data block")
    block = tail[start + 1:]
    # The XML part up to the appended block, closed so that ElementTree can parse it.
    root = ET.fromstring(head + b"</VTKFile>")
    if root.get("type") != "UnstructuredGrid" or root.get("header_type") != "UInt64":
        raise ValueError(f"{file}: expected an UnstructuredGrid with UInt64 headers")
    piece = root.find("UnstructuredGrid/Piece")
    n = int(piece.get("NumberOfPoints"))
    time_value = root.find("UnstructuredGrid/FieldData/DataArray[@Name='TimeValue']")
    time = float(time_value.text) if time_value is not None else float("nan")

    def array(element):
        kind, components = element.get("type"), int(element.get("NumberOfComponents", "1"))
        offset = int(element.get("offset"))
        size = int(np.frombuffer(block, "<u8", 1, offset)[0])
        values = np.frombuffer(block, _TYPES[kind], size // np.dtype(_TYPES[kind]).itemsize, offset + 8)
        if values.size != n * components:
            raise ValueError(f"{file}: array {element.get('Name')}: expected {n} × {components} values, got {values.size}")
        return values.reshape(n, components) if components > 1 else values

    fields = {e.get("Name"): array(e) for e in piece.findall("PointData/DataArray")}
    points = array(piece.find("Points/DataArray"))
    return Snapshot(time, points[:, :2].copy(), fields)


def read_pvd(file):
    """[(time, vtu path)] of a points.pvd collection, in time order."""
    file = Path(file)
    root = ET.parse(file).getroot()
    entries = [(float(d.get("timestep")), file.parent / d.get("file")) for d in root.iter("DataSet")]
    if not entries:
        raise ValueError(f"{file}: no DataSet entries")
    return sorted(entries)


def read_run(folder):
    """Every snapshot of a run folder (its points.pvd), in time order."""
    return [read_vtu(path) for _, path in read_pvd(Path(folder) / "points.pvd")]


def pick_times(snapshots, count):
    """`count` snapshots evenly spread from the first to the last (for figure panels)."""
    if len(snapshots) <= count:
        return list(snapshots)
    index = np.linspace(0, len(snapshots) - 1, count).round().astype(int)
    return [snapshots[i] for i in index]


def vtu_index(path):
    """The output index NNNNNN of points_NNNNNN.vtu."""
    match = re.search(r"points_(\d+)\.vtu$", str(path))
    if not match:
        raise ValueError(f"{path}: not a points_NNNNNN.vtu file")
    return int(match.group(1))
