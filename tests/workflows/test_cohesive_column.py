"""The cohesive column's stability (workflows/cohesive_column): below Culmann's kinematic bound
(Co = 0.144 at φ = 30°) a mechanism exists whose dissipation is less than the work of gravity, so a
column of the associated material, for which the limit theorems hold, must fall, and so must the
study's sand, which flows without dilatancy and is weaker still (Radenkovic: it cannot outlast the
associated material of its strength); at twice the bound both stand."""
import json
import math
import sys
import unittest

from workflow_test_util import BUILD, WORKFLOWS, WorkflowTest, run

sys.path.insert(0, str(WORKFLOWS / "cohesive_column"))
import corner_stress  # noqa: E402
import live_threshold  # noqa: E402
from plotting import scenes  # noqa: E402


class CohesiveColumnTest(WorkflowTest):
    def test_falls_below_the_bound_and_stands_well_above(self):
        for dilatancy in ("0", "30"):
            with self.subTest(dilatancy_angle=dilatancy):
                out = self.out / f"psi{dilatancy}"
                run(["/usr/bin/python3", WORKFLOWS / "cohesive_column" / "stability.py", out, "--build", BUILD,
                     "--cells", "10", "--cohesion-numbers", "0.1", "0.3", "--dilatancy-angle", dilatancy])
                result = json.loads((out / "stability.json").read_text())
                weak, strong = result["runs"]
                self.assertLess(weak["cohesion_number"], min(result["bounds"].values()))
                self.assertGreater(weak["front"], 0.1, "below the kinematic bound the column must fall")
                self.assertLess(strong["front"], result["standing"], "at twice the bound it stands")
                self.assertEqual(result["thresholds"]["10"], {"fell_at": 0.1, "stood_at": 0.3})
                self.assert_png(out / "stability.png")
        bounds = json.loads((self.out / "psi0" / "stability.json").read_text())["bounds"]
        self.assertAlmostEqual(bounds["Chen, associated: falls below"], 1 / (3.83 * math.sqrt(3)), places=12)
        # c* = c cos 30°, tan φ* = sin 30°: 1 / (3.83 cos 30° tan(45° + atan(1/2)/2)) = 0.1863.
        self.assertAlmostEqual(bounds["Chen, reduced by cos φ: stands above"], 0.1863, places=4)


