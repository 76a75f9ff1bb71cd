# SPDX-License-Identifier: GPL-3.0-or-later
"""Per-object Pelt settings (``Object.pelt``). Ranges follow ``pelt.HairParams``; soft ranges cover
what looks like fur, hard ranges what the library accepts."""

import bpy
import pelt

from ..io.presets import PRESET_KEYS, PRESETS

# The bake's one range for the fur depth (the preview and the exports share it).
FUR_DEPTH = pelt.SCHEMA["bake"]["ranges"]["fur_depth"]

LIGHTING_ITEMS = (
    ("KAJIYA_KAY", "Kajiya-Kay", "Per-pixel hair highlights from the tangent map, darker toward the skin"),
    ("PRT", "PRT", "Precomputed radiance transfer: self-shadowing of the hair volume under the World"),
)
RESOLUTION_ITEMS = tuple(
    (str(r), f"{r}²", f"Shell textures of {r}×{r} texels") for r in (64, 128, 256, 512, 1024)
)
SHELL_METHOD_ITEMS = (
    ("AUTO", "Auto", "Marched: several times faster than instanced on a CPU adapter and on a GPU"),
    ("INSTANCED", "Instanced", "Every shell drawn as a copy of the mesh (exact per layer)"),
    ("MARCHED", "Marched", "One hull whose pixels march down through the layers (one mesh of triangles)"),
    (
        "PLANES",
        "Virtual Planes",
        "One hull whose pixels trace the view ray through planes standing in the fur, each textured "
        "with its own slice of the hair (the raycast method; Bake adds the slices)",
    ),
)
COVERAGE_ITEMS = (
    ("exact", "Exact", "Analytic area of each hair's cross-section in each texel"),
    ("approx", "Approximate", "The chord and wedge approximation (faster, within a few percent)"),
    ("supersample:4", "Supersampled", "4×4 point samples per texel"),
)


def _range(name, description, default, soft_max, hard_max=1.0):
    return bpy.props.FloatVectorProperty(
        name=name,
        description=description,
        size=2,
        default=default,
        min=0.0,
        max=hard_max,
        soft_max=soft_max,
        precision=4,
    )


