#!/usr/bin/env python3
"""Write office.gltf + office.bin and office-ldt.gltf + office-ldt.bin: the sample room of
the seed paper "Three-dimensional Illuminance: a tool for lighting design?" (see README.md).

The luminaires' photometry is embedded from profiles/ (written by profiles/make_profiles.py):
  office.gltf      fluorescents: EXT_lights_ies with miral_58w.ies (+ LUXBAKE_luminaire opening)
                   spotlight:    LUXBAKE_luminaire with cns70_50w.ldt
  office-ldt.gltf  every luminaire: LUXBAKE_luminaire with the .ldt profiles
                   (miral_58w.ldt = profile 0, cns70_50w.ldt = profile 1)
Both files hold the same scene and the same candela values.

Python 3 standard library only; the output is byte-for-byte deterministic.
Run from anywhere:  python3 samples/office/make_office.py

Units are SI (metres, lm, cd, cd/m^2); glTF axes: right-handed, +Y up.
The room spans x 0..5 m (width), y 0..3.2 m (height), z 0..8 m (length).
"""

import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
PROFILE_DIR = os.path.join(HERE, "profiles")
VARIANTS = {            # variant -> (glTF name, bin name)
    "ies": ("office.gltf", "office.bin"),
    "ldt": ("office-ldt.gltf", "office-ldt.bin"),
}
MIME = {"ies": "application/x-ies-lm-63", "ldt": "application/x-eulumdat"}
MIRAL = ("miral_58w", "Miral 1/58W louvred")
CNS70 = ("cns70_50w", "CNS70 1/50W")

# ---------------------------------------------------------------- room data
ROOM_W, ROOM_H, ROOM_L = 5.0, 3.2, 8.0      # x, y, z extents (m)
WORKING_PLANE = 0.80                          # desk top height (m)

# desks: top 1.5 m (x) x 1.0 m (z), 0.03 m thick, tops at 0.80 m
DESK_TOP_X, DESK_TOP_Z, DESK_TOP_T = 1.5, 1.0, 0.03
LEG_X, LEG_Y, LEG_Z = 0.04, WORKING_PLANE - DESK_TOP_T, 0.04   # 0.04 x 0.77 x 0.04
LEG_INSET = 0.05          # leg centre 0.05 m in from each edge of the top
DESKS = [                 # (name, reflectance, centre x, centre z)
    ("desk_dark", 0.2, 1.5, 3.0),
    ("desk_light", 0.6, 3.5, 5.0),
]

# picture on the back short wall (z = 8), facing -z
PIC_SIZE = 0.5
PIC_CENTRE = (2.5, 1.6, ROOM_L - 0.005)

# luminaires: surface mounted, 1.5 m (z) x 0.2 m (x) x 0.08 m (y)
LUM_X, LUM_Y, LUM_Z = 0.2, 0.08, 1.5
LUM_ROWS_X = (1.25, 3.75)
LUM_ZS = (4.0 / 3.0, 4.0, 20.0 / 3.0)
LIGHT_DROP = 0.001                 # light node 1 mm below the diffuser centre
MAINTENANCE_FACTOR = 1.0
# Power of one luminaire (W) for the report's schedule (node extras.power_W): the lamp wattages
# the paper names (one 58 W T26 lamp; a 50 W low-voltage lamp), ballast and transformer losses
# not included.
LUM_POWER_W = 58.0
SPOT_POWER_W = 50.0
# luminaire light node: local -Z (nadir) -> world -Y, local +X (C0) -> world +Z (length)
LIGHT_ROTATION = [-0.5, -0.5, -0.5, 0.5]

# spotlight aimed at the picture centre on the wall plane; local +X stays horizontal
SPOT_POS = (2.5, 3.1, 6.0)
SPOT_TARGET = (2.5, 1.6, ROOM_L)

