#!/usr/bin/env python3
"""Lightmap error and texel lookup for luxbake bakes with --lightmaps (needs OpenEXR, numpy).

  python3 bench/lightmap_error.py compare REF.gltf TEST.gltf [TEST.gltf ...]
  python3 bench/lightmap_error.py errors REF.gltf TEST.gltf N
  python3 bench/lightmap_error.py holes OUT.gltf [OUT.gltf ...]
  python3 bench/lightmap_error.py locate OUT.gltf ATLAS COL ROW
  python3 bench/lightmap_error.py worst OUT.gltf CHANNEL [N]

compare: each TEST's EXR `illuminance` against REF's, texel by texel over the texels with
footprint > 0 in REF (same layout required: same atlases and sizes). Relative error
|E - E_ref| / E_ref (texels with E_ref = 0 counted apart); the footprint-weighted mean is
sum(fp |E - E_ref|) / sum(fp E_ref). Also the largest |change| of `illuminanceDirect` (expected 0:
direct light is exact at every texel whatever the tolerance) and the worst texel's place. The
stage time and gather count come from the summary written beside each glTF as STEM.summary.json.
errors: the N texels of TEST farthest from REF, each located.
holes: texels with footprint > 0.1 % of a texel and illuminance > 0 that have among their 8
neighbours an empty (illuminance 0) texel, or a padding texel below half or above twice their own
illuminance (bilinear filtering mixes these in: a line along the chart edge), and partial texels
(footprint < 0.99 texel) with illuminanceDirect 0 beside a lit whole texel (the part of the texel
that is really there gets no direct light), each counted by surface (top node).
locate: the surface (node path) and world point (m, glTF +Y up) under a texel centre.
worst: the N texels (default 10) with the largest jump of CHANNEL to a 4-neighbour in the same
chart (both footprints > 0), each located: where to look for seams and lines.
"""
import json
import os
import struct
import sys

import numpy as np
import OpenEXR

COMPONENT = {5120: "b", 5121: "B", 5122: "h", 5123: "H", 5125: "I", 5126: "f"}
COUNT = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def read_exr(path):
    """Channels of one atlas as float64 arrays, row 0 at the top (R, G, B split)."""
    ch = OpenEXR.File(path).channels()
    out = {}
    for name, c in ch.items():
        px = np.asarray(c.pixels, dtype=np.float64)
        if px.ndim == 3:
            for i, n in enumerate(name):
                out[n] = px[:, :, i]
        else:
            out[name] = px
    return out


def load_gltf(path):
    with open(path) as f:
        doc = json.load(f)
    base = os.path.dirname(os.path.abspath(path))
    buffers = []
    for b in doc["buffers"]:
        with open(os.path.join(base, b["uri"]), "rb") as f:
            buffers.append(f.read())
    return doc, buffers


def accessor(doc, buffers, index):
    """An accessor's elements as an (count, n) float64 array (no sparse, no normalised)."""
    a = doc["accessors"][index]
    v = doc["bufferViews"][a["bufferView"]]
    fmt = COMPONENT[a["componentType"]]
    n = COUNT[a["type"]]
    size = struct.calcsize(fmt)
    stride = v.get("byteStride") or size * n
    start = v.get("byteOffset", 0) + a.get("byteOffset", 0)
    raw = np.frombuffer(buffers[v["buffer"]], dtype=np.uint8,
                        count=stride * (a["count"] - 1) + size * n, offset=start)
    rows = np.lib.stride_tricks.as_strided(raw, (a["count"], size * n), (stride, 1))
    return np.frombuffer(rows.copy().tobytes(), dtype="<" + fmt).reshape(a["count"], n).astype(
        np.float64)


def local_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T
    t = node.get("translation", [0, 0, 0])
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    s = node.get("scale", [1, 1, 1])
    r = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    m = np.eye(4)
    m[:3, :3] = r * np.array(s)
    m[:3, 3] = t
    return m


