"""The cell-response validation (workflows/cell_response): a dense frictional cell's relaxed moduli
lie below the affine (Voigt) ones, which relaxation can only lower, and its shear modulus is the
same measured in pure and in simple shear (an isotropic packing), within a small cell's anisotropy."""
import csv

from workflow_test_util import BUILD, WORKFLOWS, WorkflowTest, run


class CellResponseTest(WorkflowTest):
    def test_moduli_of_a_dense_cell(self):
        run(["/usr/bin/python3", WORKFLOWS / "cell_response" / "moduli.py", self.out, "--build", BUILD,
             "--seeds", "1", "--pressures", "1000", "--preparations", "dense", "--spheres", "64"])
        with (self.out / "moduli.csv").open() as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 1)
        r = {k: float(v) for k, v in rows[0].items() if k != "preparation"}
        self.assertGreater(r["Z"], 4, "a dense frictional packing is hyperstatic")
        # Relaxed ≤ affine; the estimate uses (2R̄)² for ℓ², hence the 10 % for the spread of radii.
        self.assertGreater(r["K"], 0)
        self.assertLessEqual(r["K"], 1.1 * r["K_voigt"])
        self.assertGreater(r["G_pure_shear"], 0)
        self.assertLessEqual(r["G_pure_shear"], 1.1 * r["G_voigt"])
        self.assertLessEqual(r["G_simple_shear"], 1.1 * r["G_voigt"])
        self.assertAlmostEqual(r["G_simple_shear"] / r["G_pure_shear"], 1, delta=0.35)
        self.assertIn("| dense | 1000 | 1 |", (self.out / "moduli.md").read_text())
