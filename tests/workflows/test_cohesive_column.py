"""The cohesive column's stability (workflows/cohesive_column): below Culmann's kinematic bound
(Co = 0.144 at φ = 30°) a mechanism exists whose dissipation is less than the work of gravity, so the
column must fall; at twice the bound it stands."""
import json

from workflow_test_util import BUILD, WORKFLOWS, WorkflowTest, run


class CohesiveColumnTest(WorkflowTest):
    def test_falls_below_the_bound_and_stands_well_above(self):
        run(["/usr/bin/python3", WORKFLOWS / "cohesive_column" / "stability.py", self.out, "--build", BUILD,
             "--cells", "10", "--cohesion-numbers", "0.1", "0.3"])
        result = json.loads((self.out / "stability.json").read_text())
        weak, strong = result["runs"]
        self.assertLess(weak["cohesion_number"], min(result["bounds"].values()))
        self.assertGreater(weak["front"], 0.1, "below the kinematic bound the column must fall")
        self.assertLess(strong["front"], result["standing"], "at twice the bound it stands")
        self.assertEqual(result["thresholds"]["10"], {"fell_at": 0.1, "stood_at": 0.3})
        self.assert_png(self.out / "stability.png")
