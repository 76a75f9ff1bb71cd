"""Bake and export every furred object of each .blend file, headless.

Usage: ``python blender_scripts/bake_batch.py FILE.blend... --out DIR [--mode engine|geometry|both]
[--formats png,ktx2,exr]``. For each file and each mesh object with fur on (``Object.pelt.enabled``),
bakes through Pelt's pipeline and writes ``DIR/<file>/<object>/`` (``<object>_<mode>.glb``, the
texture set and ``pelt.json``), printing one line per object. Objects that fail (a NaN vertex, a
bad setting) are named at the end and the exit code is 1; the others are exported all the same.
"""

import argparse
import sys
import time
from pathlib import Path

import bpy
from _setup import register_addon


def bake_file(addon, blend: Path, out: Path, modes: list[str], formats: list[str]) -> list[str]:
    """Exports the furred objects of ``blend``; returns ``"file: object: error"`` per failure."""
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    failures = []
    objects = sorted(
        (obj for obj in bpy.data.objects if obj.type == "MESH" and obj.pelt.enabled), key=lambda o: o.name
    )
    if not objects:
        print(f"{blend.name}: no furred objects", flush=True)
    for obj in objects:
        start = time.perf_counter()
        folder = out / blend.stem / addon.blender.export.file_stem(obj.name)
        try:
            for mode in modes:
                path = folder / f"{addon.blender.export.file_stem(obj.name)}_{mode}.glb"
                _, notes = addon.blender.export.export_objects(
                    [obj], path, mode=mode, formats=formats if mode == modes[0] else []
                )
            for note in notes:
                print(f"{blend.name}: {obj.name}: note: {note}", flush=True)
        except Exception as error:  # any failure of one object must not stop the others
            failures.append(f"{blend.name}: {obj.name}: {error}")
            print(f"{blend.name}: {obj.name}: FAILED: {error}", flush=True)
            continue
        print(f"{blend.name}: {obj.name}: ok in {time.perf_counter() - start:.2f} s -> {folder}", flush=True)
    return failures


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", type=Path, help=".blend files")
    parser.add_argument("--out", type=Path, required=True, help="output folder")
    parser.add_argument("--mode", choices=("engine", "geometry", "both"), default="both")
    parser.add_argument("--formats", default="png,ktx2", help="texture formats: png, ktx2, exr")
    args = parser.parse_args()
    modes = ["engine", "geometry"] if args.mode == "both" else [args.mode]
    formats = [f for f in args.formats.split(",") if f]

    addon = register_addon()
    failures = []
    for blend in args.files:
        if not blend.is_file():
            failures.append(f"{blend}: no such file")
            print(f"{blend}: FAILED: no such file", flush=True)
            continue
        failures += bake_file(addon, blend.resolve(), args.out, modes, formats)
    if failures:
        print(f"{len(failures)} object(s) failed:", file=sys.stderr)
        for line in failures:
            print(f"  {line}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
