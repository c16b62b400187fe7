"""A room built in Blender by script, exported, baked and imported back by the LuxBake add-on;
prints what Blender holds afterwards as JSON (for tests/blender_addon.rs).

Usage: PYTHON room_roundtrip.py --bake BAKE --out DIR --profile FILE.ies
PYTHON is a Python 3.11 with PyPI `bpy` 5.0.1. The add-on is enabled from this repository's
blender/ folder. The room (Blender axes, +Z up; metres): 4 × 3 m floor, walls 2.8 m high, a
desk block, an IES luminaire on an Empty at the ceiling (nadir down the Empty's −Z), a 0.6 m
square emitting panel under the ceiling (500 cd/m²), a 10 W point light (543.5 cd at 683 lm/W),
a spot light carrying cns70_50w.ldt (from FILE's folder) aimed at the east wall, a 200 cd spot,
two probe Empties (one turned 30° about Z), a working plane at 0.8 m every 0.5 m. Bakes with
`luxbake.bake` (draft; then again with coarse lightmaps), after checking the operator's errors: a missing bake binary, a bake
that fails (bad option) and a missing profile file (the export fails).

Stdout: {"operator": ..., "scene": {"view_transform", "display": ...},
 "meshes": [{"name", "collection", "attributes": {NAME: [values]}, "materials": [...]}],
 "probes": [{"name", "properties": {...}}], "glyphs": [names in the glyph collection],
 "materials": {NAME: {"nodes": [types], "emission_from": [...]}},
 "errors": {"missing_bake" | "bad_option" | "missing_profile": [result, error, status]},
 "false_colour": {...}}
"""

import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def arg(name):
    return sys.argv[sys.argv.index(name) + 1]


