#!/usr/bin/python3
"""What a damaged library does: one byte flipped at evenly spread places of each shard of a small
sampled library, each checked by `celldb verify`; a library verify calls clean is then read in full
(`h5dump` of the shard) against the undamaged one. Each damage is reported by verify, or leaves every
dataset and attribute identical (the byte lay in unused space), or - the failure this guards against
- passes verify while the library reads differently.

    library_corruption.py [OUT] [--build BUILD] [--flips 150] [--cell CELL.json]

The library: the cell (by default the demo's 125-sphere one) prepared, and two short paths sampled
with a snapshot every 5 records. Prints the counts per shard and writes OUT/library_corruption.json.
Needs h5dump (hdf5-tools).
"""
import argparse
import json
import shutil
import subprocess
import sys
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from plotting import environment  # noqa: E402

PATHS = {"record_interval": 2e-4, "snapshot_interval": 5,
         "paths": [{"segments": [{"L": [[0, 5.0], [0, 0]], "strain": 0.004}]},
                   {"segments": [{"L": [[1.0, 0], [0, -1.0]], "strain": 0.004}]}]}


def dump(shard):
    """The shard's content as h5dump prints it, without the first line (which names the file)."""
    done = subprocess.run(["h5dump", str(shard)], capture_output=True, text=True)
    return done.returncode, done.stdout.split("\n", 1)[-1]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", nargs="?", type=Path, default=environment.output_dir("library_corruption"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--flips", type=int, default=150)
    parser.add_argument("--cell", type=Path, default=Path(__file__).resolve().parents[1] / "demo" / "cell_soft_snow_125.json")
    args = parser.parse_args()
    out, build = args.out.resolve(), args.build.resolve()
    sampler, celldb = build / "dem_sampler" / "dem_sampler", build / "database" / "celldb"
    out.mkdir(parents=True, exist_ok=True)
    undamaged = out / "undamaged"
    shutil.rmtree(undamaged, ignore_errors=True)
    (out / "paths.json").write_text(json.dumps(PATHS))
    subprocess.run([str(sampler), "prepare", str(args.cell.resolve()), "--library", str(undamaged)], check=True,
                   capture_output=True)
    subprocess.run([str(sampler), "sample", str(out / "paths.json"), "--library", str(undamaged), "--threads", "1"],
                   check=True, capture_output=True)
    summary = {}
    for shard in sorted(p.name for p in (undamaged / "shards").glob("*.h5")):
        original = (undamaged / "shards" / shard).read_bytes()
        expected = dump(undamaged / "shards" / shard)
        outcomes = Counter()
        for k in range(args.flips):
            damaged = out / "damaged"
            shutil.rmtree(damaged, ignore_errors=True)
            shutil.copytree(undamaged, damaged)
            data = bytearray(original)
            data[len(original) * k // args.flips] ^= 0xFF
            (damaged / "shards" / shard).write_bytes(bytes(data))
            verify = subprocess.run([str(celldb), "verify", str(damaged)], capture_output=True, text=True)
            if verify.returncode != 0:
                outcomes["reported by verify"] += 1
            elif dump(damaged / "shards" / shard) == expected:
                outcomes["clean and identical"] += 1
            else:
                outcomes["clean but reads differently"] += 1
        summary[shard] = {"bytes": len(original), "flips": args.flips, "outcomes": dict(outcomes)}
        print(shard, json.dumps(summary[shard]["outcomes"]), flush=True)
    (out / "library_corruption.json").write_text(json.dumps(summary, indent=1) + "\n")


if __name__ == "__main__":
    main()
