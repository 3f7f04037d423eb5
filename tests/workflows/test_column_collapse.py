"""The paper's column (workflows/column_collapse): the full-scale scene loads and runs a probe step
with the live and cache laws (estimate_time.py), and its figures are drawn from the probe."""
from workflow_test_util import WORKFLOWS, WorkflowTest, run

POINTS = 12 * 24 * 4  # a 1.2 m × 2.4 m column, 0.1 m grid cells, 2 × 2 points per cell


class ColumnCollapseTest(WorkflowTest):
    def test_probe_estimate_and_figures(self):
        folder = WORKFLOWS / "column_collapse"
        run(["/usr/bin/python3", folder / "estimate_time.py", self.out, "--laws", "live,cache", "--probe-time", "2e-4",
             "--threads", "1"])
        estimate = self.assert_json_fields(self.out / "estimate.json", ["end_time_s", "probe_time_s", "extrapolation", "laws"])
        self.assertTrue(estimate["extrapolation"])
        self.assertEqual([r["law"] for r in estimate["laws"]], ["live", "cache"])
        for row in estimate["laws"]:
            self.assertEqual(row["points"], POINTS)
            self.assertGreater(row["extrapolated_steps"], row["probe_steps"])
            self.assertGreater(row["extrapolated_wall_h"], 0)
        self.assertIn("| law |", (self.out / "estimate.md").read_text())
        snapshots = self.assert_run(self.out / "probe_live", end_time=2e-4, points=POINTS)
        self.assertAlmostEqual(snapshots[0].xy[:, 1].max(), 2.6 - 0.025, places=6)  # top row of points

        printed = run(["/usr/bin/python3", folder / "figures.py", self.out / "probe_live", self.out / "figures"])
        for name in ("velocity.png", "strain_rate_damage.png", "front_height.png", "tracked_damage.png",
                     "tracked_bonds.png"):
            self.assertIn(name, printed)
            self.assert_png(self.out / "figures" / name)