class PeltObjectSettings(bpy.types.PropertyGroup):
    enabled: bpy.props.BoolProperty(name="Fur", description="Grow Pelt fur on this object", default=False)

    # Hair (pelt.HairParams).
    seed: bpy.props.IntProperty(
        name="Seed", description="Seed of every random choice of the hair", default=1, min=0
    )
    density: bpy.props.IntProperty(
        name="Density",
        description="Hairs per texture tile",
        default=16384,
        min=0,
        max=1 << 20,
        soft_min=256,
        soft_max=65536,
    )
    guard_hairs: bpy.props.BoolProperty(
        name="Guard Hairs as Strands",
        description=(
            "Draw a share of the guard hairs as a hair Curves object over the mesh and bake the rest "
            "of the coat into the shells (sharper detail and a softer silhouette up close)"
        ),
        default=False,
    )
    guard_share: bpy.props.FloatProperty(
        name="Strand Share",
        description=(
            "Share of the guard hairs drawn as strands; the rest stay in the shells (a few thousand "
            "strands read as guard hairs; hundreds of thousands slow Blender down)"
        ),
        default=0.1,
        min=0.001,
        max=1.0,
        subtype="FACTOR",
    )
    guard_fraction: bpy.props.FloatProperty(
        name="Guard Hairs",
        description="Share of the hairs that are long, thick guard hairs",
        default=0.05,
        min=0.0,
        max=1.0,
        subtype="FACTOR",
    )
    undercoat_length: _range(
        "Undercoat Length", "Tip height range of the undercoat, share of the fur depth", (0.55, 0.8), 1.0
    )
    undercoat_width: _range(
        "Undercoat Width",
        "Base width range of the undercoat hairs, share of a tile",
        (0.004, 0.006),
        0.02,
        0.1,
    )
    overcoat_length: _range(
        "Guard Hair Length", "Tip height range of the guard hairs, share of the fur depth", (0.85, 1.0), 1.0
    )
    overcoat_width: _range(
        "Guard Hair Width", "Base width range of the guard hairs, share of a tile", (0.006, 0.0075), 0.02, 0.1
    )
    taper: bpy.props.FloatProperty(
        name="Taper", description="Tip width over base width", default=0.2, min=0.0, max=1.0, subtype="FACTOR"
    )
    curl: bpy.props.FloatProperty(
        name="Curl",
        description="Sideways bend of each hair, tip offset as a share of its height",
        default=0.1,
        min=0.0,
        max=1.0,
        subtype="FACTOR",
    )
    helix_radius: bpy.props.FloatProperty(
        name="Helix Radius",
        description="Radius of helical curls, share of a tile",
        default=0.0,
        min=0.0,
        max=0.1,
        soft_max=0.05,
        precision=4,
    )
    helix_frequency: bpy.props.FloatProperty(
        name="Helix Turns",
        description="Helical turns over a hair's height",
        default=0.0,
        min=0.0,
        max=32.0,
        soft_max=8.0,
    )
    slant: bpy.props.FloatProperty(
        name="Slant",
        description="Tilt of the hair away from the normal, toward the comb direction",
        default=0.2,
        min=0.0,
        max=1.396,
        subtype="ANGLE",
    )
    length_jitter: bpy.props.FloatProperty(
        name="Length Jitter",
        description="Random shortening of each hair",
        default=0.1,
        min=0.0,
        max=1.0,
        subtype="FACTOR",
    )
    clump_strength: bpy.props.FloatProperty(
        name="Clumping",
        description="How far tips are drawn toward their clump centre",
        default=0.0,
        min=0.0,
        max=1.0,
        subtype="FACTOR",
    )
    clump_count: bpy.props.IntProperty(
        name="Clumps", description="Clump centres per tile (0: no clumping)", default=0, min=0, max=256
    )
    root_color: bpy.props.FloatVectorProperty(
        name="Root Color",
        description="Hair color at the root. Where pelt_color is painted, only its share of the tip counts",
        subtype="COLOR",
        size=3,
        default=(0.12, 0.08, 0.05),
        min=0.0,
        max=1.0,
    )
    tip_color: bpy.props.FloatVectorProperty(
        name="Tip Color",
        description="Hair color at the tip. Where pelt_color is painted, the paint shows in its place",
        subtype="COLOR",
        size=3,
        default=(0.45, 0.32, 0.2),
        min=0.0,
        max=1.0,
    )
    color_jitter: bpy.props.FloatProperty(
        name="Color Jitter",
        description="Random darkening of each hair",
        default=0.15,
        min=0.0,
        max=1.0,
        subtype="FACTOR",
    )

    # Shells, textures and patches.
    layers: bpy.props.IntProperty(
        name="Shells",
        description="Shell layers of the hair volume, including the skin",
        default=16,
        min=2,
        max=256,
        soft_min=4,
        soft_max=64,
    )
    resolution: bpy.props.EnumProperty(
        name="Texture Size", description="Side of each shell texture", items=RESOLUTION_ITEMS, default="128"
    )
    coverage: bpy.props.EnumProperty(
        name="Coverage",
        description="How each hair's share of a texel is computed",
        items=COVERAGE_ITEMS,
        default="exact",
    )
    tile_size: bpy.props.FloatProperty(
        name="Tile Size",
        description="World-space width of one repeat of the hair texture",
        default=0.2,
        min=1e-4,
        soft_min=0.01,
        soft_max=2.0,
        subtype="DISTANCE",
        precision=3,
    )
    fur_depth: bpy.props.FloatProperty(
        name="Fur Depth",
        description="World-space height of the fur where pelt_length is 1",
        default=0.05,
        min=1e-5,
        max=FUR_DEPTH["max"],
        soft_max=0.5,
        subtype="DISTANCE",
        precision=3,
    )
    patch_seed: bpy.props.IntProperty(
        name="Patch Seed", description="Seed of the patch layout (where texture seams fall)", default=1, min=0
    )

    # Fins and level of detail.
    fins: bpy.props.BoolProperty(name="Fins", description="Draw fins at silhouettes", default=True)
    lod: bpy.props.BoolProperty(
        name="Level of Detail", description="Fewer shells when the object is small on screen", default=True
    )
    shell_method: bpy.props.EnumProperty(
        name="Shells",
        description="How the preview draws the shells",
        items=SHELL_METHOD_ITEMS,
        default="AUTO",
    )
    planes: bpy.props.IntProperty(
        name="Planes",
        description="Virtual planes per axis of the hair tile",
        default=32,
        min=1,
        max=256,
    )
    plane_loop_limit: bpy.props.IntProperty(
        name="Loop Limit",
        description="The most planes a pixel's ray crosses: the method's main cost",
        default=16,
        min=1,
        max=256,
    )
    min_shells: bpy.props.IntProperty(
        name="Min Shells",
        description="Shells drawn when the object is tiny on screen",
        default=4,
        min=0,
        max=256,
    )
    max_shells: bpy.props.IntProperty(
        name="Max Shells",
        description="Shells drawn when the object fills the view",
        default=32,
        min=1,
        max=256,
    )

    # Lighting.
    lighting: bpy.props.EnumProperty(
        name="Lighting",
        description="Lighting model of the preview",
        items=LIGHTING_ITEMS,
        default="KAJIYA_KAY",
    )
    prt_auto_order: bpy.props.BoolProperty(
        name="Auto Order",
        description="Pick the fewest spherical-harmonic bands within the tolerance",
        default=True,
    )
    prt_order: bpy.props.IntProperty(
        name="Order", description="Spherical-harmonic order of the transfer (bands)", default=5, min=1, max=8
    )
    prt_tolerance: bpy.props.FloatProperty(
        name="Tolerance",
        description="Largest relative lighting error the auto order accepts",
        default=0.025,
        min=0.001,
        max=0.5,
        subtype="FACTOR",
    )

    # State shown in the panel.
    last_check: bpy.props.StringProperty(
        name="Last Check",
        description="Statistics of the last mesh check, as JSON (shown in the Pelt panel)",
        default="",
        options={"HIDDEN"},
    )
    last_bake: bpy.props.StringProperty(
        name="Last Bake",
        description="Stage report of the last bake, as JSON (shown in the Pelt panel)",
        default="",
        options={"HIDDEN"},
    )


