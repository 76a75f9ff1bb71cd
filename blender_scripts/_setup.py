"""Shared start-up of the headless scripts: make the repository's add-on importable and registered."""

import json
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def register_addon():
    """Registers ``addon/`` from the source tree (as a developer install would) and returns it."""
    if str(REPO) not in sys.path:
        sys.path.insert(0, str(REPO))
    import addon

    addon.register()
    return addon


def write_cases(cases: list, path: Path | None) -> None:
    """Prints benchmark cases and writes them as ``pelt bench`` JSON to ``path`` (when given)."""
    for case in cases:
        case.update(peak_bytes=None, error=None, error_metric=None, baseline=None, speedup=None)
        print(f"{case['name']:<30} {case['seconds'] * 1000:9.2f} ms  {case['size']}")
    if path:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps({"cases": cases}, indent=2) + "\n")
