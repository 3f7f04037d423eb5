"""A study's run that was stopped (the study killed, the session ended) goes on from mpm_solver's
last checkpoint instead of starting again: hours of DEM are not thrown away.

mpm_solver writes `restart.h5` into its output folder at snapshots (`--checkpoint-every`) and when it
is stopped by a signal; `mpm_solver SCENE --restart R --out NEW` continues from it bit for bit, into
a new folder. Here each continuation is a segment, `FOLDER/resumed_1`, `resumed_2`, …, each started
from the newest checkpoint (the last segment's that has one). Once the last segment has finished,
`join` makes FOLDER read as one run: its `series.csv`, `points.pvd` and `tracked_points.csv` become
each segment's rows and snapshots up to the next segment's start, then the next segment's after it
(the snapshot files stay in their segment's folder, named from the collection), and the last
segment's `summary.json` is the run's, as mpm_solver wrote it for that segment, with the CPU seconds each
segment's mpm_solver reported (`segments_cpu_s`, None for one that reported none: killed outright, or
an older build's). A run stopped at a
checkpoint and resumed so reads to the byte as the same run never stopped. Joining again gives the
same files, so a join that is itself stopped is simply done again. The cells of tracked points stay
in each segment's `cells/` (collapse_figures reads a run's segments).
"""
import json
import math
import os
from pathlib import Path

from . import tables, vtu

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


def segment_starts(run_dirs):
    """The time each segment of a resumed run after the first takes over: its first snapshot."""
    return [vtu.read_pvd(Path(d) / "points.pvd")[0][0] for d in run_dirs[1:]]


def _seam_limits(parts):
    """For each segment, the last time it may give a row: up to and including the next segment's start
    (its row there is the same state, and it carries the step that led to it, where the next segment's
    first row has none); infinity for the last."""
    return [start * (1 + 1e-12) for start in segment_starts(parts)] + [math.inf]


def _write_atomically(file, text):
    scratch = file.with_name(file.name + ".joining")
    scratch.write_text(text)
    os.replace(scratch, file)


def _across_seams(timed_items, limits):
    """Of each segment's (t, item) pairs, in time order, those after the previous segments' last kept
    time and up to the segment's limit. Within a segment several items may share a time (the rows of
    tracked_points.csv, one per point)."""
    last = -math.inf
    for items, limit in zip(timed_items, limits):
        kept = [(t, item) for t, item in items if last < t <= limit]
        yield from (item for _, item in kept)
        last = kept[-1][0] if kept else last


def _join_csv(folder, parts, limits, name):
    if not all((part / name).exists() for part in parts):
        return
    first_header, timed_rows = None, []
    for part in parts:
        header, *lines = tables.complete_lines(part / name)
        first_header = first_header or header
        if header != first_header:
            raise ValueError(f"{part / name}: header differs from the first segment's {Path(folder) / name}")
        timed_rows.append([(float(line.split(",", 1)[0]), line) for line in lines])
    rows = list(_across_seams(timed_rows, limits))
    _write_atomically(Path(folder) / name, "\n".join([first_header, *rows]) + "\n")


def _join_pvd(folder, parts, limits):
    collections = ([(t, (t, os.path.relpath(path, folder))) for t, path in vtu.read_pvd(part / "points.pvd")]
                   for part in parts)
    entries = "".join(f'    <DataSet timestep="{t!r}" group="" part="0" file="{file}"/>\n'
                      for t, file in _across_seams(collections, limits))
    text = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
            "  <Collection>\n" + entries + "  </Collection>\n</VTKFile>\n")
    _write_atomically(Path(folder) / "points.pvd", text)


def _segments_cpu_s(folder, parts):
    """Each part's CPU seconds as its mpm_solver reported them (None where it did not); the run's own
    folder's from the joined summary that replaced its own, when it was joined before."""
    found = []
    for part in parts:
        file = part / "summary.json"
        summary = json.loads(file.read_text()) if file.exists() else {}
        found.append(summary["segments_cpu_s"][0] if part == folder and "segments_cpu_s" in summary
                     else summary.get("process_cpu_time"))
    return found


def join(folder):
    """Makes FOLDER, a run and its finished segments, read as one run (above), and returns the joined
    summary (None when the last segment wrote none). Nothing to do without segments."""
    folder = Path(folder)
    parts = segments(folder)
    if not parts:
        return None
    parts = [folder, *parts]
    cpu_s = _segments_cpu_s(folder, parts)
    limits = _seam_limits(parts)
    _join_csv(folder, parts, limits, "series.csv")
    _join_csv(folder, parts, limits, "tracked_points.csv")
    _join_pvd(folder, parts, limits)
    if (parts[-1] / "summary.json").exists():  # a segment that failed may have written none
        summary = json.loads((parts[-1] / "summary.json").read_text())
        summary["resumed_segments"] = [str(part.relative_to(folder)) for part in parts[1:]]
        summary["segments_cpu_s"] = cpu_s
        _write_atomically(folder / "summary.json", json.dumps(summary, indent=2) + "\n")
        return summary
    return None
