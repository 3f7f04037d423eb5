"""The Lube validation (workflows/lube_validation): the quick study runs the coarse a = 1 column to
rest and writes its table, JSON and figures; the deposit's edges lie in order inside its front; the
scene generator's column is what the study measures, with or without μ(I), and in a channel; the
front's convergence study measures each grid once; a heap below its friction angle stands; a thin
layer launched along the base slides as far as a rigid block."""
import json
import math
import shutil
import subprocess
import sys

from workflow_test_util import BUILD, WORKFLOWS, WorkflowTest, run

sys.path.insert(0, str(WORKFLOWS / "lube_validation"))
import live_study  # noqa: E402  (after the path set-up)


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
        # A thinner threshold reaches at least as far, and no edge passes the farthest point (bins are h wide).
        e = r["edges"]
        self.assertGreaterEqual(e["0.05"], e["0.1"])
        self.assertGreaterEqual(e["0.1"], e["0.15"])
        self.assertLessEqual(e["0.05"], r["runout"] + r["h"] / 0.2 + 1e-9)
        self.assertIn("| case | a |", (self.out / "results.md").read_text())
        self.assert_png(self.out / "runout.png")
        self.assert_png(self.out / "deposit.png")
        scene = json.loads((self.out / r["case"] / "scene.json").read_text())
        self.assertEqual(scene["integration"], {"transfer": {"apic_flip": {"pic_rate": 5.0}}})
        self.assertEqual(scene["obstacles"][2]["remove_at"], 0.02)

    def test_front_convergence_measures_each_grid_once(self):
        """front_convergence.py on two coarse grids of separating sand: per grid the front in time, its
        peak speed, and edges in order inside the front; a second call measures the runs again
        without re-running them."""
        command = ["/usr/bin/python3", WORKFLOWS / "lube_validation" / "front_convergence.py", self.out, "--build",
                   BUILD, "--cell-sizes", "0.04", "0.02", "--end", "0.2", "--times", "0.1", "--separation"]
        run(command)
        results = self.assert_json_fields(self.out / "fronts.json", [])
        self.assertEqual([r["L0_over_h"] for r in results], [5, 10])
        for r in results:
            scene = json.loads((self.out / f"h{r['h']:g}" / "scene.json").read_text())
            self.assertTrue(scene["materials"][0]["separation"])
            self.assertEqual(scene["time"]["end"], 0.2)
            self.assertGreater(r["front"], 0)
            # Faster than free fall from the top, sqrt(2 g H0), no point can be.
            self.assertGreater(r["peak_speed"], 0)
            self.assertLess(r["peak_speed"], math.sqrt(2 * 9.81 * 0.2))
            e = [r["edges"][k] for k in ("0.01", "0.025", "0.05", "0.1") if not math.isnan(r["edges"][k])]
            self.assertEqual(e, sorted(e, reverse=True))
            self.assertLessEqual(e[0], r["front"] + r["h"] / 0.2 + 1e-9)
        stamps = {r["h"]: (self.out / f"h{r['h']:g}" / "run" / "summary.json").stat().st_mtime_ns for r in results}
        first = (self.out / "fronts.json").read_text()
        run(command)
        for h, stamp in stamps.items():
            self.assertEqual((self.out / f"h{h:g}" / "run" / "summary.json").stat().st_mtime_ns, stamp)
        self.assertEqual((self.out / "fronts.json").read_text(), first)
        self.assertIn("| L0/h |", (self.out / "fronts.md").read_text())
        self.assert_png(self.out / "fronts.png")

    def test_front_convergence_of_the_live_twin(self):
        """--material live_twin runs the Drucker–Prager twin of the live study's cell: its friction angle
        from the cell's critical-state ratio (sin φ = μ_s < sin 30°), one point per grid cell, the live
        study's gate; the front is measured from that point spacing."""
        out = self.out / "twin"
        run(["/usr/bin/python3", WORKFLOWS / "lube_validation" / "front_convergence.py", out, "--build", BUILD,
             "--cell-sizes", "0.04", "--end", "0.12", "--times", "0.1", "--separation", "--material", "live_twin"])
        scene = json.loads((out / "h0.04" / "scene.json").read_text())
        twin = scene["materials"][0]
        self.assertTrue(twin["separation"])
        self.assertLess(twin["friction_angle"], 25)
        self.assertGreater(twin["friction_angle"], 10)
        self.assertEqual(scene["regions"][0]["points_per_cell"], 1)
        result = json.loads((out / "fronts.json").read_text())[0]
        # Before the gate opens at 0.05 s nothing moves, so the front starts at 0: the point radius
        # of one point per cell (h / 2) is the one added to the outermost centre.
        self.assertAlmostEqual(result["series"]["front"][0], 0, delta=1e-9)
        self.assertGreater(result["front"], 0)
        # At the sand's two points per cell, the point radius is h / 4, and the front starts at 0 again.
        out = self.out / "twin_ppc2"
        run(["/usr/bin/python3", WORKFLOWS / "lube_validation" / "front_convergence.py", out, "--build", BUILD,
             "--cell-sizes", "0.04", "--end", "0.06", "--times", "0.05", "--material", "live_twin",
             "--points-per-cell", "2"])
        self.assertEqual(json.loads((out / "h0.04" / "scene.json").read_text())["regions"][0]["points_per_cell"], 2)
        self.assertAlmostEqual(json.loads((out / "fronts.json").read_text())[0]["series"]["front"][0], 0, delta=1e-9)

    def test_scene_with_inertial_rheology(self):
        out = self.out / "mu_i.json"
        run(["/usr/bin/python3", WORKFLOWS / "lube_validation" / "column_scene.py", out, "--aspect-ratio", "1",
             "--inertial-rheology"])
        sand = json.loads(out.read_text())["materials"][0]
        self.assertEqual(sand["friction_angle"], 30.0)
        self.assertGreater(sand["inertial_rheology"]["mu_2"], 0.5)  # above the static sin 30°
        run([BUILD / "mpm_solver" / "mpm_solver", out, "--out", self.out / "mu_i", "--threads", "1",
             "--set", "/time/end=0.03"])
        self.assertTrue((self.out / "mu_i" / "summary.json").exists())

    def test_scene_in_a_channel(self):
        out = self.out / "channel.json"
        run(["/usr/bin/python3", WORKFLOWS / "lube_validation" / "column_scene.py", out, "--aspect-ratio", "1",
             "--channel-width", "0.2"])
        scene = json.loads(out.read_text())
        self.assertTrue(scene["effects"]["channel_walls"])
        # The side walls take the back wall's friction unless told otherwise.
        self.assertEqual(scene["channel_walls"], {"width": 0.2, "friction": scene["obstacles"][1]["friction"]})
        run([BUILD / "mpm_solver" / "mpm_solver", out, "--out", self.out / "channel", "--threads", "1",
             "--set", "/time/end=0.03"])
        self.assertTrue((self.out / "channel" / "summary.json").exists())

    def test_heap_below_its_friction_angle_stands(self):
        """heap.py on a coarse 25° heap of the 30° sand: it prints its row, and the apex settles only
        elastically (ρ g H² / 2E = 0.013 mm; stop 47's contact let it creep 0.42 mm)."""
        out = run(["/usr/bin/python3", WORKFLOWS / "lube_validation" / "heap.py", self.out, "--build", BUILD,
                   "--slopes", "25", "--cell-sizes", "0.02", "--transfers", "apic_flip:5"])
        row = [line for line in out.splitlines() if line.startswith("| 25° | apic_flip:5 | 0.02 |")]
        self.assertEqual(len(row), 1, out)
        settled_mm = float(row[0].split("|")[5])
        self.assertLess(abs(settled_mm), 0.05)
        self.assertTrue((self.out / "slope25_apic_flip5_h0.02" / "run" / "summary.json").exists())

    def test_a_launched_thin_layer_slides_as_far_as_a_rigid_block(self):
        """thin_layer.py --velocity: layers one and two grid cells thick, launched at 1 m/s on a base
        of friction 0.3 (less than the sand carries in simple shear, sin 30° = 0.5, so the base's
        friction sets the slide), stop with their centre of mass where a rigid block would, v0²/(2 μ g) = 169.9 mm,
        within 4 %, and within 1 % of each other: the base contact takes its whole Coulomb friction from
        a layer as thin as the grid. Their fronts run ahead of the centre (the layer stretches as it
        slows), so the layer is not a block: since stop 76, with the base's force acting where the points
        touch it, the centres stop 2.9–3.0 % beyond the block at one, two and four cells (before,
        0.9–2.3 %)."""
        out = run(["/usr/bin/python3", WORKFLOWS / "lube_validation" / "thin_layer.py", self.out, "--build", BUILD,
                   "--thickness", "0.01", "--cells", "1", "2", "--transfers", "apic_flip:5", "--velocity", "1",
                   "--base-friction", "0.3"])
        rigid = 1000 * 1.0**2 / (2 * 0.3 * 9.81)
        self.assertIn(f"rigid block: {rigid:.1f}", out)
        rows = [line.split("|") for line in out.splitlines() if line.startswith("| apic_flip:5 |")]
        self.assertEqual([int(r[2]) for r in rows], [1, 2], out)
        centres = []
        for r in rows:
            centre, front, rear = (float(r[i]) for i in (3, 4, 5))
            self.assertLess(abs(centre / rigid - 1), 0.04, out)
            self.assertGreater(front, centre)
            self.assertLess(rear, centre)
            centres.append(centre)
        self.assertLess(abs(centres[1] / centres[0] - 1), 0.01, out)

    def test_thin_layer_refuses_a_negative_speed(self):
        done = subprocess.run(["/usr/bin/python3", WORKFLOWS / "lube_validation" / "thin_layer.py", self.out,
                               "--build", BUILD, "--velocity", "-1"], capture_output=True, text=True)
        self.assertEqual(done.returncode, 2)
        self.assertIn("--velocity: expected a speed >= 0 [m/s], got -1.0", done.stderr)
        self.assertEqual(list(self.out.iterdir()), [])  # refused before any run folder is made


