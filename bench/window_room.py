#!/usr/bin/env python3
"""Write a furnished room lit by a window panel as an input glTF: python3 bench/window_room.py OUT_DIR.

A 4 x 3 x 5 m room (+Y up, metres; inward faces, reflectance 0.6), the shelf_on_wall plank
(1.4 m x 3 cm x 0.3 m against the wall z = 0, open at the back), a desk (1.2 x 0.75 x 0.7 m
box) and a window panel 1.6 x 1.2 m, 2 mm proud of the wall x = 0, facing +x, emitting
3 000 cd/m2 (LUXBAKE_material luminance) with reflectance 0.1: issue 57's "light sources look
dark" scene. Writes OUT_DIR/window_room.gltf and .bin."""
import json, os, struct, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from quad_room import box_quads

out = sys.argv[1]
groups = {"walls": [], "window": []}
box_quads(groups["walls"], (0, 0, 0), (4, 3, 5), True)
box_quads(groups["walls"], (1.3, 1.5, 0), (2.7, 1.53, 0.3), False, skip=(4,))
box_quads(groups["walls"], (1.4, 0, 2.6), (2.6, 0.75, 3.3), False, skip=(2,))
# The window: a box 2 mm thick on the wall x = 0; its +x face (index 1) emits.
box_quads(groups["window"], (0, 0.9, 1.7), (0.002, 2.1, 3.3), False, skip=(0,))
materials = [
    {"name": "walls", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.6, 1], "metallicFactor": 0},
     "extensions": {"LUXBAKE_material": {"reflectance": 0.6}}},
    {"name": "window", "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.1, 0.1, 1], "metallicFactor": 0},
     "extensions": {"LUXBAKE_material": {"reflectance": 0.1, "emission": {"luminance": 3000}}}},
]
buf = b""; views = []; accessors = []; meshes = []; nodes = []
for m, name in enumerate(groups):
    pos, idx = [], []
    for q in groups[name]:
        b = len(pos); pos += q; idx += [b, b + 1, b + 2, b, b + 2, b + 3]
    bp = b"".join(struct.pack("<3f", *p) for p in pos)
    bi = b"".join(struct.pack("<I", i) for i in idx)
    views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(bp), "target": 34962}); buf += bp
    views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(bi), "target": 34963}); buf += bi
    mn = [min(p[i] for p in pos) for i in range(3)]; mx = [max(p[i] for p in pos) for i in range(3)]
    accessors.append({"bufferView": len(views) - 2, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": mn, "max": mx})
    accessors.append({"bufferView": len(views) - 1, "componentType": 5125, "count": len(idx), "type": "SCALAR"})
    meshes.append({"name": name, "primitives": [{"attributes": {"POSITION": len(accessors) - 2}, "indices": len(accessors) - 1, "material": m}]})
    nodes.append({"name": name, "mesh": m})
nodes.append({"name": "camera_room", "camera": 0, "translation": [3.7, 1.7, 4.7],
              "rotation": [-0.048939, 0.36142, 0.019, 0.930924]})
doc = {"asset": {"version": "2.0", "generator": "luxbake bench window_room"},
       "extensionsUsed": ["LUXBAKE_material"], "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}],
       "nodes": nodes, "meshes": meshes, "materials": materials,
       "cameras": [{"type": "perspective", "perspective": {"yfov": 1.0, "znear": 0.05, "aspectRatio": 1.5}}],
       "buffers": [{"byteLength": len(buf), "uri": "window_room.bin"}], "bufferViews": views, "accessors": accessors}
open(os.path.join(out, "window_room.bin"), "wb").write(buf)
json.dump(doc, open(os.path.join(out, "window_room.gltf"), "w"), indent=1)
