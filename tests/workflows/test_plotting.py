"""The shared helpers of workflows/plotting against known answers: the VTU/PVD reader on a rigid
translation run by mpm_solver, the flow measures and errors on hand-made snapshots, the tables and
the PNG check; a study's run of a scene that mpm_solver rejects."""

import json
import signal
import subprocess
import sys
import time

import numpy as np

from workflow_test_util import BUILD, TINY_SCENE, WORKFLOWS, WorkflowTest, run, run_rigid_translation
from plotting import flow, fluctuations, png, resumed_run, run_compare, spreading, tables, vtu
from plotting.collapse_figures import joined_tables
from plotting.figures import plt


def snapshot(xy, stress=None, ids=None):
    xy = np.asarray(xy, dtype=float)
    n = len(xy)
    full = np.zeros((n, 9))
    if stress is not None:
        s = np.asarray(stress, dtype=float)
        full[:, 0], full[:, 4], full[:, 1], full[:, 3] = s[:, 0], s[:, 1], s[:, 2], s[:, 2]
    return vtu.Snapshot(0.0, xy, {"stress": full, "id": np.arange(n) if ids is None else np.asarray(ids)})


class ReaderTest(WorkflowTest):
    def test_rigid_translation_read_back(self):
        snapshots = vtu.read_run(run_rigid_translation(self.out, speed=1.0, end=0.02))
        self.assertEqual([round(s.time, 9) for s in snapshots], [0.0, 0.01, 0.02])
        first, last = snapshots[0], snapshots[-1]
        self.assertEqual(len(first), 16)  # 2 × 2 cells, 2 × 2 points per cell
        np.testing.assert_allclose(last.by_id(last.xy), first.by_id(first.xy) + [0.02, 0.0], atol=1e-12)
        np.testing.assert_allclose(last.speed(), 1.0, atol=1e-12)
        np.testing.assert_allclose(first.spacing(), 0.05, atol=1e-12)
        np.testing.assert_allclose(last.fields["density"], 1000, rtol=1e-12)

    def test_malformed_vtu_names_the_file(self):
        bad = self.out / "points_000000.vtu"
        bad.write_bytes(b"<VTKFile/>")
        with self.assertRaisesRegex(ValueError, "points_000000.vtu"):
            vtu.read_vtu(bad)


def thrown_block(end):
    """An elastic block thrown along a frictional floor under gravity, to `end` [s]: a scene whose
    every step is cheap and whose state changes from step to step."""
    return {"grid": {"cell_size": 0.1, "cells": [10, 6]},
            "time": {"end": end, "output_interval": 0.01, "series_interval": 0.005},
            "gravity": {"g": [0, -9.81]}, "effects": {"gravity": True, "boundary_friction": True},
            "materials": [{"name": "m", "law": "elastic", "density": 1000, "young": 1e5, "poisson": 0.3}],
            "regions": [{"material": "m", "rectangle": {"min": [0.2, 0.12], "max": [0.4, 0.32]},
                         "velocity": [0.5, 0.0]}],
            "obstacles": [{"line": [[0, 0.1], [1.0, 0.1]], "k_n": 2e5, "k_t": 2e5, "friction": 0.5, "damping": 0.5}],
            "tracked_points": [[0.22, 0.14], [0.38, 0.3]]}


