"""Writes docs/benchmarks.md from ``pelt bench --json`` files (and the Blender benchmarks').

Usage: python scripts/bench_report.py --out docs/benchmarks.md out/bench.json out/bench_blender.json \
    out/bench_preview.json

The tables are written anew; what the existing file holds below ``KEEP_MARKER`` (figures written
by hand: one-off runs, the figures behind the design) is kept. Without ``--out`` the tables go to
standard output.
"""

import argparse
import contextlib
import io
import json
import os
import tempfile
from pathlib import Path

# The line below which docs/benchmarks.md is written by hand and kept by `make bench`.
KEEP_MARKER = "<!-- Written by hand below this line; make bench keeps it. -->"

# Goals from the issues, in seconds, on the 2-core reference machine.
# Goals in seconds, by case name, or by `name@text` for the case of that name whose size holds
# `text` (one case name can be measured at several sizes with different goals).
GOALS = {
    "mesh.build": 0.030,
    "blender.transfer": 0.100,
    "blender.bake.overhead": 0.5,
    "blender.preview.frame": 0.1,
    "blender.preview.redraw": 0.005,
    "blender.preview.groom": 0.1,
    "render.frame@512x512": 0.040,
    "volume.bake.exact@128x128x16": 0.050,
    "volume.bake.exact@1024x1024x64": 2.0,
    "prt.transfer.sweep": 1.0,
    "lapped.build.15k": 0.100,
    "lapped.build.100k": 1.0,
    "export.gltf.engine": 1.0,
    "export.gltf.geometry": 3.0,
    "export.gltf.skinned.engine": 1.0,
    "export.gltf.skinned.geometry": 3.0,
    "reference.render@512x512": 60.0,
}


def goal_of(case):
    for key, goal in GOALS.items():
        name, _, size = key.partition("@")
        if name == case["name"] and size in (case.get("size") or ""):
            return goal
    return None


def cell(value, fmt):
    return "–" if value is None else format(value, fmt)


def text(value):
    """Free text for a table cell: a `|` would end the cell."""
    return "–" if not value else str(value).replace("|", "\\|")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("reports", nargs="+", type=Path)
    parser.add_argument("--out", type=Path, help="the Markdown file to write (its hand-written part kept)")
    args = parser.parse_args()
    tables = io.StringIO()
    with contextlib.redirect_stdout(tables):
        write_tables([json.loads(p.read_text()) for p in args.reports])
    if args.out is None:
        print(tables.getvalue(), end="")
        return
    kept = ""
    if args.out.exists():
        old = args.out.read_text()
        if KEEP_MARKER in old:
            kept = old[old.index(KEEP_MARKER) + len(KEEP_MARKER) :]
    text = f"{tables.getvalue().rstrip()}\n\n{KEEP_MARKER}{kept or chr(10)}"
    # Written beside the target and renamed over it, so a failed run leaves the old file whole.
    with tempfile.NamedTemporaryFile("w", dir=args.out.parent, suffix=".tmp", delete=False) as tmp:
        tmp.write(text)
    os.replace(tmp.name, args.out)


def write_tables(reports) -> None:
    head = reports[0]
    print("# Benchmarks\n")
    print(
        "Written by `make bench` (`pelt bench`, `blender_scripts/bench_transfer.py` and "
        "`blender_scripts/bench_preview.py`); do not edit above the line that marks "
        "the hand-written part."
    )
    print(
        f"pelt {head.get('pelt', '?')}, {head.get('threads', '?')} threads, "
        f"adapter: {head.get('adapter') or 'none used'}. Seconds are medians of several runs.\n"
    )
    print("| case | size | seconds | goal | peak MiB | error | error metric | speedup |")
    print("|---|---|---:|---:|---:|---:|---|---:|")
    cases = [case for report in reports for case in report["cases"]]
    images = [case for case in cases if case["name"].startswith("image.")]
    for case in cases:
        if case["name"].startswith("image."):
            continue
        goal = goal_of(case)
        verdict = "" if goal is None else (" ✓" if case["seconds"] <= goal else " ✗")
        peak = None if case.get("peak_bytes") is None else case["peak_bytes"] / 2**20
        speedup = case.get("speedup")
        versus = "–" if speedup is None else f"{speedup:.1f}× vs `{case.get('baseline')}`"
        print(
            f"| `{case['name']}` | {text(case['size'])} | {case['seconds']:.4f}{verdict} | "
            f"{cell(goal, '.3f')} | {cell(peak, '.1f')} | {cell(case.get('error'), '.2e')} | "
            f"{text(case.get('error_metric'))} | {versus} |"
        )
    if images:
        image_table(images)


def image_table(images):
    """The preview against the reference (docs/accuracy.md has the plot and the pictures)."""
    print("\n## Picture accuracy (`image.*`: preview against the reference renderer)\n")
    print(
        "Seconds: the preview's frame (`volume`: the reference's volume mode, whose error is against "
        "the strands); error: relative MSE (linear); vs volume: the preview's relative MSE against "
        "the volume mode; see docs/accuracy.md.\n"
    )
    print(
        "| case | seconds | relative MSE | ꟻLIP | ꟻLIP 4× down | luminance ratio | alpha profile "
        "| dolly jump | vs volume |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for case in images:
        print(
            f"| `{case['name']}` | {case['seconds']:.4f} | {case['error']:.3f} | {case['flip']:.3f} | "
            f"{case['flip_down4']:.3f} | {case['luminance_ratio']:.2f} | {case['alpha_profile_error']:.2f} | "
            f"{cell(case.get('dolly_jump'), '.3f')} | {cell(case.get('volume_error'), '.3f')} |"
        )


if __name__ == "__main__":
    main()
