"""The glTF importer's user-extension hooks: a luxbake bake made readable in Blender.

io_scene_gltf2 finds `glTF2ImportUserExtension` in every enabled add-on's module and calls its
`gather_import_*` methods during an import (File > Import > glTF, or the Bake operator), with
the importer's `gltf` as the last argument. When the file is a luxbake output (its scene's
`extras.luxbake`, or a material with `LUXBAKE_lightmap`):
- its materials are rebuilt to show the bake as a glTF viewer does (shading.py): base colour ×
  the colour attribute `Color`, or the lightmap's display texture × `emissiveFactor`, through
  the shared display / false-colour group; the scene's view transform becomes Standard;
- each probe's results (`extras.luxbake`, also kept as Blender's nested custom property
  `luxbake`) become flat, readable custom properties named as the `--probes-out` CSV columns:
  `E+x_lx` … `E-z_lx` (faces in the probe's glTF axes, +y up), `direct+x_lx` …,
  `indirect+x_lx` …, `scalar_lx`, `horizontal_lx`, `cylindrical_lx`, … (the per-face lists,
  `vertical` and `semicylindrical`, stay in `luxbake` only);
- probe glyphs (`<probe>_glyph` nodes) move to the collection "LuxBake probe glyphs";
- each luminaire (`EXT_lights_ies`, `LUXBAKE_luminaire`) gets its luminous opening drawn as a
  white emitting rectangle (or disc) facing its nadir, in the collection "LuxBake luminaires"
  (openings.py), unless the file draws them itself (display-only nodes, `extras.luxbake.
  displayOnly`: outputs since issue 57, whose openings every glTF viewer shows);
- the false-colour range is set to the illuminance's range over the imported meshes.
"""

import math
import os
from urllib.parse import unquote

import bpy

from . import openings, shading

GLYPHS = "LuxBake probe glyphs"
LUMINAIRES = "LuxBake luminaires"
FACES = ("+x", "-x", "+y", "-y", "+z", "-z")
METRICS = {  # probe metric → custom property (the --probes-out CSV column)
    "vectorMagnitude": "vector_magnitude_lx", "altitudeDeg": "altitude_deg",
    "azimuthDeg": "azimuth_deg", "symmetricMean": "symmetric_mean_lx", "scalar": "scalar_lx",
    "vectorScalarRatio": "vector_scalar_ratio", "horizontal": "horizontal_lx",
    "cylindrical": "cylindrical_lx", "exactScalar": "exact_scalar_lx",
    "exactCylindrical": "exact_cylindrical_lx", "cuttleIndirect": "cuttle_indirect_lx",
}


def probe_properties(result):
    """Flat {property: value} of one probe's result object (`extras.luxbake`)."""
    props = {}
    for key, prefix in (("faces", "E"), ("facesDirect", "direct"), ("facesIndirect", "indirect")):
        for face in FACES:
            value = result.get(key, {}).get(face)
            if value is not None:
                props[f"{prefix}{face}_lx"] = float(value)
    metrics = result.get("metrics", {})
    for key, name in METRICS.items():
        if metrics.get(key) is not None:
            props[name] = float(metrics[key])
    for i, axis in enumerate("xyz"):
        if metrics.get("vector") is not None:
            props[f"vector_{axis}_lx"] = float(metrics["vector"][i])
    return props


def is_bake(gltf):
    scene = gltf.data.scenes[gltf.data.scene] if gltf.data.scene is not None else None
    extras = scene.extras if scene is not None and isinstance(scene.extras, dict) else {}
    if "luxbake" in extras:
        return True
    return any(m.extensions and "LUXBAKE_lightmap" in m.extensions
               for m in (gltf.data.materials or []))


class glTF2ImportUserExtension:
    def __init__(self):
        self.materials = []  # (Blender material, glTF material, colour attribute name or None)

    def gather_import_material_after_hook(self, pymaterial, vertex_color, mat, gltf):
        self.materials.append((mat, pymaterial, vertex_color))

    def gather_import_scene_after_nodes_hook(self, gltf_scene, blender_scene, gltf):
        if not is_bake(gltf):
            return
        objects = []
        glyph_materials = set()
        # Outputs since issue 57 carry the openings as display-only nodes: not drawn twice.
        drawn = any(
            isinstance(n.extras, dict)
            and isinstance(n.extras.get("luxbake"), dict)
            and n.extras["luxbake"].get("displayOnly") is True
            for n in gltf.data.nodes or []
        )
        for vnode_id, vnode in gltf.vnodes.items():
            obj = getattr(vnode, "blender_object", None)
            if obj is None:
                continue
            objects.append(obj)
            extras = gltf.data.nodes[vnode_id].extras if isinstance(vnode_id, int) else None
            if isinstance(extras, dict) and setup_node(obj, extras):
                glyph_materials.update(s.material for s in obj.material_slots if s.material)
            if isinstance(vnode_id, int) and not drawn:
                size = luminaire_opening(gltf, gltf.data.nodes[vnode_id])
                if size is not None:
                    add_opening(obj, *size)
        for mat, pymaterial, vertex_color in self.materials:
            setup_material(mat, pymaterial, vertex_color, plain=mat in glyph_materials)
        setup_scene(blender_scene, objects)


def setup_node(obj, extras):
    """Probe results as flat properties; a glyph moved to its collection (returns True)."""
    result = extras.get("luxbake")
    if not isinstance(result, dict):
        return False
    if "faces" in result:
        for key, value in probe_properties(result).items():
            obj[key] = value
    if "glyph" in result:
        move_to_collection(obj, GLYPHS)
        return True
    return False


