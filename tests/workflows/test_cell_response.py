"""The cell-response validation (workflows/cell_response): a dense frictional cell's relaxed moduli
lie below the affine (Voigt) ones, which relaxation can only lower, and its shear modulus is the
same measured in pure and in simple shear (an isotropic packing), within a small cell's anisotropy;
under a held normal stress its faster shear flow is looser and more frictional. A bonded cell is
stronger at its peak than once its bonds near the shear have broken, and its peak envelope has a
cohesion."""
import copy
import csv
import json
import subprocess
import sys

from workflow_test_util import BUILD, WORKFLOWS, WorkflowTest, run

sys.path.insert(0, str(WORKFLOWS / "cell_response"))
import moduli  # noqa: E402


class CellResponseTest(WorkflowTest):
    def test_moduli_of_a_dense_cell(self):
        run(["/usr/bin/python3", WORKFLOWS / "cell_response" / "moduli.py", self.out, "--build", BUILD,
             "--seeds", "1", "--pressures", "1000", "--preparations", "dense", "--spheres", "64"])
        with (self.out / "moduli.csv").open() as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 1)
        r = {k: float(v) for k, v in rows[0].items() if k not in ("preparation", "refused")}
        self.assertEqual(rows[0]["refused"], "", "a dense packing is in equilibrium")
        self.assertLess(r["rest_drift"], 0.05 * 1000, "the preparation's check holds it to 5 % of p0")
        self.assertGreater(r["Z"], 4, "a dense frictional packing is hyperstatic")
        # Relaxed ≤ affine; the estimate uses (2R̄)² for ℓ², hence the 10 % for the spread of radii.
        self.assertGreater(r["K"], 0)
        self.assertLessEqual(r["K"], 1.1 * r["K_voigt"])
        self.assertGreater(r["G_pure_shear"], 0)
        self.assertLessEqual(r["G_pure_shear"], 1.1 * r["G_voigt"])
        self.assertLessEqual(r["G_simple_shear"], 1.1 * r["G_voigt"])
        self.assertAlmostEqual(r["G_simple_shear"] / r["G_pure_shear"], 1, delta=0.35)
        self.assertIn("| dense | 1000 | 1 |", (self.out / "moduli.md").read_text())

    def test_a_refused_cell_is_left_out_of_the_means_and_named(self):
        """Hand-made rows: the second loose cell's preparation was refused, not in equilibrium."""
        def row(seed, shear):
            return {"preparation": "loose", "seed": seed, "pressure": 1000.0, "phi": 0.56, "Z": 4.1, "K": 8e5,
                    "G_compression": shear, "G_pure_shear": shear, "G_simple_shear": shear, "K_voigt": 1.2e6,
                    "G_voigt": 1.1e6, "young": 1.0, "poisson": 0.3, "rest_drift": 9.4, "refused": ""}
        refused = {"preparation": "loose", "seed": 2, "pressure": 1000.0, "spheres": 125,
                   "refused": "preparation: the packing is not in equilibrium"}
        text = moduli.table([row(1, 2e5), refused, row(3, 4e5)])
        self.assertIn("| loose | 1000 | 2 of 3 |", text)
        self.assertIn("| 0.3 ± 0.14 |", text, "G over the two cells in equilibrium: 0.2 and 0.4 MPa")
        self.assertIn("Left out: loose, p0 = 1000 Pa, seed 2: preparation: the packing is not in equilibrium", text)

    def test_a_cell_dem_sampler_refuses_is_named_not_measured(self):
        """A real refusal: the preparation's equilibrium check, set tighter than any packing can hold
        (1e-9 of p0), refuses the cell, and the study names it instead of stopping."""
        cell = moduli.cell_spec(1, 1000, 64, "dense")
        cell["preparation"]["equilibrium_drift"] = 1e-9
        (self.out / "tight.json").write_text(json.dumps(cell))
        run(["/usr/bin/python3", WORKFLOWS / "cell_response" / "moduli.py", self.out / "study", "--build", BUILD,
             "--cells", self.out / "tight.json"])
        with (self.out / "study" / "moduli.csv").open() as f:
            rows = list(csv.DictReader(f))
        self.assertIn("preparation.equilibrium_drift", rows[0]["refused"])
        self.assertEqual(rows[0]["K"], "", "no modulus read from a refused cell")
        self.assertIn("Left out: tight, p0 = 1000 Pa, seed 1: ", (self.out / "study" / "moduli.md").read_text())

    def test_moduli_of_a_bonded_cell_as_it_stands(self):
        """Bonds are springs in parallel with the contacts: the same packing bonded is stiffer than
        without its bonds. E and ν are the isotropic solid's from K and G, so E = 2G(1 + ν)."""
        cell = json.loads((WORKFLOWS / "demo" / "cell_soft_snow_125.json").read_text())
        cell["preparation"]["spheres"] = 64
        unbonded = copy.deepcopy(cell)
        unbonded["effects"]["cohesion"] = False
        del unbonded["material"]["bond"]
        (self.out / "bonded.json").write_text(json.dumps(cell))
        (self.out / "unbonded.json").write_text(json.dumps(unbonded))
        run(["/usr/bin/python3", WORKFLOWS / "cell_response" / "moduli.py", self.out, "--build", BUILD,
             "--cells", self.out / "bonded.json", self.out / "unbonded.json"])
        with (self.out / "moduli.csv").open() as f:
            bonded, free = list(csv.DictReader(f))
        self.assertEqual((bonded["preparation"], bonded["pressure"], bonded["spheres"]), ("bonded", "200", "64"))
        self.assertEqual(bonded["K_voigt"], "", "the Voigt estimate has no bonds in it")
        self.assertGreater(float(free["K_voigt"]), 0)
        self.assertAlmostEqual(float(bonded["phi"]), float(free["phi"]), delta=1e-4, msg="one packing")
        for key in ("K", "G_pure_shear", "G_simple_shear"):
            self.assertGreater(float(bonded[key]), float(free[key]), key)
        for r in (bonded, free):
            self.assertTrue(0 < float(r["poisson"]) < 0.5, r["poisson"])
            self.assertAlmostEqual(float(r["young"]), 2 * float(r["G_pure_shear"]) * (1 + float(r["poisson"])),
                                   delta=1e-9 * float(r["young"]))
        self.assertIn("| bonded | 200 | 1 |", (self.out / "moduli.md").read_text())
        (self.out / "broken.json").write_text("{\"material\": ")
        refused = subprocess.run(["/usr/bin/python3", WORKFLOWS / "cell_response" / "moduli.py", self.out / "bad",
                                  "--build", BUILD, "--cells", self.out / "broken.json"], capture_output=True, text=True)
        self.assertNotEqual(refused.returncode, 0)
        self.assertIn("broken.json: expected a cell JSON file", refused.stderr)

    def test_mu_of_i(self):
        run(["/usr/bin/python3", WORKFLOWS / "cell_response" / "mu_of_i.py", self.out, "--build", BUILD,
             "--seeds", "1", "--inertial-numbers", "0.01", "0.2", "--spheres", "64", "--strain", "3",
             "--pressure", "2000", "--restitution", "0.5", "--tangential-ratio", "0.5", "--diameter-spread", "0.2"])
        with (self.out / "mu_of_i.csv").open() as f:
            slow, fast = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
        for r in (slow, fast):
            self.assertAlmostEqual(r["normal_stress"], 2000, delta=40)  # the servo holds P
        cell = json.loads((self.out / "seed1" / "cell.json").read_text())
        self.assertEqual((cell["material"]["restitution"], cell["preparation"]["pressure"]), (0.5, 2000.0))
        self.assertEqual(cell["material"]["k_t"], 0.5 * cell["material"]["k_n"])
        diameter = cell["preparation"]["diameter"]
        self.assertAlmostEqual(diameter["max"] / diameter["min"], 1.2 / 0.8)
        self.assertAlmostEqual(diameter["max"] + diameter["min"], 0.74e-3)  # the mean diameter kept
        self.assertGreater(fast["mu"], slow["mu"])
        self.assertLess(fast["phi"], slow["phi"])
        self.assertIn("Fit: μ_s =", (self.out / "mu_of_i.md").read_text())
        self.assert_png(self.out / "mu_of_i.png")
        for option, value in (("--pressure", "-1"), ("--restitution", "1.5"), ("--tangential-ratio", "0"),
                              ("--diameter-spread", "1")):
            refused = subprocess.run(["/usr/bin/python3", WORKFLOWS / "cell_response" / "mu_of_i.py", self.out / "bad",
                                      option, value], capture_output=True, text=True)
            self.assertNotEqual(refused.returncode, 0)
            self.assertIn(f"{option}: expected", refused.stderr)

    def test_strength_of_the_bonded_snow_cell(self):
        run(["/usr/bin/python3", WORKFLOWS / "cell_response" / "strength.py", self.out, "--build", BUILD,
             "--seeds", "1", "--pressures", "500", "2000"])
        result = json.loads((self.out / "strength.json").read_text())
        for r in result["rows"]:
            # The servo holds P; within 10 % here, as the window (γ = 0.1–0.15) closely follows the bonds'
            # failure, a jump the servo's filter (over γ = 0.02) takes a while to follow.
            self.assertAlmostEqual(r["normal_stress"], r["P"], delta=0.1 * r["P"])
            self.assertGreater(r["peak_shear"], r["mu"] * r["normal_stress"], "bonds add strength before they break")
        cohesion, friction_angle = result["tan"]["cohesion"], result["tan"]["friction_angle"]
        self.assertGreater(cohesion, 0)
        self.assertTrue(10 < friction_angle < 45, friction_angle)
        self.assertGreater(result["sin"]["friction_angle"], friction_angle)  # asin μ > atan μ
        self.assert_png(self.out / "strength.png")

    def test_unconfined_compression_of_the_bonded_cell(self):
        """Free sides hold σ_xx at zero while the platens load σ_yy; the bonds then break at once (a brittle
        peak, the stress falling away), and limit analysis turns q_u into the two bounds on a cut's height
        in the ratio of their N_s."""
        run(["/usr/bin/python3", WORKFLOWS / "cell_response" / "unconfined.py", self.out, "--build", BUILD,
             "--cell", WORKFLOWS / "demo" / "cell_soft_snow_125.json", "--cell-size", "0.025",
             "--strain-rate", "0.1", "--strain", "0.008"])
        result = json.loads((self.out / "unconfined.json").read_text())
        q_u = result["q_u"]
        self.assertTrue(result["peak_reached"])
        self.assertGreater(q_u, 200, "above the cell's preparation pressure: the platen loaded it")
        self.assertLess(abs(result["lateral_at_peak"]), 0.05 * q_u, "unconfined: σ_xx stays near zero")
        self.assertLess(result["after_peak"], 0.2 * q_u, "the bonds break and the strength falls away")
        self.assertGreater(result["rows"][-1]["damage"], result["damage_at_peak"] + 0.1)
        bounds = result["critical_height"]
        self.assertAlmostEqual(bounds["Culmann (N_s = 4)"] / bounds["Chen (N_s = 3.83)"], 4 / 3.83)
        self.assertAlmostEqual(bounds["Chen (N_s = 3.83)"], 1.915 * q_u / (result["density"] * 9.81), places=6)
        self.assert_png(self.out / "unconfined.png")
