"""The generalization benchmark (workflows/generalization/study.py) in its smoke version: the tiny
column as the one held-out scene, its eight runs (two draws of the surrogate with its budget), summary.json with the per-scene fields, the table and
the figure, both libraries sampled and the second library's run measured against the live run of its
own template, every template prepared with the spheres asked for and the surrogate with the keys of --surrogate at the tolerance (and, in its budget run, the error budget) asked for; and the live reference is deterministic: its scene run again gives no error at all. Surrogate keys that are not a JSON object are refused, naming the file, before anything runs."""
import json
import math
import sqlite3
import subprocess

from workflow_test_util import BUILD, WORKFLOWS, WorkflowTest, run

from plotting import run_compare  # noqa: E402  (workflow_test_util puts workflows/ on the path)


class GeneralizationTest(WorkflowTest):
    def test_smoke_benchmark(self):
        run(["/usr/bin/python3", WORKFLOWS / "generalization" / "study.py", self.out, "--smoke", "--threads", "1",
             "--spheres", "64", "--surrogate", WORKFLOWS / "generalization" / "surrogate_fast.json",
             "--tolerance", "40", "--error-budget", "150", "--draws", "2"])
        summary = self.assert_json_fields(self.out / "summary.json", ["paths", "spheres", "end_s", "libraries_cpu_s", "scenes"])
        self.assertEqual(summary["spheres"], 64)
        self.assertEqual(summary["surrogate"]["tolerance"], 40)
        scene_material = json.loads((self.out / "scenes" / "aspect_1_bond_1_surrogate.json").read_text())["materials"][0]
        self.assertEqual((scene_material["law"], scene_material["tolerance"]), ("surrogate", 40))
        # --surrogate's other keys reach the runs (the faster setting's shorter catch-ups).
        self.assertEqual(scene_material["fallback"]["catch_up_steps"], 100)
        self.assertNotIn("error_budget", scene_material)
        budget_material = json.loads((self.out / "scenes" / "aspect_1_bond_1_surrogate_budget.json").read_text())["materials"][0]
        self.assertEqual((budget_material["law"], budget_material["tolerance"], budget_material["error_budget"]),
                         ("surrogate", 40, 150))
        for library in ("lib_bond_1", "lib_bond_1_seed"):
            self.assert_template_spheres(self.out / library, 64)
            # Both hold the sampled paths: the other seed's library answers surrogate_budget_seed.
            catalogue = sqlite3.connect(self.out / library / "catalogue.sqlite")
            try:
                self.assertEqual(catalogue.execute("SELECT COUNT(*) FROM paths").fetchone()[0], 2, library)
            finally:
                catalogue.close()
        self.assertEqual(list(summary["scenes"]), ["aspect_1_bond_1"])
        scene = summary["scenes"]["aspect_1_bond_1"]
        for key in ("cpu_ratio_to_live", "live_fraction", "runout_rel_error", "runout_rel_change_draws", "noise_floor",
                    "chaos_floor", "runout_rel_error_seed_library", "damage_change", "damage_noise_floor",
                    "kinetic_energy_change", "kinetic_energy_change_draws", "kinetic_energy_noise_floor"):
            self.assertIn(key, scene)
        # The kinetic energy's change: the mean of the draws' signed changes, each its run's against live.
        draws = [scene["runs"][run]["kinetic_energy_change"] for run in ("surrogate_budget", "surrogate_budget_draw_1")]
        self.assertEqual(scene["kinetic_energy_change_draws"], draws)
        if None not in draws:
            self.assertAlmostEqual(scene["kinetic_energy_change"], sum(draws) / 2)
        # The tiny column's cells are bonded: D is a share of bonds, its change between two runs at most 1.
        self.assertEqual(scene["damage_change"], scene["runs"]["surrogate_budget"]["damage_change"])
        self.assertLessEqual(abs(scene["damage_change"]), 1.0)
        self.assertEqual(scene["damage_noise_floor"], abs(scene["runs"]["live_seed"]["damage_change"]))
        self.assertEqual(summary["draws"], 2)
        self.assertEqual(len(scene["runout_rel_change_draws"]), 2)
        # The headline is the state key with its error budget, the demo's setting.
        self.assertEqual(scene["cpu_ratio_to_live"], scene["runs"]["surrogate_budget"]["cpu_ratio_to_live"])
        self.assertEqual(sorted(scene["runs"]),
                         ["hybrid", "live", "live_perturbed", "live_seed", "surrogate", "surrogate_budget",
                          "surrogate_budget_draw_1", "surrogate_budget_seed"])
        # The second library's run is measured against the live run of its own template.
        seeded = scene["runs"]["surrogate_budget_seed"]
        self.assertEqual(seeded["reference"], "live_seed")
        self.assertEqual(scene["runs"]["surrogate_budget"]["reference"], "live")
        self.assertAlmostEqual(seeded["cpu_ratio_to_live"], seeded["cpu_s"] / scene["runs"]["live_seed"]["cpu_s"])
        seeded_material = json.loads((self.out / "scenes" / "aspect_1_bond_1_surrogate_budget_seed.json").read_text())
        self.assertTrue(seeded_material["materials"][0]["library"].endswith("lib_bond_1_seed"))
        for name, r in scene["runs"].items():
            self.assertEqual(r["failed"], "", name)
            self.assertTrue(math.isfinite(r["cpu_s"]) and r["cpu_s"] > 0, name)
            self.assertTrue(0 <= r["live_fraction"] <= 1, name)
            self.assertTrue(0 <= r["catch_up_share"] <= 1, name)
            self.assertTrue(math.isfinite(r["stress_rel_l2"]), name)
        self.assertEqual(scene["runs"]["live"]["live_fraction"], 1.0)
        self.assertEqual(scene["runs"]["live"]["catch_up_share"], 0.0)  # a live cell never catches up
        self.assertLess(scene["runs"]["surrogate"]["live_fraction"], 1.0)
        # Another packing seed is another run: its stress field differs from the reference's.
        self.assertGreater(scene["runs"]["live_seed"]["stress_rel_l2"], 0.0)
        # The chaos floor: the reference with gravity changed in its 12th digit, on the reference's own
        # template, is another trajectory, nearer the reference than another packing's.
        gravity = [json.loads((self.out / "scenes" / f"aspect_1_bond_1_{name}.json").read_text())["gravity"]["g"]
                   for name in ("live", "live_perturbed")]
        self.assertNotEqual(gravity[1], gravity[0])
        self.assertEqual(gravity[1], [g * (1 + 1e-12) for g in gravity[0]])
        # The surrogate's second draw: its run with the length scales fitted on the next set of probes
        # and on the same perturbed gravity, against the live reference.
        draw = json.loads((self.out / "scenes" / "aspect_1_bond_1_surrogate_budget_draw_1.json").read_text())
        self.assertEqual(draw["gravity"]["g"], gravity[1])
        self.assertEqual(draw["materials"][0], {**budget_material, "fit_seed": 1})
        self.assertEqual(scene["runs"]["surrogate_budget_draw_1"]["reference"], "live")
        perturbed = scene["runs"]["live_perturbed"]
        self.assertEqual(perturbed["reference"], "live")
        self.assertGreater(perturbed["stress_rel_l2"], 0.0)
        self.assertLess(perturbed["stress_rel_l2"], scene["runs"]["live_seed"]["stress_rel_l2"])
        self.assertIn("| aspect_1_bond_1 | surrogate |", (self.out / "table.md").read_text())
        self.assert_png(self.out / "generalization.png")

        again = self.out / "live_again"
        run([BUILD / "mpm_solver" / "mpm_solver", self.out / "scenes" / "aspect_1_bond_1_live.json", "--out", again,
             "--threads", "1"])
        errors = run_compare.errors(again, self.out / "runs" / "aspect_1_bond_1" / "live")
        for key in ("runout_rel_err", "mass_edge_rel_err", "centroid_rel_err"):
            self.assertIn(errors.pop(key), (None, 0.0))
        self.assertEqual(errors, {"front_rel_err": 0.0, "stress_rel_l2": 0.0, "stress_smoothed_rel_l2": 0.0,
                                  "deposit_rms_m": 0.0, "damage_change": 0.0, "kinetic_energy_change": 0.0})
        self.assertTrue(json.loads((again / "summary.json").read_text())["final_time"] > 0)

    def test_surrogate_keys_that_are_not_a_json_object_are_refused_naming_the_file(self):
        for text, expected in (("{\"tolerance\": 150", "expected a readable JSON object"), ("[150]", "got list")):
            keys = self.out / "keys.json"
            keys.write_text(text)
            done = subprocess.run(["/usr/bin/python3", str(WORKFLOWS / "generalization" / "study.py"), str(self.out / "study"),
                                   "--surrogate", str(keys)], capture_output=True, text=True)
            self.assertNotEqual(done.returncode, 0)
            self.assertIn(f"{keys}: --surrogate: ", done.stderr)
            self.assertIn(expected, done.stderr)
            self.assertFalse((self.out / "study" / "runs").exists())
