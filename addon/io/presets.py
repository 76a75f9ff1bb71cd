# SPDX-License-Identifier: GPL-3.0-or-later
"""Fur presets: values for ``Object.pelt`` settings, by name (no bpy), so scripts and tests can read
them; ``props.apply_preset`` writes one onto an object's settings.

Hair lengths are shares of the fur depth and widths are in tile units (``pelt.HairParams``);
``fur_depth`` and ``tile_size`` are world units, chosen for an object about 2 units across
(Blender's default primitives).
"""

import pelt

# Every preset sets these keys, so switching presets never leaves another preset's values behind.
# The values live in the crate's data file ``crates/pelt-core/presets.json``, which
# ``pelt bake --preset`` reads too.
PRESETS = pelt.PRESETS

# Settings a preset writes (everything but its label and description).
PRESET_KEYS = tuple(key for key in PRESETS["MINK"] if key not in ("label", "description"))