# The seed's three viewpoints (its Appendix C, HELIOS synthetic cameras; see README "Cameras").
# Seed axes: Z up, room X 0..5, Y 0..8 (front wall Y = 0, back wall Y = 8), Z 0..3.2.
# (name, view distance, front plane, X size, Y size, eye, focus) in seed coordinates, then our
# znear: the front plane where it clips nothing in the room at any aspect up to 2:1, else
# 0.01 m (side: -1.99 is behind the eye) or 0.1 m (interior: 1.7 m would clip the left wall
# at the image's left edge from an aspect of about 1.7, e.g. 1280 x 720). Tilt 0; the window
# scale (1.1 / 1.9 / 1.1) is not used (see README).
SEED_CAMERAS = [
    ("camera_front", 3.5, 7.25, 820, 530, (2.5, -10.0, 1.6), (2.5, 0.1, 1.6), 7.25),
    ("camera_side", 2.0, -1.99, 800, 380, (14.0, 4.0, 1.6), (2.5, 4.0, 1.6), 0.01),
    ("camera_interior", 1.2, 1.7, 900, 600, (0.6, 0.1, 1.6), (5.0, 8.0, 1.6), 0.1),
]

# --------------------------------------------------------------- vector math


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def add(*vs):
    return tuple(sum(c) for c in zip(*vs))


def scale(a, s):
    return tuple(x * s for x in a)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def norm(a):
    n = math.sqrt(dot(a, a))
    return tuple(x / n for x in a)


def r6(x):
    """Round to 1 um / 1e-6 so float noise never reaches the file; -0 -> 0."""
    v = round(x, 6)
    return 0.0 if v == 0 else v


# ------------------------------------------------------------- geometry kit
# A "face" is (corners[4], normal). Corners go counter-clockwise seen from
# the side the normal points to (glTF front face), triangles (0,1,2),(0,2,3).


def quad(p, u, v, expect_normal):
    """Rectangle p, p+u, p+u+v, p+v; its normal u x v must be expect_normal."""
    n = norm(cross(u, v))
    assert all(abs(a - b) < 1e-12 for a, b in zip(n, expect_normal)), (n, expect_normal)
    return ([p, add(p, u), add(p, u, v), add(p, v)], expect_normal)


def box_faces(centre, size):
    """Closed box, outward normals, flat shaded. Returns {'+x': face, ...}."""
    half = [s / 2.0 for s in size]
    faces = {}
    for a in range(3):
        for sgn in (1, -1):
            b, c = (a + 1) % 3, (a + 2) % 3
            if sgn < 0:
                b, c = c, b          # swap so that e_b x e_c = -e_a
            n = [0.0, 0.0, 0.0]
            n[a] = float(sgn)
            p = list(centre)
            p[a] += sgn * half[a]
            p[b] -= half[b]
            p[c] -= half[c]
            u = [0.0, 0.0, 0.0]
            u[b] = size[b]
            v = [0.0, 0.0, 0.0]
            v[c] = size[c]
            key = ("+" if sgn > 0 else "-") + "xyz"[a]
            faces[key] = quad(tuple(p), tuple(u), tuple(v), tuple(n))
    return faces


def face_area(face):
    c, _ = face
    return math.sqrt(dot(*(2 * [cross(sub(c[1], c[0]), sub(c[3], c[0]))])))


# ----------------------------------------------------------- buffer builder


