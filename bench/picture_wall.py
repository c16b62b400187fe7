#!/usr/bin/env python3
"""The picture-wall scene: contact geometry on a wall (Python standard library only).

A closed room 4 x 3 x 5 m (x 0..4, y 0..3, z 0..5; glTF axes, +Y up), faces wound to face into
the room, reflectance 0.5; a picture 0.8 m wide x 0.6 m tall (x 1.6..2.4, y 1.2..1.8) of
reflectance 0.3 on the wall z = 0; an isotropic point light of 1000 lm (1000 / 4 pi cd,
KHR_lights_punctual) at (2.0, 1.5, 1.5). Units: m, lm, cd.

Variants (the picture):
  box   a closed thin box, 1 cm deep: its back face lies on the wall (z = 0, facing -z), its front
        face at z = 0.01 faces +z
  quad  a single quad 1 cm proud of the wall (z = 0.01), facing +z
  none  no picture: the reference room

    python3 bench/picture_wall.py OUT_DIR     # writes OUT_DIR/picture-wall-{box,quad,none}.gltf
"""

import base64
import json
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scenes import _box_faces, _normal  # noqa: E402

ROOM = ((0.0, 0.0, 0.0), (4.0, 3.0, 5.0))
WALL_RHO = 0.5
PICTURE_RHO = 0.3
PICTURE = ((1.6, 1.2, 0.0), (2.4, 1.8, 0.01))  # x, y, z extents of the box (quad: front face)
LIGHT_POS = (2.0, 1.5, 1.5)
LIGHT_FLUX = 1000.0  # lm, isotropic
VARIANTS = ("box", "quad", "none")


def picture_faces(variant):
    """The picture's quads (counter-clockwise seen from outside the picture)."""
    if variant == "none":
        return []
    (ax, ay, _), (bx, by, bz) = PICTURE
    front = [(ax, ay, bz), (bx, ay, bz), (bx, by, bz), (ax, by, bz)]  # faces +z
    if variant == "quad":
        return [front]
    # _box_faces winds faces to face into the box: reversed, they face out of it.
    return [face[::-1] for face in _box_faces(*PICTURE)]


def gltf(meshes, lights):
    """glTF JSON text (buffer embedded as a data: URI) of quads and point lights.

    meshes: [(name, reflectance, [quad, ...])], one node and one material each; a quad is four
    (x, y, z) corners, counter-clockwise seen from its front. lights: [(name, (x, y, z), flux_lm)],
    isotropic points of intensity flux / 4 pi cd.
    """
    blob, views, accessors, doc_meshes, materials, nodes = b"", [], [], [], [], []

    def add(data, target, count, kind, ctype, extra=None):
        nonlocal blob
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data),
                      "target": target})
        blob += data + b"\0" * (-len(data) % 4)
        accessors.append({"bufferView": len(views) - 1, "componentType": ctype, "count": count,
                          "type": kind, **(extra or {})})
        return len(accessors) - 1

    for name, rho, quads in meshes:
        positions, normals, indices = [], [], []
        for q in quads:
            base = len(positions)
            positions += q
            normals += [_normal(q)] * 4
            indices += [base, base + 1, base + 2, base, base + 2, base + 3]
        bounds = {"min": [min(p[i] for p in positions) for i in range(3)],
                  "max": [max(p[i] for p in positions) for i in range(3)]}
        pos = add(b"".join(struct.pack("<3f", *p) for p in positions), 34962, len(positions),
                  "VEC3", 5126, bounds)
        nrm = add(b"".join(struct.pack("<3f", *n) for n in normals), 34962, len(normals),
                  "VEC3", 5126)
        idx = add(struct.pack(f"<{len(indices)}H", *indices), 34963, len(indices), "SCALAR",
                  5123)
        materials.append({
            "name": name,
            "pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, 1.0],
                                     "metallicFactor": 0.0, "roughnessFactor": 1.0},
            "extensions": {"LUXBAKE_material": {"reflectance": rho}},
        })
        doc_meshes.append({"name": name, "primitives": [
            {"attributes": {"POSITION": pos, "NORMAL": nrm}, "indices": idx,
             "material": len(materials) - 1}]})
        nodes.append({"name": name, "mesh": len(doc_meshes) - 1})
    for k, (name, position, flux) in enumerate(lights):
        nodes.append({"name": name, "translation": list(position),
                      "extensions": {"KHR_lights_punctual": {"light": k}}})
    doc = {
        "asset": {"version": "2.0", "generator": "luxbake bench/picture_wall.py"},
        "extensionsUsed": ["KHR_lights_punctual", "LUXBAKE_material"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": name, "type": "point", "color": [1, 1, 1],
             "intensity": flux / (4 * math.pi)} for name, _, flux in lights]}},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": doc_meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(blob).decode("ascii")}],
    }
    return json.dumps(doc, indent=1) + "\n"


def picture_wall_gltf(variant):
    """The picture-wall scene of one variant (box, quad or none) as glTF JSON text."""
    meshes = [("room", WALL_RHO, _box_faces(*ROOM))]
    if variant != "none":
        meshes.append(("picture", PICTURE_RHO, picture_faces(variant)))
    return gltf(meshes, [("light", LIGHT_POS, LIGHT_FLUX)])


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "."
    os.makedirs(out, exist_ok=True)
    for v in VARIANTS:
        path = os.path.join(out, f"picture-wall-{v}.gltf")
        with open(path, "w") as f:
            f.write(picture_wall_gltf(v))
        print(path)


if __name__ == "__main__":
    main()
