"""Builds the Blender extension zip: the add-on from ``addon/`` plus the wheel built by maturin.

Usage: python scripts/package_extension.py WHEEL --out DIST

Copies the add-on into ``build/extension``, adds the wheel under ``wheels/``, writes the wheel's
file name into the manifest, then runs Blender's own ``blender_ext.py build --split-platforms``
and ``validate`` on the result. Prints the zip's path.
"""

import argparse
import importlib.util
import re
import shutil
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def blender_ext() -> Path:
    """Blender's extension tool, shipped inside the bpy wheel (it needs only the standard library)."""
    spec = importlib.util.find_spec("bpy")
    if spec is None or not spec.submodule_search_locations:
        sys.exit("bpy is not installed in this Python")
    bpy_dir = Path(next(iter(spec.submodule_search_locations)))
    found = sorted(bpy_dir.glob("*/scripts/addons_core/bl_pkg/cli/blender_ext.py"))
    if not found:
        sys.exit(f"blender_ext.py not found under {bpy_dir}")
    return found[-1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("wheel", type=Path)
    parser.add_argument("--out", type=Path, default=REPO / "dist")
    args = parser.parse_args()

    staging = REPO / "build" / "extension"
    shutil.rmtree(staging, ignore_errors=True)
    shutil.copytree(REPO / "addon", staging, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    (staging / "wheels").mkdir()
    shutil.copy2(args.wheel, staging / "wheels" / args.wheel.name)
    manifest = staging / "blender_manifest.toml"
    text, count = re.subn(
        r"^wheels = \[.*\]$", f'wheels = ["./wheels/{args.wheel.name}"]', manifest.read_text(), flags=re.M
    )
    if count != 1:
        sys.exit("blender_manifest.toml must have exactly one `wheels = [...]` line")
    manifest.write_text(text)
    shutil.copy2(REPO / "addon" / "LICENSE", staging / "LICENSE")

    args.out.mkdir(parents=True, exist_ok=True)
    tool = blender_ext()
    build = [sys.executable, str(tool), "build", "--source-dir", str(staging), "--output-dir", str(args.out)]
    subprocess.run([*build, "--split-platforms"], check=True)
    version = re.search(r'^version = "(.+)"$', text, flags=re.M).group(1)
    archive = args.out / f"pelt-{version}-linux_x64.zip"
    subprocess.run([sys.executable, str(tool), "validate", str(archive)], check=True)
    print(archive)


if __name__ == "__main__":
    main()
