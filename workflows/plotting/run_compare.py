"""Running a scene for a study, timed and resumable, and its errors against a reference run of the
same scene: front = worst relative runout error (rows with a reference runout above 1 cm), runout =
relative error of the final runout (None when the reference ran out less than 1 cm), stress = mean
relative L2 of the in-plane stress field (points matched by id, by nearest position when the
discretisation differs), smoothed stress = the same of both fields averaged over one point spacing
(flow.smoothed_stress_error), deposit = RMS difference of the free-surface height at the last common
output [m], mass edge and centroid = relative errors of the
advance of the 95 % mass edge and of the centroid there (None when the reference's moved less than 1 cm):
the bulk measures, which converge with the grid where the front does not; kinetic energy = its signed
relative change at the last common row (None when the reference is nearly at rest there)."""
import json
from pathlib import Path

import numpy as np

from plotting import flow, resumed_run, tables, vtu
from plotting.timing import timed_run


def timed_scene_run(build, scene_file, folder, threads):
    """Runs mpm_solver on `scene_file` into `folder` unless a finished run is there; returns
    {wall_s, cpu_s, failed}. A run that was stopped before it finished goes on from its last
    checkpoint (plotting/resumed_run.py); then `resumed_from` names the checkpoint, wall_s is of its
    last segment, and cpu_s adds the earlier segments' CPU as their mpm_solver reported it, naming
    in `uncounted_segments` those that reported none (killed outright, or an older build's). A run
    that stops (e.g. a point thrown out of the grid) is a result too: its error message is kept and its outputs up to the stop are compared; not so a run
    stopped by a signal (RuntimeError, nothing recorded: the study's next run resumes it). A run that
    stops before its first output (a scene mpm_solver rejects) has nothing to compare: RuntimeError
    with its error, and nothing is recorded, so that the study runs it again once the scene is
    mended."""
    folder = Path(folder)
    if (folder / "study_run.json").exists():
        return json.loads((folder / "study_run.json").read_text())
    checkpoint = resumed_run.newest_checkpoint(folder)
    out = resumed_run.next_segment(folder) if checkpoint else folder
    wall, cpu, error = timed_run([Path(build) / "mpm_solver" / "mpm_solver", scene_file, "--out", out,
                                  "--threads", threads, *(["--restart", checkpoint] if checkpoint else [])])
    if error and not (out / "series.csv").exists():
        raise RuntimeError(f"{scene_file}: mpm_solver stopped before its first output: {error}")
    if (out / "summary.json").exists() and json.loads((out / "summary.json").read_text()).get("interrupted"):
        # Stopped by a signal to mpm_solver alone: not a result, and the next study resumes it.
        raise RuntimeError(f"{scene_file}: {error}; run the study again to resume it")
    result = {"wall_s": wall, "cpu_s": cpu, "failed": error or ""}
    if checkpoint:
        joined = resumed_run.join(folder)
        result["resumed_from"] = str(checkpoint.relative_to(folder))
        # The stopped segments' CPU died with the process that timed them; their mpm_solver reported it.
        if joined:  # not when the last segment failed before writing its summary
            earlier = list(zip([".", *joined["resumed_segments"]], joined["segments_cpu_s"]))[:-1]
            result["cpu_s"] += sum(cpu for _, cpu in earlier if cpu is not None)
            uncounted = [name for name, cpu in earlier if cpu is None]
            if uncounted:
                result["uncounted_segments"] = uncounted
    (folder / "study_run.json").write_text(json.dumps(result) + "\n")
    return result


def stress_error(snapshot, reference):
    if len(snapshot) == len(reference) and (snapshot.fields["id"] == reference.fields["id"]).all():
        return flow.stress_error(snapshot, reference)
    return flow.stress_error_nearest(snapshot, reference)


def last_shared_row(series, reference, ours, theirs):
    """(t, ours[k], theirs[j]) at the last time both series have a row (times to 1e-9 s), or None."""
    ref = dict(zip(np.round(reference["t"], 9), theirs))
    common = [(t, value) for t, value in zip(np.round(series["t"], 9), ours) if t in ref]
    if not common:
        return None
    t, value = common[-1]
    return t, value, ref[t]


