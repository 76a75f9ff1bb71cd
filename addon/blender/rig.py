# SPDX-License-Identifier: GPL-3.0-or-later
"""An armature-skinned mesh as the arrays a glTF skin needs: the node tree (the armature object,
then its bones), rest and animated local matrices, the bind matrix and per-vertex joints and
weights, read in bulk (no per-vertex Python loop), plus notes on what Blender does that the
file cannot carry.

The armature object is node 0 and the root of the joints: a vertex the Armature modifier leaves
unmoved (no deforming weight) is bound to it, so it follows the armature object as the mesh,
parented to it, does in Blender. Matrices are row-major (``np.array(mathutils.Matrix)``) in
glTF's Y-up world. Reading changes nothing in the file: the temporary object and node group
that read the vertex groups are removed, and the frame and the armature's transforms are put
back after sampling the action.

This module imports nothing else from the add-on."""

from dataclasses import dataclass

import bpy
import numpy as np

# Blender's Z-up world to glTF's Y-up world: (x, y, z) -> (x, z, -y).
Y_UP = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, -1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
# The Armature modifier leaves a vertex whose deforming weights sum to no more than this unmoved.
UNMOVED = np.float32(1e-4)
# Transform properties that sampling the action overwrites where they are animated (unkeyed
# edits included): saved before and put back after.
_BONE_TRANSFORMS = (("location", 3), ("rotation_quaternion", 4), ("rotation_euler", 3),
                    ("rotation_axis_angle", 4), ("scale", 3))  # fmt: skip
_OBJECT_TRANSFORMS = ("location", "rotation_quaternion", "rotation_euler", "rotation_axis_angle",
                      "scale", "delta_location", "delta_rotation_quaternion", "delta_rotation_euler",
                      "delta_scale")  # fmt: skip
_TEMPORARY = ".pelt_rig_weights"


@dataclass
class Animation:
    """One action sampled at every frame of its range."""

    name: str
    times: np.ndarray  # float32 (T,): seconds from the first frame
    poses: np.ndarray  # float32 (T, N, 4, 4): every node's local matrix at each time


@dataclass
class Rig:
    """A skinned mesh's skin: nodes, rest pose, bind matrix, weights and animations."""

    armature: str
    names: list[str]  # node 0: the armature object; then its bones in ``data.bones`` order
    parents: np.ndarray  # int32 (N,): -1 for node 0, 0 for root bones
    rest: np.ndarray  # float32 (N, 4, 4): local rest matrices
    bind: np.ndarray  # float32 (4, 4): the mesh object's world matrix (Y-up)
    joints: np.ndarray  # uint32 (V, K): node per vertex and column
    weights: np.ndarray  # float32 (V, K): neither reduced nor normalized
    animations: list[Animation]
    notes: list[str]


def armature_modifier(obj):
    """The first Armature modifier shown in the viewport that has an armature, or ``None``."""
    for modifier in obj.modifiers:
        if modifier.type == "ARMATURE" and modifier.show_viewport and modifier.object is not None:
            return modifier
    return None


def object_transform(obj) -> np.ndarray:
    """``obj``'s world matrix in glTF's Y-up world, float32 (4, 4)."""
    return (Y_UP @ np.array(obj.matrix_world)).astype(np.float32)


def _matrices(collection, prop: str, count: int) -> np.ndarray:
    """A matrix property of every item, float64 (count, 4, 4) row-major: ``foreach_get`` gives
    Blender's column-major storage."""
    flat = np.empty(count * 16, np.float32)
    collection.foreach_get(prop, flat)
    return flat.reshape(count, 4, 4).transpose(0, 2, 1).astype(np.float64)


def _inverse(matrices: np.ndarray) -> np.ndarray:
    """Inverses, pseudo-inverses where a matrix is singular (a bone scaled to 0, a common way
    to hide one), which ``np.linalg.inv`` refuses for the whole batch."""
    try:
        return np.linalg.inv(matrices)
    except np.linalg.LinAlgError:
        return np.linalg.pinv(matrices)


def _local(world: np.ndarray, parents: np.ndarray) -> np.ndarray:
    """Local matrices ``parent^-1 @ world`` (``world`` itself where the parent is -1), over the
    last three axes of ``world`` (..., B, 4, 4)."""
    local = world.copy()
    child = parents >= 0
    local[..., child, :, :] = _inverse(world[..., parents[child], :, :]) @ world[..., child, :, :]
    return local


