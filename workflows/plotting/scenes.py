"""Variants of an mpm_solver scene for the workflows: another law for its DEM-backed materials, a cell
library, a shorter end time, or any knob (substepping, lookup, grid). The loader refuses keys that
do not belong to a law (a `lookup` block on a live material), so a law change also drops them.

  python3 -m plotting.scenes BASE.json OUT.json [--law L] [--library LIB] [--material KEYS.json] [--end T]
                            [--output-interval T] [--points-per-cell N]
"""
import argparse
import copy
import json
from pathlib import Path

DEM_BACKED = ("live", "cache", "hybrid")
# Keys of a DEM-backed material per law (mpm_solver/io/scene_input.cpp).
COMMON_KEYS = {"name", "law", "cell", "library", "template", "substepping", "q_h"}
LAW_KEYS = {"live": set(), "cache": {"lookup"}, "hybrid": {"lookup", "fallback", "enrich", "snapshot_interval"}}


def load(file):
    """The scene with its relative `cell` and `library` paths made absolute (so it runs from anywhere)."""
    file = Path(file).resolve()
    scene = json.loads(file.read_text())
    for material in scene["materials"]:
        for key in ("cell", "library"):
            if key in material:
                material[key] = str((file.parent / material[key]).resolve())
    return scene


def dem_materials(scene):
    return [m for m in scene["materials"] if m.get("law") in DEM_BACKED]


def variant(scene, law=None, library=None, material=None, time=None, top=None):
    """A copy of `scene`: `law` and `library` for every DEM-backed material (a library replaces `cell`,
    template 1 unless the material names one), `material` keys merged into them (a `cell` there drops
    the library), `time` keys into the
    time block, `top` keys (grid, regions, integration …) replacing the scene's."""
    scene = copy.deepcopy(scene)
    for m in dem_materials(scene):
        if law:
            m["law"] = law
        if library:
            m.pop("cell", None)
            m["library"] = str(Path(library).resolve())
            m.setdefault("template", 1)
        if material and "cell" in material:  # a cell of its own instead of the library's template
            m.pop("library", None)
            m.pop("template", None)
        m.update(copy.deepcopy(material or {}))
        allowed = COMMON_KEYS | LAW_KEYS[m["law"]]
        for key in [k for k in m if k not in allowed]:
            del m[key]
    scene["time"].update(time or {})
    scene.update(copy.deepcopy(top or {}))
    return scene


def save(scene, file):
    Path(file).parent.mkdir(parents=True, exist_ok=True)
    Path(file).write_text(json.dumps(scene, indent=2) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("base")
    parser.add_argument("out")
    parser.add_argument("--law", choices=DEM_BACKED)
    parser.add_argument("--library")
    parser.add_argument("--material", type=Path, help="JSON object of keys merged into the DEM-backed materials")
    parser.add_argument("--end", type=float)
    parser.add_argument("--output-interval", type=float)
    parser.add_argument("--points-per-cell", type=int, help="of every region (n × n material points per grid cell)")
    args = parser.parse_args()
    time = {k: v for k, v in (("end", args.end), ("output_interval", args.output_interval)) if v is not None}
    material = json.loads(args.material.read_text()) if args.material else None
    base = load(args.base)
    top = None
    if args.points_per_cell:
        top = {"regions": [{**region, "points_per_cell": args.points_per_cell} for region in base["regions"]]}
    save(variant(base, args.law, args.library, material, time, top), args.out)


if __name__ == "__main__":
    main()