class LiveThresholdTest(WorkflowTest):
    """The two-scale column (workflows/cohesive_column/live_threshold.py): the unconfined strength of the
    two-scale material (workflows/cell_response/unconfined.py) predicts the highest vertical cut that
    stands; with live cells a column well below it stands, and one of a far weaker cell, well above
    that cell's own, falls."""

    CELL = WORKFLOWS / "demo" / "cell_soft_snow_125.json"

    def unconfined(self, cell, name):
        """unconfined.json of the coarse test on `cell`."""
        out = self.out / name
        run(["/usr/bin/python3", WORKFLOWS / "cell_response" / "unconfined.py", out, "--build", BUILD, "--cell", cell,
             "--cell-size", "0.025", "--strain-rate", "0.1", "--strain", "0.008"])
        return out / "unconfined.json"

    def threshold(self, cell, prediction, *options, regularized=False):
        """The study's one run of `options`, local or regularized, from its live_threshold.json."""
        run(["/usr/bin/python3", WORKFLOWS / "cohesive_column" / "live_threshold.py", self.out / "live",
             "--unconfined", prediction, "--build", BUILD, "--threads", "1", "--cell", cell, "--width", "0.1",
             "--cell-size", "0.05", "--watch", "1", *options])
        result = json.loads((self.out / "live" / "live_threshold.json").read_text())
        (row,) = [r for r in result["runs"] if r["cell"] == str(cell.resolve())
                  and (r["nonlocal_length"] is not None) == regularized]
        (predicted,) = row["predicted"].values()
        return row, predicted

    def test_stands_well_below_the_critical_height_and_falls_well_above(self):
        prediction = self.unconfined(self.CELL, "strong")
        critical = json.loads(prediction.read_text())["critical_height"]["Chen (N_s = 3.83)"]
        # At most a third of it, in whole grid cells of 0.05 m (the points sit half a cell off the walls).
        height = 0.05 * max(1, math.floor(critical / 3 / 0.05))
        short, predicted = self.threshold(self.CELL, prediction, "--heights", f"{height:g}")
        self.assertEqual(predicted, "may stand")
        self.assertTrue(short["stands"], short)
        self.assertFalse(short["front_reached"])
        self.assertAlmostEqual(short["end"], short["planned_end"], places=9, msg="a column that stands is watched to the end")
        # The result carries the cell's strength, and without heights the study runs nothing and reports
        # its runs again against the prediction given.
        measured = json.loads(prediction.read_text())
        result = json.loads((self.out / "live" / "live_threshold.json").read_text())
        self.assertEqual(result["unconfined"], {"q_u": measured["q_u"], "density": measured["density"]})
        table = (self.out / "live" / "live_threshold.md").read_text()
        run(["/usr/bin/python3", WORKFLOWS / "cohesive_column" / "live_threshold.py", self.out / "live",
             "--unconfined", prediction, "--build", BUILD, "--cell", self.CELL, "--heights"])
        self.assertEqual((self.out / "live" / "live_threshold.md").read_text(), table)

        weak = json.loads(self.CELL.read_text())
        for strength in ("tensile_strength", "shear_strength"):
            weak["material"]["bond"][strength] *= 0.02
        weak_cell = self.out / "weak_cell.json"
        weak_cell.write_text(json.dumps(weak))
        weak_prediction = self.unconfined(weak_cell, "weak")
        self.assertLess(json.loads(weak_prediction.read_text())["critical_height"]["Chen (N_s = 3.83)"], 0.1)
        tall, predicted = self.threshold(weak_cell, weak_prediction, "--heights", "0.2")
        self.assertEqual(predicted, "must fall")
        self.assertFalse(tall["stands"], tall)
        # Once its front has run twice the standing criterion, its verdict is in and the run ends there.
        self.assertTrue(tall["front_reached"], tall)
        self.assertLess(tall["end"], tall["planned_end"])
        self.assertIn("falls (stopped once fallen)", (self.out / "live" / "live_threshold.md").read_text())
        self.assertGreater(tall["top_drop"], 0, "the top sinks as the column falls")
        self.assertIsNone(tall["nonlocal_length"])

        # Regularized over two grid cells, the weak column still falls: the average spreads failure, it
        # does not hold up a column of a cell too weak for it. Its scene carries the length.
        regularized, predicted = self.threshold(weak_cell, weak_prediction, "--heights", "0.2",
                                                "--nonlocal-length", "0.1", regularized=True)
        self.assertEqual(predicted, "must fall")
        self.assertFalse(regularized["stands"], regularized)
        scene = json.loads((self.out / "live" / "scenes" / "h0.2_l0.1_dx0.05_nl0.1.json").read_text())
        self.assertEqual(scene["regularization"], {"nonlocal_length": 0.1})
        verdicts = json.loads((self.out / "live" / "live_threshold.json").read_text())["verdicts"]
        (verdict,) = verdicts.values()
        self.assertEqual(sorted(verdict["threshold_over_critical"]), ["local, H0/h = 4", "ℓ = 0.1 m, H0/h = 4"])
        self.assert_png(self.out / "live" / "live_threshold.png")

    def test_refuses_points_per_cell_below_one_an_unknown_transfer_or_a_bad_friction_before_anything_runs(self):
        with self.assertRaises(AssertionError) as refused:
            self.threshold(self.CELL, self.out / "never_read.json", "--heights", "0.05", "--points-per-cell", "0")
        self.assertIn("--points-per-cell: expected an integer >= 1, got 0", str(refused.exception))
        with self.assertRaises(AssertionError) as refused:
            self.threshold(self.CELL, self.out / "never_read.json", "--heights", "0.05", "--transfer", "flip")
        self.assertIn("--transfer: expected apic, pic, RATE or apic_flip:RATE, got flip", str(refused.exception))
        with self.assertRaises(AssertionError) as refused:
            self.threshold(self.CELL, self.out / "never_read.json", "--heights", "0.05", "--floor-friction", "nan")
        self.assertIn("--floor-friction: expected a friction coefficient >= 0, got nan", str(refused.exception))
        self.assertFalse((self.out / "live").exists())

    def test_refuses_the_prediction_of_another_cell_or_of_a_test_that_never_peaked(self):
        other = WORKFLOWS / "demo" / "cell_soft_snow_250.json"
        prediction = {"cell": str(other), "cell_json": json.loads(other.read_text()), "q_u": 1000.0,
                      "peak_reached": True, "critical_height": {"Chen (N_s = 3.83)": 0.3}}
        (self.out / "other.json").write_text(json.dumps(prediction))
        with self.assertRaises(AssertionError) as refused:
            self.threshold(self.CELL, self.out / "other.json", "--heights", "0.05")
        self.assertIn(f"{self.out / 'other.json'}: field 'cell_json'", str(refused.exception))
        prediction.update(cell=str(self.CELL), cell_json=json.loads(self.CELL.read_text()), peak_reached=False)
        (self.out / "unpeaked.json").write_text(json.dumps(prediction))
        with self.assertRaises(AssertionError) as refused:
            self.threshold(self.CELL, self.out / "unpeaked.json", "--heights", "0.05")
        self.assertIn(f"{self.out / 'unpeaked.json'}: field 'peak_reached' is false", str(refused.exception))
        self.assertFalse((self.out / "live" / "runs").exists(), "nothing is run on a prediction refused")