class StudyRunTest(WorkflowTest):
    def test_a_rejected_scene_is_an_error_naming_it_and_is_not_recorded_as_a_result(self):
        scene = json.loads(TINY_SCENE.read_text())
        scene["time"]["finish"] = 1.0
        bad = self.out / "bad_scene.json"
        bad.write_text(json.dumps(scene))
        with self.assertRaisesRegex(RuntimeError, r"bad_scene\.json: mpm_solver stopped before its first output: .*finish"):
            run_compare.timed_scene_run(BUILD, bad, self.out / "run", 1)
        self.assertFalse((self.out / "run" / "study_run.json").exists())

    def test_a_stopped_run_goes_on_from_its_checkpoint_and_reads_as_the_run_never_stopped(self):
        # The stopped run is the same scene stopped at 0.02 s (mpm_solver writes its checkpoint when it
        # stops), with no study record.
        scene = thrown_block(end=0.04)
        file = self.out / "scene.json"
        file.write_text(json.dumps(scene))
        whole, stopped = self.out / "whole", self.out / "stopped"
        self.assertNotIn("resumed_from", run_compare.timed_scene_run(BUILD, file, whole, 1))
        run([BUILD / "mpm_solver" / "mpm_solver", file, "--out", stopped, "--threads", "1", "--set", "/time/end=0.02"])
        self.assertEqual(resumed_run.newest_checkpoint(stopped), stopped / "restart.h5")

        first_cpu_s = json.loads((stopped / "summary.json").read_text())["process_cpu_time"]
        self.assertGreater(first_cpu_s, 0)
        result = run_compare.timed_scene_run(BUILD, file, stopped, 1)
        self.assertEqual(result["resumed_from"], "restart.h5")
        self.assertEqual(resumed_run.segments(stopped), [stopped / "resumed_1"])
        # Its CPU is both segments': the first as its mpm_solver reported it, the second as timed.
        cpu_s = json.loads((stopped / "summary.json").read_text())["segments_cpu_s"]
        self.assertEqual(cpu_s[0], first_cpu_s)
        self.assertGreaterEqual(result["cpu_s"], first_cpu_s + cpu_s[1] * 0.99)
        self.assertNotIn("uncounted_segments", result)
        self.assertEqual((stopped / "series.csv").read_text(), (whole / "series.csv").read_text())
        tracked = (stopped / "tracked_points.csv").read_text()
        self.assertEqual(tracked, (whole / "tracked_points.csv").read_text())
        self.assertEqual(len(tracked.splitlines()), 1 + 2 * 9, "two points at each of 9 series times")
        ours, theirs = vtu.read_run(stopped), vtu.read_run(whole)
        self.assertEqual([s.time for s in ours], [0, 0.01, 0.02, 0.03, 0.04])
        self.assertEqual([s.time for s in ours], [s.time for s in theirs])
        for a, b in zip(ours, theirs):
            np.testing.assert_array_equal(a.xy, b.xy)
            np.testing.assert_array_equal(a.fields["stress"], b.fields["stress"])
        self.assertEqual(json.loads((stopped / "summary.json").read_text())["resumed_segments"], ["resumed_1"])
        joined = (stopped / "points.pvd").read_text()
        resumed_run.join(stopped)
        self.assertEqual((stopped / "points.pvd").read_text(), joined, "joining again changes nothing")
        self.assertEqual(json.loads((stopped / "summary.json").read_text())["segments_cpu_s"], cpu_s)
        self.assertEqual(run_compare.timed_scene_run(BUILD, file, stopped, 1), result, "a finished run is kept")

        # A segment written by a build whose series has other columns cannot be joined row by row: the
        # join names that segment's file and leaves the joined run as it was.
        segment_series = stopped / "resumed_1" / "series.csv"
        header, rest = segment_series.read_text().split("\n", 1)
        segment_series.write_text(header + ",extra\n" + rest)
        joined_series = (stopped / "series.csv").read_text()
        with self.assertRaisesRegex(ValueError, r"resumed_1/series\.csv: header differs from the first segment's"):
            resumed_run.join(stopped)
        self.assertEqual((stopped / "series.csv").read_text(), joined_series)

    def test_a_study_stopped_by_a_signal_leaves_its_run_checkpointed_and_unrecorded_and_resumes_it(self):
        # An end the block would take long to reach; the study is a Python process running
        # timed_scene_run, stopped by SIGTERM once mpm_solver has written rows.
        scene = thrown_block(end=1000.0)
        file, folder = self.out / "scene.json", self.out / "run"
        file.write_text(json.dumps(scene))
        study = subprocess.Popen([sys.executable, "-c", "import sys; sys.path.insert(0, sys.argv[1]); "
                                  "from plotting import run_compare; "
                                  "run_compare.timed_scene_run(sys.argv[2], sys.argv[3], sys.argv[4], 1)",
                                  WORKFLOWS, BUILD, file, folder], stderr=subprocess.PIPE, text=True)
        # Synchronised on the run's own output: three rows past its first mean mpm_solver is stepping.
        while not (folder / "series.csv").exists() or len((folder / "series.csv").read_text().splitlines()) < 5:
            self.assertIsNone(study.poll(), "the study ended before it was stopped")
            time.sleep(0.01)
        study.send_signal(signal.SIGTERM)
        _, stderr = study.communicate()
        self.assertNotEqual(study.returncode, 0)
        self.assertIn("KeyboardInterrupt", stderr)
        summary = json.loads((folder / "summary.json").read_text())
        self.assertTrue(summary["interrupted"], "mpm_solver was stopped, not killed")
        self.assertTrue((folder / "restart.h5").exists())
        self.assertFalse((folder / "study_run.json").exists(), "a stopped run is no result")

        # Resumed, to an end just past where it stopped.
        stopped_at = summary["final_time"]
        scene["time"]["end"] = stopped_at + 0.02
        file.write_text(json.dumps(scene))
        result = run_compare.timed_scene_run(BUILD, file, folder, 1)
        self.assertEqual(result["resumed_from"], "restart.h5")
        self.assertEqual(result["failed"], "")
        self.assertGreater(result["cpu_s"], summary["process_cpu_time"], "the stopped segment's CPU counts")
        t = tables.read_csv(folder / "series.csv")["t"]
        self.assertTrue((np.diff(t) > 0).all(), "one row per time across the seam")
        self.assertAlmostEqual(json.loads((folder / "summary.json").read_text())["final_time"], stopped_at + 0.02,
                               delta=1e-12)
        self.assertLess(t[0], stopped_at)
        self.assertGreater(t[-1], stopped_at)