def final_runout_change(series, reference, min_runout=0.01):
    """(runout − reference runout) / reference runout at the last row they share, signed (negative:
    the run falls short); None when the reference runout is below `min_runout` [m] there (a ratio of
    noise over a tiny number)."""
    row = last_shared_row(series, reference, flow.runout(series), flow.runout(reference))
    if row is None or row[2] < min_runout:
        return None
    _, runout, ref_runout = row
    return float((runout - ref_runout) / ref_runout)


def final_kinetic_energy_change(series, reference, min_share_of_peak=0.01):
    """(kinetic energy − reference's) / reference's at the last row they share, signed (positive: the
    run moves more); None when the reference's kinetic energy there is below `min_share_of_peak` of its
    peak up to then (a column at rest: a ratio of noise over a tiny number). The inertial measure of a
    flow: its bulk may move faster or slower while its front, set by a few points, keeps its place."""
    ref_energy = np.asarray(reference["kinetic_energy"], dtype=float)
    row = last_shared_row(series, reference, series["kinetic_energy"], ref_energy)
    if row is None:
        return None
    t, energy, ref_at_t = row
    peak = ref_energy[np.round(reference["t"], 9) <= t].max()
    if not ref_at_t > 0 or ref_at_t < min_share_of_peak * peak:
        return None
    return float((energy - ref_at_t) / ref_at_t)


def final_runout_error(series, reference, min_runout=0.01):
    """|final_runout_change|, or None where it is."""
    change = final_runout_change(series, reference, min_runout)
    return None if change is None else abs(change)


def bulk_errors(final, initial, ref_final, ref_initial, min_advance=0.01):
    """Relative errors of the advances of the mass edge and of the centroid (flow.bulk_advance); None
    for one whose reference moved less than `min_advance` [m]."""
    ours, theirs = flow.bulk_advance(final, initial), flow.bulk_advance(ref_final, ref_initial)
    return [float(abs(a - b) / abs(b)) if abs(b) >= min_advance else None for a, b in zip(ours, theirs)]


def errors(folder, reference_folder):
    series, ref_series = (tables.read_csv(Path(f) / "series.csv") for f in (folder, reference_folder))
    snaps = {round(s.time, 9): s for s in vtu.read_run(folder)}
    ref_snaps = {round(s.time, 9): s for s in vtu.read_run(reference_folder)}
    initial, ref_initial = snaps[min(snaps)], ref_snaps[min(ref_snaps)]
    common = sorted(set(snaps) & set(ref_snaps))[1:]  # the initial state is the same by construction
    if not common:
        raise ValueError(f"{folder}: no output time in common with the reference {reference_folder}")
    final, ref_final = snaps[common[-1]], ref_snaps[common[-1]]
    # Columns of two reference point spacings across every x either run reaches.
    width = 2 * ref_final.spacing()
    x = np.concatenate([final.xy[:, 0], ref_final.xy[:, 0]])
    bins = np.arange(x.min(), x.max() + 2 * width, width)
    mass_edge, centroid = bulk_errors(final, initial, ref_final, ref_initial)
    return {
        "front_rel_err": flow.front_error(series, ref_series),
        "runout_rel_err": final_runout_error(series, ref_series),
        "stress_rel_l2": float(np.mean([stress_error(snaps[t], ref_snaps[t]) for t in common])),
        "stress_smoothed_rel_l2": float(np.mean([flow.smoothed_stress_error(snaps[t], ref_snaps[t]) for t in common])),
        "deposit_rms_m": flow.profile_error(final, ref_final, bins),
        "mass_edge_rel_err": mass_edge,
        "centroid_rel_err": centroid,
        # Signed, in D's own units: a surrogate's bias in the bonds it breaks, which the stress and the
        # runout need not show (README, "Stop 57").
        "damage_change": flow.mean_damage(final) - flow.mean_damage(ref_final),
        "kinetic_energy_change": final_kinetic_energy_change(series, ref_series),
    }