class Builder:
    def __init__(self):
        self.bin = bytearray()
        self.buffer_views = []
        self.accessors = []

    def _view(self, data, target):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.buffer_views.append({"buffer": 0, "byteOffset": len(self.bin),
                                  "byteLength": len(data), "target": target})
        self.bin += data
        return len(self.buffer_views) - 1

    def add_blob(self, data):
        """A bufferView holding a whole file (no target), 4-byte aligned like the rest."""
        while len(self.bin) % 4:
            self.bin.append(0)
        self.buffer_views.append({"buffer": 0, "byteOffset": len(self.bin),
                                  "byteLength": len(data)})
        self.bin += data
        return len(self.buffer_views) - 1

    def add_faces(self, faces):
        """POSITION, NORMAL and uint16 indices for a list of faces.
        Returns the attributes dict and the indices accessor index."""
        pos, nrm, idx = [], [], []
        for corners, n in faces:
            base = len(pos)
            for c in corners:
                pos.append(tuple(r6(x) for x in c))
                nrm.append(n)
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
        fpos = b"".join(struct.pack("<3f", *p) for p in pos)
        fnrm = b"".join(struct.pack("<3f", *n) for n in nrm)
        fidx = struct.pack("<%dH" % len(idx), *idx)
        # min/max must be those of the float32 values actually stored
        f32 = [struct.unpack("<3f", struct.pack("<3f", *p)) for p in pos]
        a_pos = self._accessor(self._view(fpos, 34962), 5126, len(pos), "VEC3",
                               [min(p[i] for p in f32) for i in range(3)],
                               [max(p[i] for p in f32) for i in range(3)])
        a_nrm = self._accessor(self._view(fnrm, 34962), 5126, len(nrm), "VEC3")
        a_idx = self._accessor(self._view(fidx, 34963), 5123, len(idx), "SCALAR")
        return {"POSITION": a_pos, "NORMAL": a_nrm}, a_idx

    def _accessor(self, view, ctype, count, typ, mn=None, mx=None):
        acc = {"bufferView": view, "componentType": ctype, "count": count, "type": typ}
        if mn is not None:
            acc["min"] = mn
            acc["max"] = mx
        self.accessors.append(acc)
        return len(self.accessors) - 1


# --------------------------------------------------------------- photometry


def read_profile(key, fmt):
    with open(os.path.join(PROFILE_DIR, "%s.%s" % (key, fmt)), "rb") as f:
        return f.read()


def ies_nadir_cd(data):
    """Candela at (C, gamma) = (0, 0) of one of our LM-63 files (first value after the
    angle lists, times the multiplier; vertical angles start at 0)."""
    lines = data.decode("ascii").split("\r\n")
    i = next(k for k, ln in enumerate(lines) if ln.startswith("TILT="))
    nums = " ".join(lines[i + 1:]).split()
    nv, nh = int(nums[3]), int(nums[4])
    assert float(nums[13]) == 0.0
    return float(nums[2]) * float(nums[13 + nv + nh])


def ies_axial_cd(data, gamma_deg):
    """Candela of an axially symmetric LM-63 file at gamma, linear in gamma."""
    lines = data.decode("ascii").split("\r\n")
    i = next(k for k, ln in enumerate(lines) if ln.startswith("TILT="))
    nums = " ".join(lines[i + 1:]).split()
    nv, nh = int(nums[3]), int(nums[4])
    assert nh == 1
    g = [float(x) for x in nums[13:13 + nv]]
    v = [float(nums[2]) * float(x) for x in nums[14 + nv:14 + 2 * nv]]
    for k in range(nv - 1):
        if g[k] <= gamma_deg <= g[k + 1]:
            t = (gamma_deg - g[k]) / (g[k + 1] - g[k])
            return v[k] + t * (v[k + 1] - v[k])
    return 0.0


def look_rotation_minus_z(direction):
    """Unit quaternion [x,y,z,w] turning local -Z onto `direction`
    (shortest arc from (0,0,-1))."""
    d = norm(direction)
    f = (0.0, 0.0, -1.0)
    axis = cross(f, d)
    c = dot(f, d)
    s = math.sqrt(dot(axis, axis))
    if s < 1e-12:
        raise ValueError("direction parallel to -Z: pick an axis by hand")
    axis = scale(axis, 1.0 / s)
    ang = math.atan2(s, c)
    h = math.sin(ang / 2.0)
    return [axis[0] * h, axis[1] * h, axis[2] * h, math.cos(ang / 2.0)]


def seed_to_gltf(p):
    """Seed point (X, Y, Z), Z up -> glTF (x, y, z), +Y up: x = 5 - X, y = Z, z = Y.
    A proper rotation (180 deg about (0, 1, 1)/sqrt 2, det +1) plus a shift of 5 m in x: keeps
    handedness, the front wall at z = 0 and the back wall at z = 8."""
    return (ROOM_W - p[0], p[2], p[1])


