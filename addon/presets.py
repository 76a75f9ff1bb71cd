# SPDX-License-Identifier: GPL-3.0-or-later
"""Fur presets: values for ``Object.pelt`` settings, by name. Pure data (no bpy), so scripts and tests
can read them; ``props.apply_preset`` writes one onto an object's settings.

Hair lengths are shares of the fur depth and widths are in tile units (``pelt.HairParams``);
``fur_depth`` and ``tile_size`` are world units, chosen for an object about 2 units across
(Blender's default primitives).
"""

# Every preset sets these keys, so switching presets never leaves another preset's values behind.
PRESETS = {
    "SHORT_VELVET": {
        "label": "Short Velvet",
        "description": "Very dense, short, upright pile with no guard hairs",
        "density": 32768,
        "guard_fraction": 0.0,
        "undercoat_length": (0.8, 0.95),
        "undercoat_width": (0.003, 0.004),
        "overcoat_length": (0.95, 1.0),
        "overcoat_width": (0.004, 0.005),
        "curl": 0.02,
        "helix_radius": 0.0,
        "helix_frequency": 0.0,
        "slant": 0.05,
        "length_jitter": 0.05,
        "clump_strength": 0.0,
        "clump_count": 0,
        "root_color": (0.10, 0.02, 0.04),
        "tip_color": (0.35, 0.05, 0.10),
        "fur_depth": 0.012,
        "tile_size": 0.1,
    },
    "MINK": {
        "label": "Mink",
        "description": "Dense soft underfur under glossy, slanted guard hairs",
        "density": 24576,
        "guard_fraction": 0.08,
        "undercoat_length": (0.5, 0.7),
        "undercoat_width": (0.004, 0.005),
        "overcoat_length": (0.9, 1.0),
        "overcoat_width": (0.006, 0.008),
        "curl": 0.05,
        "helix_radius": 0.0,
        "helix_frequency": 0.0,
        "slant": 0.35,
        "length_jitter": 0.1,
        "clump_strength": 0.0,
        "clump_count": 0,
        "root_color": (0.05, 0.03, 0.02),
        "tip_color": (0.22, 0.12, 0.06),
        "fur_depth": 0.04,
        "tile_size": 0.15,
    },
    "LONG_SHAGGY": {
        "label": "Long Shaggy",
        "description": "Long, clumped, strongly slanted and uneven hair",
        "density": 8192,
        "guard_fraction": 0.15,
        "undercoat_length": (0.4, 0.7),
        "undercoat_width": (0.005, 0.007),
        "overcoat_length": (0.8, 1.0),
        "overcoat_width": (0.008, 0.010),
        "curl": 0.3,
        "helix_radius": 0.0,
        "helix_frequency": 0.0,
        "slant": 0.6,
        "length_jitter": 0.3,
        "clump_strength": 0.5,
        "clump_count": 48,
        "root_color": (0.20, 0.16, 0.11),
        "tip_color": (0.70, 0.62, 0.48),
        "fur_depth": 0.12,
        "tile_size": 0.25,
    },
    "CURLY": {
        "label": "Curly",
        "description": "Tight helical curls gathered in small clumps",
        "density": 12288,
        "guard_fraction": 0.0,
        "undercoat_length": (0.6, 0.9),
        "undercoat_width": (0.005, 0.007),
        "overcoat_length": (0.9, 1.0),
        "overcoat_width": (0.006, 0.008),
        "curl": 0.4,
        "helix_radius": 0.02,
        "helix_frequency": 3.0,
        "slant": 0.2,
        "length_jitter": 0.15,
        "clump_strength": 0.3,
        "clump_count": 64,
        "root_color": (0.30, 0.24, 0.18),
        "tip_color": (0.85, 0.80, 0.70),
        "fur_depth": 0.06,
        "tile_size": 0.12,
    },
}

# Settings a preset writes (everything but its label and description).
PRESET_KEYS = tuple(key for key in PRESETS["MINK"] if key not in ("label", "description"))
