"""Scenes the harness writes itself (Python standard library only).

CIE 171:2006 test 5.8 as glTF: a 4 m cube (S = 96 m^2) of uniform diffuse reflectance rho,
faces wound to face into the cube, single-sided, with an isotropic point light of 10 000 lm
(KHR_lights_punctual point, I = 10 000 / 4 pi cd) at its centre. The closed form of the
area-weighted mean indirect illuminance (docs/ANALYTIC.md section 3) is rho * PHI / (S * (1 - rho)).
Units: metres, lm, cd; glTF axes, +Y up.
"""

import base64
import json
import math
import struct

CIE_SIZE = 4.0
CIE_FLUX = 10_000.0
CIE_AREA = 6 * CIE_SIZE * CIE_SIZE


def cie_5_8_indirect(rho):
    """Closed-form mean indirect illuminance (lx) of CIE 171 test 5.8."""
    return rho * CIE_FLUX / (CIE_AREA * (1.0 - rho))


def _box_faces(lo, hi):
    """The six faces of an axis-aligned box, counter-clockwise seen from INSIDE
    (the same order and winding as luxbake's src/fixtures.rs box_faces)."""
    (ax, ay, az), (bx, by, bz) = lo, hi
    return [
        [(ax, ay, az), (ax, ay, bz), (bx, ay, bz), (bx, ay, az)],  # floor, +Y
        [(ax, by, az), (bx, by, az), (bx, by, bz), (ax, by, bz)],  # ceiling, -Y
        [(ax, ay, az), (ax, by, az), (ax, by, bz), (ax, ay, bz)],  # x = lo, +X
        [(bx, ay, az), (bx, ay, bz), (bx, by, bz), (bx, by, az)],  # x = hi, -X
        [(ax, ay, az), (bx, ay, az), (bx, by, az), (ax, by, az)],  # z = lo, +Z
        [(ax, ay, bz), (ax, by, bz), (bx, by, bz), (bx, ay, bz)],  # z = hi, -Z
    ]


def _normal(c):
    u = [c[1][i] - c[0][i] for i in range(3)]
    v = [c[2][i] - c[0][i] for i in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    length = math.sqrt(sum(x * x for x in n))
    return [x / length for x in n]


def cie_5_8_gltf(rho):
    """The glTF JSON text (buffer embedded as a data: URI) of CIE 171 test 5.8 at reflectance rho."""
    positions, normals, indices = [], [], []
    for face in _box_faces((0.0, 0.0, 0.0), (CIE_SIZE,) * 3):
        n = _normal(face)
        base = len(positions)
        positions += face
        normals += [n] * 4
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    pos_bytes = b"".join(struct.pack("<3f", *p) for p in positions)
    nrm_bytes = b"".join(struct.pack("<3f", *n) for n in normals)
    idx_bytes = struct.pack(f"<{len(indices)}H", *indices)
    idx_bytes += b"\0" * (-len(idx_bytes) % 4)
    blob = pos_bytes + nrm_bytes + idx_bytes
    c = CIE_SIZE / 2
    doc = {
        "asset": {"version": "2.0", "generator": "luxbake bench/scenes.py"},
        "extensionsUsed": ["KHR_lights_punctual", "LUXBAKE_material"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "source", "type": "point", "color": [1, 1, 1],
             "intensity": CIE_FLUX / (4 * math.pi)}]}},
        "scene": 0,
        "scenes": [{"name": f"cie171_5.8_rho{rho}", "nodes": [0, 1]}],
        "nodes": [
            {"name": "room", "mesh": 0},
            {"name": "source", "translation": [c, c, c],
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
        ],
        "meshes": [{"name": "room", "primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "materials": [{
            "name": "walls",
            "pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, 1.0],
                                     "metallicFactor": 0.0, "roughnessFactor": 1.0},
            "extensions": {"LUXBAKE_material": {"reflectance": rho}},
        }],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3",
             "min": [0.0] * 3, "max": [CIE_SIZE] * 3},
            {"bufferView": 1, "componentType": 5126, "count": len(normals), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos_bytes), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos_bytes), "byteLength": len(nrm_bytes),
             "target": 34962},
            {"buffer": 0, "byteOffset": len(pos_bytes) + len(nrm_bytes),
             "byteLength": len(indices) * 2, "target": 34963},
        ],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(blob).decode("ascii")}],
    }
    return json.dumps(doc, indent=1) + "\n"