def quat_from_basis(x, y, z):
    """Unit quaternion [x,y,z,w] of the rotation whose matrix has columns x, y, z."""
    m = [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]]
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = 2.0 * math.sqrt(1.0 + tr)
        q = [(m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, s / 4]
    elif m[0][0] >= m[1][1] and m[0][0] >= m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2])
        q = [s / 4, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s]
    elif m[1][1] >= m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2])
        q = [(m[0][1] + m[1][0]) / s, s / 4, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1])
        q = [(m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, s / 4, (m[1][0] - m[0][1]) / s]
    if q[3] < 0:
        q = [-c for c in q]
    return q


def look_at_rotation(eye, target, up=(0.0, 1.0, 0.0)):
    """Camera node rotation: local -Z toward target, local +Y toward `up` (+X right)."""
    f = norm(sub(target, eye))
    right = norm(cross(f, up))
    return quat_from_basis(right, cross(right, f), scale(f, -1.0))


def seed_camera(vd, xs, ys, znear):
    """glTF perspective camera of a HELIOS camera. Assumed HELIOS window: +-1 on the view
    plane in the image's larger direction, so tan(half fov) = 1 / view distance there."""
    aspect = xs / ys
    tan_half_x = 1.0 / vd if xs >= ys else aspect / vd
    yfov = 2.0 * math.atan(tan_half_x / aspect)
    return {"aspectRatio": r6(aspect), "yfov": r6(yfov), "znear": znear}


def rotate(q, v):
    x, y, z, w = q
    u = (x, y, z)
    t = scale(cross(u, v), 2.0)
    return add(v, scale(t, w), cross(u, t))


# ----------------------------------------------------------------- materials


def material(name, refl, emission=None, core_emissive_strength=None):
    m = {"name": name,
         "pbrMetallicRoughness": {"baseColorFactor": [refl, refl, refl, 1.0],
                                  "metallicFactor": 0.0, "roughnessFactor": 1.0},
         "extensions": {"LUXBAKE_material": {"reflectance": refl}}}
    if emission is not None:
        m["extensions"]["LUXBAKE_material"]["emission"] = emission
        m["emissiveFactor"] = [1.0, 1.0, 1.0]
        m["extensions"]["KHR_materials_emissive_strength"] = {
            "emissiveStrength": core_emissive_strength}
    return m


def build(variant):
    assert variant in VARIANTS
    b = Builder()
    materials, meshes, nodes = [], [], []
    mat_idx = {}

    def add_material(m):
        materials.append(m)
        mat_idx[m["name"]] = len(materials) - 1

    # diffuser: no longer an emitter for luxbake (luminance 0); plain viewers get the
    # opening's mean luminance seen from straight below, I(0, 0) / area, as core emission
    diffuser_area = LUM_X * LUM_Z
    miral_ies = read_profile(MIRAL[0], "ies")
    diffuser_luminance = ies_nadir_cd(miral_ies) / diffuser_area

    add_material(material("floor", 0.3))
    add_material(material("ceiling", 0.7))
    add_material(material("wall", 0.5))        # both long side walls + front wall
    add_material(material("wall_back", 0.6))   # back short wall, z = 8
    add_material(material("desk_dark", 0.2))
    add_material(material("desk_light", 0.6))
    add_material(material("picture", 0.5))
    add_material(material("luminaire_housing", 0.7))
    add_material(material("luminaire_diffuser", 0.5,
                          emission={"luminance": 0},
                          core_emissive_strength=r6(diffuser_luminance)))

    def add_mesh(name, prims):
        """prims: list of (faces, material name)."""
        ps = []
        for faces, mname in prims:
            attrs, ind = b.add_faces(faces)
            ps.append({"attributes": attrs, "indices": ind,
                       "material": mat_idx[mname], "mode": 4})
        meshes.append({"name": name, "primitives": ps})
        return len(meshes) - 1

    def add_node(node):
        nodes.append(node)
        return len(nodes) - 1

    W, H, L = ROOM_W, ROOM_H, ROOM_L
    X, Y, Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
    # ---- room: world coordinates, single-sided, normals into the room
    room = [
        ("floor", "floor", quad((0, 0, 0), (0, 0, L), (W, 0, 0), Y)),
        ("ceiling", "ceiling", quad((0, H, 0), (W, 0, 0), (0, 0, L), scale(Y, -1))),
        ("wall_left", "wall", quad((0, 0, 0), (0, H, 0), (0, 0, L), X)),
        ("wall_right", "wall", quad((W, 0, 0), (0, 0, L), (0, H, 0), scale(X, -1))),
        ("wall_front", "wall", quad((0, 0, 0), (W, 0, 0), (0, H, 0), Z)),
        ("wall_back", "wall_back", quad((0, 0, L), (0, H, 0), (W, 0, 0), scale(Z, -1))),
    ]
    scene_nodes = []
    for name, mname, face in room:
        scene_nodes.append(add_node({"name": name, "mesh": add_mesh(name, [([face], mname)])}))

    # ---- desks: parent node with translation, children top and leg_1..4
    # Top slab geometry, local to the `top` node (centre of the slab).
    top_faces = list(box_faces((0.0, 0.0, 0.0), (DESK_TOP_X, DESK_TOP_T, DESK_TOP_Z)).values())
    leg_faces = list(box_faces((0.0, 0.0, 0.0), (LEG_X, LEG_Y, LEG_Z)).values())
    top_y = WORKING_PLANE - DESK_TOP_T / 2.0          # slab centre 0.785
    leg_y = LEG_Y / 2.0                               # leg centre 0.385
    lx = DESK_TOP_X / 2.0 - LEG_INSET                 # 0.70
    lz = DESK_TOP_Z / 2.0 - LEG_INSET                 # 0.45
    leg_pos = [(-lx, -lz), (lx, -lz), (lx, lz), (-lx, lz)]
    for dname, _refl, cx, cz in DESKS:
        m_top = add_mesh(dname + "_top", [(top_faces, dname)])
        m_leg = add_mesh(dname + "_leg", [(leg_faces, dname)])
        children = [add_node({"name": "top", "mesh": m_top,
                              "translation": [0.0, r6(top_y), 0.0]})]
        for i, (px, pz) in enumerate(leg_pos, 1):
            children.append(add_node({"name": "leg_%d" % i, "mesh": m_leg,
                                      "translation": [r6(px), r6(leg_y), r6(pz)]}))
        scene_nodes.append(add_node({"name": dname, "translation": [cx, 0.0, cz],
                                     "children": children}))

    # ---- picture: single-sided quad facing -z, local to its node
    hp = PIC_SIZE / 2.0
    pic = quad((hp, -hp, 0.0), (-PIC_SIZE, 0.0, 0.0), (0.0, PIC_SIZE, 0.0), scale(Z, -1))
    scene_nodes.append(add_node({"name": "picture",
                                 "mesh": add_mesh("picture", [([pic], "picture")]),
                                 "translation": [r6(c) for c in PIC_CENTRE]}))

    # ---- luminaires: ONE mesh, origin at the centre of the box's top face
    # (the ceiling mounting point); box spans local y -0.08..0.
    lf = box_faces((0.0, -LUM_Y / 2.0, 0.0), (LUM_X, LUM_Y, LUM_Z))
    housing = [lf[k] for k in ("+x", "-x", "+y", "+z", "-z")]
    diffuser = [lf["-y"]]
    assert abs(face_area(lf["-y"]) - diffuser_area) < 1e-12
    m_lum = add_mesh("luminaire", [(housing, "luminaire_housing"),
                                   (diffuser, "luminaire_diffuser")])
    lum_nodes = []
    for x in LUM_ROWS_X:
        for z in LUM_ZS:
            lum_nodes.append(add_node({"name": "luminaire_%d" % (len(lum_nodes) + 1),
                                       "mesh": m_lum, "translation": [x, ROOM_H, r6(z)]}))
            scene_nodes.append(lum_nodes[-1])

    # ---- spotlight (LUXBAKE_luminaire, EULUMDAT profile), -Z aimed at the picture centre
    aim = norm(sub(SPOT_TARGET, SPOT_POS))
    q = look_rotation_minus_z(aim)
    got = rotate(q, (0.0, 0.0, -1.0))
    assert all(abs(a - b_) < 1e-12 for a, b_ in zip(got, aim)), (got, aim)
    spot_x = rotate(q, (1.0, 0.0, 0.0))
    assert abs(spot_x[1]) < 1e-12, spot_x                       # local +X horizontal
    spot_profile = 0 if variant == "ies" else 1
    spot_node = add_node({"name": "spotlight",
                          "translation": list(SPOT_POS),
                          "rotation": [c if abs(c) > 1e-15 else 0.0 for c in q],
                          "extensions": {"LUXBAKE_luminaire": {
                              "profile": spot_profile,
                              "maintenanceFactor": MAINTENANCE_FACTOR}},
                          "extras": {"power_W": SPOT_POWER_W}})
    scene_nodes.append(spot_node)

    # ---- one light node per fluorescent, child of luminaire_N, 1 mm below the diffuser
    ql = LIGHT_ROTATION
    for v, want in (((0.0, 0.0, -1.0), (0.0, -1.0, 0.0)),     # nadir straight down
                    ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),       # C0 along the length (+z)
                    ((0.0, 1.0, 0.0), (1.0, 0.0, 0.0))):      # C90 across (+x)
        got = rotate(ql, v)
        assert all(abs(a - b_) < 1e-12 for a, b_ in zip(got, want)), (v, got, want)
    opening = {"length": LUM_Z, "width": LUM_X, "height": 0.0}
    for i, parent in enumerate(lum_nodes, 1):
        if variant == "ies":
            ext = {"EXT_lights_ies": {"light": 0, "multiplier": 1.0, "color": [1.0, 1.0, 1.0]},
                   "LUXBAKE_luminaire": {"maintenanceFactor": MAINTENANCE_FACTOR,
                                         "opening": dict(opening)}}
        else:
            ext = {"LUXBAKE_luminaire": {"profile": 0, "maintenanceFactor": MAINTENANCE_FACTOR,
                                         "opening": dict(opening)}}
        child = add_node({"name": "luminaire_%d_light" % i,
                          "translation": [0.0, r6(-LUM_Y - LIGHT_DROP), 0.0],
                          "rotation": list(ql),
                          "extensions": ext,
                          "extras": {"power_W": LUM_POWER_W}})
        nodes[parent]["children"] = [child]

    # ---- cameras: the seed's Appendix C viewpoints, root nodes after every other node
    cameras = []
    for cname, vd, _front, xs, ys, eye_s, focus_s, znear in SEED_CAMERAS:
        eye, focus = seed_to_gltf(eye_s), seed_to_gltf(focus_s)
        qc = look_at_rotation(eye, focus)
        got = rotate(qc, (0.0, 0.0, -1.0))
        assert all(abs(a - b_) < 1e-12 for a, b_ in zip(got, norm(sub(focus, eye)))), cname
        assert abs(rotate(qc, (1.0, 0.0, 0.0))[1]) < 1e-12, cname       # no roll (tilt 0)
        assert rotate(qc, (0.0, 1.0, 0.0))[1] > 0, cname                 # image up is +Y
        cameras.append({"name": cname, "type": "perspective",
                        "perspective": seed_camera(vd, xs, ys, znear)})
        scene_nodes.append(add_node({"name": cname, "camera": len(cameras) - 1,
                                     "translation": [r6(c) for c in eye],
                                     "rotation": [r6(c) for c in qc]}))

    # ---- the profiles, embedded after all geometry
    root_ext = {}
    if variant == "ies":
        v_miral = b.add_blob(miral_ies)
        v_cns = b.add_blob(read_profile(CNS70[0], "ldt"))
        root_ext["EXT_lights_ies"] = {"lights": [
            {"bufferView": v_miral, "mimeType": MIME["ies"], "name": MIRAL[1]}]}
        root_ext["LUXBAKE_luminaire"] = {"profiles": [
            {"bufferView": v_cns, "mimeType": MIME["ldt"], "name": CNS70[1]}]}
    else:
        v_miral = b.add_blob(read_profile(MIRAL[0], "ldt"))
        v_cns = b.add_blob(read_profile(CNS70[0], "ldt"))
        root_ext["LUXBAKE_luminaire"] = {"profiles": [
            {"bufferView": v_miral, "mimeType": MIME["ldt"], "name": MIRAL[1]},
            {"bufferView": v_cns, "mimeType": MIME["ldt"], "name": CNS70[1]}]}
    used = sorted(set(root_ext) | {"KHR_materials_emissive_strength", "LUXBAKE_material"})

    # the spot's direct illuminance at the picture centre (a number for tests)
    pic_centre = PIC_CENTRE
    d = sub(pic_centre, SPOT_POS)
    dist = math.sqrt(dot(d, d))
    theta = math.degrees(math.acos(min(1.0, dot(norm(d), aim))))
    cos_inc = dot(scale(d, -1.0 / dist), (0.0, 0.0, -1.0))
    spot_cd = ies_axial_cd(read_profile(CNS70[0], "ies"), theta)
    e_pic = spot_cd * cos_inc / dist ** 2

    while len(b.bin) % 4:
        b.bin.append(0)
    _, bin_name = VARIANTS[variant]
    gltf = {
        "asset": {"version": "2.0", "generator": "luxbake samples/office/make_office.py",
                  "extras": {"units": "SI: m, lm, cd, cd/m^2",
                             "source": "Sample room of 'Three-dimensional Illuminance: "
                                       "a tool for lighting design?' (layout chosen, see README)"}},
        "extensionsUsed": used,
        "extensions": root_ext,
        "scene": 0,
        "scenes": [{"name": "office", "nodes": scene_nodes}],
        "nodes": nodes,
        "cameras": cameras,
        "meshes": meshes,
        "materials": materials,
        "accessors": b.accessors,
        "bufferViews": b.buffer_views,
        "buffers": [{"uri": bin_name, "byteLength": len(b.bin)}],
    }
    info = {"spot_rotation": q, "spot_aim": aim, "diffuser_luminance": diffuser_luminance,
            "pic_theta": theta, "pic_cd": spot_cd, "pic_cos": cos_inc, "pic_dist": dist,
            "pic_E": e_pic}
    return gltf, bytes(b.bin), info


