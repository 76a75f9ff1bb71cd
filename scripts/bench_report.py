"""Writes docs/benchmarks.md from ``pelt bench --json`` files (and the Blender benchmarks').

Usage: python scripts/bench_report.py out/bench.json out/bench_blender.json out/bench_preview.json \
    > docs/benchmarks.md
"""

import json
import sys
from pathlib import Path

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
    reports = [json.loads(Path(p).read_text()) for p in sys.argv[1:]]
    head = reports[0]
    print("# Benchmarks\n")
    print(
        "Written by `make bench` (`pelt bench`, `blender_scripts/bench_transfer.py` and "
        "`blender_scripts/bench_preview.py`); do not edit."
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
