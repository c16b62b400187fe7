#!/usr/bin/env python3
"""Write cornell-box.obj + cornell-box.mtl from the Cornell Program of Computer
Graphics' published Cornell Box geometry (millimetres), converted to metres.

Python 3 standard library only; deterministic output. See README.md.
Run:  python3 samples/cornell-box/make_cornell_box.py
"""

import os
from decimal import Decimal

HERE = os.path.dirname(os.path.abspath(__file__))

# ---- published data, millimetres, as listed by Cornell (quads, in their order)
# Only the ceiling is restructured: the light sits in a hole in it (see below).
FLOOR = [(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2), (549.6, 0.0, 559.2)]
LIGHT = [(343.0, 548.8, 227.0), (343.0, 548.8, 332.0), (213.0, 548.8, 332.0), (213.0, 548.8, 227.0)]
CEILING = [(556.0, 548.8, 0.0), (556.0, 548.8, 559.2), (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)]
BACK_WALL = [(549.6, 0.0, 559.2), (0.0, 0.0, 559.2), (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)]
RIGHT_WALL = [(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0), (0.0, 548.8, 559.2)]  # green
LEFT_WALL = [(552.8, 0.0, 0.0), (549.6, 0.0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)]  # red
SHORT_BLOCK = [
    [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)],
    [(290.0, 0.0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0), (240.0, 0.0, 272.0)],
    [(130.0, 0.0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0), (290.0, 0.0, 114.0)],
    [(82.0, 0.0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0), (130.0, 0.0, 65.0)],
    [(240.0, 0.0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0), (82.0, 0.0, 225.0)],
]
TALL_BLOCK = [
    [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0), (472.0, 330.0, 406.0)],
    [(423.0, 0.0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0), (472.0, 0.0, 406.0)],
    [(472.0, 0.0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0), (314.0, 0.0, 456.0)],
    [(314.0, 0.0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0), (265.0, 0.0, 296.0)],
    [(265.0, 0.0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0), (423.0, 0.0, 247.0)],
]

# ---- materials (RGB reflectances commonly derived from the measured spectra)
WHITE = (0.725, 0.71, 0.68)
RED = (0.63, 0.065, 0.05)
GREEN = (0.14, 0.45, 0.091)
LIGHT_KD = (0.78, 0.78, 0.78)
# Ke: luminance per channel in cd/m^2, warm 17:12:4, scaled so that
# Y = 0.2126 R + 0.7152 G + 0.0722 B is 10 000 cd/m^2 (to 0.1 cd/m^2 rounding).
KE_RATIO = (17.0, 12.0, 4.0)
KE_TARGET_Y = 10000.0


def lum(rgb):
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]


KE = tuple(round(c * KE_TARGET_Y / lum(KE_RATIO), 1) for c in KE_RATIO)


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def newell(poly):
    """Newell normal (area-weighted, not normalised) of a polygon."""
    n = [0.0, 0.0, 0.0]
    for i, p in enumerate(poly):
        q = poly[(i + 1) % len(poly)]
        n[0] += (p[1] - q[1]) * (p[2] + q[2])
        n[1] += (p[2] - q[2]) * (p[0] + q[0])
        n[2] += (p[0] - q[0]) * (p[1] + q[1])
    return tuple(n)


def is_planar(poly, tol_mm=0.01):
    n = newell(poly)
    ln = dot(n, n) ** 0.5
    return all(abs(dot(n, sub(p, poly[0]))) / ln <= tol_mm for p in poly)


def orient(poly, want):
    """Return poly wound counter-clockwise as seen from the side `want` points to
    (i.e. its normal has a positive component along want)."""
    if dot(newell(poly), want) < 0:
        return list(reversed(poly)), True
    return list(poly), False


def ceiling_ring(outer, hole):
    """The ceiling minus the light's hole: 4 trapezoids joining each outer edge to
    the matching hole edge (no T-junctions, both polygons share the same plane)."""
    # outer corners sorted by (x, z): pair each with the nearest hole corner
    def key(p):
        return (p[0] > 278.0, p[2] > 279.6)
    o = {key(p): p for p in outer}
    h = {key(p): p for p in hole}
    order = [(False, False), (True, False), (True, True), (False, True)]  # around +y
    quads = []
    for i in range(4):
        a, b = order[i], order[(i + 1) % 4]
        quads.append([o[a], o[b], h[b], h[a]])
    return quads


