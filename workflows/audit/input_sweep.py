#!/usr/bin/python3
"""Bad input, field by field: every field of a product input is replaced in turn by a wrong type,
-1, 0, ±1e300, 1e308, 1e19, 1e-300, null, true, [] or {}, removed, and each object gets an unknown
key; the tool runs on each copy and every outcome is classed:
- refused: exit 1 with one line (the line is kept);
- ran: exit 0 (for the scene, with no NaN in series.csv; for paths, `celldb verify` passes);
- changed: refused after changing the library (paths only), the failure this guards against;
- crash: killed by a signal; timeout: still running after --timeout seconds.

    input_sweep.py OUT --kind scene|cell|paths [--build BUILD] [--timeout 90]

scene: the demo column (workflows/demo/column.json) to t = 0.5 ms on the demo's library (its
250-sphere cell and paths.json, sampled once into OUT/lib). cell: the demo's 250-sphere cell.json at
32 spheres, prepared into a new library. paths: a small paths.json (an explicit path, a generator
and a probe) sampled into a copy of a prepared 32-sphere library. Writes OUT/KIND.json (counts and
every run's outcome) and prints the counts.
"""
import argparse
import copy
import hashlib
import json
import shutil
import subprocess
import sys
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from plotting import environment  # noqa: E402

DEMO = Path(__file__).resolve().parents[1] / "demo"
VALUES = [("string", "x"), ("-1", -1), ("0", 0), ("1e308", 1e308), ("null", None), ("true", True), ("[]", []),
          ("{}", {}), ("1e19", 10**19), ("1e-300", 1e-300), ("-1e300", -1e300)]
SMALL_PATHS = {"record_interval": 2e-4, "snapshot_interval": 25, "substepping": {"q_t": 0.1, "q_n": 1, "q_sigma": 0.2},
               "paths": [{"segments": [{"L": [[0, 5.0], [0, 0]], "strain": 0.002}]}],
               "generators": [{"count": 1, "rate": {"min": 0.3, "max": 10}, "strain": 0.002, "segments": 2,
                               "changes": ["reversal", "rotation"], "volumetric": 0.3, "spin": 0.3}],
               "probes": [{"bases": ["shear"], "depths": [1e-4], "base_rate": 0.5, "psi": [0], "beta": [0],
                           "rates": [1], "probe_strain": 3e-4}]}


def fields(node, pointer=""):
    """(pointer, value) of every member and element below `node`, depth first."""
    children = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else []
    for key, value in children:
        yield f"{pointer}/{key}", value
        yield from fields(value, f"{pointer}/{key}")


def member(document, pointer):
    """The node of `document` at the JSON pointer (its parts, as strings)."""
    node = document
    for part in pointer:
        node = node[int(part)] if isinstance(node, list) else node[part]
    return node


def variants(document):
    """(pointer, what, mutated copy) for every field and every object of `document`."""
    for pointer, value in fields(document):
        parts = pointer.split("/")[1:]
        replacements = VALUES if not isinstance(value, (dict, list)) else [("string", "x"), ("null", None), ("1", 1)]
        for what, replacement in replacements + [("removed", KeyError)]:
            mutated = copy.deepcopy(document)
            parent = member(mutated, parts[:-1])
            last = int(parts[-1]) if isinstance(parent, list) else parts[-1]
            if replacement is KeyError:
                del parent[last]
            else:
                parent[last] = copy.deepcopy(replacement)
            yield pointer, what, mutated
    for pointer, value in [("", document)] + list(fields(document)):
        if isinstance(value, dict):
            mutated = copy.deepcopy(document)
            member(mutated, pointer.split("/")[1:])["unknown_key"] = 1
            yield pointer or "/", "unknown key", mutated