class FlowTest(WorkflowTest):
    def test_front_error_is_the_worst_relative_runout_error_past_1_cm(self):
        reference = {"t": np.array([0, 1, 2, 3.0]), "front": np.array([1.0, 1.005, 1.02, 1.04])}
        series = {"t": np.array([0, 1, 2, 3.0]), "front": np.array([1.0, 1.0, 1.03, 1.05])}
        # t = 1 is skipped (reference runout 5 mm); t = 2: 0.01/0.02; t = 3: 0.01/0.04.
        self.assertAlmostEqual(flow.front_error(series, reference), 0.5)
        self.assertEqual(flow.front_error(reference, reference), 0.0)

    def test_final_runout_change_is_signed_and_its_error_is_its_size(self):
        reference = {"t": np.array([0, 1, 2.0]), "front": np.array([1.0, 1.02, 1.04])}
        short = {"t": np.array([0, 1, 2.0]), "front": np.array([1.0, 1.01, 1.03])}
        long = {"t": np.array([0, 1, 2.0]), "front": np.array([1.0, 1.03, 1.05])}
        # At t = 2 the reference has run out 4 cm: 1 cm short is −25 %, 1 cm long +25 %.
        self.assertAlmostEqual(run_compare.final_runout_change(short, reference), -0.25)
        self.assertAlmostEqual(run_compare.final_runout_change(long, reference), 0.25)
        self.assertAlmostEqual(run_compare.final_runout_error(short, reference), 0.25)
        # A reference that ran out less than 1 cm has no relative change.
        creeping = {"t": np.array([0, 1, 2.0]), "front": np.array([1.0, 1.002, 1.005])}
        self.assertIsNone(run_compare.final_runout_change(short, creeping))
        self.assertIsNone(run_compare.final_runout_error(short, creeping))

    def test_final_kinetic_energy_change_is_signed_and_none_at_rest(self):
        reference = {"t": np.array([0, 1, 2.0]), "kinetic_energy": np.array([0.0, 4.0, 2.0])}
        series = {"t": np.array([0, 1, 2.0]), "kinetic_energy": np.array([0.0, 5.0, 2.5])}
        self.assertAlmostEqual(run_compare.final_kinetic_energy_change(series, reference), 0.25)
        self.assertAlmostEqual(run_compare.final_kinetic_energy_change(reference, series), -0.2)
        # The last shared row counts: a longer run is compared where the reference ends.
        longer = {"t": np.array([0, 1, 2, 3.0]), "kinetic_energy": np.array([0.0, 5.0, 1.0, 9.0])}
        self.assertAlmostEqual(run_compare.final_kinetic_energy_change(longer, reference), -0.5)
        # A reference at rest, below 1 % of its peak, has no relative change.
        settled = {"t": np.array([0, 1, 2.0]), "kinetic_energy": np.array([0.0, 4.0, 0.03])}
        self.assertIsNone(run_compare.final_kinetic_energy_change(series, settled))

    def test_stress_errors(self):
        xy = [[0, 0], [1, 0], [0, 1]]
        stress = [[-1, -2, 0.5], [-3, -1, 0], [0, -4, 1]]
        ref = snapshot(xy, stress)
        self.assertAlmostEqual(flow.stress_error(snapshot(xy, 1.1 * np.array(stress)), ref), 0.1)
        # The same points listed in another order: matched by id, or by position.
        order = [2, 0, 1]
        shuffled = snapshot(np.array(xy)[order], np.array(stress)[order], ids=order)
        self.assertAlmostEqual(flow.stress_error(shuffled, ref), 0.0)
        self.assertAlmostEqual(flow.stress_error_nearest(shuffled, ref), 0.0)

    def test_the_smoothed_stress_error_counts_a_smooth_difference_and_not_a_point_to_point_one(self):
        xy = [[0.05 * i, 0.05 * j] for i in range(16) for j in range(16)]
        uniform = np.tile([-1000.0, -2000.0, 300.0], (len(xy), 1))
        ref = snapshot(xy, uniform)
        # Averaging is linear: a field 10 % stronger everywhere is 10 % off after it too.
        self.assertAlmostEqual(flow.smoothed_stress_error(snapshot(xy, 1.1 * uniform), ref), 0.1)
        # The same mean stress put on every other row (0 and twice): 100 % off point by point, a
        # small part of that over one spacing, most of it at the top and bottom rows.
        rows = np.array([1.0 + (-1) ** j for i in range(16) for j in range(16)])
        alternating = snapshot(xy, uniform * rows[:, None])
        self.assertAlmostEqual(flow.stress_error(alternating, ref), 1.0)
        self.assertLess(flow.smoothed_stress_error(alternating, ref), 0.15)
        # Averaged a few positions at a time, the same to round-off.
        np.testing.assert_allclose(flow.smoothed_stress(alternating, ref.xy, 0.05, block=7),
                                   flow.smoothed_stress(alternating, ref.xy, 0.05), rtol=1e-12)

    def test_mean_damage_is_the_share_of_bonds_broken_over_points(self):
        s = snapshot([[0, 0], [1, 0], [0, 1], [1, 1]])
        s.fields["damage"] = np.array([0.0, 0.2, 0.5, 0.9])
        self.assertAlmostEqual(flow.mean_damage(s), 0.4)
        s.fields["damage"] = np.zeros(4)  # a law without bonds
        self.assertEqual(flow.mean_damage(s), 0.0)

    def test_deposit_profile_is_the_highest_point_per_column(self):
        s = snapshot([[0.05, 0.1], [0.05, 0.3], [0.15, 0.2], [0.35, 0.05]])
        np.testing.assert_allclose(flow.deposit_profile(s, [0, 0.1, 0.2, 0.3, 0.4]), [0.3, 0.2, 0.0, 0.05])
        lower = snapshot([[0.05, 0.1], [0.15, 0.2], [0.35, 0.05]])
        self.assertAlmostEqual(flow.profile_error(lower, s, [0, 0.1, 0.2, 0.3, 0.4]), np.sqrt(0.2 ** 2 / 4))


