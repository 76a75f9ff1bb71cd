# SPDX-License-Identifier: GPL-3.0-or-later
"""``pelt.export``: the selected furred objects as a glTF binary for engines and viewers, with their
texture set (PNG, KTX2, EXR) and a ``pelt.json`` manifest beside it (File > Export > Pelt Fur).

Each object's bake comes from its cached pipeline, so exporting right after a bake re-runs
nothing; an object whose bake fails is reported and nothing is written. Objects stand where they
stand in the scene (turned to glTF's Y-up); an object deformed by an armature is exported skinned
(``rig.py``): the armature's bones as joints, its active action as an animation, and the fur's
shells and fins bound with the skin they stand on. Objects sharing an armature share its nodes.
An object without an armature takes its own active action, its node moving as the object does.
Faces the fur leaves bald keep the object's own materials (``material_slots.py``).
"""

from dataclasses import asdict, dataclass, field
from pathlib import Path

import bpy
import pelt
from bpy_extras.io_utils import ExportHelper

from . import bake, material_slots, rig

ENGINE_HELP = (
    "The base mesh with PeltUV, color, length and comb attributes, the textures and a description "
    "of the shell stack, for engine-side shell shaders"
)
GEOMETRY_HELP = "Shells and fins baked into alpha-blended meshes: any glTF viewer shows the fur"
MODES = (("ENGINE", "Engine", ENGINE_HELP), ("GEOMETRY", "Geometry", GEOMETRY_HELP))


def file_stem(name: str) -> str:
    """``name`` made safe as a file name (letters, digits, ``-``, ``_``, ``.`` kept)."""
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name) or "object"


def furred_objects(context, selected_only: bool) -> list:
    """Mesh objects to export: the selected ones with fur on (or the active one)."""
    candidates = context.selected_objects if selected_only else context.scene.objects
    objects = [obj for obj in candidates if obj.type == "MESH" and obj.pelt.enabled]
    active = context.active_object
    if not objects and active is not None and active.type == "MESH":
        objects = [active]
    return sorted(objects, key=lambda obj: obj.name)


def assets_of(objects) -> list:
    """Each object's bake (cached stages are reused); raises the first bake's error."""
    assets = []
    for obj in objects:
        job = bake.start_job(obj).start()
        job.wait()
        if job.error is not None:
            raise pelt.PeltError(f"{obj.name}: {job.error}") from job.error
        bake.remember(obj.session_uid, job)
        assets.append(job.asset)
    return assets


@dataclass
class Rigging:
    """``pelt.export_gltf``'s placement and skinning arguments for a list of objects."""

    transforms: list = field(default_factory=list)
    skins: list = field(default_factory=list)
    skeletons: list = field(default_factory=list)
    animations: list = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


def rigging(objects, scene) -> Rigging:
    """Each object's transform and, for an armature-deformed one, its skin (one skeleton per
    armature), else its own action."""
    out = Rigging()
    skeleton_of: dict[str, int] = {}
    for obj in objects:
        found = rig.gather(obj, scene)
        if found is None:
            out.transforms.append(rig.object_transform(obj))
            out.skins.append(None)
            out.animations.append([asdict(a) for a in rig.object_animations(obj, scene)])
            continue
        out.animations.append([])
        out.transforms.append(found.bind)
        index = skeleton_of.get(found.armature)
        if index is None:
            index = skeleton_of[found.armature] = len(out.skeletons)
            animations = [asdict(a) for a in found.animations]
            out.skeletons.append(
                {"names": found.names, "parents": found.parents, "rest": found.rest, "animations": animations}
            )
        out.skins.append({"skeleton": index, "joints": found.joints, "weights": found.weights})
        out.notes.extend(f"{obj.name}: {note}" for note in found.notes)
    return out


def weight_notes(objects, reports) -> list[str]:
    """What binding each skinned object changed, in words."""
    notes = []
    for obj, report in zip(objects, reports, strict=True):
        if report and report["reduced"]:
            notes.append(
                f"{obj.name}: {report['reduced']} of {report['vertices']} vertices had more than 4 bones; "
                "the 4 strongest were kept"
            )
    return notes