def digest(library):
    h = hashlib.sha256()
    for f in sorted(library.rglob("*")):
        if f.is_file() and f.name != "sampler.lock":
            h.update(f.name.encode())
            h.update(f.read_bytes())
    return h.hexdigest()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path)
    parser.add_argument("--kind", choices=["scene", "cell", "paths"], required=True)
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--timeout", type=float, default=90)
    args = parser.parse_args()
    out, build = args.out.resolve(), args.build.resolve()
    sampler, solver = build / "dem_sampler" / "dem_sampler", build / "mpm_solver" / "mpm_solver"
    out.mkdir(parents=True, exist_ok=True)
    small_cell = json.loads((DEMO / "cell_soft_snow_250.json").read_text())
    small_cell["preparation"]["spheres"] = 32
    library = out / "lib"
    if args.kind == "scene":
        base = json.loads((DEMO / "column.json").read_text())
        base["materials"][0]["library"] = str(library)
        base["time"]["end"] = 0.0005
        if not (library / "done").exists():
            subprocess.run([str(sampler), "prepare", str(DEMO / "cell_soft_snow_250.json"), "--library", str(library)],
                           check=True, capture_output=True)
            subprocess.run([str(sampler), "sample", str(DEMO / "paths.json"), "--library", str(library), "--threads", "1"],
                           check=True, capture_output=True)
            (library / "done").write_text("")
    elif args.kind == "cell":
        base = small_cell
    else:
        base = SMALL_PATHS
        if not (library / "catalogue.sqlite").exists():
            (out / "cell.json").write_text(json.dumps(small_cell))
            subprocess.run([str(sampler), "prepare", str(out / "cell.json"), "--library", str(library)], check=True,
                           capture_output=True)
    library_before = digest(library) if library.exists() else None

    runs, counts = [], Counter()
    for pointer, what, document in variants(base):
        work = out / "run"
        shutil.rmtree(work, ignore_errors=True)
        work.mkdir()
        input_file = work / f"{args.kind}.json"
        input_file.write_text(json.dumps(document))
        if args.kind == "scene":
            command = [str(solver), str(input_file), "--out", str(work / "out"), "--threads", "1"]
        elif args.kind == "cell":
            command = [str(sampler), "prepare", str(input_file), "--library", str(work / "lib")]
        else:
            shutil.copytree(library, work / "lib")
            command = [str(sampler), "sample", str(input_file), "--library", str(work / "lib"), "--threads", "1"]
        try:
            done = subprocess.run(command, capture_output=True, text=True, timeout=args.timeout)
        except subprocess.TimeoutExpired:
            outcome, line = "timeout", ""
        else:
            lines = done.stderr.strip().splitlines()
            line = lines[-1] if lines else ""
            if done.returncode < 0 or done.returncode > 128:
                outcome = "crash"
            elif done.returncode == 0:
                outcome = "ran"
                if args.kind == "scene" and "nan" in (work / "out" / "series.csv").read_text().lower():
                    outcome = "ran with NaN"
                if args.kind == "paths" and subprocess.run([str(build / "database" / "celldb"), "verify",
                                                            str(work / "lib")], capture_output=True).returncode:
                    outcome = "ran, verify fails"
            elif args.kind == "paths" and digest(work / "lib") != library_before:
                outcome = "changed"
            else:
                outcome = "refused" if done.returncode == 1 and len(lines) == 1 else f"exit {done.returncode}"
        counts[outcome] += 1
        runs.append({"field": pointer, "value": what, "outcome": outcome, "message": line})
        print(f"{outcome:10s} {pointer} = {what}: {line[:160]}", flush=True)
    unchanged = library_before is None or digest(library) == library_before
    summary = {"kind": args.kind, "runs": len(runs), "outcomes": dict(counts), "shared_library_unchanged": unchanged,
               "all": runs}
    (out / f"{args.kind}.json").write_text(json.dumps(summary, indent=1) + "\n")
    print(json.dumps({k: summary[k] for k in ("runs", "outcomes", "shared_library_unchanged")}))


if __name__ == "__main__":
    main()