def main():
    for variant, (gltf_name, bin_name) in VARIANTS.items():
        gltf, binary, info = build(variant)
        with open(os.path.join(HERE, bin_name), "wb") as f:
            f.write(binary)
        with open(os.path.join(HERE, gltf_name), "w", encoding="utf-8", newline="\n") as f:
            json.dump(gltf, f, indent=1)
            f.write("\n")
        print("wrote %s (%d nodes, %d meshes, %d materials) and %s (%d bytes)" % (
            gltf_name, len(gltf["nodes"]), len(gltf["meshes"]), len(gltf["materials"]),
            bin_name, len(binary)))
    print("luminaire light rotation [x,y,z,w] = %s" % LIGHT_ROTATION)
    print("spot rotation [x,y,z,w] = %s, aim = %s" % (
        ["%.7f" % (c + 0.0) for c in info["spot_rotation"]], ["%.6f" % c for c in info["spot_aim"]]))
    print("spot at the picture centre: %.4f deg off axis, I = %.2f cd, d = %.5f m, cos = %.5f"
          " -> direct E = %.1f lx" % (info["pic_theta"], info["pic_cd"], info["pic_dist"],
                                      info["pic_cos"], info["pic_E"]))
    print("diffuser core emission (viewers only): %.3f cd/m^2 = I(0,0) / %.2f m^2" % (
        info["diffuser_luminance"], LUM_X * LUM_Z))


if __name__ == "__main__":
    main()
