"""workflows/audit: a damaged restart file is refused or runs exactly as the undamaged one, and a
damaged library shard is reported by celldb verify or reads exactly as the undamaged one; never
differently (restart_corruption.py and library_corruption.py, three flipped bytes each, a 125-sphere
cell)."""
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

    def test_a_damaged_library_never_passes_verify_and_reads_differently(self):
        run(["/usr/bin/python3", WORKFLOWS / "audit" / "library_corruption.py", self.out, "--build", BUILD,
             "--flips", "3"])
        summary = json.loads((self.out / "library_corruption.json").read_text())
        self.assertEqual(sorted(summary), ["rank0.h5", "templates.h5"])
        for shard, result in summary.items():
            outcomes = result["outcomes"]
            self.assertEqual(sum(outcomes.values()), 3, shard)
            self.assertLessEqual(set(outcomes), {"reported by verify", "clean and identical"}, (shard, outcomes))
            # The first flip is the shard's first byte, its HDF5 signature.
            self.assertGreaterEqual(outcomes.get("reported by verify", 0), 1, (shard, outcomes))


if __name__ == "__main__":
    unittest.main()
