"""workflows/mpi_scaling: the live column on 1 x 1, 1 x 2 and 2 x 1, two steps, and the model."""
import json
import unittest

from workflow_test_util import BUILD, WORKFLOWS, WorkflowTest, run


class MpiScalingTest(WorkflowTest):
    def test_smoke_runs_and_model(self):
        run(["/usr/bin/python3", WORKFLOWS / "mpi_scaling" / "scaling.py", self.out, "--smoke", "--build", BUILD])
        result = json.loads((self.out / "scaling.json").read_text())
        runs = result["runs"]
        self.assertEqual(sorted(runs), ["1x1", "1x2", "2x1"])
        # Every run took the same steps of the same scene; only the two-rank run exchanged bytes,
        # one record per point per step.
        self.assertEqual(len({r["steps"] for r in runs.values()}), 1)
        self.assertEqual(runs["1x1"]["load"]["shared_bytes_per_step"], 0)
        self.assertGreater(runs["2x1"]["load"]["shared_bytes_per_step"], 100 * result["points"])
        self.assertEqual(len(runs["2x1"]["load"]["update_seconds_by_rank"]), 2)
        self.assertEqual(result["points"], 1152)
        # The model: more ranks never take longer per step, and efficiency falls with the rank count.
        by_id = [m for m in result["projection"] if m["placement"] == "by id"]
        self.assertEqual([m["ranks"] for m in by_id], [64, 128, 256, 512, 1024])
        for a, b in zip(by_id, by_id[1:]):
            self.assertLessEqual(b["step_s"], a["step_s"])
            self.assertLessEqual(b["efficiency"], a["efficiency"] + 1e-9)
        self.assertIn("Assumed interconnect", (self.out / "scaling.md").read_text())


if __name__ == "__main__":
    unittest.main()