def mm_to_m(v):
    """Exact decimal conversion of a millimetre value to metres, as text."""
    d = Decimal(repr(v)) / Decimal(1000)
    s = format(d.normalize(), "f")
    return "0" if s in ("0", "-0") else s


def build():
    parts = []  # (object name, material, [polygons])
    notes = []

    def add(name, mtl, polys, want_fn):
        out = []
        for poly in polys:
            p, flipped = orient(poly, want_fn(poly))
            if flipped:
                notes.append(name)
            out.append(p)
        parts.append((name, mtl, out))

    inward = {
        "floor": (0.0, 1.0, 0.0), "ceiling": (0.0, -1.0, 0.0), "back_wall": (0.0, 0.0, -1.0),
        "left_wall": (-1.0, 0.0, 0.0), "right_wall": (1.0, 0.0, 0.0), "light": (0.0, -1.0, 0.0),
    }
    add("floor", "white", [FLOOR], lambda p: inward["floor"])
    add("ceiling", "white", ceiling_ring(CEILING, LIGHT), lambda p: inward["ceiling"])
    add("back_wall", "white", [BACK_WALL], lambda p: inward["back_wall"])
    add("left_wall", "red", [LEFT_WALL], lambda p: inward["left_wall"])
    add("right_wall", "green", [RIGHT_WALL], lambda p: inward["right_wall"])

    def outward_of(block):
        c = tuple(sum(p[i] for f in block for p in f) / (4 * len(block)) for i in range(3))
        return lambda poly: sub(tuple(sum(p[i] for p in poly) / 4 for i in range(3)), c)
    add("short_block", "white", SHORT_BLOCK, outward_of(SHORT_BLOCK))
    add("tall_block", "white", TALL_BLOCK, outward_of(TALL_BLOCK))
    add("light", "light", [LIGHT], lambda p: inward["light"])
    return parts, notes


def write():
    parts, flipped = build()
    lines = [
        "# Cornell Box (Cornell University Program of Computer Graphics, published measured",
        "# geometry), converted from millimetres to METRES. Y up; open at the front (z = 0,",
        "# towards the camera at z = -0.8). Faces wound counter-clockwise seen from inside the",
        "# box (blocks: from outside the block). Light in a hole of the ceiling, facing -y.",
        "# Generated by make_cornell_box.py; see README.md.",
        "mtllib cornell-box.mtl",
    ]
    vi = 0
    for name, mtl, polys in parts:
        lines.append("o %s" % name)
        verts, faces = [], []
        for poly in polys:
            if is_planar(poly):
                faces.append(list(range(vi + len(verts) + 1, vi + len(verts) + 5)))
            else:  # warped quad (as published): split into two triangles
                b = vi + len(verts) + 1
                faces += [[b, b + 1, b + 2], [b, b + 2, b + 3]]
            verts += poly
        for v in verts:
            lines.append("v %s %s %s" % tuple(mm_to_m(c) for c in v))
        lines.append("usemtl %s" % mtl)
        for f in faces:
            lines.append("f " + " ".join(str(i) for i in f))
        vi += len(verts)
    with open(os.path.join(HERE, "cornell-box.obj"), "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")

    def fmt(rgb):
        return " ".join(repr(c) for c in rgb)
    mtl = [
        "# Cornell Box materials. Kd: linear diffuse reflectance (RGB). Ke: Lambertian",
        "# emitted luminance per channel in cd/m^2 (luxbake's OBJ reading of Ke).",
        "# light Ke luminance Y = 0.2126 R + 0.7152 G + 0.0722 B = %.2f cd/m^2" % lum(KE),
        "",
    ]
    for name, kd in (("white", WHITE), ("red", RED), ("green", GREEN), ("light", LIGHT_KD)):
        mtl += ["newmtl %s" % name, "Ka 0 0 0", "Kd %s" % fmt(kd), "Ks 0 0 0"]
        if name == "light":
            mtl.append("Ke %s" % fmt(KE))
        mtl += ["illum 1", ""]
    with open(os.path.join(HERE, "cornell-box.mtl"), "w", newline="\n") as f:
        f.write("\n".join(mtl))
    print("wrote cornell-box.obj (%d vertices) and cornell-box.mtl" % vi)
    print("reversed from the published order to face into the box:", sorted(set(flipped)))
    print("light Ke = %s, Y = %.3f cd/m^2" % (fmt(KE), lum(KE)))


if __name__ == "__main__":
    write()
