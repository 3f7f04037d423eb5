"""The library precomputation (workflows/precompute/precompute.sh) on the tiny paths: by default it
writes under GRAINBANK_OUT, not the source tree; a second run finds the template and every path done."""
import json

from workflow_test_util import BUILD, TINY_PATHS, WORKFLOWS, WorkflowTest, run


class PrecomputeTest(WorkflowTest):
    def test_default_library_under_the_output_root_then_resumes(self):
        script = WORKFLOWS / "precompute" / "precompute.sh"
        first = run(["sh", script], GRAINBANK_OUT=self.out, PATHS=TINY_PATHS)
        self.assertIn("sampled 2 path(s)", first)
        library = self.out / "precompute" / "lib"
        info = json.loads(run([BUILD / "database" / "celldb", "info", library, "--json"]))
        self.assertEqual(info["counts"]["templates"], 1)
        self.assertEqual(info["paths"]["done"]["paths"], 2)
        self.assertGreater(info["committed_records"], 0)

        second = run(["sh", script, library], PATHS=TINY_PATHS)
        self.assertIn("template 1 (already in the library)", second)
        self.assertIn("sampled 0 path(s)", second)