class SpreadingTest(WorkflowTest):
    def test_a_rigid_translation_runs_out_on_one_side_and_back_on_the_other(self):
        snapshots = vtu.read_run(run_rigid_translation(self.out, speed=1.0, end=0.02))
        rows = spreading.spreading(snapshots)
        first, last = rows[0], rows[-1]
        self.assertAlmostEqual(last["runout_right"], 0.02, places=12)
        self.assertAlmostEqual(last["runout_left"], -0.02, places=12)
        self.assertAlmostEqual(last["centroid_shift"], 0.02, places=12)
        self.assertAlmostEqual(first["centroid_shift"], 0.0, places=12)
        for corner in ("corner_left", "corner_right"):
            np.testing.assert_allclose(last[corner], np.array(first[corner]) + [0.02, 0.0], atol=1e-12)
        self.assertLess(first["corner_left"][0], first["corner_right"][0])
        spreading.deposit_figure(snapshots, rows, self.out / "deposit.png")
        self.assert_png(self.out / "deposit.png")

    def test_a_symmetric_spread_has_no_asymmetry_and_a_lopsided_one_has(self):
        xy = np.array([[x, y] for x in (1.0, 2.0, 3.0) for y in (0.0, 1.0)])
        start = vtu.Snapshot(0.0, xy, {"id": np.arange(6)})
        symmetric = vtu.Snapshot(1.0, np.column_stack([2 + 2 * (xy[:, 0] - 2), 0.5 * xy[:, 1]]), {"id": np.arange(6)})
        lopsided_x = np.where(xy[:, 0] > 2, xy[:, 0] + 3, xy[:, 0] - 1)
        lopsided = vtu.Snapshot(1.0, np.column_stack([lopsided_x, xy[:, 1]]), {"id": np.arange(6)})
        even = spreading.spreading([start, symmetric])[-1]
        self.assertEqual((even["runout_left"], even["runout_right"], even["asymmetry"]), (1.0, 1.0, 0.0))
        self.assertEqual(even["centroid_shift"], 0.0)
        self.assertEqual(even["height"], 0.5)
        self.assertEqual((even["corner_left"], even["corner_right"]), ([0.0, 0.5], [4.0, 0.5]))
        uneven = spreading.spreading([start, lopsided])[-1]
        self.assertEqual((uneven["runout_left"], uneven["runout_right"]), (1.0, 3.0))
        self.assertAlmostEqual(uneven["asymmetry"], 1.0)  # (3 − 1) / 2
        self.assertAlmostEqual(uneven["centroid_shift"], (2 * 3 - 4 * 1) / 6)  # two points +3, four −1


    def test_a_point_thrown_ahead_sets_the_runout_but_not_the_deposit_edge(self):
        xy = np.array([[x, y] for x in (1.0, 2.0, 3.0) for y in (0.0, 1.0)])
        start = vtu.Snapshot(0.0, xy, {"id": np.arange(6)})
        spread_x = 2 + 2 * (xy[:, 0] - 2)  # 0, 2, 4: gaps of 2 initial spacings, one deposit
        spread = vtu.Snapshot(1.0, np.column_stack([spread_x, xy[:, 1]]), {"id": np.arange(6)})
        thrown_x = spread_x.copy()
        thrown_x[5] = 4 + 3.5  # the top right point 3.5 spacings beyond the rest
        thrown = vtu.Snapshot(2.0, np.column_stack([thrown_x, xy[:, 1]]), {"id": np.arange(6)})
        _, even, ahead = spreading.spreading([start, spread, thrown])
        self.assertEqual((even["deposit_left"], even["deposit_right"], even["detached_points"]), (1.0, 1.0, 0))
        self.assertEqual((ahead["runout_left"], ahead["runout_right"]), (1.0, 4.5))
        self.assertEqual((ahead["deposit_left"], ahead["deposit_right"], ahead["detached_points"]), (1.0, 1.0, 1))