def lightmap_triangles(path):
    """Per atlas: UV triangles (k, 3, 2), world triangles (k, 3, 3) and node paths (k)."""
    doc, buffers = load_gltf(path)
    out = {}

    def visit(i, parent, names):
        node = doc["nodes"][i]
        m = parent @ local_matrix(node)
        names = names + [node.get("name", f"node{i}")]
        if "mesh" in node:
            for p in doc["meshes"][node["mesh"]]["primitives"]:
                mat = doc["materials"][p["material"]] if "material" in p else {}
                lm = mat.get("extensions", {}).get("LUXBAKE_lightmap")
                if lm is None:
                    continue
                uv = accessor(doc, buffers, p["attributes"][f"TEXCOORD_{lm['texCoord']}"])
                pos = accessor(doc, buffers, p["attributes"]["POSITION"])
                pos = (m @ np.c_[pos, np.ones(len(pos))].T).T[:, :3]
                idx = (accessor(doc, buffers, p["indices"]).astype(int).ravel()
                       if "indices" in p else np.arange(len(pos)))
                tri = idx.reshape(-1, 3)
                e = out.setdefault(lm["atlas"], ([], [], []))
                e[0].append(uv[tri])
                e[1].append(pos[tri])
                e[2].extend(["/".join(names)] * len(tri))
        for c in node.get("children", []):
            visit(c, m, names)

    for r in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        visit(r, np.eye(4), [])
    return {a: (np.concatenate(u), np.concatenate(w), n) for a, (u, w, n) in out.items()}


def locate(tris, width, height, col, row):
    """(node path, world point, inside?) at a texel centre: the UV triangle holding it, else
    the nearest one (a padding texel)."""
    uv, world, names = tris
    p = np.array([(col + 0.5) / width, (row + 0.5) / height])
    a, b, c = uv[:, 0], uv[:, 1], uv[:, 2]
    v0, v1, v2 = b - a, c - a, p - a
    d = v0[:, 0] * v1[:, 1] - v1[:, 0] * v0[:, 1]
    ok = np.abs(d) > 1e-14  # zero-area UV triangles hold no texel
    d = np.where(ok, d, 1.0)
    l1 = (v2[:, 0] * v1[:, 1] - v1[:, 0] * v2[:, 1]) / d
    l2 = (v0[:, 0] * v2[:, 1] - v2[:, 0] * v0[:, 1]) / d
    bary = np.stack([1 - l1 - l2, l1, l2], axis=1)
    outside = np.where(ok, np.maximum(0, -bary).sum(axis=1), np.inf)
    k = int(np.argmin(outside))
    w = np.clip(bary[k], 0, None)
    w /= w.sum()
    return names[k], w @ world[k], outside[k] < 1e-9


def atlases(path):
    """[(atlas index, EXR path, width, height)] of a baked glTF."""
    with open(path) as f:
        doc = json.load(f)
    seen = {}
    for m in doc.get("materials", []):
        lm = m.get("extensions", {}).get("LUXBAKE_lightmap")
        if lm:
            seen[lm["atlas"]] = (lm["atlas"], os.path.join(os.path.dirname(os.path.abspath(path)),
                                                           lm["uri"]), lm["width"], lm["height"])
    return [seen[k] for k in sorted(seen)]


def summary(path):
    s = os.path.splitext(path)[0] + ".summary.json"
    if not os.path.exists(s):
        return None
    with open(s) as f:
        return json.load(f)


def fmt_place(name, point):
    return f"{name} ({point[0]:.3f}, {point[1]:.3f}, {point[2]:.3f})"