def box(bpy, name, size, location, material):
    mesh = bpy.data.meshes.new(name)
    sx, sy, sz = (s / 2 for s in size)
    verts = [(x * sx, y * sy, z * sz) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    mesh.from_pydata(verts, [], faces)
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    bpy.context.scene.collection.objects.link(obj)
    return obj


def quad(bpy, name, corners, material):
    """A single-sided quad; corners counter-clockwise seen from the side it faces."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(corners, [], [(0, 1, 2, 3)])
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def material(bpy, name, reflectance=None, rgb=None):
    m = bpy.data.materials.new(name)
    m.use_backface_culling = True  # single-sided in glTF (doubleSided false)
    s = m.luxbake_settings
    if reflectance is not None:
        s.reflectance_mode = "VALUE"
        s.reflectance = reflectance
    if rgb is not None:
        s.reflectance_mode = "RGB"
        s.reflectance_rgb = rgb
    return m


def build(bpy, profile):
    W, D, H = 4.0, 3.0, 2.8
    floor = material(bpy, "floor", 0.3)
    wall = material(bpy, "wall", 0.5)
    ceiling = material(bpy, "ceiling", rgb=(0.7, 0.7, 0.65))
    desk = material(bpy, "desk")
    desk.diffuse_color = (0.4, 0.3, 0.2, 1)
    desk.luxbake_settings.reflectance_mode = "BASE_COLOR"
    bsdf = desk.node_tree.nodes["Principled BSDF"] if desk.node_tree else None
    if bsdf is not None:
        bsdf.inputs["Base Color"].default_value = (0.4, 0.3, 0.2, 1)
    panel = material(bpy, "panel", 0.5)
    panel.luxbake_settings.emission_mode = "LUMINANCE"
    panel.luxbake_settings.luminance = 500.0
    panel.luxbake_settings.emission_color = (1.0, 0.9, 0.8)

    quad(bpy, "floor", [(0, 0, 0), (W, 0, 0), (W, D, 0), (0, D, 0)], floor)
    quad(bpy, "ceiling", [(0, 0, H), (0, D, H), (W, D, H), (W, 0, H)], ceiling)
    quad(bpy, "wall_south", [(0, 0, 0), (0, 0, H), (W, 0, H), (W, 0, 0)], wall)
    quad(bpy, "wall_north", [(0, D, 0), (W, D, 0), (W, D, H), (0, D, H)], wall)
    quad(bpy, "wall_west", [(0, 0, 0), (0, D, 0), (0, D, H), (0, 0, H)], wall)
    quad(bpy, "wall_east", [(W, 0, 0), (W, 0, H), (W, D, H), (W, D, 0)], wall)
    box(bpy, "desk", (1.2, 0.6, 0.75), (1.2, 1.0, 0.375), desk)
    quad(bpy, "panel", [(2.7, 1.7, H - 0.01), (3.3, 1.7, H - 0.01), (3.3, 2.3, H - 0.01),
                        (2.7, 2.3, H - 0.01)], panel)

    lum = bpy.data.objects.new("downlight", None)
    lum.location = (1.2, 1.0, H - 0.01)
    lum.luxbake_settings.profile = profile
    lum.luxbake_settings.maintenance_factor = 0.8
    bpy.context.scene.collection.objects.link(lum)

    lamp = bpy.data.lights.new("bulb", "POINT")
    lamp.energy = 10.0
    light = bpy.data.objects.new("bulb", lamp)
    light.location = (3.0, 0.7, 2.2)
    bpy.context.scene.collection.objects.link(light)

    # a spot light carrying a EULUMDAT profile, aimed at the east wall (its −Z along +X),
    # and a spot light given in cd
    washer = bpy.data.objects.new("washer", bpy.data.lights.new("washer", "SPOT"))
    washer.location = (2.0, 1.5, 2.5)
    washer.rotation_euler = (0.0, math.radians(-90.0), 0.0)
    washer.luxbake_settings.profile = os.path.join(os.path.dirname(profile), "cns70_50w.ldt")
    bpy.context.scene.collection.objects.link(washer)
    spot = bpy.data.objects.new("spot", bpy.data.lights.new("spot", "SPOT"))
    spot.location = (0.5, 2.5, 2.6)
    spot.luxbake_settings.use_photometric = True
    spot.luxbake_settings.intensity = 200.0
    bpy.context.scene.collection.objects.link(spot)

    for name, location, turn in (("probe_desk", (1.2, 1.0, 1.2), 0.0),
                                 ("probe_corner", (3.2, 2.4, 1.2), 30.0)):
        probe = bpy.data.objects.new(name, None)
        probe.location = location
        probe.rotation_euler = (0.0, 0.0, math.radians(turn))
        probe.luxbake_settings.probe = True
        bpy.context.scene.collection.objects.link(probe)

    s = bpy.context.scene.luxbake_settings
    s.use_working_plane = True
    s.working_plane_height = 0.8
    s.working_plane_spacing = 0.5
    s.quality = "draft"
    s.probe_glyphs = True


def values(attr):
    out = [0.0] * len(attr.data)
    attr.data.foreach_get("value", out)
    return out


def describe(bpy, collection):
    meshes, probes, materials = [], [], {}
    for obj in sorted(collection.all_objects, key=lambda o: o.name):
        if obj.type == "MESH":
            attrs = {a.name: values(a) for a in obj.data.attributes
                     if a.name in ("_ILLUMINANCE", "_LUMINANCE", "_ILLUMINANCE_DIRECT")}
            meshes.append({"name": obj.name, "vertex_count": len(obj.data.vertices),
                           "attributes": attrs,
                           "materials": [s.material.name for s in obj.material_slots if s.material]})
        if any(k.startswith("E+") for k in obj.keys()):
            probes.append({"name": obj.name,
                           "properties": {k: obj[k] for k in obj.keys()
                                          if isinstance(obj[k], (int, float))}})
    for mat in bpy.data.materials:
        if not mat.node_tree:
            continue
        nodes = mat.node_tree.nodes
        out = next((n for n in nodes if n.type == "OUTPUT_MATERIAL"), None)
        surface = out.inputs["Surface"].links[0].from_node.type if out and out.inputs["Surface"].links else None
        materials[mat.name] = {"nodes": sorted(n.type for n in nodes), "surface": surface}
    glyphs = bpy.data.collections.get("LuxBake probe glyphs")
    return meshes, probes, materials, sorted(o.name for o in glyphs.objects) if glyphs else []


class Layout:
    """A stand-in for a panel's layout (panels cannot draw without a window): every `prop` must
    name a property the data has; counts what was drawn."""

    def __init__(self, counts):
        self.counts = counts

    def prop(self, data, name, **_):
        if not hasattr(data, name):
            raise AttributeError(f"panel draws {name}, which {data!r} lacks")
        self.counts["props"] += 1

    def label(self, **_):
        self.counts["labels"] += 1

    def operator(self, idname, **_):
        self.counts["operators"] += 1

    def template_color_ramp(self, data, name, **_):
        getattr(data, name)
        self.counts["ramps"] += 1

    def row(self, **_):
        return self

    column = box = row


def draw_panels(bpy):
    """Draw every LuxBake panel's contents into the stand-in layout, for every material, object
    and display mode."""
    from luxbake import ui

    counts = {"props": 0, "labels": 0, "operators": 0, "ramps": 0}
    layout = Layout(counts)
    context = bpy.context
    for material in bpy.data.materials:
        for mode in ("BASE_COLOR", "VALUE", "RGB"):
            material.luxbake_settings.reflectance_mode = mode
            for emission in ("NONE", "LUMINANCE", "FLUX"):
                material.luxbake_settings.emission_mode = emission
                ui.draw_material(layout, material)
    for obj in bpy.data.objects:
        s = obj.luxbake_settings
        for on in (False, True):
            s.use_photometric = s.probe = s.use_toward = s.use_opening = on
            if obj.type in {"EMPTY", "LIGHT"}:
                s.profile = "//x.ies" if on else ""
            ui.draw_object(layout, obj)
        ui.draw_results(layout, obj)
    for display in ("DISPLAY", "ILLUMINANCE", "LUMINANCE"):
        context.scene.luxbake_settings.display = display
        ui.draw_scene(layout, context)
    return counts


def run_operator(bpy, scene):
    """The operator's result, the error it raised (a script sees a reported error as
    RuntimeError) and the status it left."""
    try:
        return [sorted(bpy.ops.luxbake.bake()), None, scene.luxbake_settings.status]
    except RuntimeError as error:
        return [None, str(error), scene.luxbake_settings.status]


def main():
    bake, out, profile = arg("--bake"), arg("--out"), arg("--profile")
    stdout_fd = os.dup(1)
    os.dup2(2, 1)
    sys.path.insert(0, os.path.dirname(HERE))
    import bpy
    import addon_utils

    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("luxbake", default_set=True, handle_error=None)
    prefs = bpy.context.preferences.addons["luxbake"].preferences

    build(bpy, profile)
    scene = bpy.context.scene
    scene.luxbake_settings.output_dir = out

    errors = {}
    prefs.bake_path = os.path.join(out, "no-such-bake")
    errors["missing_bake"] = run_operator(bpy, scene)
    prefs.bake_path = bake
    scene.luxbake_settings.extra_args = "--exposure bright"
    errors["bad_option"] = run_operator(bpy, scene)
    scene.luxbake_settings.extra_args = ""
    lum = bpy.data.objects["downlight"].luxbake_settings
    lum.profile = os.path.join(out, "missing.ies")
    errors["missing_profile"] = run_operator(bpy, scene)
    lum.profile = profile

    result = sorted(bpy.ops.luxbake.bake())
    shown = bpy.context.scene.name  # the window shows the bake's scene
    collection = bpy.data.collections["scene-lit"]
    baked_scene = bpy.data.scenes["scene-lit"]
    authoring = {"objects": len(scene.objects),
                 "view_transform": scene.view_settings.view_transform,
                 "bake_objects_here": sum(1 for o in scene.objects if collection in o.users_collection)}
    # baking from the bake's own scene is refused
    from_bake_scene = run_operator(bpy, baked_scene)
    bpy.context.window.scene = scene  # back to the authoring scene, as a user would
    meshes, probes, materials, glyphs = describe(bpy, collection)

    # the false-colour switch (in the bake's scene): the shared group's state after switching
    s = baked_scene.luxbake_settings
    s.display = "ILLUMINANCE"
    s.range_min, s.range_max = 0.0, 500.0
    group = bpy.data.node_groups["LuxBake display"]
    fc = {
        "false_colour": group.nodes["false_colour"].inputs[0].default_value,
        "range": [group.nodes["range"].inputs["From Min"].default_value,
                  group.nodes["range"].inputs["From Max"].default_value],
    }
    bake_scene_info = {"view_transform": baked_scene.view_settings.view_transform,
                       "objects": len(baked_scene.objects)}
    # lightmaps: the same room baked again with --lightmaps (its scene is replaced)
    s.display = "DISPLAY"
    s = scene.luxbake_settings
    s.lightmaps = True
    s.extra_args = "--texel-size 0.25"  # coarse: fast
    s.output_dir = os.path.join(out, "lightmaps")  # the first bake stays for the test to read
    lightmapped = run_operator(bpy, scene)
    with open(os.path.join(out, "lightmaps", "scene.gltf")) as f:
        second_export = sorted(n["name"] for n in json.load(f)["nodes"])
    lightmap_materials = {}
    for obj in bpy.data.collections["scene-lit"].all_objects:
        for slot in obj.material_slots:
            mat = slot.material
            if mat is None or not mat.node_tree:
                continue
            images = [n for n in mat.node_tree.nodes if n.type == "TEX_IMAGE"]
            if not images:
                continue
            uv = [l.from_node for l in images[0].inputs["Vector"].links]
            lightmap_materials[mat.name] = {
                "nodes": sorted(n.type for n in mat.node_tree.nodes),
                "image": images[0].image.name if images[0].image else None,
                "uv_map": uv[0].uv_map if uv and uv[0].type == "UVMAP" else None,
                "has_illuminance": "_ILLUMINANCE" in obj.data.attributes,
            }
    panels = draw_panels(bpy)
    report = {
        "panels": panels,
        "lightmapped": lightmapped, "lightmap_materials": lightmap_materials,
        "second_export_nodes": second_export,
        "operator": result, "status": s.status,
        "scene": bake_scene_info,
        "authoring": authoring, "from_bake_scene": from_bake_scene, "shown": shown,
        "meshes": meshes, "probes": probes, "materials": materials, "glyphs": glyphs,
        "errors": errors, "false_colour": fc,
    }
    sys.stdout.flush()
    os.dup2(stdout_fd, 1)
    json.dump(report, sys.stdout, indent=1)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
