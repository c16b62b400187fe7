"""Scenes the harness writes itself (Python standard library only).

CIE 171:2006 test 5.8 as glTF: a 4 m cube (S = 96 m^2) of uniform diffuse reflectance rho,
faces wound to face into the cube, single-sided, with an isotropic point light of 10 000 lm
(KHR_lights_punctual point, I = 10 000 / 4 pi cd) at its centre. The closed form of the
area-weighted mean indirect illuminance (docs/ANALYTIC.md section 3) is rho * PHI / (S * (1 - rho)).
Units: metres, lm, cd; glTF axes, +Y up.

`office-panels`: the seed office modelled as the seed's HELIOS run modelled it (docs: bench/README):
samples/office's room shell and picture (no desks), its six fluorescents replaced by Lambertian
panels (LUXBAKE_material emission) just below the ceiling.
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


def _quads_primitive_bytes(quads):
    """(positions, normals, indices) bytes of quads (4 corners each, counter-clockwise seen
    from the front), two triangles a quad, flat normals."""
    positions, normals, indices = [], [], []
    for q in quads:
        n = _normal(q)
        base = len(positions)
        positions += q
        normals += [n] * 4
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return positions, normals, indices


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


# ---------------------------------------------------------------- office-panels

PANEL_FLUX = 5200.0          # lm per panel (the seed's 58 W T26 lamp)
PANEL_SIZE = (0.2, 1.2)      # m: short side, long side (the long side as the office's luminaires)


def office_panels_gltf(office_path, gap=0.01, picture=True):
    """The glTF JSON text of `office-panels`, and a description of what it holds.

    From samples/office (office_path): the room box (floor and ceiling bounds), the reflectances
    of floor, ceiling, walls and back wall (and picture), the picture quad, and the six ceiling
    luminaires' centres (nodes luminaire_1..6, translation = ceiling mounting point) and the
    direction of their long side (the longer horizontal extent of their mesh). Each luminaire
    becomes a single-sided 0.2 x 1.2 m quad facing down (-Y), `gap` m below the ceiling, black
    (reflectance 0: RADIANCE's `light` reflects nothing either), emitting PANEL_FLUX lm
    (LUXBAKE_material emission luminousFlux: one material for the six panels, 6 x 5200 lm shared
    by area, i.e. 5200 lm each). Desks, luminaire boxes and the spotlight are left out.
    +Y up; room x 0..5 (width), y 0..3.2, z 0..8 (length)."""
    import radiance  # the bench's glTF reader
    g = radiance.Gltf(office_path)
    doc = g.doc
    mats = {m["name"]: m for m in doc["materials"]}
    world_quads = {}
    lum_centres, lum_extent = [], None
    for _, node, world in g.walk():
        name = node.get("name", "")
        if "mesh" not in node:
            continue
        mesh = doc["meshes"][node["mesh"]]
        if mesh["name"] == "luminaire":
            lum_centres.append([world[i][3] for i in range(3)])
            pos = [radiance._apply(world, p) for prim in mesh["primitives"]
                   for p in g.accessor(prim["attributes"]["POSITION"])]
            lum_extent = [max(p[i] for p in pos) - min(p[i] for p in pos) for i in range(3)]
            continue
        if name not in ("floor", "ceiling", "wall_left", "wall_right", "wall_front",
                        "wall_back", "picture"):
            continue
        (prim,) = mesh["primitives"]
        pos = [radiance._apply(world, p) for p in g.accessor(prim["attributes"]["POSITION"])]
        ind = g.accessor(prim["indices"])
        if len(pos) != 4 or ind != [0, 1, 2, 0, 2, 3]:
            raise SystemExit(f"scenes: office node {name} is not one quad as expected")
        world_quads[name] = (pos, doc["materials"][prim["material"]]["name"])
    if len(lum_centres) != 6 or lum_extent is None:
        raise SystemExit(f"scenes: expected six luminaires in {office_path}")
    ceiling_y = world_quads["ceiling"][0][0][1]
    long_axis = 0 if lum_extent[0] > lum_extent[2] else 2  # world x or z
    half = [PANEL_SIZE[0] / 2, PANEL_SIZE[1] / 2]
    hx, hz = (half[1], half[0]) if long_axis == 0 else (half[0], half[1])
    y = ceiling_y - gap
    panels = []
    for (cx, _, cz) in sorted(lum_centres, key=lambda c: (c[0], c[2])):
        # counter-clockwise seen from below: front face and normal -Y
        panels.append([(cx - hx, y, cz - hz), (cx + hx, y, cz - hz), (cx + hx, y, cz + hz),
                       (cx - hx, y, cz + hz)])
    surfaces = [(n, q, m) for n, (q, m) in world_quads.items() if picture or n != "picture"]
    surfaces += [(f"panel_{k + 1}", q, "panel") for k, q in enumerate(panels)]
    used = []
    for _, _, m in surfaces:
        if m not in used:
            used.append(m)

    def material(name):
        if name == "panel":
            return {"name": "panel",
                    "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0],
                                             "metallicFactor": 0.0, "roughnessFactor": 1.0},
                    "extensions": {"LUXBAKE_material": {
                        "reflectance": 0.0,
                        "emission": {"luminousFlux": PANEL_FLUX * len(panels)}}}}
        rho = mats[name]["extensions"]["LUXBAKE_material"]["reflectance"]
        return {"name": name,
                "pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, 1.0],
                                         "metallicFactor": 0.0, "roughnessFactor": 1.0},
                "extensions": {"LUXBAKE_material": {"reflectance": rho}}}

    blob = b""
    views, accessors, meshes, nodes = [], [], [], []
    for name, quad, mat in surfaces:
        positions, normals, indices = _quads_primitive_bytes([quad])
        first = len(accessors)
        for data, target in ((b"".join(struct.pack("<3f", *p) for p in positions), 34962),
                             (b"".join(struct.pack("<3f", *n) for n in normals), 34962),
                             (struct.pack(f"<{len(indices)}H", *indices), 34963)):
            views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data),
                          "target": target})
            blob += data + b"\0" * (-len(data) % 4)
        accessors += [
            {"bufferView": first, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [min(p[i] for p in positions) for i in range(3)],
             "max": [max(p[i] for p in positions) for i in range(3)]},
            {"bufferView": first + 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": first + 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]
        meshes.append({"name": name, "primitives": [
            {"attributes": {"POSITION": first, "NORMAL": first + 1}, "indices": first + 2,
             "material": used.index(mat)}]})
        nodes.append({"name": name, "mesh": len(meshes) - 1})
    gltf = {
        "asset": {"version": "2.0", "generator": "luxbake bench/scenes.py"},
        "extensionsUsed": ["LUXBAKE_material"],
        "scene": 0,
        "scenes": [{"name": "office-panels", "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": [material(m) for m in used],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(blob).decode("ascii")}],
    }
    info = {"gapMetres": gap, "picture": picture, "panelFluxLm": PANEL_FLUX,
            "panelSize": list(PANEL_SIZE), "panelLongSide": "xz"[long_axis // 2],
            "panelCentres": [[round(v, 6) for v in ((p[0][0] + p[2][0]) / 2, y,
                                                    (p[0][2] + p[2][2]) / 2)] for p in panels],
            "reflectances": {m: material(m)["extensions"]["LUXBAKE_material"]["reflectance"]
                             for m in used}}
    return json.dumps(gltf, indent=1) + "\n", info