class FluctuationsTest(WorkflowTest):
    """fluctuations.split: a round trip through the grid brings back a smooth field and not a pattern that
    alternates from point to point (2 × 2 points per cell)."""

    def setUp(self):
        super().setUp()
        h, spacing = 0.05, 0.025
        i, j = np.meshgrid(np.arange(8, 32), np.arange(8, 32), indexing="ij")
        self.xy = np.c_[(i.ravel() + 0.5) * spacing, (j.ravel() + 0.5) * spacing]
        self.sign = np.where((i.ravel() + j.ravel()) % 2 == 0, 1.0, -1.0)
        self.mass, self.h = np.full(len(self.xy), 2.0), h

    def test_a_uniform_velocity_is_carried_whole(self):
        velocity = np.tile([0.1, -0.05], (len(self.xy), 1))
        carried, fluctuation, _, rough = fluctuations.split(self.xy, velocity, self.mass, self.h)
        np.testing.assert_allclose(carried, velocity, atol=1e-15)
        self.assertLess(fluctuations.rms(fluctuation), 1e-15)
        self.assertLess(fluctuations.rms(rough), 1e-15)

    def test_a_point_to_point_pattern_is_almost_all_rough_and_carries_no_momentum(self):
        velocity = np.c_[0.01 * self.sign, np.zeros(len(self.xy))]
        carried, fluctuation, carried_fluctuation, rough = fluctuations.split(self.xy, velocity, self.mass, self.h)
        self.assertLess(fluctuations.rms(carried), 0.01 * fluctuations.rms(velocity))
        self.assertGreater(fluctuations.rms(rough), 0.99 * fluctuations.rms(velocity))
        np.testing.assert_allclose((self.mass[:, None] * rough).sum(axis=0), 0, atol=1e-15)
        shifted = fluctuations.split(self.xy + 0.3, velocity, self.mass, self.h, origin=(0.3, 0.3))
        np.testing.assert_allclose(shifted[3], rough, atol=1e-15)


