"""The convergence studies (workflows/convergence): each run is the demo column with its own cell and
grid, so two packing seeds of one N run different packings and two grid sizes different point sets;
a study run again keeps its finished runs."""
import json

from workflow_test_util import BUILD, WORKFLOWS, WorkflowTest, run, vtu


class ConvergenceTest(WorkflowTest):
    def test_cell_size_and_mesh_studies(self):
        command = ["/usr/bin/python3", WORKFLOWS / "convergence" / "cell_size.py", self.out, "--build", BUILD,
                   "--spheres", "32", "--seeds", "1", "2", "--end", "0.02", "--times", "0.01", "0.02", "--threads", "1"]
        run(command)
        result = json.loads((self.out / "cell_size.json").read_text())
        self.assertEqual([(r["seed"], r["t"]) for r in result["rows"]], [(1, 0.01), (1, 0.02), (2, 0.01), (2, 0.02)])
        self.assertTrue(all(r["runout_m"] is not None and not r["failed"] for r in result["rows"]))
        cells = [json.loads((self.out / "cells" / f"n32_seed{s}.json").read_text())["preparation"] for s in (1, 2)]
        self.assertEqual([(c["spheres"], c["seed"]) for c in cells], [(32, 1), (32, 2)])
        finals = [vtu.read_run(self.out / "runs" / f"n32_seed{s}")[-1] for s in (1, 2)]
        self.assertGreater(abs(finals[0].in_plane_stress() - finals[1].in_plane_stress()).max(), 0,
                           "two packing seeds must give two different runs")
        # Runouts far below 1 cm: a spread would be noise over a tiny number.
        self.assertTrue(all(s["spread"] is None for s in result["summary"]))
        self.assertIsNone(result["representative"])
        # Run again: the finished runs are kept, not rerun.
        stamp = (self.out / "runs" / "n32_seed1" / "study_run.json").stat().st_mtime_ns
        run(command)
        self.assertEqual((self.out / "runs" / "n32_seed1" / "study_run.json").stat().st_mtime_ns, stamp)
        self.assert_png(self.out / "cell_size.png")

        # The mesh study into the same OUT: it reuses the run at h = 0.05 m and reads the spread just
        # measured.
        run(["/usr/bin/python3", WORKFLOWS / "convergence" / "mesh.py", self.out, "--build", BUILD,
             "--spheres", "32", "--grid-factors", "2", "1", "--end", "0.02", "--times", "0.02", "--threads", "1"])
        self.assertEqual((self.out / "runs" / "n32_seed1" / "study_run.json").stat().st_mtime_ns, stamp)
        result = json.loads((self.out / "mesh.json").read_text())
        self.assertEqual([r["h_m"] for r in result["rows"]], [0.1, 0.05])
        points = [len(vtu.read_run(self.out / "runs" / name)[0]) for name in ("n32_seed1_h2", "n32_seed1")]
        self.assertEqual(points[1], 4 * points[0], "half the grid size, one point per cell: four times the points")
        # Both runouts are far below 1 cm, where no change and no spread is reported.
        self.assertTrue(all(c["change"] is None for c in result["changes"]))
        self.assertEqual(result["seed_spread"], [{"t": 0.02, "spread": None}])  # at N = 32, from cell_size.json
        self.assert_png(self.out / "mesh.png")
