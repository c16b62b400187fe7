"""Import one glTF file with Blender's own importer and print what Blender made of it, as JSON.

Usage: PYTHON blender_import.py FILE [--max-values N]
PYTHON is a Python 3.11 with the PyPI `bpy` module (5.0.1), e.g. `.venv-bpy/bin/python`.

The file is imported with `bpy.ops.import_scene.gltf(filepath=FILE)` into an empty scene. Stdout
receives one JSON object (Blender's own log lines are sent to stderr):
  {"blender": "5.0.1",
   "scene": {"name", "properties"},                 # scene custom properties (glTF scene extras)
   "objects": [{"name", "type", "parent", "properties"}],  # every object, sorted by name
   "meshes": [{"name", "mesh", "vertex_count", "corner_count", "properties",
               "attributes": [{"name", "domain", "data_type"}], "uv_layers": [NAME],
               "materials": [NAME],                 # the object's material slots
               "values": {ATTRIBUTE: {...}}}],      # for _ILLUMINANCE, _ILLUMINANCE_DIRECT,
                                                    # _LUMINANCE and Color
   "materials": [{"name", "textures": [{"image", "uv_map", "interpolation", "extension",
                                        "feeds": [[NODE_TYPE, INPUT]]}]}]}
A texture's "uv_map" is that of the UV Map node feeding its Vector input (null: none), and
"feeds" the shader inputs its colour reaches (through any mixing nodes).
Scalar attributes give {"domain", "count", "min", "max", "mean", "first": [...]}. The colour
attribute (8-bit, corner domain) additionally gives per-vertex values: "vertex_linear" and
"vertex_srgb" (Blender stores byte colours sRGB-encoded; "linear" is Blender's decoding of them).
At most N values are listed per array (default 100000); the statistics cover all of them.
Exit status 0 on success, 1 when the import fails.
"""

import json
import os
import sys


def plain(value):
    """Blender ID properties as JSON values (groups to objects, arrays to lists)."""
    if hasattr(value, "to_dict"):
        return {k: plain(v) for k, v in value.to_dict().items()}
    if hasattr(value, "to_list"):
        return [plain(v) for v in value.to_list()]
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    return str(value)


def properties(idblock):
    return {key: plain(idblock[key]) for key in sorted(idblock.keys())}


def stats(values, limit):
    n = len(values)
    out = {"count": n, "first": values[:limit]}
    if n:
        out.update(min=min(values), max=max(values), mean=sum(values) / n)
    return out


def scalar_values(attr, limit):
    values = [d.value for d in attr.data]
    return {"domain": attr.domain, **stats(values, limit)}


def color_values(mesh, attr, limit):
    linear = [list(d.color) for d in attr.data]
    srgb = [list(d.color_srgb) for d in attr.data]
    out = {"domain": attr.domain, "data_type": attr.data_type, "count": len(linear)}
    if attr.domain == "CORNER":
        vertex_linear = [None] * len(mesh.vertices)
        vertex_srgb = [None] * len(mesh.vertices)
        for loop in mesh.loops:
            vertex_linear[loop.vertex_index] = linear[loop.index]
            vertex_srgb[loop.vertex_index] = srgb[loop.index]
    else:
        vertex_linear, vertex_srgb = linear, srgb
    out["vertex_linear"] = vertex_linear[:limit]
    out["vertex_srgb"] = vertex_srgb[:limit]
    return out


def describe_mesh(obj, limit):
    mesh = obj.data
    attributes = [
        {"name": a.name, "domain": a.domain, "data_type": a.data_type}
        for a in mesh.attributes
    ]
    values = {}
    for name in ("_ILLUMINANCE", "_ILLUMINANCE_DIRECT", "_LUMINANCE"):
        attr = mesh.attributes.get(name)
        if attr is not None:
            values[name] = scalar_values(attr, limit)
    color = mesh.color_attributes.get("Color")
    if color is not None:
        values["Color"] = color_values(mesh, color, limit)
    return {
        "name": obj.name,
        "mesh": mesh.name,
        "vertex_count": len(mesh.vertices),
        "corner_count": len(mesh.loops),
        "properties": properties(obj),
        "attributes": attributes,
        "uv_layers": [uv.name for uv in mesh.uv_layers],
        "materials": [s.material.name for s in obj.material_slots if s.material],
        "values": values,
    }


SHADERS = ("BSDF_PRINCIPLED", "EMISSION", "OUTPUT_MATERIAL")


def feeds(node, depth=0):
    """The shader inputs a node's outputs reach, through other nodes (at most 4 deep)."""
    reached = []
    for output in node.outputs:
        for link in output.links:
            if link.to_node.type in SHADERS or depth >= 4:
                reached.append([link.to_node.type, link.to_socket.name])
            else:
                reached.extend(feeds(link.to_node, depth + 1))
    return reached


def describe_material(material):
    textures = []
    nodes = material.node_tree.nodes if material.node_tree else []
    for node in sorted(nodes, key=lambda n: n.name):
        if node.type != "TEX_IMAGE":
            continue
        uv = [l.from_node for l in node.inputs["Vector"].links]
        textures.append(
            {
                "image": node.image.name if node.image else None,
                "uv_map": uv[0].uv_map if uv and uv[0].type == "UVMAP" else None,
                "interpolation": node.interpolation,
                "extension": node.extension,
                "feeds": feeds(node),
            }
        )
    return {"name": material.name, "textures": textures}


def main(argv):
    if not argv or argv[0].startswith("-"):
        print(__doc__, file=sys.stderr)
        return 2
    path = os.path.abspath(argv[0])
    limit = int(argv[argv.index("--max-values") + 1]) if "--max-values" in argv else 100000

    # Blender writes its log to fd 1; keep stdout for the JSON alone.
    stdout_fd = os.dup(1)
    os.dup2(2, 1)
    try:
        import bpy

        bpy.ops.wm.read_factory_settings(use_empty=True)
        result = bpy.ops.import_scene.gltf(filepath=path)
        if "FINISHED" not in result:
            raise RuntimeError(f"import returned {result}")
        scene = bpy.context.scene
        report = {
            "blender": bpy.app.version_string,
            "scene": {"name": scene.name, "properties": properties(scene)},
            "objects": [
                {
                    "name": o.name,
                    "type": o.type,
                    "parent": o.parent.name if o.parent else None,
                    "properties": properties(o),
                }
                for o in sorted(bpy.data.objects, key=lambda o: o.name)
            ],
            "meshes": [
                describe_mesh(o, limit)
                for o in sorted(bpy.data.objects, key=lambda o: o.name)
                if o.type == "MESH"
            ],
            "materials": [
                describe_material(m) for m in sorted(bpy.data.materials, key=lambda m: m.name)
            ],
        }
    except Exception as error:  # report any failure as one clear line
        sys.stdout.flush()
        os.dup2(stdout_fd, 1)
        print(f"blender import of {path} failed: {error!r}", file=sys.stderr)
        return 1
    sys.stdout.flush()
    os.dup2(stdout_fd, 1)
    json.dump(report, sys.stdout, indent=1)
    sys.stdout.write("\n")
    sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