def apply_preset(settings, name: str) -> None:
    """Writes preset ``name`` (a key of ``presets.PRESETS``) onto ``settings``."""
    preset = PRESETS[name]
    for key in PRESET_KEYS:
        setattr(settings, key, preset[key])


class PELT_OT_apply_preset(bpy.types.Operator):
    """Set the active object's hair settings from a preset"""

    bl_idname = "pelt.apply_preset"
    bl_label = "Apply Fur Preset"
    bl_options = {"REGISTER", "UNDO"}

    preset: bpy.props.EnumProperty(
        name="Preset",
        items=tuple((key, p["label"], p["description"]) for key, p in PRESETS.items()),
    )

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"

    def execute(self, context):
        apply_preset(context.active_object.pelt, self.preset)
        self.report({"INFO"}, f"Pelt: preset {PRESETS[self.preset]['label']}")
        return {"FINISHED"}


class PELT_MT_presets(bpy.types.Menu):
    bl_label = "Fur Presets"
    bl_idname = "PELT_MT_presets"

    def draw(self, context):
        for key, preset in PRESETS.items():
            self.layout.operator(PELT_OT_apply_preset.bl_idname, text=preset["label"]).preset = key


CLASSES = (PeltObjectSettings, PELT_OT_apply_preset, PELT_MT_presets)