def export_objects(
    objects, path: Path, *, mode: str, formats: list[str], fins: bool = True, scene=None
) -> tuple[dict, list[str]]:
    """Writes ``objects`` as ``path`` (a .glb) plus their texture set in ``path``'s folder (for
    non-empty ``formats``); returns the manifest of the texture set (or an empty dict) and notes
    on what the file cannot carry as Blender shows it."""
    assets = assets_of(objects)
    names = [obj.name for obj in objects]
    rigs = rigging(objects, scene if scene is not None else bpy.context.scene)
    slots = [
        material_slots.material_slots(obj, asset.mesh.face_count)
        for obj, asset in zip(objects, assets, strict=True)
    ]
    path.parent.mkdir(parents=True, exist_ok=True)
    reports = pelt.export_gltf(
        assets,
        path,
        mode=mode.lower(),
        name=names,
        fins=fins,
        transform=rigs.transforms,
        skin=rigs.skins,
        skeletons=rigs.skeletons,
        materials=slots,
        animations=rigs.animations,
    )
    notes = rigs.notes + weight_notes(objects, reports)
    if not formats:
        return {}, notes
    return pelt.write_texture_set(assets, path.parent, formats=formats, name=names), notes


class PELT_OT_export(bpy.types.Operator, ExportHelper):
    """Export the furred objects as glTF (.glb) with their fur textures and a pelt.json manifest"""

    bl_idname = "pelt.export"
    bl_label = "Export Pelt Fur"
    bl_options = {"REGISTER", "PRESET"}

    filename_ext = ".glb"
    filter_glob: bpy.props.StringProperty(default="*.glb", options={"HIDDEN"})
    mode: bpy.props.EnumProperty(name="Mode", items=MODES, default="GEOMETRY")
    png: bpy.props.BoolProperty(name="PNG", description="Per-layer and atlas PNG textures", default=True)
    ktx2: bpy.props.BoolProperty(
        name="KTX2", description="KTX2 texture arrays with mipmaps (RGBA8 and float16)", default=True
    )
    exr: bpy.props.BoolProperty(
        name="EXR", description="Float data (density, transfer) as OpenEXR", default=False
    )
    fins: bpy.props.BoolProperty(name="Fins", description="Include the fins (geometry mode)", default=True)
    selected_only: bpy.props.BoolProperty(
        name="Selected Only", description="Export the selected furred objects only", default=True
    )

    @classmethod
    def poll(cls, context):
        return any(obj.type == "MESH" for obj in context.selected_objects) or (
            context.active_object is not None and context.active_object.type == "MESH"
        )

    def execute(self, context):
        objects = furred_objects(context, self.selected_only)
        if not objects:
            self.report({"ERROR"}, "Pelt: no mesh object to export")
            return {"CANCELLED"}
        formats = [name for name in ("png", "ktx2", "exr") if getattr(self, name)]
        path = Path(self.filepath)
        try:
            _, notes = export_objects(
                objects, path, mode=self.mode, formats=formats, fins=self.fins, scene=context.scene
            )
        except pelt.PeltError as error:
            self.report({"ERROR"}, f"Pelt: export failed, nothing written: {error}")
            return {"CANCELLED"}
        except OSError as error:
            self.report({"ERROR"}, f"Pelt: {error}")
            return {"CANCELLED"}
        for note in notes:
            self.report({"WARNING"}, f"Pelt: {note}")
        self.report({"INFO"}, f"Pelt: exported {len(objects)} object(s) to {path}")
        return {"FINISHED"}


def menu_export(self, context):
    self.layout.operator(PELT_OT_export.bl_idname, text="Pelt Fur (.glb)")


CLASSES = (PELT_OT_export,)


def register_menus() -> None:
    bpy.types.TOPBAR_MT_file_export.append(menu_export)


def unregister_menus() -> None:
    bpy.types.TOPBAR_MT_file_export.remove(menu_export)
