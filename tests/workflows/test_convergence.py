"""The convergence studies (workflows/convergence): each run is the demo column with its own cell and
grid, so two packing seeds of one N run different packings and two grid sizes different point sets;
a study run again keeps its finished runs. Their measures of how far a column has gone agree on a rigid
translation."""
import json
import sys

from workflow_test_util import BUILD, WORKFLOWS, WorkflowTest, run, run_rigid_translation, vtu

sys.path.insert(0, str(WORKFLOWS / "convergence"))
from live_demo import MEASURES, measures_at  # noqa: E402


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
        # From the two seed runs at N = 32, one per measure; too short a runout for a spread.
        self.assertEqual([(s["measure"], s["spread"]) for s in result["seed_spread"]],
                         [(key, None) for key in MEASURES])
        self.assertTrue(all(r[key] is not None for r in result["rows"] for key in MEASURES))
        self.assert_png(self.out / "mesh.png")

        # Regularized: runs of their own, their scenes carrying the length, the noise floor still the local
        # seeds'.
        regularized = self.out / "regularized"
        run(["/usr/bin/python3", WORKFLOWS / "convergence" / "mesh.py", regularized, "--build", BUILD,
             "--spheres", "32", "--grid-factors", "2", "--end", "0.02", "--times", "0.02", "--threads", "1",
             "--nonlocal-length", "0.2", "--noise-floor", self.out])
        self.assertEqual(json.loads((regularized / "mesh.json").read_text())["nonlocal_length"], 0.2)
        scene = json.loads((regularized / "scenes" / "n32_seed1_h2_nl0.2.json").read_text())
        self.assertEqual(scene["regularization"], {"nonlocal_length": 0.2})
        self.assertTrue((regularized / "runs" / "n32_seed1_h2_nl0.2" / "study_run.json").exists())

    def test_every_measure_is_the_shift_of_a_rigid_translation(self):
        # At 1 m/s, front, mass edge and centroid all advance by 1 m/s × t.
        translated = run_rigid_translation(self.out, speed=1.0, end=0.02)
        measured = measures_at(translated, (0.01, 0.02, 0.03))
        for t in (0.01, 0.02):
            measures = measured[t]
            self.assertEqual(sorted(measures), sorted(MEASURES))
            for key, value in measures.items():
                self.assertAlmostEqual(value, t, delta=1e-9, msg=key)
        self.assertEqual(measured[0.03], dict.fromkeys(MEASURES))  # past the end
