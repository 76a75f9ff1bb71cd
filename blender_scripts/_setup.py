"""Shared start-up of the headless scripts: make the repository's add-on importable and registered."""

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