class LiveLubeTest(WorkflowTest):
    """live_study.py: the column with live DEM cells and its Drucker–Prager twin."""

    def test_smoke_study(self):
        run(["/usr/bin/python3", WORKFLOWS / "lube_validation" / "live_study.py", self.out, "--smoke", "--build", BUILD])
        results = self.assert_json_fields(self.out / "live.json", [])
        self.assertEqual([r["case"] for r in results], ["live_smoke"])
        r = results[0]
        cell = json.loads((self.out / "live_smoke" / "cell.json").read_text())
        self.assertEqual(cell["material"]["friction"], 0.5)
        self.assertNotIn("bond", cell["material"])  # cohesionless
        self.assertEqual(cell["preparation"]["spheres"], 27)
        summary = json.loads((self.out / "live_smoke" / "run" / "summary.json").read_text())
        self.assertEqual(summary["coupling"]["laws"][0]["law"], "live")
        self.assertGreater(summary["coupling"]["point_steps"], 0)
        # Measured at the run's end, past the gate: nothing behind the wall, nothing above the top.
        self.assertFalse(r["at_rest"])
        self.assertGreaterEqual(r["rest_time"], 0.05)
        self.assertGreaterEqual(r["runout"], -r["h"] / 0.2)
        self.assertLessEqual(r["final_height"], 1.0 + 1e-3)
        self.assertIn("Drucker–Prager twin", (self.out / "live.md").read_text())
        self.assert_png(self.out / "live.png")

    def test_grid_pair_is_measured_at_one_time(self):
        """The grid comparison measures both runs at the earlier of their ends: the smoke run under both
        names is measured twice at its last row and snapshot, and without the pair nothing is drawn."""
        run(["/usr/bin/python3", WORKFLOWS / "lube_validation" / "live_study.py", self.out, "--smoke", "--build", BUILD])
        self.assertEqual(live_study.grid_pair(self.out), [])
        pair_out = self.out / "pair"
        for name in live_study.GRID_PAIR:
            shutil.copytree(self.out / "live_smoke", pair_out / name)
        coarse, fine = live_study.grid_pair(pair_out)
        self.assertEqual((coarse["case"], fine["case"]), live_study.GRID_PAIR)
        self.assertEqual(coarse["until"], fine["until"])
        self.assertEqual(coarse["rest_time"], coarse["until"])  # measured at the last row
        self.assertLessEqual(coarse["profile_time"], coarse["until"])
        self.assertEqual(coarse["profile_time"], fine["profile_time"])
        live_study.plot_grid([coarse, fine], self.out / "grid.png")
        self.assert_png(self.out / "grid.png")

    def test_twin_friction_is_the_cells_critical_state(self):
        """The twin's cone: sin φ is the μ_s of the cell's μ(I) fit, which lies in the published
        range for spheres with μ_p = 0.5 within the fit's own scatter; its moduli are the cell's."""
        twin = live_study.twin_material()
        mu_s = math.sin(math.radians(twin["friction_angle"]))
        self.assertAlmostEqual(mu_s, live_study.critical_state_ratio(), places=12)
        self.assertGreater(mu_s, 0.32)
        self.assertLess(mu_s, 0.40)
        young, poisson, solid_fraction = live_study.cell_elasticity()
        self.assertEqual((twin["young"], twin["poisson"]), (young, poisson))
        self.assertGreater(poisson, 0)
        self.assertLess(poisson, 0.5)
        self.assertAlmostEqual(twin["density"], 920 * solid_fraction)
