#!/usr/bin/python3
"""What a damaged restart file does: one byte flipped at evenly spread and random places of a live
run's restart.h5, each resumed for two steps; every resume is refused (exit 1, one line), or runs
exactly as the undamaged restart does, or - the failure this guards against - runs differently.

    restart_corruption.py [OUT] [--build BUILD] [--flips 270] [--cell CELL.json] [--restart FILE]

The scene is the demo column, its cell (by default the demo's 250-sphere one) prepared into OUT/lib,
run live for 4 steps.
--restart takes an existing restart of that scene instead (e.g. one an older build wrote) and
resumes it. Prints the counts and writes OUT/restart_corruption.json.
"""
import argparse
import json
import random
import re
import shutil
import subprocess
import sys
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from plotting import environment  # noqa: E402

DEMO = Path(__file__).resolve().parents[1] / "demo"


def run(build, library, out, end, restart=None):
    command = [str(build / "mpm_solver" / "mpm_solver"), str(DEMO / "column.json"), "--library", str(library),
               "--law", "live", "--set", f"/time/end={end}", "--set", "/time/output_interval=0.0002",
               "--checkpoint-every", "0", "--out", str(out), "--threads", "1"]
    if restart:
        command += ["--restart", str(restart)]
    shutil.rmtree(out, ignore_errors=True)
    return subprocess.run(command, capture_output=True, text=True, timeout=600)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", nargs="?", type=Path, default=environment.output_dir("restart_corruption"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--flips", type=int, default=270)
    parser.add_argument("--cell", type=Path, default=DEMO / "cell_soft_snow_250.json")
    parser.add_argument("--restart", type=Path, help="a restart of the scene to damage instead of a fresh one")
    args = parser.parse_args()
    out, build = args.out.resolve(), args.build.resolve()
    out.mkdir(parents=True, exist_ok=True)
    library = out / "lib"
    if not (library / "catalogue.sqlite").exists():
        subprocess.run([str(build / "dem_sampler" / "dem_sampler"), "prepare", str(args.cell.resolve()),
                        "--library", str(library)], check=True, capture_output=True)
    restart = args.restart
    if restart is None:
        first = run(build, library, out / "first", 0.0004)
        if first.returncode != 0:
            sys.exit(f"the undamaged run failed: {first.stderr.strip()}")
        restart = out / "first" / "restart.h5"
    reference = run(build, library, out / "reference", 0.0006, restart)
    if reference.returncode != 0:
        sys.exit(f"the undamaged resume failed: {reference.stderr.strip()}")
    expected = (out / "reference" / "points_000001.vtu").read_bytes()

    original = restart.read_bytes()
    rng = random.Random(5)
    spread = args.flips * 5 // 9
    places = [len(original) * k // spread for k in range(spread)] + \
             [rng.randrange(len(original)) for _ in range(args.flips - spread)]
    outcomes, messages = Counter(), Counter()
    for place in places:
        damaged = bytearray(original)
        damaged[place] ^= 0xFF
        (out / "damaged.h5").write_bytes(bytes(damaged))
        r = run(build, library, out / "resumed", 0.0006, out / "damaged.h5")
        if r.returncode == 0:
            same = (out / "resumed" / "points_000001.vtu").read_bytes() == expected
            outcomes["ran the same" if same else "ran differently"] += 1
        elif r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1:
            outcomes["refused"] += 1
            messages[re.sub(r"cell_\d+", "cell_N", r.stderr.split(": ", 2)[-1].split(":")[0].strip())] += 1
        else:
            outcomes[f"exit {r.returncode}"] += 1
    summary = {"restart": str(restart), "bytes": len(original), "flips": len(places), "outcomes": dict(outcomes),
               "refused_at": dict(messages.most_common())}
    (out / "restart_corruption.json").write_text(json.dumps(summary, indent=1) + "\n")
    print(json.dumps(summary["outcomes"]))


if __name__ == "__main__":
    main()