def compare(ref_path, tests):
    ref = [(a, read_exr(p), w, h) for a, p, w, h in atlases(ref_path)]
    tris = lightmap_triangles(ref_path)
    rs = summary(ref_path)
    print("| bake | tolerance | gathered texels | lightmap s | p50 | p90 | p99 | max | "
          "fp-weighted mean abs | max abs (lx) | max abs change of direct (lx) | worst texel |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for t in [ref_path] + tests:
        s = summary(t)
        tol = s["settings"]["lightmaps"].get("tolerance") if s else None
        q = s["settings"]["quality"] if s else None
        tol = (f"default ({ {'draft': 0.03, 'default': 0.01, 'high': 0.0}[q]:g})" if q else "?") \
            if tol is None else f"{tol:g}"
        gathered = f"{s['lightmaps']['gatheredTexels']} / {s['lightmaps']['texels']}" if s else "?"
        secs = f"{s['timingsSeconds']['lightmaps']:.2f}" if s else "?"
        got = [(a, read_exr(p), w, h) for a, p, w, h in atlases(t)]
        if [(a, w, h) for a, _, w, h in got] != [(a, w, h) for a, _, w, h in ref]:
            print(f"| {os.path.basename(t)} | {tol} | {gathered} | {secs} | layout differs "
                  f"from the reference | | | | | | | |")
            continue
        rel, num, den, worst, zero_abs, dmax = [], 0.0, 0.0, None, 0.0, 0.0
        for (a, r, w, h), (_, g, _, _) in zip(ref, got):
            fp = r["footprint"]
            m = fp > 0
            e0, e1 = r["illuminance"], g["illuminance"]
            err = np.abs(e1 - e0)
            num += float((fp * err)[m].sum())
            den += float((fp * e0)[m].sum())
            pos = m & (e0 > 0)
            rr = np.zeros_like(e0)
            rr[pos] = err[pos] / e0[pos]
            rel.append(rr[pos])
            zero_abs = max(zero_abs, float(err[m & (e0 <= 0)].max(initial=0.0)))
            dmax = max(dmax, float(np.abs(g["illuminanceDirect"] - r["illuminanceDirect"])[m]
                                   .max(initial=0.0)))
            k = np.unravel_index(np.argmax(np.where(pos, rr, -1)), rr.shape)
            if worst is None or rr[k] > worst[0]:
                worst = (rr[k], a, int(k[1]), int(k[0]), e0[k], e1[k], w, h)
        rel = np.concatenate(rel)
        q = np.percentile(rel, [50, 90, 99]) * 100
        v, a, col, row, e0, e1, w, h = worst
        name, point, _ = locate(tris[a], w, h, col, row)
        maxabs = max(zero_abs, max(float(np.abs(g2["illuminance"] - r2["illuminance"])
                                         [r2["footprint"] > 0].max(initial=0.0))
                                   for (_, r2, _, _), (_, g2, _, _) in zip(ref, got)))
        print(f"| {os.path.basename(t)} | {tol} | {gathered} | {secs} | {q[0]:.3f} % | "
              f"{q[1]:.3f} % | {q[2]:.2f} % | {v * 100:.1f} % | {num / den * 100:.3f} % | "
              f"{maxabs:.1f} | {dmax:.3g} | atlas {a} ({col}, {row}): {e1:.1f} vs {e0:.1f} lx, "
              f"{fmt_place(name, point)} |")
    if rs:
        print(f"\nReference: every texel gathered ({rs['lightmaps']['texels']} texels, "
              f"{rs['lightmaps']['charts']} charts, atlases {rs['lightmaps']['atlases']}).")


def errors(ref_path, test_path, n):
    """The N texels of TEST farthest (relative) from REF's illuminance, each located."""
    tris = lightmap_triangles(ref_path)
    rows = []
    for (a, p0, w, h), (_, p1, _, _) in zip(atlases(ref_path), atlases(test_path)):
        r, g = read_exr(p0), read_exr(p1)
        e0, e1 = r["illuminance"], g["illuminance"]
        rel = np.where((r["footprint"] > 0) & (e0 > 0), np.abs(e1 - e0) / np.maximum(e0, 1e-300),
                       0)
        for k in np.argsort(rel, axis=None)[::-1][:n]:
            row, col = np.unravel_index(k, rel.shape)
            rows.append((rel[row, col], a, col, row, e1[row, col], e0[row, col], w, h))
    rows.sort(key=lambda x: -x[0])
    print(f"| atlas | texel | {os.path.basename(test_path)} (lx) | reference (lx) | error | "
          "surface (node), world point (m, +Y up) |")
    print("| --- | --- | --- | --- | --- | --- |")
    for v, a, col, row, e1, e0, w, h in rows[:n]:
        name, pt, _ = locate(tris[a], w, h, col, row)
        print(f"| {a} | ({col}, {row}) | {e1:.1f} | {e0:.1f} | {(e1 - e0) / e0 * 100:+.1f} % | "
              f"{fmt_place(name, pt)} |")


def holes(paths):
    """Per bake: texels whose bilinear neighbourhood holds an empty texel or padding far from
    their own value, and partial texels with no direct light beside a lit whole texel."""
    print("| bake | texels | lit texels beside an empty (E = 0) texel | where | lit texels beside "
          "padding off by > 2× | where | partial texels | partial, direct 0, beside a lit whole "
          "texel | where |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for path in paths:
        with open(path) as f:
            doc = json.load(f)
        ts = next(m["extensions"]["LUXBAKE_lightmap"]["texelSize"] for m in doc["materials"]
                  if "LUXBAKE_lightmap" in m.get("extensions", {}))
        tris = lightmap_triangles(path)
        n = {"texels": 0, "empty": 0, "off": 0, "part": 0, "hole": 0}
        where = {"empty": {}, "off": {}, "hole": {}}
        for a, p, w, h in atlases(path):
            x = read_exr(p)
            fp, e, ed = x["footprint"], x["illuminance"], x["illuminanceDirect"]
            fp = np.where(fp >= 1e-3 * ts * ts, fp, 0)  # slivers (an edge on a texel border)
            real = fp > 0
            zero = np.pad(e <= 0, 1, constant_values=True)
            pad_e = np.pad(np.where(real, np.nan, e), 1, constant_values=np.nan)
            full = np.pad(np.where(fp >= 0.99 * ts * ts, ed, 0), 1)
            near_zero = np.zeros(fp.shape, bool)
            off = np.zeros(fp.shape, bool)
            lit_full = np.zeros(fp.shape)
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    win = (slice(1 + dy, 1 + dy + h), slice(1 + dx, 1 + dx + w))
                    near_zero |= zero[win]
                    with np.errstate(invalid="ignore"):
                        off |= (pad_e[win] < 0.5 * e) | (pad_e[win] > 2 * e)
                    lit_full = np.maximum(lit_full, full[win])
            part = real & (fp < 0.99 * ts * ts)
            masks = {"empty": real & (e > 0) & near_zero, "off": real & (e > 0) & off,
                     "hole": part & (ed <= 0) & (lit_full > 0)}
            n["texels"] += int(real.sum())
            n["part"] += int(part.sum())
            for k, mask in masks.items():
                n[k] += int(mask.sum())
                for r, c in zip(*np.nonzero(mask)):
                    s = locate(tris[a], w, h, c, r)[0].split("/")[0]
                    where[k][s] = where[k].get(s, 0) + 1

        def top(d):
            return ", ".join(f"{k} {v}" for k, v in sorted(d.items(), key=lambda x: -x[1])[:4])

        print(f"| {os.path.basename(path)} | {n['texels']} | {n['empty']} | {top(where['empty'])} "
              f"| {n['off']} | {top(where['off'])} | {n['part']} | {n['hole']} | "
              f"{top(where['hole'])} |")


def worst(path, channel, n):
    """The largest jumps of CHANNEL between 4-neighbour texels that both have footprint > 0."""
    tris = lightmap_triangles(path)
    rows = []
    for a, p, w, h in atlases(path):
        x = read_exr(p)
        fp, v = x["footprint"], x[channel]
        for axis in (0, 1):
            d = np.abs(np.diff(v, axis=axis))
            both = (fp > 0) & np.roll(fp > 0, -1, axis=axis)
            both = both[:-1, :] if axis == 0 else both[:, :-1]
            base = np.maximum(np.minimum(v[:-1, :], v[1:, :]) if axis == 0 else
                              np.minimum(v[:, :-1], v[:, 1:]), 1e-9)
            jump = np.where(both, d / base, 0)
            for k in np.argsort(jump, axis=None)[::-1][:n]:
                r, c = np.unravel_index(k, jump.shape)
                r2, c2 = (r + 1, c) if axis == 0 else (r, c + 1)
                rows.append((jump[r, c], a, c, r, c2, r2, v[r, c], v[r2, c2], w, h))
    rows.sort(key=lambda x: -x[0])
    print(f"| atlas | texel | neighbour | {channel} | neighbour's | surface (node), world point "
          f"(m, +Y up) |")
    print("| --- | --- | --- | --- | --- | --- |")
    for j, a, c, r, c2, r2, v1, v2, w, h in rows[:n]:
        name, pt, inside = locate(tris[a], w, h, c, r)
        name2, _, _ = locate(tris[a], w, h, c2, r2)
        where = fmt_place(name, pt) + ("" if inside else " (nearest; centre outside)")
        if name2 != name:
            where += f" / neighbour on {name2}"
        print(f"| {a} | ({c}, {r}) | ({c2}, {r2}) | {v1:.1f} | {v2:.1f} | {where} |")


def main():
    if len(sys.argv) >= 4 and sys.argv[1] == "compare":
        compare(sys.argv[2], sys.argv[3:])
    elif len(sys.argv) >= 3 and sys.argv[1] == "holes":
        holes(sys.argv[2:])
    elif len(sys.argv) == 5 and sys.argv[1] == "errors":
        errors(sys.argv[2], sys.argv[3], int(sys.argv[4]))
    elif len(sys.argv) == 6 and sys.argv[1] == "locate":
        path, a, col, row = sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
        info = {k: (w, h) for k, _, w, h in atlases(path)}
        w, h = info[a]
        name, pt, inside = locate(lightmap_triangles(path)[a], w, h, col, row)
        print(fmt_place(name, pt), "" if inside else "(padding: nearest triangle)")
    elif len(sys.argv) in (4, 5) and sys.argv[1] == "worst":
        worst(sys.argv[2], sys.argv[3], int(sys.argv[4]) if len(sys.argv) == 5 else 10)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