def _sheared(local: np.ndarray) -> np.ndarray:
    """Which matrices (..., N, 4, 4) are not translation, rotation and scale (a non-uniform scale
    under a rotated child): glTF nodes cannot hold them. Bool (..., N)."""
    basis = local[..., :3, :3]
    gram = np.einsum("...ki,...kj->...ij", basis, basis)
    diagonal = np.einsum("...ii->...i", gram)
    off = np.abs(gram - diagonal[..., None] * np.eye(3)).max(axis=(-2, -1))
    return off > 1e-4 * np.maximum(diagonal.max(axis=-1), 1e-12)


def vertex_group_weights(obj, names: list[str]) -> np.ndarray:
    """The weights of ``obj``'s vertex groups ``names`` on the mesh as edited, float32 (G, V), 0
    where a vertex is not in a group.

    bpy reads vertex weights one vertex at a time, so a temporary object sharing the mesh runs a
    temporary Geometry Nodes tree that stores each group (read by name, as Geometry Nodes sees
    vertex groups) as a float point attribute, read from its evaluated mesh with
    ``foreach_get``. Only a modifier of its own runs, so the vertices are those of ``obj.data``
    in their order."""
    mesh = obj.data
    count = len(mesh.vertices)
    weights = np.zeros((len(names), count), np.float32)
    if not names or count == 0:
        return weights
    # Names to store under that no vertex group or attribute already uses.
    prefix = ".pelt_rig_w"
    taken = [*obj.vertex_groups.keys(), *mesh.attributes.keys()]
    while any(name.startswith(prefix) for name in taken):
        prefix += "_"
    group = temporary = None
    try:
        group = bpy.data.node_groups.new(_TEMPORARY, "GeometryNodeTree")
        group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
        geometry = group.nodes.new("NodeGroupInput").outputs[0]
        for column, name in enumerate(names):
            read = group.nodes.new("GeometryNodeInputNamedAttribute")
            read.data_type = "FLOAT"
            read.inputs["Name"].default_value = name
            store = group.nodes.new("GeometryNodeStoreNamedAttribute")
            store.data_type = "FLOAT"
            store.domain = "POINT"
            store.inputs["Name"].default_value = f"{prefix}{column}"
            group.links.new(geometry, store.inputs["Geometry"])
            group.links.new(read.outputs["Attribute"], store.inputs["Value"])
            geometry = store.outputs["Geometry"]
        group.links.new(geometry, group.nodes.new("NodeGroupOutput").inputs[0])

        temporary = bpy.data.objects.new(_TEMPORARY, mesh)
        temporary.modifiers.new(_TEMPORARY, "NODES").node_group = group
        # Evaluated only in a view layer: the scene's own collection is in every one.
        bpy.context.scene.collection.objects.link(temporary)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        evaluated = temporary.evaluated_get(depsgraph)
        stored = evaluated.to_mesh()
        try:
            for column in range(len(names)):
                stored.attributes[f"{prefix}{column}"].data.foreach_get("value", weights[column])
        finally:
            evaluated.to_mesh_clear()
    finally:
        if temporary is not None:
            bpy.data.objects.remove(temporary, do_unlink=True)
        if group is not None:
            bpy.data.node_groups.remove(group)
    return weights