class TablesTest(WorkflowTest):
    def test_csv_round_trip_and_errors(self):
        rows = [{"t": 0.0, "point": 1, "d": 0.5}, {"t": 0.0, "point": 2, "d": 0.25}, {"t": 1.0, "point": 1, "d": 0.75}]
        tables.write_csv(self.out / "a.csv", rows)
        per_point = tables.split_by(tables.read_csv(self.out / "a.csv"), "point")
        np.testing.assert_array_equal(per_point[1]["d"], [0.5, 0.75])
        np.testing.assert_array_equal(per_point[2]["t"], [0.0])
        (self.out / "bad.csv").write_text("t,x\n0,1\n1\n")
        with self.assertRaisesRegex(ValueError, r"bad.csv:3: expected 2 fields, got 1"):
            tables.read_csv(self.out / "bad.csv")
        # The row a killed run was writing (no line end) is dropped; a complete short row is an error.
        (self.out / "cut.csv").write_text("t,x\n0,1\n1,2\n2")
        np.testing.assert_array_equal(tables.read_csv(self.out / "cut.csv")["t"], [0, 1])
        tables.write_markdown(self.out / "a.md", rows)
        self.assertEqual((self.out / "a.md").read_text().splitlines()[2], "| 0 | 1 | 0.5 |")

    def test_segments_of_a_resumed_run_join_where_the_next_takes_over(self):
        killed = {"t": np.array([0.0, 0.1, 0.2, 0.3]), "x": np.array([0.0, 1.0, 2.0, 3.0])}
        resumed = {"t": np.array([0.2, 0.3, 0.4]), "x": np.array([2.0, 3.0, 4.0]), "new": np.zeros(3)}
        joined = joined_tables([killed, resumed], [0.2 * (1 - 1e-12), np.inf])
        self.assertEqual(sorted(joined), ["t", "x"])  # the columns both segments have
        np.testing.assert_array_equal(joined["t"], [0.0, 0.1, 0.2, 0.3, 0.4])

    def test_png_size_from_ihdr(self):
        fig = plt.figure(figsize=(2, 1))
        fig.savefig(self.out / "f.png", dpi=50)
        plt.close(fig)
        self.assertEqual(png.png_size(self.out / "f.png"), (100, 50))
        (self.out / "not.png").write_bytes(b"GIF89a" + bytes(30))
        with self.assertRaisesRegex(ValueError, "not.png: not a PNG"):
            png.png_size(self.out / "not.png")
