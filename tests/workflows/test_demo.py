"""The demo (workflows/demo/run_demo.sh) end to end on the tiny column and library, twice: outputs,
figures and report, then the second run reuses the library. The tiny column runs with the demo's own
law and settings (workflows/demo/column.json's material)."""
import json

from workflow_test_util import BUILD, TINY_PATHS, TINY_SCENE, WORKFLOWS, WorkflowTest, run

from plotting import scenes, vtu  # noqa: E402  (workflow_test_util puts workflows/ on the path)

FIGURES = ["velocity.png", "strain_rate_damage.png", "source.png", "front_height.png", "hit_rate.png",
           "spreading.png", "deposit.png", "tracked_damage.png", "run_audit_error_vs_time.png",
           "run_audit_histogram.png"]


class DemoTest(WorkflowTest):
    def run_demo(self):
        demo_material = json.loads((WORKFLOWS / "demo" / "column.json").read_text())["materials"][0]
        scene = self.out / "tiny_demo_scene.json"
        material = {k: v for k, v in demo_material.items() if k not in ("name", "library", "template")}
        material["fallback"] = {**material.get("fallback", {}), "start": None}  # the tiny scene's hybrid start
        scenes.variant(BUILD, TINY_SCENE, scene, law=demo_material["law"], material=material)
        return run(["sh", WORKFLOWS / "demo" / "run_demo.sh", self.out], DEMO_SCENE=scene, DEMO_PATHS=TINY_PATHS)

    def test_outputs_then_reuses_the_library(self):
        first = self.run_demo()
        self.assertIn("template 1 (prepared)", first)
        self.assertIn("sampled 2 path(s)", first)
        self.assert_run(self.out / "run", end_time=0.003, points=4)
        # Tracked points write their DEM cell while live; their bond counts then get a figure too.
        figures = FIGURES + (["tracked_bonds.png"] if any((self.out / "run" / "cells").glob("*.vtk")) else [])
        for name in figures:
            self.assert_png(self.out / "figures" / name)
        report = self.assert_json_fields(self.out / "report.json", [
            "points", "steps", "library", "hit_rate_of_lookups", "went_live", "runout_m", "wall_time_s", "figures"])
        self.assertEqual(report["points"], 4)
        self.assertEqual(report["steps"], 30)  # 0.003 s at the scene's max_time_step 1e-4
        self.assertGreaterEqual(report["library"]["paths"], 2)
        self.assertTrue(0 <= report["hit_rate_of_lookups"] <= 1)
        self.assertEqual(report["law"], "surrogate")
        self.assertEqual(sorted(report["figures"]), sorted(figures + ["spreading.json"]))
        spreading = self.assert_json_fields(self.out / "figures" / "spreading.json",
                                            ["final", "kinetic_energy_peak", "kinetic_energy_over_peak", "rows"])
        self.assertEqual(len(spreading["rows"]), len(vtu.read_run(self.out / "run")))
        self.assertIn("seed Eq. 5", (self.out / "report.txt").read_text())
        # The audit re-ran the scene's 2 audited points live at each of the 30 steps.
        audit = self.assert_json_fields(self.out / "run" / "audit" / "run_audit.json",
                                        ["kind", "points", "steps_compared", "by_source", "cached", "all"])
        self.assertEqual(audit["steps_compared"], 2 * 30)
        self.assertEqual(report["audit"]["steps_compared"], 60)
        sources = audit["by_source"]
        self.assertEqual(sum(sources[s]["count"] for s in ("hit", "miss", "live")), 60)
        # ... and again with a cell of another packing seed: the noise floor, positive since the two
        # packings differ, and in the report.
        self.assertEqual(audit["noise_floor"]["all"]["count"], 60)
        self.assertGreater(audit["noise_floor"]["all"]["max"], 0)
        self.assertIn("noise floor", (self.out / "report.txt").read_text())
        # Element tests of the demo's law on its library, against the same floor cell.
        run(["/usr/bin/python3", WORKFLOWS / "audit" / "element_tests.py", self.out / "elements", "--library",
             self.out / "lib", "--floor-cell", self.out / "floor_cell.json", "--loadings", "oedometric", "unloading",
             "--strain", "2e-4", "--build", BUILD])
        elements = json.loads((self.out / "elements" / "element_tests.json").read_text())
        self.assertEqual([row["loading"] for row in elements["loadings"]], ["oedometric", "unloading"])
        for row in elements["loadings"]:
            self.assertEqual(row["steps"], 20)  # 2e-4 at |D| = 0.1 /s in steps of 1e-4 s
            self.assertGreater(row["floor_median"], 0)
            self.assertTrue(0 <= row["error_median"] <= row["error_p95"] < float("inf"))
        # Oedometric compression compresses along y in every cell.
        oedometric = elements["loadings"][0]
        for stress in ("final_run_Pa", "final_live_Pa", "final_floor_cell_Pa"):
            self.assertLess(oedometric[stress][1], -200)
        # Shear under a held normal stress: the servo holds the live cells' mean σ_yy near −P, and each
        # law flows with a positive friction; the law's row has its error over the floor's.
        run(["/usr/bin/python3", WORKFLOWS / "audit" / "held_shear.py", self.out / "held", "--library", self.out / "lib",
             "--floor-cell", self.out / "floor_cell.json", "--pressures", "500", "--rates", "3", "--strain", "0.3",
             "--build", BUILD])
        held = json.loads((self.out / "held" / "held_shear.json").read_text())["runs"]
        self.assertEqual([row["run"] for row in held], ["reference", "floor", "surrogate"])
        for row in held[:2]:
            self.assertLess(abs(row["normal_stress_Pa"] - 500), 100, row)
            self.assertEqual(row["live_share"], 1)
        for row in held:
            self.assertTrue(0 < row["friction"] < 5, row)
        self.assertIsNotNone(held[2]["friction_error_over_floor"])
        self.assert_png(self.out / "held" / "held_shear.png")

        second = self.run_demo()
        self.assertIn("template 1 (already in the library)", second)
        self.assertIn("sampled 0 path(s)", second)
        self.assert_run(self.out / "run", end_time=0.003, points=4)
