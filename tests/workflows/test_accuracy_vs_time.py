"""The accuracy-versus-time study (workflows/accuracy_vs_time/study.py) in its smoke version: the
tiny column, live reference, its noise and chaos floors, three variants (one the surrogate) and a hybrid run on a library the study enriched with the
scene's own states; table, Pareto plot and study JSON; resumed with a run left out. The creeping set
(the former cache_vs_live) on the tiny column: its own cell, no generic paths, its scenes written by
`mpm_solver scene`. Every run of the sets on the demo's column makes a scene the solver takes. flow_state reads a run's
flowing points by the source of their stress."""
import csv
import json
import math
import shutil
import sys
import types
import xml.etree.ElementTree as ET
from pathlib import Path

from workflow_test_util import BUILD, TINY_PATHS, TINY_SCENE, WORKFLOWS, WorkflowTest, run, run_rigid_translation

from plotting import flow, run_compare, tables, vtu

sys.path.insert(0, str(WORKFLOWS / "accuracy_vs_time"))
import flow_state  # noqa: E402  (after the path set-up)
import study  # noqa: E402
import variants  # noqa: E402


ERRORS = ["front_rel_err", "runout_rel_err", "stress_rel_l2", "stress_smoothed_rel_l2", "deposit_rms_m",
          "mass_edge_rel_err", "centroid_rel_err", "damage_change", "kinetic_energy_change"]
AGAINST_NOISE = ["front_rel_err", "stress_rel_l2", "stress_smoothed_rel_l2", "deposit_rms_m", "mass_edge_rel_err",
                 "centroid_rel_err"]
COLUMNS = ["run", "knob", "value", "law", "points", "steps", "wall_s", "cpu_s", *ERRORS,
           *(f"{key}_over_noise" for key in AGAINST_NOISE), "failed"]


