"""Shared by the workflow tests: where the tools are, running a workflow command, a run with a known
answer (a rigid translation), and checks that an output is well-formed (a VTU that parses, a PNG that
decodes, a JSON with its fields)."""
import json
import os
import subprocess
import sqlite3
import sys
import tempfile
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
WORKFLOWS = HERE.parents[1] / "workflows"
sys.path.insert(0, str(WORKFLOWS))
import matplotlib.image  # noqa: E402

from plotting import png, vtu  # noqa: E402

BUILD = Path(os.environ.get("GRAINBANK_BUILD_DIR", HERE.parents[1] / "build"))
TINY_SCENE = HERE / "tiny_column.json"
TINY_PATHS = HERE / "tiny_paths.json"


def run(command, **env):
    """Runs a workflow command with the test's build directory and one thread; returns its stdout and
    fails the test with its output when it fails."""
    environment = {**os.environ, "GRAINBANK_BUILD_DIR": str(BUILD), "THREADS": "1", **env}
    done = subprocess.run([str(c) for c in command], env=environment, capture_output=True, text=True)
    if done.returncode != 0:
        raise AssertionError(f"{command} exited with {done.returncode}:\n{done.stdout}\n{done.stderr}")
    return done.stdout


def run_rigid_translation(out, speed=1.0, end=0.02):
    """Elastic points moving at `speed` [m/s] along x, with no gravity and no obstacle, run by mpm_solver
    to `end` [s] with output every 0.01 s: an exact translation. Returns the run folder."""
    scene = {"grid": {"cell_size": 0.1, "cells": [10, 4]}, "time": {"end": end, "output_interval": 0.01},
             "materials": [{"name": "m", "law": "elastic", "density": 1000, "young": 1e5, "poisson": 0.3}],
             "regions": [{"material": "m", "rectangle": {"min": [0.2, 0.1], "max": [0.4, 0.3]},
                          "velocity": [speed, 0.0]}]}
    (out / "scene.json").write_text(json.dumps(scene))
    run([BUILD / "mpm_solver" / "mpm_solver", out / "scene.json", "--out", out / "run", "--threads", "1"])
    return out / "run"


class WorkflowTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory(prefix="gb_workflow_")
        self.out = Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def assert_template_spheres(self, library, spheres):
        """Every template in the library's catalogue has `spheres` spheres."""
        catalogue = sqlite3.connect(Path(library) / "catalogue.sqlite")
        try:
            self.assertEqual(catalogue.execute("SELECT spheres FROM templates").fetchall(), [(spheres,)], library)
        finally:
            catalogue.close()

    def assert_png(self, file, min_size=(200, 150)):
        width, height = png.png_size(file)
        self.assertGreaterEqual(width, min_size[0], file)
        self.assertGreaterEqual(height, min_size[1], file)
        self.assertEqual(matplotlib.image.imread(file).shape[:2], (height, width), file)

    def assert_run(self, folder, end_time, points):
        """A run folder of mpm_solver: every VTU of points.pvd parses with `points` points and the
        fields of the figures, times from 0 to `end_time`."""
        snapshots = vtu.read_run(folder)
        self.assertAlmostEqual(snapshots[0].time, 0.0)
        self.assertAlmostEqual(snapshots[-1].time, end_time, delta=1e-9)
        for s in snapshots:
            self.assertEqual(len(s), points)
            for field in ("velocity", "strain_rate_q", "damage", "stress", "id"):
                self.assertIn(field, s.fields)
        return snapshots

    def assert_json_fields(self, file, fields):
        data = json.loads(Path(file).read_text())
        for field in fields:
            self.assertIn(field, data, file)
        return data