class ThresholdResolutionTest(unittest.TestCase):
    """live_threshold.py --points-per-cell: the scene seeds that many points (cells) per grid cell and
    direction, and runs of another number of points per cell are bracketed apart."""

    def test_the_scene_seeds_the_points_per_cell_and_the_brackets_keep_them_apart(self):
        scene = json.loads(live_threshold.SCENE.read_text())
        settings, _, _ = live_threshold.column_settings(scene, 0.3, 0.2, 0.05, None, 2)
        self.assertEqual(settings["/regions/0/points_per_cell"], 2)
        row = {"height": 0.3, "cell_size": 0.05, "nonlocal_length": None}
        one, two = {**row, "stands": True}, {**row, "points_per_cell": 2, "stands": False}
        self.assertEqual(live_threshold.resolution(one), "local, H0/h = 6")  # rows from before the option
        self.assertEqual(live_threshold.resolution(two), "local, H0/h = 6, 2 points per cell")
        self.assertEqual(live_threshold.threshold_brackets([one, two]),
                         {"local, H0/h = 6": (0.3, None), "local, H0/h = 6, 2 points per cell": (None, 0.3)})

    def test_the_floor_friction_is_the_scenes_unless_given_and_is_bracketed_apart(self):
        scene = json.loads(live_threshold.SCENE.read_text())
        settings, _, _ = live_threshold.column_settings(scene, 0.3, 0.2, 0.05, None, 1)
        self.assertFalse([pointer for pointer in settings if pointer.endswith("/friction")])
        settings, _, _ = live_threshold.column_settings(scene, 0.3, 0.2, 0.05, None, 1, 0.0)
        (floor,) = [k for k, o in enumerate(scene["obstacles"]) if o["line"][0][1] == o["line"][1][1]]
        self.assertEqual(settings[f"/obstacles/{floor}/friction"], 0.0)
        row = {"height": 0.3, "cell_size": 0.05, "nonlocal_length": None}
        rough, smooth = {**row, "stands": False}, {**row, "floor_friction": 0.0, "stands": True}
        self.assertEqual(live_threshold.resolution(smooth), "local, H0/h = 6, floor friction 0")
        self.assertEqual(live_threshold.threshold_brackets([rough, smooth]),
                         {"local, H0/h = 6": (None, 0.3), "local, H0/h = 6, floor friction 0": (0.3, None)})

    def test_a_run_under_another_transfer_is_bracketed_apart(self):
        row = {"height": 0.3, "cell_size": 0.05, "nonlocal_length": None, "points_per_cell": 2}
        default, damped = {**row, "stands": False}, {**row, "transfer": "apic_flip:50", "stands": True}
        self.assertEqual(live_threshold.resolution(damped), "local, H0/h = 6, 2 points per cell, transfer apic_flip:50")
        self.assertEqual(live_threshold.threshold_brackets([default, damped]),
                         {"local, H0/h = 6, 2 points per cell": (None, 0.3),
                          "local, H0/h = 6, 2 points per cell, transfer apic_flip:50": (0.3, None)})
        self.assertEqual(scenes.transfer_settings("apic_flip:50"),
                         ({"/integration/transfer": {"apic_flip": {"pic_rate": 50.0}}}, "_apic_flip50"))
        self.assertEqual(scenes.transfer_settings(None), ({}, ""))


    def test_a_gate_let_go_of_gradually_releases_over_its_time_and_is_bracketed_apart(self):
        scene = json.loads(live_threshold.SCENE.read_text())
        (gate,) = [k for k, o in enumerate(scene["obstacles"]) if "remove_at" in o]
        settings, start, end = live_threshold.column_settings(scene, 0.3, 0.2, 0.05, None, 1)
        self.assertEqual(settings[f"/obstacles/{gate}"]["remove_at"], start)
        self.assertEqual(end, start)
        settings, start, end = live_threshold.column_settings(scene, 0.3, 0.2, 0.05, None, 1, release=0.1)
        self.assertNotIn("remove_at", settings[f"/obstacles/{gate}"])
        self.assertEqual(settings[f"/obstacles/{gate}"]["release"], {"start": start, "end": start + 0.1})
        self.assertEqual(end, start + 0.1)
        row = {"height": 0.3, "cell_size": 0.05, "nonlocal_length": None}
        sudden, gradual = {**row, "stands": False}, {**row, "release": 0.1, "stands": True}
        self.assertEqual(live_threshold.resolution(gradual), "local, H0/h = 6, gate let go of over 0.1 s")
        self.assertEqual(live_threshold.threshold_brackets([sudden, gradual]),
                         {"local, H0/h = 6": (None, 0.3), "local, H0/h = 6, gate let go of over 0.1 s": (0.3, None)})