def profile_bytes(gltf, entry):
    """The bytes and MIME type of a root profile entry (bufferView or a relative uri)."""
    from io_scene_gltf2.io.imp.gltf2_io_binary import BinaryData

    if "bufferView" in entry:
        return bytes(BinaryData.get_buffer_view(gltf, entry["bufferView"])), entry.get("mimeType")
    uri = entry.get("uri", "")
    if uri and not uri.startswith("data:"):
        path = os.path.join(os.path.dirname(gltf.filename), unquote(uri))
        mime = "application/x-eulumdat" if uri.lower().endswith(".ldt") else "application/x-ies-lm-63"
        with open(path, "rb") as f:
            return f.read(), mime
    return None, None


def luminaire_opening(gltf, node):
    """(length, width) in m of the luminaire at a glTF node, or None (not a luminaire)."""
    exts = node.extensions or {}
    root = gltf.data.extensions or {}
    entry = None
    if "EXT_lights_ies" in exts:
        entry = root.get("EXT_lights_ies", {}).get("lights", [])[exts["EXT_lights_ies"]["light"]]
    elif "profile" in exts.get("LUXBAKE_luminaire", {}):
        entry = root.get("LUXBAKE_luminaire", {}).get("profiles", [])[exts["LUXBAKE_luminaire"]["profile"]]
    if entry is None:
        return None
    try:
        data, mime = profile_bytes(gltf, entry)
    except OSError:
        data, mime = None, None
    size = openings.opening(exts, data, mime)
    return size if size is not None and size[0] > 0 else None


def add_opening(obj, length, width):
    """A white emitting rectangle length × width (a disc when width is 0) at `obj`, facing the
    node's glTF −Z, which the importer turned into the object's local +Y."""
    if width > 0:
        corners = [(-length / 2, 0, -width / 2), (-length / 2, 0, width / 2),
                   (length / 2, 0, width / 2), (length / 2, 0, -width / 2)]
    else:  # round: the circle seen from the nadir, counter-clockwise about +Y
        corners = [(length / 2 * math.sin(a), 0, length / 2 * math.cos(a))
                   for a in (2 * math.pi * k / 24 for k in range(24))]
    mesh = bpy.data.meshes.new(f"{obj.name} opening")
    mesh.from_pydata(corners, [], [tuple(range(len(corners)))])
    material = bpy.data.materials.get("LuxBake luminous opening")
    if material is None:
        material = bpy.data.materials.new("LuxBake luminous opening")
        material.use_nodes = True
        nodes = material.node_tree.nodes
        nodes.clear()
        emission = nodes.new("ShaderNodeEmission")
        emission.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        output = nodes.new("ShaderNodeOutputMaterial")
        material.node_tree.links.new(emission.outputs[0], output.inputs["Surface"])
    mesh.materials.append(material)
    shape = bpy.data.objects.new(f"{obj.name} opening", mesh)
    shape.parent = obj
    move_to_collection(shape, LUMINAIRES)
    return shape


def move_to_collection(obj, name):
    """Move `obj` into the collection `name` inside the collection the import fills (one per
    import: found by its role, so a second bake gets its own)."""
    parent = bpy.context.collection
    collection = next((c for c in parent.children if c.get("luxbake_role") == name), None)
    if collection is None:
        collection = bpy.data.collections.new(name)
        collection["luxbake_role"] = name
        parent.children.link(collection)
    for other in list(obj.users_collection):
        other.objects.unlink(obj)
    collection.objects.link(obj)


def setup_material(mat, pymaterial, vertex_color, plain=False):
    """Rebuild one imported material to show the bake (see shading.build_material)."""
    pbr = pymaterial.pbr_metallic_roughness
    base = list(pbr.base_color_factor) if pbr is not None and pbr.base_color_factor else [1.0] * 4
    ext = pymaterial.extensions or {}
    if "LUXBAKE_lightmap" in ext:
        factor = list(pymaterial.emissive_factor or [1.0, 1.0, 1.0])
        try:
            shading.build_material(mat, shading.lightmap_texture, factor)
        except LookupError:
            return
    elif "KHR_materials_unlit" in ext and vertex_color:
        # The importer passes the glTF name (COLOR_0) and names the attribute "Color": read
        # the mesh's render colour attribute (the layer name left empty).
        shading.build_material(mat, shading.vertex_colour(""), base[:3])
    else:
        return
    if plain:
        group_node = next(n for n in mat.node_tree.nodes if n.type == "GROUP")
        src = group_node.inputs["Display"].links[0].from_socket
        dst = group_node.outputs["Color"].links[0].to_socket
        mat.node_tree.nodes.remove(group_node)
        mat.node_tree.links.new(src, dst)


def attribute_range(objects, name):
    lo, hi = None, None
    for obj in objects:
        if obj.type != "MESH":
            continue
        attr = obj.data.attributes.get(name)
        if attr is None or not len(attr.data):
            continue
        values = [0.0] * len(attr.data)
        attr.data.foreach_get("value", values)
        lo = min(values) if lo is None else min(lo, min(values))
        hi = max(values) if hi is None else max(hi, max(values))
    return lo, hi


def setup_scene(scene, objects):
    shading.standard_view(scene)
    s = scene.luxbake_settings
    lo, hi = attribute_range(objects, "_ILLUMINANCE")
    if hi is not None and hi > 0:
        s["range_min"] = 0.0
        s["range_max"] = float(hi)
    shading.apply_display(scene)
