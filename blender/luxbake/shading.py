"""Materials that show a bake as a glTF viewer does, and a switch to false colour.

Inputs: an imported bake's materials (Blender material, glTF base colour and emissive factors,
whether it is lightmapped), the scene's display settings (props.LuxbakeScene). Outputs: each
material rebuilt as Emission (strength 1) ← the shared node group "LuxBake display" ← the
display colour, and the scene's colour management set to Standard.

Why: a bake's `COLOR_0` is already the display colour (the illuminance over the exposure, with a
shoulder), and an unlit viewer shows base colour × `COLOR_0`; lightmapped materials show the
display texture × `emissiveFactor`. An emission shader of `Color` alone drops the base colour
(too bright, colourless), and Blender's default view transform (AgX) compresses and desaturates
it again: washed out. With base colour × colour as emission of strength 1 and the Standard view
transform (plain sRGB), a render shows each pixel as the unlit viewer does.

The group also maps `_ILLUMINANCE` (lx) or `_LUMINANCE` (cd/m²) between min and max (linear or
logarithmic) onto luxbake's false-colour palette (src/picture/scale.rs, dark indigo → magenta);
lightmapped surfaces use their vertex values there.
"""

import math

import bpy

GROUP = "LuxBake display"

# src/picture/scale.rs PALETTE (sRGB bytes), evenly spaced.
PALETTE = [
    (24, 0, 84), (38, 42, 196), (18, 128, 238), (0, 200, 206), (44, 214, 92),
    (176, 226, 30), (252, 196, 20), (240, 88, 22), (196, 10, 96),
]


def srgb_to_linear(c):
    c /= 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def _socket(sockets, identifier):
    return next(s for s in sockets if s.identifier == identifier)


def _mix(nodes, data_type, name, x):
    node = nodes.new("ShaderNodeMix")
    node.data_type = data_type
    node.name = node.label = name
    node.location = (x, 0)
    if data_type == "RGBA":
        node.blend_type = "MIX"
    return node


def ensure_group():
    """The shared node group: Display colour in, display or false colour out."""
    group = bpy.data.node_groups.get(GROUP)
    if group is not None:
        return group
    group = bpy.data.node_groups.new(GROUP, "ShaderNodeTree")
    group.interface.new_socket(name="Display", in_out="INPUT", socket_type="NodeSocketColor")
    group.interface.new_socket(name="Color", in_out="OUTPUT", socket_type="NodeSocketColor")
    nodes, links = group.nodes, group.links
    inp = nodes.new("NodeGroupInput")
    inp.location = (-1200, 200)
    out = nodes.new("NodeGroupOutput")
    out.location = (600, 0)

    attrs = []
    for i, name in enumerate(("_ILLUMINANCE", "_LUMINANCE")):
        attr = nodes.new("ShaderNodeAttribute")
        attr.attribute_type = "GEOMETRY"
        attr.attribute_name = name
        attr.location = (-1200, -150 - 200 * i)
        attrs.append(attr)
    quantity = _mix(nodes, "FLOAT", "quantity", -1000)
    links.new(attrs[0].outputs["Fac"], _socket(quantity.inputs, "A_Float"))
    links.new(attrs[1].outputs["Fac"], _socket(quantity.inputs, "B_Float"))
    positive = nodes.new("ShaderNodeMath")
    positive.operation = "MAXIMUM"
    positive.inputs[1].default_value = 1e-9
    positive.location = (-800, -200)
    links.new(_socket(quantity.outputs, "Result_Float"), positive.inputs[0])
    log = nodes.new("ShaderNodeMath")
    log.operation = "LOGARITHM"
    log.inputs[1].default_value = 10.0
    log.location = (-600, -200)
    links.new(positive.outputs[0], log.inputs[0])
    scale = _mix(nodes, "FLOAT", "log", -400)
    links.new(_socket(quantity.outputs, "Result_Float"), _socket(scale.inputs, "A_Float"))
    links.new(log.outputs[0], _socket(scale.inputs, "B_Float"))
    span = nodes.new("ShaderNodeMapRange")
    span.name = span.label = "range"
    span.clamp = True
    span.location = (-200, -100)
    links.new(_socket(scale.outputs, "Result_Float"), span.inputs["Value"])
    ramp = nodes.new("ShaderNodeValToRGB")
    ramp.name = ramp.label = "palette"
    ramp.location = (0, -100)
    elements = ramp.color_ramp.elements
    while len(elements) < len(PALETTE):
        elements.new(0.5)
    for k, (element, rgb) in enumerate(zip(elements, PALETTE)):
        element.position = k / (len(PALETTE) - 1)
        element.color = (*(srgb_to_linear(c) for c in rgb), 1.0)
    links.new(span.outputs["Result"], ramp.inputs["Fac"])
    pick = _mix(nodes, "RGBA", "false_colour", 300)
    links.new(inp.outputs["Display"], _socket(pick.inputs, "A_Color"))
    links.new(ramp.outputs["Color"], _socket(pick.inputs, "B_Color"))
    links.new(_socket(pick.outputs, "Result_Color"), out.inputs["Color"])
    return group


