# SPDX-License-Identifier: GPL-3.0-or-later
"""A small helper to write node trees as expressions, shared by the shader and geometry trees.

Blender nodes carry several sockets of the same name (one per data type, most of them hidden), so
sockets are picked by name among the available ones. Values are either sockets (wired) or plain
numbers / vectors / booleans (set as the socket's default value). This module never imports bpy.
"""


class NodeGraph:
    """Builds nodes in ``tree`` (a ``bpy.types.NodeTree``), laid out left to right in call order."""

    def __init__(self, tree):
        self.tree = tree
        self._column = 0

    def node(self, idname: str, inputs: dict | None = None, **props):
        """A new node of type ``idname``: ``props`` are its properties (set first, since they decide
        which sockets are available), ``inputs`` maps socket names (``"Name"`` or ``("Name", n)``
        for the n-th available socket of that name) to sockets or values."""
        node = self.tree.nodes.new(idname)
        node.location = (200.0 * self._column, 0.0)
        self._column += 1
        for key, value in props.items():
            setattr(node, key, value)
        for key, value in (inputs or {}).items():
            name, nth = key if isinstance(key, tuple) else (key, 0)
            self.set(socket(node.inputs, name, nth), value)
        return node

    def set(self, target, value) -> None:
        """Wires ``value`` into the input socket ``target``, or sets it as its default value."""
        if hasattr(value, "is_output"):
            self.tree.links.new(value, target)
        else:
            target.default_value = value

    def value(self, name: str, default: float):
        """A Value node called ``name`` (a parameter set later by name); returns its output."""
        node = self.node("ShaderNodeValue", name=name, label=name)
        node.outputs[0].default_value = default
        return node.outputs[0]

    def math(self, operation: str, *values):
        """A scalar math node; returns its output socket."""
        inputs = {("Value", i): v for i, v in enumerate(values)}
        return self.node("ShaderNodeMath", inputs, operation=operation).outputs[0]

    def vector_math(self, operation: str, *values, scale=None):
        """A vector math node; returns its vector output (its ``Value`` output for DOT_PRODUCT and
        LENGTH)."""
        inputs = {("Vector", i): v for i, v in enumerate(values)}
        if scale is not None:
            inputs["Scale"] = scale
        node = self.node("ShaderNodeVectorMath", inputs, operation=operation)
        return output(node, "Value" if operation in ("DOT_PRODUCT", "LENGTH", "DISTANCE") else "Vector")

    def combine(self, x, y, z=0.0):
        """A Combine XYZ node's vector."""
        return self.node("ShaderNodeCombineXYZ", {"X": x, "Y": y, "Z": z}).outputs[0]

    def separate(self, vector):
        """The X, Y, Z outputs of a Separate XYZ node."""
        node = self.node("ShaderNodeSeparateXYZ", {"Vector": vector})
        return node.outputs["X"], node.outputs["Y"], node.outputs["Z"]


def socket(sockets, name: str, nth: int = 0):
    """The ``nth`` available socket called ``name`` in ``sockets`` (a node's inputs or outputs)."""
    matches = [s for s in sockets if s.name == name and not s.is_unavailable]
    if nth >= len(matches):
        raise KeyError(f"no available socket '{name}' #{nth} among {[s.name for s in sockets]}")
    return matches[nth]


def output(node, name: str, nth: int = 0):
    """The ``nth`` available output of ``node`` called ``name``."""
    return socket(node.outputs, name, nth)