class CornerStressTest(WorkflowTest):
    """corner_stress.py: the live column's elastic twins. Each settles in equilibrium, its bottom row
    carrying the weight above it; on a frictionless floor nothing restrains the base, so its corners
    are in uniaxial compression under their overburden, which the gate's release can only have
    exceeded on the way; and one critical load either separates the live verdicts or is said not to."""

    def test_the_twins_carry_their_weight_and_a_frictionless_toe_is_uniaxial(self):
        out = self.out / "corner"
        run(["/usr/bin/python3", WORKFLOWS / "cohesive_column" / "corner_stress.py", out, "--build", BUILD,
             "--threads", "1", "--column", "0.3", "0.2", "--ratios", "3", "6", "--floor-friction", "0",
             "--end", "0.5", "--average-from", "0.3"])
        result = json.loads((out / "corner_stress.json").read_text())
        self.assertEqual([r["ratio"] for r in result["refinement"]], [3, 6])
        for r in result["refinement"]:
            depth = 1 - 1 / (2 * r["ratio"])  # the corners' points', over H0
            self.assertAlmostEqual(r["bottom_row_load"], 1, delta=0.05)
            for name, corner in r["corners"].items():
                with self.subTest(ratio=r["ratio"], corner=name):
                    self.assertAlmostEqual(corner["two_tau_max"], depth, delta=0.05 * depth)
                    self.assertLess(abs(corner["sigma_1"]), 0.02)
                    # Released by the gate at 0.08 s, the settled stress is a lower bound of the peak after it.
                    self.assertGreaterEqual(corner["peak_two_tau_max"], 0.95 * corner["two_tau_max"])
                    self.assertGreaterEqual(corner["peak_time"], 0.08)
        self.assertEqual(result["refinement"][1]["corners"]["toe"]["point"], [0.375, 0.225])
        self.assertEqual(result["refinement"][1]["corners"]["heel"]["point"], [0.225, 0.225])

    def test_a_gate_let_go_of_over_many_wave_transits_unloads_the_corners_without_overshoot(self):
        # The twin's wave crosses the 0.3 m column in H0 / sqrt(E/ρ) = 7 ms; let go of over 0.1 s, the
        # face unloads quasi-statically and the corners' peaks stay at their settled stress, where a
        # sudden removal's unloading wave overshoots it.
        peaks = {}
        for release in (None, 0.1):
            out = self.out / f"corner_release{release}"
            run(["/usr/bin/python3", WORKFLOWS / "cohesive_column" / "corner_stress.py", out, "--build", BUILD,
                 "--threads", "1", "--column", "0.3", "0.2", "--ratios", "12", "--floor-friction", "0",
                 "--end", "0.5", "--average-from", "0.3"] + ([] if release is None else ["--release", str(release)]))
            result = json.loads((out / "corner_stress.json").read_text())
            self.assertEqual(result["release"], release)
            (twin,) = result["refinement"]
            peaks[release] = {name: (c["peak_two_tau_max"], c["two_tau_max"]) for name, c in twin["corners"].items()}
        for name in ("heel", "toe"):
            with self.subTest(corner=name):
                gradual_peak, settled = peaks[0.1][name]
                self.assertLess(gradual_peak, 1.02 * settled)
                sudden_peak, _ = peaks[None][name]
                self.assertGreater(sudden_peak, gradual_peak + 0.02 * settled)

    def test_refuses_a_file_that_is_not_a_threshold_result_before_anything_runs(self):
        (self.out / "not_runs.json").write_text(json.dumps({"runs": {"height": 0.3}}))
        with self.assertRaises(AssertionError) as refused:
            run(["/usr/bin/python3", WORKFLOWS / "cohesive_column" / "corner_stress.py", self.out / "corner", "--build",
                 BUILD, "--threshold", self.out / "not_runs.json"])
        self.assertIn(f"--threshold {self.out / 'not_runs.json'}: expected a live_threshold.json with a list 'runs'",
                      str(refused.exception))
        self.assertFalse((self.out / "corner").exists())

    def test_a_runs_peak_is_weighed_against_its_own_cells_strength(self):
        # A 0.3 m column whose corners peak at 2τ_max = 0.9 ρ g H0, of a cell of q_u = ρ g × 0.27 m: at its
        # strength exactly. A file from before the strength was recorded gives no ratio.
        run = {"peak_load": 0.9 * 0.3, "strength": {"q_u": 540 * corner_stress.G * 0.27, "density": 540}}
        self.assertAlmostEqual(corner_stress.peak_over_strength(run), 1.0, places=12)
        self.assertIsNone(corner_stress.peak_over_strength({"peak_load": 0.27, "strength": None}))

    def test_each_cells_runs_are_ranked_alone_where_the_cells_together_overlap(self):
        # Two packings whose verdicts each one load separates (1.10–1.15 and 1.16–1.20 of their q_u),
        # but a standing run of the stronger lies above a falling run of the weaker.
        def verdict(cell, ratio, stands):
            return {"cell": f"dir/{cell}.json", "floor_friction": None, "stands": stands, "toe_load": ratio,
                    "peak_load": ratio, "peak_over_strength": ratio}
        runs = [verdict("weak", 1.10, True), verdict("weak", 1.15, False),
                verdict("strong", 1.16, True), verdict("strong", 1.20, False)]
        critical, per_cell = corner_stress.critical_loads(runs)
        together = critical["the scene's"]["peak_over_strength"]
        self.assertEqual((together["highest_standing"], together["lowest_falling"]), (1.16, 1.15))
        self.assertFalse(together["separates_every_run"])
        for cell, (high, low) in (("weak.json", (1.10, 1.15)), ("strong.json", (1.16, 1.20))):
            alone = per_cell["the scene's"][cell]["peak_over_strength"]
            self.assertEqual((alone["highest_standing"], alone["lowest_falling"]), (high, low))
            self.assertTrue(alone["separates_every_run"])
        self.assertEqual(corner_stress.critical_loads(runs[:2])[1], {}, "one cell: nothing per cell")

    def test_a_critical_toe_load_separates_the_verdicts_or_is_said_not_to(self):
        rows = [{"toe_load": 0.26, "stands": True}, {"toe_load": 0.28, "stands": True},
                {"toe_load": 0.29, "stands": False}, {"toe_load": 0.31, "stands": False}]
        def critical(rows):
            c = corner_stress.critical_load(rows, "toe_load")
            return c["highest_standing"], c["lowest_falling"], c["separates_every_run"]
        self.assertEqual(critical(rows), (0.28, 0.29, True))
        self.assertEqual(critical(rows + [{"toe_load": 0.30, "stands": True}]), (0.30, 0.29, False))
        self.assertEqual(critical(rows[:2]), (0.28, None, True))