class AccuracyVsTimeTest(WorkflowTest):
    def test_smoke_study(self):
        run(["/usr/bin/python3", WORKFLOWS / "accuracy_vs_time" / "study.py", self.out, "--scene", TINY_SCENE,
             "--paths", TINY_PATHS, "--variants", "smoke", "--threads", "1"])
        with (self.out / "results.csv").open() as f:
            rows = {r["run"]: r for r in csv.DictReader(f)}
        self.assertEqual(sorted(rows), ["enriching", "hybrid", "hybrid_enriched", "live", "other_seed", "perturbed",
                                        "q_sigma_0.5", "surrogate"])
        self.assertEqual(list(rows["live"]), COLUMNS)
        # The reference against itself has no error; the variants are different runs of the same scene.
        self.assertIn(rows["live"]["runout_rel_err"], ("", "0.0"))  # empty: the tiny column ran out < 1 cm
        for key in ("front_rel_err", "stress_rel_l2", "stress_smoothed_rel_l2", "deposit_rms_m", "damage_change"):
            self.assertEqual(float(rows["live"][key]), 0.0)
        self.assertGreater(float(rows["q_sigma_0.5"]["stress_rel_l2"]), 0.0)
        self.assertGreater(float(rows["hybrid"]["stress_rel_l2"]), 0.0)
        # The surrogate runs as the demo's law does, on the generic library, and answers from it.
        surrogate = json.loads((self.out / "scenes" / "surrogate.json").read_text())["materials"][0]
        self.assertEqual((surrogate["law"], surrogate["tolerance"], surrogate["fallback"]["return_after"]),
                         ("surrogate", 50.0, 5))
        self.assertEqual(surrogate["library"], str((self.out / "lib").resolve()))
        self.assertGreater(sum(tables.read_csv(self.out / "runs" / "surrogate" / "series.csv")["hits"]), 0)
        self.assertGreater(float(rows["surrogate"]["stress_rel_l2"]), 0.0)
        # flow_state splits every point-snapshot by where its stress came from: all of live's from its
        # cells, the surrogate's from the library too.
        everything = {"after": 0.0, "rate": -1.0, "pressure": -math.inf}
        snapshots = len(vtu.read_run(self.out / "runs" / "live"))
        live_state = flow_state.flowing_state(self.out / "runs" / "live", **everything)
        self.assertEqual(list(live_state), ["live"])
        self.assertEqual(live_state["live"][0], 4 * snapshots)
        surrogate_state = flow_state.flowing_state(self.out / "runs" / "surrogate", **everything)
        self.assertIn("hit", surrogate_state)
        self.assertEqual(sum(s[0] for s in surrogate_state.values()), 4 * len(vtu.read_run(self.out / "runs" / "surrogate")))
        # The noise floor: the live law on a cell packed with another seed is another run, not a copy.
        demo_cell = json.loads((WORKFLOWS / "demo" / "cell_soft_snow_250.json").read_text())
        other_cell = json.loads((self.out / "cells" / "other_seed.json").read_text())
        self.assertNotEqual(other_cell["preparation"].pop("seed"), demo_cell["preparation"].pop("seed"))
        self.assertEqual(other_cell, demo_cell)
        noise = rows["other_seed"]
        self.assertGreater(float(noise["stress_rel_l2"]), 0.0)
        # The chaos floor: the reference with gravity changed in its 12th digit is another trajectory
        # of the same packing, nearer the reference than another packing's.
        gravity = [json.loads((self.out / "scenes" / f"{name}.json").read_text())["gravity"]["g"]
                   for name in ("live", "perturbed")]
        self.assertEqual(gravity[1], [g * (1 + 1e-12) for g in gravity[0]])
        self.assertNotEqual(gravity[1], gravity[0])
        self.assertGreater(float(rows["perturbed"]["stress_rel_l2"]), 0.0)
        self.assertLess(float(rows["perturbed"]["stress_rel_l2"]), float(noise["stress_rel_l2"]))
        # Every error is stated over the noise floor's: the noise floor is 1 against itself, live 0.
        for key in AGAINST_NOISE:
            if noise[key] and float(noise[key]) > 0:
                self.assertAlmostEqual(float(noise[f"{key}_over_noise"]), 1.0)
                self.assertEqual(float(rows["live"][f"{key}_over_noise"]), 0.0)
                for r in rows.values():
                    self.assertAlmostEqual(float(r[f"{key}_over_noise"]) * float(noise[key]), float(r[key]))
            else:
                self.assertTrue(all(r[f"{key}_over_noise"] == "" for r in rows.values()))
        # Hybrid on the bare template turns every point live at its first step: the live law to round-off.
        self.assertLess(float(rows["enriching"]["stress_rel_l2"]), 1e-9)
        # The run after it finds the states it stored.
        self.assertGreater(sum(tables.read_csv(self.out / "runs" / "hybrid_enriched" / "series.csv")["hits"]), 0)
        for r in rows.values():
            self.assertTrue(float(r["cpu_s"]) > 0 and float(r["wall_s"]) > 0)
            # Finite, or not measured (the final runout error of a reference that ran out < 1 cm).
            self.assertTrue(all(r[k] == "" or math.isfinite(float(r[k])) for k in COLUMNS[6:-1]))
            self.assertEqual(r["failed"], "")
        markdown = (self.out / "results.md").read_text().splitlines()
        self.assertEqual(len(markdown), 2 + len(rows))
        self.assertTrue(markdown[0].startswith("| run | knob |"))
        self.assert_png(self.out / "pareto.png")
        study = self.assert_json_fields(self.out / "study.json", ["variants", "library_cost", "runs"])
        self.assertEqual(len(study["runs"]), 8)
        for run_name in rows:
            self.assert_run(self.out / "runs" / run_name, end_time=0.003, points=4)

        # Resumed with a run left out: the finished runs are reused as they are, the table drops it.
        before = (self.out / "runs" / "hybrid" / "summary.json").read_text()
        run(["/usr/bin/python3", WORKFLOWS / "accuracy_vs_time" / "study.py", self.out, "--scene", TINY_SCENE,
             "--paths", TINY_PATHS, "--variants", "smoke", "--threads", "1", "--skip", "q_sigma_0.5"])
        with (self.out / "results.csv").open() as f:
            self.assertEqual(sorted(r["run"] for r in csv.DictReader(f)),
                             ["enriching", "hybrid", "hybrid_enriched", "live", "other_seed", "perturbed", "surrogate"])
        self.assertEqual((self.out / "runs" / "hybrid" / "summary.json").read_text(), before)

    def test_every_variant_on_the_demo_column_is_a_scene_the_solver_takes(self):
        """Each run of the sets that use the demo's column, written as the study writes it, starts: the
        solver refuses unknown keys, and a variant that kept one of the demo material's keys its law
        does not take (the hybrid runs kept the surrogate's fallback.stress_tolerance) stopped the
        reduced set after an hour of runs. One step each, on a 27-sphere version of the demo's cell and
        the tiny paths. The surrogate's draws refit its length scales, each on its own fit_seed."""
        cell = study.with_preparation(WORKFLOWS / "demo" / "cell_soft_snow_250.json", {"spheres": 27},
                                      self.out / "cell.json")
        library = self.out / "lib"
        run([BUILD / "dem_sampler" / "dem_sampler", "prepare", cell, "--library", library])
        run([BUILD / "dem_sampler" / "dem_sampler", "sample", TINY_PATHS, "--library", library, "--threads", "1"])
        args = types.SimpleNamespace(out=self.out, cell=cell, scene=WORKFLOWS / "demo" / "column.json", end=None)
        for name, spec in {**variants.FULL, **variants.ENRICHED}.items():
            scene = study.write_scene(name, spec, library, BUILD, args)
            run([BUILD / "mpm_solver" / "mpm_solver", scene, "--out", self.out / "runs" / name, "--threads", "1",
                 "--set", "/time/end=1e-4"])
            with self.subTest(run=name):
                self.assertTrue((self.out / "runs" / name / "summary.json").exists())
                if "_draw_" in name:  # a draw refits the length scales on another set of probes
                    material = json.loads(Path(scene).read_text())["materials"][0]
                    self.assertEqual(material["fit_seed"], int(name.rsplit("_", 1)[1]))

    def test_creeping_set_runs_on_its_own_cell_and_the_enriched_library(self):
        run(["/usr/bin/python3", WORKFLOWS / "accuracy_vs_time" / "study.py", self.out, "--scene", TINY_SCENE,
             "--variants", "creeping", "--spheres", "64", "--threads", "1", "--skip",
             "other_seed,hybrid_enriched_coarse,cache_enriched_coarse,hybrid_enriched_tol_1,hybrid_enriched,cache_enriched"])
        with (self.out / "results.csv").open() as f:
            rows = {r["run"]: r for r in csv.DictReader(f)}
        self.assertEqual(sorted(rows), ["enriching", "hybrid_enriched_skip", "live"])
        self.assertTrue(all(r["failed"] == "" for r in rows.values()))
        # The set's own cell, prepared with the spheres asked for, is the template, and no generic path was sampled.
        weak = json.loads((WORKFLOWS / "accuracy_vs_time" / "cell_weak_snow_125.json").read_text())
        library = self.assert_json_fields(self.out / "study.json", ["library_cost"])
        self.assertGreater(library["library_cost"]["cpu_s"], 0)
        info = json.loads(run([BUILD / "database" / "celldb", "info", self.out / "lib", "--json"]))
        self.assertEqual(info["counts"]["paths"], 0)
        self.assertEqual(info["counts"]["templates"], 1)
        self.assertEqual(info["material"]["bond"]["tensile_strength"], weak["material"]["bond"]["tensile_strength"])
        self.assert_template_spheres(self.out / "lib", 64)
        scene = json.loads((self.out / "scenes" / "hybrid_enriched_skip.json").read_text())
        material = scene["materials"][0]
        self.assertEqual(material["law"], "hybrid")
        self.assertEqual(material["library"], str((self.out / "lib_enriched").resolve()))
        self.assertEqual(material["lookup"], {"k": 4, "tolerance": 0.5})
        self.assertFalse(material["enrich"])
        self.assertNotIn("fallback", material)  # the tiny scene's, removed: the law's default
        self.assertEqual(scene["integration"]["skip_strain_increment"], 1e-6)
        self.assertNotIn("lookup", json.loads((self.out / "scenes" / "live.json").read_text())["materials"][0])

    def test_a_stopped_run_is_compared_up_to_its_stop(self):
        # The reference alone, then a copy of it cut at t = 0.0015 s (what a run that stopped there
        # leaves): compared at the times both reached, it has no error at all.
        run(["/usr/bin/python3", WORKFLOWS / "accuracy_vs_time" / "study.py", self.out, "--scene", TINY_SCENE,
             "--paths", TINY_PATHS, "--variants", "smoke", "--threads", "1",
             "--skip", "other_seed,perturbed,q_sigma_0.5,hybrid,surrogate,enriching,hybrid_enriched"])
        reference, stopped = self.out / "runs" / "live", self.out / "stopped"
        shutil.copytree(reference, stopped)
        stop = 0.0015
        pvd = ET.parse(stopped / "points.pvd")
        collection = pvd.getroot().find("Collection")
        for dataset in list(collection):
            if float(dataset.get("timestep")) > stop + 1e-12:
                collection.remove(dataset)
        pvd.write(stopped / "points.pvd")
        lines = (stopped / "series.csv").read_text().splitlines()
        kept = [lines[0]] + [line for line in lines[1:] if float(line.split(",")[0]) <= stop + 1e-12]
        self.assertLess(len(kept), len(lines))
        (stopped / "series.csv").write_text("\n".join(kept) + "\n")

        errors = run_compare.errors(stopped, reference)
        for key in ("runout_rel_err", "mass_edge_rel_err", "centroid_rel_err"):
            self.assertIn(errors.pop(key), (None, 0.0))  # None: the tiny column moved < 1 cm
        self.assertEqual(errors, {"front_rel_err": 0.0, "stress_rel_l2": 0.0, "stress_smoothed_rel_l2": 0.0,
                                  "deposit_rms_m": 0.0, "damage_change": 0.0, "kinetic_energy_change": 0.0})
        # Not zero by accident: past the stop the reference's stress field still changes.
        snapshots = {round(s.time, 9): s for s in vtu.read_run(reference)}
        last_before_stop = max(t for t in snapshots if t <= stop)
        self.assertGreater(flow.stress_error(snapshots[max(snapshots)], snapshots[last_before_stop]), 0.0)

    def test_bulk_errors_of_a_faster_rigid_translation(self):
        # Blocks translated at 1.0 and 1.1 m/s: every advance is v t, so each bulk error is 10 %; at
        # 0.02 s the reference has moved 2 cm, past the 1 cm below which no error is stated.
        for name in ("reference", "faster"):
            (self.out / name).mkdir()
        reference = run_rigid_translation(self.out / "reference", speed=1.0, end=0.02)
        faster = run_rigid_translation(self.out / "faster", speed=1.1, end=0.02)
        errors = run_compare.errors(faster, reference)
        self.assertAlmostEqual(errors["mass_edge_rel_err"], 0.1, delta=1e-6)
        self.assertAlmostEqual(errors["centroid_rel_err"], 0.1, delta=1e-6)
        self.assertAlmostEqual(errors["runout_rel_err"], 0.1, delta=1e-6)
        # Kinetic energy goes as v²: 1.1² − 1.
        self.assertAlmostEqual(errors["kinetic_energy_change"], 0.21, delta=1e-6)
        self.assertEqual(run_compare.errors(reference, reference)["centroid_rel_err"], 0.0)
