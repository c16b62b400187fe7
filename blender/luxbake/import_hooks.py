"""The glTF importer's user-extension hooks: a luxbake bake made readable in Blender.

io_scene_gltf2 finds `glTF2ImportUserExtension` in every enabled add-on's module and calls its
`gather_import_*` methods during an import (File > Import > glTF, or the Bake operator), with the
importer's `gltf` as the last argument. When the
file is a luxbake output (its scene's `extras.luxbake`, or a material with `LUXBAKE_lightmap`):
- its materials are rebuilt to show the bake as a glTF viewer does (shading.py): base colour ×
  the colour attribute `Color`, or the lightmap's display texture × `emissiveFactor`, through
  the shared display / false-colour group; the scene's view transform becomes Standard;
- each probe's results (`extras.luxbake`, also kept as Blender's nested custom property
  `luxbake`) become flat, readable custom properties named as the `--probes-out` CSV columns:
  `E+x_lx` … `E-z_lx` (faces in the probe's glTF axes, +y up), `direct+x_lx` …,
  `indirect+x_lx` …, `scalar_lx`, `horizontal_lx`, `cylindrical_lx`, …;
- probe glyphs (`<probe>_glyph` nodes) move to the collection "LuxBake probe glyphs";
- the false-colour range is set to the illuminance's range over the imported meshes.
"""

import bpy

from . import shading

GLYPHS = "LuxBake probe glyphs"
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
        for vnode_id, vnode in gltf.vnodes.items():
            obj = getattr(vnode, "blender_object", None)
            if obj is None:
                continue
            objects.append(obj)
            extras = gltf.data.nodes[vnode_id].extras if isinstance(vnode_id, int) else None
            if isinstance(extras, dict) and setup_node(obj, extras):
                glyph_materials.update(s.material for s in obj.material_slots if s.material)
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


def move_to_collection(obj, name):
    collection = bpy.data.collections.get(name)
    if collection is None:
        collection = bpy.data.collections.new(name)
        bpy.context.scene.collection.children.link(collection)
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
        shading.build_material(mat, shading.vertex_colour(vertex_color), base[:3])
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
