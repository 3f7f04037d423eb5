"""workflows/audit: a damaged restart file is refused or runs exactly as the undamaged one, never
differently (restart_corruption.py, three flipped bytes, a 125-sphere cell)."""
import json
import unittest

from workflow_test_util import BUILD, WORKFLOWS, WorkflowTest, run


class AuditTest(WorkflowTest):
    def test_a_damaged_restart_never_runs_differently(self):
        run(["/usr/bin/python3", WORKFLOWS / "audit" / "restart_corruption.py", self.out, "--build", BUILD,
             "--flips", "3", "--cell", WORKFLOWS / "demo" / "cell_soft_snow_125.json"])
        summary = json.loads((self.out / "restart_corruption.json").read_text())
        outcomes = summary["outcomes"]
        self.assertEqual(sum(outcomes.values()), 3)
        self.assertLessEqual(set(outcomes), {"refused", "ran the same"}, outcomes)
        # The first flip is the file's first byte, its HDF5 signature: refused whatever the layout.
        self.assertGreaterEqual(outcomes.get("refused", 0), 1, outcomes)


if __name__ == "__main__":
    unittest.main()
