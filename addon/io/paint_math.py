# SPDX-License-Identifier: GPL-3.0-or-later
"""Defaults of the painted attributes and the gray scale that paints ``pelt_length``; numpy only.

Blender's Vertex Paint paints color attributes only, so the length is painted as the gray of the
helper color attribute ``pelt_length_paint`` and copied into ``pelt_length`` by
``pelt.apply_length_paint``. The gray is read as the user sees and picks it (sRGB-encoded), not
as linear light: black is bald, mid gray (0.5) the default length 1, white ``LENGTH_PAINT_MAX``.
"""

import numpy as np

# pelt_length where nobody painted: the hair parameters' full length.
DEFAULT_LENGTH = 1.0
# Length painted by white. Longer painted lengths are clamped to it when the helper is made.
LENGTH_PAINT_MAX = 2.0


def srgb_to_linear(encoded: np.ndarray) -> np.ndarray:
    """The sRGB transfer function, inverted (IEC 61966-2-1)."""
    c = np.clip(np.asarray(encoded, dtype=np.float64), 0.0, 1.0)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(linear: np.ndarray) -> np.ndarray:
    """The sRGB transfer function (IEC 61966-2-1)."""
    c = np.clip(np.asarray(linear, dtype=np.float64), 0.0, 1.0)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * c ** (1.0 / 2.4) - 0.055)


def starting_color(root_color, tip_color) -> tuple[float, float, float, float]:
    """Linear RGBA that a new ``pelt_color`` is filled with: per channel the brighter of the coat's
    root and tip colors. Over painted colors the bake keeps only the coat's shading (its colors
    divided by exactly this), so the fur looks as it did before anything was painted."""
    rgb = np.maximum(np.asarray(root_color, np.float64), np.asarray(tip_color, np.float64))
    return (*(float(c) for c in rgb), 1.0)


def length_to_paint(length: np.ndarray) -> np.ndarray:
    """``[N]`` lengths as ``[N, 4]`` linear RGBA grays (opaque) for ``pelt_length_paint``."""
    gray = srgb_to_linear(np.asarray(length, dtype=np.float64) / LENGTH_PAINT_MAX)
    rgba = np.ones((len(gray), 4), dtype=np.float32)
    rgba[:, :3] = gray[:, None]
    return rgba


def paint_to_length(rgba: np.ndarray) -> np.ndarray:
    """``[N, 4]`` linear RGBA of ``pelt_length_paint`` as ``[N]`` lengths: the mean of the
    sRGB-encoded channels times ``LENGTH_PAINT_MAX`` (alpha is ignored)."""
    encoded = linear_to_srgb(np.asarray(rgba, dtype=np.float64)[:, :3])
    return (encoded.mean(axis=1) * LENGTH_PAINT_MAX).astype(np.float32)
