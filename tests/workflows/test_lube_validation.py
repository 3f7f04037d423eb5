"""The Lube validation (workflows/lube_validation): the quick study runs the coarse a = 1 column to
rest and writes its table, JSON and figure; the scene generator's column is what the study measures."""
import json

from workflow_test_util import BUILD, WORKFLOWS, WorkflowTest, run


class LubeValidationTest(WorkflowTest):
    def test_quick_study(self):
        folder = WORKFLOWS / "lube_validation"
        run(["/usr/bin/python3", folder / "study.py", self.out, "--quick", "--build", BUILD])
        results = self.assert_json_fields(self.out / "results.json", [])
        self.assertEqual(len(results), 1)
        r = results[0]
        self.assertTrue(r["at_rest"], "the column must come to rest before the scene's end")
        self.assertGreater(r["runout"], 0.1)
        self.assertLess(r["runout"], 2 * r["lube_runout"])
        self.assertGreater(r["final_height"], 0.5)
        self.assertLessEqual(r["final_height"], 1.0 + 1e-3)  # nothing rises above the initial top
        self.assertIn("| case | a |", (self.out / "results.md").read_text())
        self.assert_png(self.out / "runout.png")
        scene = json.loads((self.out / r["case"] / "scene.json").read_text())
        self.assertEqual(scene["integration"], {"transfer": {"apic_flip": {"pic_rate": 5.0}}})
        self.assertEqual(scene["obstacles"][2]["remove_at"], 0.02)
