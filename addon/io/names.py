# SPDX-License-Identifier: GPL-3.0-or-later
"""The names Pelt gives things in Blender (DESIGN.md §3), in one place.

Scripts, the exported files and the runtimes read these by name, so they change only together with
the design. Names that stay inside Pelt's own node trees (``materials.LAYER_ATTRIBUTE``, the guard
hairs' root attributes, the template tags) live beside the code that writes and reads them.
"""

# Point attributes of the furred mesh, one value per vertex.
COLOR = "pelt_color"  # FLOAT_COLOR (BYTE_COLOR is read too): linear RGBA of the hair
COMB = "pelt_comb"  # FLOAT_VECTOR, object space: the direction the hair leans
LENGTH = "pelt_length"  # FLOAT: hair length multiplier, 0 = bald
# The gray color attribute Vertex Paint edits for LENGTH (``paint_math``), copied into it on apply.
LENGTH_PAINT = "pelt_length_paint"

# What a bake writes on the mesh: the patch UVs (tile units) and each face's patch (INT, -1 bald).
UV_MAP = "PeltUV"
PATCH_ATTRIBUTE = "pelt_patch"

# Custom properties on every datablock Pelt creates (``ownership``): the owning object's name, what
# the datablock is for that object, and the signature of the code that built its node tree.
OWNER = "pelt_owner"
ROLE = "pelt_role"
BUILT = "pelt_built"

PREFIX = "Pelt"


def datablock_name(kind: str, owner_name: str | None = None) -> str:
    """``Pelt <kind> <owner>``: the name of a datablock Pelt creates (for the object ``owner_name``).
    Only a starting point: Blender numbers it when taken, and Pelt finds its own by the tags."""
    return f"{PREFIX} {kind}" if owner_name is None else f"{PREFIX} {kind} {owner_name}"
