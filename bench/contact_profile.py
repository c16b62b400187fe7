#!/usr/bin/env python3
"""The wall's illuminance beside the picture of the picture-wall scene (bench/picture_wall.py).

Samples a baked output's per-vertex `_ILLUMINANCE` (lx) on the wall z = 0 (triangles lying in
that plane and facing +z; glTF axes, +Y up, metres) by barycentric interpolation on the output's
triangles, along two lines that end on the picture's outline, every 1 cm:
  left   y = 1.5 (through the picture's centre), x = 1.0 .. 1.6 (the picture's left edge)
  above  x = 2.0 (through the picture's centre), y = 2.4 .. 1.8 (the picture's top edge)
and divides by the same points of a bake of the room without the picture. Python standard
library only.

    python3 bench/contact_profile.py --reference NONE.gltf BAKED.gltf [BAKED.gltf ...]

Prints Markdown tables (per line: the point, then per bake E in lx and E / E_reference) and the
ratio 3 cm outside the picture's outline on each line ((1.57, 1.5) and (2.0, 1.83)).
Reads .gltf with .bin beside it or data: URIs.
"""

import argparse
import base64
import json
import os
import struct

# name: the points (x, y) from far to the outline, and the point 3 cm outside the outline
LINES = {
    "left": ([(round(1.0 + 0.01 * i, 2), 1.5) for i in range(61)], (1.57, 1.5)),
    "above": ([(2.0, round(2.4 - 0.01 * i, 2)) for i in range(61)], (2.0, 1.83)),
}
EPS = 1e-6  # m: plane and edge tolerance
COMPONENTS = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}
FORMATS = {5126: "f", 5125: "I", 5123: "H", 5121: "B"}


def load(path):
    """The glTF JSON and its buffers' bytes."""
    doc = json.load(open(path))
    buffers = []
    for b in doc["buffers"]:
        uri = b["uri"]
        if uri.startswith("data:"):
            buffers.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            buffers.append(open(os.path.join(os.path.dirname(path), uri), "rb").read())
    return doc, buffers


def accessor(doc, buffers, index):
    """An accessor's elements as tuples (tightly packed or strided; no sparse, no normalised)."""
    a = doc["accessors"][index]
    view = doc["bufferViews"][a["bufferView"]]
    n = COMPONENTS[a["type"]]
    fmt = "<" + FORMATS[a["componentType"]] * n
    size = struct.calcsize(fmt)
    stride = view.get("byteStride", size)
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    data = buffers[view["buffer"]]
    return [struct.unpack_from(fmt, data, start + i * stride) for i in range(a["count"])]


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def local_matrix(node):
    """A node's 4x4 row-major local matrix (matrix, or translation x rotation x scale)."""
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    tx, ty, tz = node.get("translation", [0, 0, 0])
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    sx, sy, sz = node.get("scale", [1, 1, 1])
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    return [[r[0][0] * sx, r[0][1] * sy, r[0][2] * sz, tx],
            [r[1][0] * sx, r[1][1] * sy, r[1][2] * sz, ty],
            [r[2][0] * sx, r[2][1] * sy, r[2][2] * sz, tz],
            [0, 0, 0, 1]]


def wall_triangles(path):
    """[(p0, p1, p2, e0, e1, e2)]: world triangles in the plane z = 0 facing +z, with the
    `_ILLUMINANCE` (lx; the luminance Y if stored per channel) of their vertices."""
    doc, buffers = load(path)
    out = []

    def visit(n, parent):
        node = doc["nodes"][n]
        m = mat_mul(parent, local_matrix(node))
        if "mesh" in node:
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                if prim.get("mode", 4) != 4 or "_ILLUMINANCE" not in prim["attributes"]:
                    continue
                pos = accessor(doc, buffers, prim["attributes"]["POSITION"])
                lux = accessor(doc, buffers, prim["attributes"]["_ILLUMINANCE"])
                lux = [e[0] if len(e) == 1 else 0.2126 * e[0] + 0.7152 * e[1] + 0.0722 * e[2]
                       for e in lux]
                world = [tuple(sum(m[r][c] * (p + (1,))[c] for c in range(4)) for r in range(3))
                         for p in pos]
                idx = ([i[0] for i in accessor(doc, buffers, prim["indices"])]
                       if "indices" in prim else list(range(len(pos))))
                for t in range(0, len(idx), 3):
                    a, b, c = (world[i] for i in idx[t:t + 3])
                    if max(abs(a[2]), abs(b[2]), abs(c[2])) > EPS:
                        continue
                    if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) <= 0:
                        continue  # faces -z (e.g. the picture box's back face) or degenerate
                    out.append((a, b, c, *(lux[i] for i in idx[t:t + 3])))
        for child in node.get("children", []):
            visit(child, m)

    identity = [[float(i == j) for j in range(4)] for i in range(4)]
    for n in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        visit(n, identity)
    return out


def sample(triangles, x, y):
    """Barycentric interpolation at (x, y, 0): the mean over the triangles containing the
    point (one inside a triangle, two or more on an edge or a vertex)."""
    values = []
    for a, b, c, ea, eb, ec in triangles:
        d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        u = ((b[0] - x) * (c[1] - y) - (b[1] - y) * (c[0] - x)) / d
        v = ((c[0] - x) * (a[1] - y) - (c[1] - y) * (a[0] - x)) / d
        w = 1.0 - u - v
        if min(u, v, w) >= -1e-7:
            values.append(u * ea + v * eb + w * ec)
    if not values:
        raise SystemExit(f"no wall triangle contains ({x}, {y}, 0)")
    return sum(values) / len(values)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--reference", required=True, help="bake of the room without the picture")
    p.add_argument("bakes", nargs="+", help="bakes with the picture")
    a = p.parse_args()
    ref = wall_triangles(a.reference)
    bakes = [(os.path.basename(path), wall_triangles(path)) for path in a.bakes]
    names = [n for n, _ in bakes]
    summary = []
    for line, (points, at_3cm) in LINES.items():
        e_ref = {q: sample(ref, *q) for q in points}
        e = {n: {q: sample(t, *q) for q in points} for n, t in bakes}
        print(f"Line {line}: wall z = 0, E in lx; reference: {os.path.basename(a.reference)}\n")
        print("| x (m) | y (m) | E reference | "
              + " | ".join(f"E {n} | ratio {n}" for n in names) + " |")
        print("|---" * (3 + 2 * len(names)) + "|")
        for q in points:
            cells = " | ".join(f"{e[n][q]:.3f} | {e[n][q] / e_ref[q]:.4f}" for n in names)
            print(f"| {q[0]:.2f} | {q[1]:.2f} | {e_ref[q]:.3f} | {cells} |")
        print()
        for n in names:
            summary.append(f"{n}: line {line}, 3 cm outside the picture at {at_3cm}: ratio "
                           f"{e[n][at_3cm] / e_ref[at_3cm]:.4f} "
                           f"({e[n][at_3cm]:.3f} / {e_ref[at_3cm]:.3f} lx)")
    print("\n".join(summary))


if __name__ == "__main__":
    main()
