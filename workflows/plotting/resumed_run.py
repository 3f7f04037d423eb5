"""A study's run that was stopped (the study killed, the session ended) goes on from mpm_solver's
last checkpoint instead of starting again: hours of DEM are not thrown away.

mpm_solver writes `restart.h5` into its output folder at snapshots (`--checkpoint-every`) and when it
is stopped by a signal; `mpm_solver SCENE --restart R --out NEW` continues from it bit for bit, into
a new folder. Here each continuation is a segment, `FOLDER/resumed_1`, `resumed_2`, …, each started
from the newest checkpoint (the last segment's that has one). Once the last segment has finished,
`join` makes FOLDER read as one run: its `series.csv`, `points.pvd` and `tracked_points.csv` become
each segment's rows and snapshots up to the next segment's start, then the next segment's after it
(the snapshot files stay in their segment's folder, named from the collection), and the last
segment's `summary.json` is the run's, as mpm_solver wrote it for that segment. A run stopped at a
checkpoint and resumed so reads to the byte as the same run never stopped. Joining again gives the
same files, so a join that is itself stopped is simply done again. The cells of tracked points stay
in each segment's `cells/` (collapse_figures reads a run's segments).
"""
import json
import math
import os
from pathlib import Path

from . import vtu

SEGMENT = "resumed_"


def segments(folder):
    """The run's continuation folders, in order: FOLDER/resumed_1, resumed_2, … (those that exist)."""
    folder = Path(folder)
    found = []
    while (folder / f"{SEGMENT}{len(found) + 1}").is_dir():
        found.append(folder / f"{SEGMENT}{len(found) + 1}")
    return found


def newest_checkpoint(folder):
    """The restart file a stopped run goes on from: its last segment's that has one, else the run's
    own; None when the run wrote none (it starts again)."""
    for part in [*reversed(segments(folder)), Path(folder)]:
        if (part / "restart.h5").exists() and (part / "series.csv").exists():
            return part / "restart.h5"
    return None


def next_segment(folder):
    return Path(folder) / f"{SEGMENT}{len(segments(folder)) + 1}"


def _seam_limits(parts):
    """For each segment, the last time it may give a row: up to and including the next segment's start
    (its row there is the same state, and it carries the step that led to it, where the next segment's
    first row has none); infinity for the last."""
    starts = [vtu.read_pvd(part / "points.pvd")[0][0] for part in parts[1:]]
    return [start * (1 + 1e-12) for start in starts] + [math.inf]


def _time(line):
    return float(line.split(",", 1)[0])


def _complete_lines(file):
    """The header and the complete rows of a CSV (a last row without its line end is the one a killed
    run was writing)."""
    text = file.read_text()
    lines = text.splitlines()
    if lines and not text.endswith("\n"):
        lines.pop()
    if not lines:
        raise ValueError(f"{file}: empty, expected a header line")
    return lines[0], lines[1:]


def _write_atomically(file, text):
    scratch = file.with_name(file.name + ".joining")
    scratch.write_text(text)
    os.replace(scratch, file)


def _join_csv(folder, parts, limits, name):
    if not all((part / name).exists() for part in parts):
        return
    header, rows, last = None, [], -math.inf
    for part, limit in zip(parts, limits):
        head, lines = _complete_lines(part / name)
        if header is not None and head != header:
            raise ValueError(f"{part / name}: header differs from the first segment's {Path(folder) / name}")
        header = head
        kept = [line for line in lines if last < _time(line) <= limit]
        rows += kept
        last = _time(kept[-1]) if kept else last
    _write_atomically(Path(folder) / name, "\n".join([header, *rows]) + "\n")


def _join_pvd(folder, parts, limits):
    entries, last = [], -math.inf
    for part, limit in zip(parts, limits):
        for t, path in vtu.read_pvd(part / "points.pvd"):
            if last < t <= limit:
                file = os.path.relpath(path, folder)
                entries.append(f'    <DataSet timestep="{t!r}" group="" part="0" file="{file}"/>')
                last = t
    text = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
            "  <Collection>\n" + "".join(e + "\n" for e in entries) + "  </Collection>\n</VTKFile>\n")
    _write_atomically(Path(folder) / "points.pvd", text)


def join(folder):
    """Makes FOLDER, a run and its finished segments, read as one run (above). Nothing to do without
    segments."""
    folder = Path(folder)
    parts = segments(folder)
    if not parts:
        return
    parts = [folder, *parts]
    limits = _seam_limits(parts)
    _join_csv(folder, parts, limits, "series.csv")
    _join_csv(folder, parts, limits, "tracked_points.csv")
    _join_pvd(folder, parts, limits)
    if (parts[-1] / "summary.json").exists():  # a segment that failed may have written none
        summary = json.loads((parts[-1] / "summary.json").read_text())
        summary["resumed_segments"] = [str(part.relative_to(folder)) for part in parts[1:]]
        _write_atomically(folder / "summary.json", json.dumps(summary, indent=2) + "\n")