def _skin(obj, modifier, bone_index: dict[str, int], notes: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """Joints and weights (V, K): node 0 where no deforming weight moves the vertex, then one
    column per vertex group the modifier deforms with."""
    bones = modifier.object.data.bones
    deforming, others = [], []
    # Without its vertex groups option the modifier moves nothing by them (envelopes are noted).
    if modifier.use_vertex_groups:
        for group in obj.vertex_groups:
            used = group.name in bone_index and bones[group.name].use_deform
            (deforming if used else others).append(group.name)
    read = vertex_group_weights(obj, deforming + others)
    bone_weights = read[: len(deforming)]
    ignored = [name for name, values in zip(others, read[len(deforming) :], strict=True) if values.any()]
    if ignored:
        notes.append(
            "Vertex groups that name no deforming bone are ignored by the armature, and by the file: "
            + ", ".join(repr(name) for name in ignored)
        )

    # Blender leaves a vertex with (nearly) no deforming weight where it is, whatever tiny
    # weights it has: bind it to the armature object alone.
    unmoved = bone_weights.sum(axis=0, dtype=np.float32) <= UNMOVED
    bone_weights[:, unmoved] = 0.0
    weights = np.empty((len(obj.data.vertices), 1 + len(deforming)), np.float32)
    weights[:, 0] = unmoved
    weights[:, 1:] = bone_weights.T
    columns = np.array([0] + [bone_index[name] for name in deforming], np.uint32)
    joints = np.ascontiguousarray(np.broadcast_to(columns, weights.shape))
    return joints, weights


def _save_object(obj) -> list:
    return [tuple(getattr(obj, prop)) for prop in _OBJECT_TRANSFORMS]


def _restore_object(obj, saved: list) -> None:
    for prop, value in zip(_OBJECT_TRANSFORMS, saved, strict=True):
        setattr(obj, prop, value)


def _save_transforms(arm) -> tuple[list[np.ndarray], list]:
    bones = arm.pose.bones
    saved_bones = []
    for prop, size in _BONE_TRANSFORMS:
        values = np.empty(len(bones) * size, np.float32)
        bones.foreach_get(prop, values)
        saved_bones.append(values)
    return saved_bones, _save_object(arm)


def _restore_transforms(arm, saved: tuple[list[np.ndarray], list]) -> None:
    saved_bones, saved_object = saved
    for (prop, _), values in zip(_BONE_TRANSFORMS, saved_bones, strict=True):
        arm.pose.bones.foreach_set(prop, values)
    _restore_object(arm, saved_object)
    # foreach_set tags nothing: evaluate the pose again (not the action: the frame is unchanged),
    # so that the world matrices read next are those of the restored pose.
    arm.update_tag(refresh={"OBJECT", "DATA"})
    bpy.context.evaluated_depsgraph_get()


def _sample(obj, arm, scene, frames: range, bone_order: np.ndarray):
    """The armature's world matrix, its bones' armature-space matrices (in ``data.bones`` order)
    and the mesh object's world matrix at each frame: (T, 4, 4), (T, B, 4, 4), (T, 4, 4)."""
    count = len(bone_order)
    armature_world = np.empty((len(frames), 4, 4))
    mesh_world = np.empty((len(frames), 4, 4))
    bones = np.empty((len(frames), count, 4, 4))
    frame, subframe = scene.frame_current, scene.frame_subframe
    saved = _save_transforms(arm)
    try:
        for t, f in enumerate(frames):
            scene.frame_set(f)
            armature_world[t] = arm.matrix_world
            mesh_world[t] = obj.matrix_world
            bones[t, bone_order] = _matrices(arm.pose.bones, "matrix", count)
    finally:
        scene.frame_set(frame, subframe=subframe)
        _restore_transforms(arm, saved)
    return armature_world, bones, mesh_world


def _animation(obj, arm, scene, bone_parents, bone_order, notes, at_rest) -> list[Animation]:
    """The active action sampled; ``at_rest``: the mesh object in the armature's space now."""
    data = arm.animation_data
    if data is None:
        return []
    if len(data.nla_tracks):
        notes.append(
            f"The NLA tracks of {arm.name!r} are not exported: only its active action is, sampled "
            "with whatever the tracks add to it"
        )
    action = data.action
    if action is None:
        return []
    first, last = (round(f) for f in action.frame_range)
    frames = range(first, last + 1)
    armature_world, bones, mesh_world = _sample(obj, arm, scene, frames, bone_order)

    poses = np.empty((len(frames), 1 + len(bone_order), 4, 4))
    poses[:, 0] = Y_UP @ armature_world
    poses[:, 1:] = _local(bones, bone_parents)
    # glTF moves a skinned mesh with its joints only: a mesh that does not keep its place
    # relative to the armature (not its child while the armature moves) ends up elsewhere.
    relative = _inverse(armature_world) @ mesh_world
    if np.abs(relative - at_rest).max() > 1e-4 * max(1.0, np.abs(at_rest).max()):
        notes.append(
            f"{obj.name!r} does not follow {arm.name!r} as it moves in {action.name!r} (not its "
            "child?): in the file the mesh moves with the armature"
        )
    return [Animation(action.name, _times(len(frames), scene), poses.astype(np.float32))]


def _times(count: int, scene) -> np.ndarray:
    """Seconds of ``count`` frames from the first, at the scene's frame rate."""
    fps = scene.render.fps / scene.render.fps_base
    return (np.arange(count, dtype=np.float64) / fps).astype(np.float32)


def object_animations(obj, scene) -> list[Animation]:
    """The active action of an unskinned ``obj`` sampled at every frame of its range: its world
    matrix (Y-up) at each time, poses (T, 4, 4); none without an action. What its parents do
    while it plays is in the samples. Leaves the frame and the object's transforms as they were."""
    data = obj.animation_data
    action = data.action if data is not None else None
    if action is None:
        return []
    first, last = (round(f) for f in action.frame_range)
    frames = range(first, last + 1)
    poses = np.empty((len(frames), 4, 4))
    frame, subframe = scene.frame_current, scene.frame_subframe
    saved = _save_object(obj)
    try:
        for t, f in enumerate(frames):
            scene.frame_set(f)
            poses[t] = Y_UP @ np.array(obj.matrix_world)
    finally:
        scene.frame_set(frame, subframe=subframe)
        _restore_object(obj, saved)
    return [Animation(action.name, _times(len(frames), scene), poses.astype(np.float32))]


def _modifier_notes(obj, modifier, notes: list[str]) -> None:
    name = repr(modifier.name)
    if modifier.use_bone_envelopes:
        notes.append(f"Bone envelopes deform the mesh in Blender ({name}); the file has only its weights")
    if modifier.use_deform_preserve_volume:
        notes.append(
            f"{name} preserves volume (dual quaternions); glTF skins blend linearly, so bent joints "
            "lose volume in the file"
        )
    if modifier.vertex_group:
        notes.append(f"{name} is limited by the vertex group {modifier.vertex_group!r}; the file is not")
    if modifier.use_multi_modifier:
        notes.append(f"{name} blends with the modifiers before it (Multi Modifier); the file does not")
    others = [m.name for m in obj.modifiers if m.type == "ARMATURE" and m.show_viewport and m != modifier]
    if others:
        notes.append(
            "Only one armature is exported; also deforming in Blender: "
            + ", ".join(repr(name) for name in others)
        )
    if modifier.object.data.pose_position == "REST":
        notes.append(
            f"{modifier.object.name!r} shows its rest position, so its animation is exported unmoving"
        )
    deforming = [bone for bone in modifier.object.data.bones if bone.use_deform]
    curved = [bone.name for bone in deforming if bone.bbone_segments > 1]
    if curved:
        notes.append(
            "B-Bones bend in segments in Blender, as straight bones in the file: "
            + ", ".join(repr(name) for name in curved)
        )
    enveloped = [bone.name for bone in deforming if bone.use_envelope_multiply]
    if enveloped:
        notes.append(
            "Bones that multiply their weights by their envelope, which the file does not: "
            + ", ".join(repr(name) for name in enveloped)
        )


def gather(obj, scene) -> Rig | None:
    """``obj``'s skin by its first Armature modifier, or ``None`` without one. Leaves the file,
    the frame and the pose as they were."""
    modifier = armature_modifier(obj)
    if modifier is None:
        return None
    arm = modifier.object
    bones = arm.data.bones
    names = [bone.name for bone in bones]
    bone_index = {name: 1 + i for i, name in enumerate(names)}
    bone_parents = np.array(
        [bone_index[bone.parent.name] - 1 if bone.parent else -1 for bone in bones], np.int32
    )
    # Pose bones are matched by name: their order is not promised to be ``data.bones``'.
    bone_order = np.array([bone_index[bone.name] - 1 for bone in arm.pose.bones], np.intp)
    notes: list[str] = []
    _modifier_notes(obj, modifier, notes)

    # The object matrices before sampling the action moves them.
    armature_world, bind = np.array(arm.matrix_world), object_transform(obj)
    mesh_in_armature = _inverse(armature_world) @ np.array(obj.matrix_world)
    rest = np.empty((1 + len(bones), 4, 4))
    rest[0] = Y_UP @ armature_world
    rest[1:] = _local(_matrices(bones, "matrix_local", len(bones)), bone_parents)
    joints, weights = _skin(obj, modifier, bone_index, notes)
    animations = _animation(obj, arm, scene, bone_parents, bone_order, notes, mesh_in_armature)

    node_names = [arm.name, *names]
    sheared = _sheared(rest)
    for animation in animations:
        sheared |= _sheared(animation.poses).any(axis=0)
    if sheared.any():
        notes.append(
            "Shear (non-uniform scale under rotation) that glTF's translation, rotation and scale "
            "cannot hold: " + ", ".join(repr(node_names[i]) for i in np.flatnonzero(sheared))
        )
    return Rig(
        armature=arm.name,
        names=node_names,
        parents=np.concatenate([[-1], bone_parents + 1]).astype(np.int32),
        rest=rest.astype(np.float32),
        bind=bind,
        joints=joints,
        weights=weights,
        animations=animations,
        notes=notes,
    )