def apply_display(scene):
    """Set the shared group from the scene's display settings (the update of those properties)."""
    group = bpy.data.node_groups.get(GROUP)
    if group is None:
        return
    s = scene.luxbake_settings
    nodes = group.nodes
    _socket(nodes["false_colour"].inputs, "Factor_Float").default_value = float(s.display != "DISPLAY")
    _socket(nodes["quantity"].inputs, "Factor_Float").default_value = float(s.display == "LUMINANCE")
    _socket(nodes["log"].inputs, "Factor_Float").default_value = float(s.log_scale)
    lo, hi = s.range_min, s.range_max
    if s.log_scale:
        lo, hi = math.log10(max(lo, 1e-9)), math.log10(max(hi, 1e-9))
    if hi <= lo:
        hi = lo + 1e-6
    nodes["range"].inputs["From Min"].default_value = lo
    nodes["range"].inputs["From Max"].default_value = hi


def build_material(material, display, factor):
    """Rebuild `material`: Emission ← group ← `display` colour × `factor` (RGB).

    `display(nodes)` makes the node whose first colour output is the display colour (a colour
    attribute, or the lightmap's display texture)."""
    group = ensure_group()
    material.use_nodes = True
    tree = material.node_tree
    keep = display(tree.nodes)
    source = keep[-1]
    for node in list(tree.nodes):
        if node not in keep:
            tree.nodes.remove(node)
    nodes, links = tree.nodes, tree.links
    times = _mix(nodes, "RGBA", "base colour", -300)
    times.blend_type = "MULTIPLY"
    _socket(times.inputs, "Factor_Float").default_value = 1.0
    _socket(times.inputs, "B_Color").default_value = (*factor, 1.0)
    links.new(source.outputs[0], _socket(times.inputs, "A_Color"))
    shown = nodes.new("ShaderNodeGroup")
    shown.node_tree = group
    shown.location = (-100, 0)
    links.new(_socket(times.outputs, "Result_Color"), shown.inputs["Display"])
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1.0
    emission.location = (100, 0)
    links.new(shown.outputs["Color"], emission.inputs["Color"])
    output = nodes.new("ShaderNodeOutputMaterial")
    output.location = (300, 0)
    links.new(emission.outputs["Emission"], output.inputs["Surface"])


def vertex_colour(layer):
    """A `display` maker for build_material: the colour attribute `layer` (empty: the mesh's
    render colour attribute)."""
    def make(nodes):
        node = nodes.new("ShaderNodeVertexColor")
        node.layer_name = layer
        node.location = (-500, 0)
        return [node]
    return make


def lightmap_texture(nodes):
    """A `display` maker for build_material: the imported material's emission texture (and the
    nodes feeding its UVs), kept."""
    images = [n for n in nodes if n.type == "TEX_IMAGE"]
    if not images:
        raise LookupError("no display texture")
    image = images[0]
    keep = []

    def upstream(node):
        for socket in node.inputs:
            for link in socket.links:
                upstream(link.from_node)
        keep.append(node)
    upstream(image)
    return keep


def standard_view(scene):
    """Plain sRGB display: the bake's display colours reach the screen unchanged."""
    view = scene.view_settings
    view.view_transform = "Standard"
    view.look = "None"
    view.exposure = 0.0
    view.gamma = 1.0
    scene.display_settings.display_device = "sRGB"
    world = scene.world or bpy.data.worlds.new("LuxBake")
    scene.world = world
    world.use_nodes = True
    background = world.node_tree.nodes.get("Background")
    if background is not None:
        background.inputs["Color"].default_value = (0.02, 0.02, 0.02, 1.0)
        background.inputs["Strength"].default_value = 1.0
