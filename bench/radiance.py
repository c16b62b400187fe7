"""luxbake glTF scene -> RADIANCE scene, and RADIANCE runs (Python standard library only).

What the conversion does (see bench/README.md, "RADIANCE side by side"):
- every mesh primitive (triangles, world coordinates from the node tree, glTF axes kept: RADIANCE
  has no preferred up axis for interior scenes) becomes RADIANCE `polygon`s with a `plastic`
  material whose RGB reflectance is the material's LUXBAKE_material reflectance (specularity 0,
  roughness 0: a pure Lambertian reflector, as luxbake assumes);
- every luminaire node (EXT_lights_ies or LUXBAKE_luminaire) becomes the output of RADIANCE's own
  `ies2rad` for its IES LM-63 profile (`-dm`: dimensions in metres; `-t default`: white lamp, no
  lamp-table depreciation; `-m`: the node's multiplier x maintenance factor x Y(colour)), moved
  into place with RADIANCE's `xform`. The profile frame is the same in both tools: nadir along
  local -Z, C = 0 along local +X, C = 90 along local +Y (source.cal's src_phi; luxbake's
  EXT_lights_ies convention), so the node's world rotation is used as is;
- ies2rad's `light` is turned into an `illum` with no alternate material: the same emitter for
  shadow rays, invisible to other rays, so indirect rays reach the luminaire's diffuser face 1 mm
  behind it (a reflector of 0.5 in the glTF) exactly as luxbake's patches do;
- an emitting material (LUXBAKE_material emission: luminance, or luminousFlux shared by area)
  becomes a `light` of radiance L / 179 (front side only, black from behind, no reflection: a
  single-sided black Lambertian emitter), each of its quads one polygon (RADIANCE samples long
  thin triangular sources poorly); emitters it cannot express are refused;
- a EULUMDAT profile has no RADIANCE converter: the caller maps it to the IES file that encodes
  the same candela values (samples/office/profiles/README.md).

Units: ies2rad divides candela by 179 lm/W (RADIANCE's WHTEFFICACY), so RADIANCE radiance is in
W/(sr m^2) and `rtrace -I` returns irradiance in W/m^2; illuminance E = 179 x (0.265 R + 0.670 G
+ 0.065 B) lx (RADIANCE's luminance weights; the office is grey, so R = G = B).
"""

import base64
import json
import math
import os
import struct
import subprocess

EFFICACY = 179.0  # lm/W, RADIANCE's WHTEFFICACY


RADIANCE_WEIGHTS = (0.265, 0.670, 0.065)
# luxbake's luminance weights (Rec. 709 Y): RGB results of the same transport, weighed as luxbake
# weighs its own, compare colour-neutrally (surface_accuracy.py).
REC709_WEIGHTS = (0.2126, 0.7152, 0.0722)


def illuminance(rgb, weights=RADIANCE_WEIGHTS):
    """RADIANCE irradiance (W/m^2, RGB) -> illuminance (lx)."""
    return EFFICACY * sum(w * c for w, c in zip(weights, rgb))


# ---------------------------------------------------------------- glTF reading

def _mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def _node_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    t = node.get("translation", [0, 0, 0])
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    s = node.get("scale", [1, 1, 1])
    r = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
    return [[r[i][0] * s[0], r[i][1] * s[1], r[i][2] * s[2], t[i]] for i in range(3)] + [
        [0, 0, 0, 1]]


def _apply(m, p):
    return [m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3] for i in range(3)]


class Gltf:
    """A minimal glTF 2.0 (.gltf + buffers) reader for what the conversion needs."""

    def __init__(self, path):
        self.dir = os.path.dirname(os.path.abspath(path))
        with open(path, encoding="utf-8") as f:
            self.doc = json.load(f)
        self.buffers = [self._uri_bytes(b["uri"]) for b in self.doc.get("buffers", [])]

    def _uri_bytes(self, uri):
        if uri.startswith("data:"):
            return base64.b64decode(uri.split(",", 1)[1])
        with open(os.path.join(self.dir, uri), "rb") as f:
            return f.read()

    def view_bytes(self, index):
        v = self.doc["bufferViews"][index]
        start = v.get("byteOffset", 0)
        return self.buffers[v["buffer"]][start:start + v["byteLength"]]

    def accessor(self, index):
        a = self.doc["accessors"][index]
        v = self.doc["bufferViews"][a["bufferView"]]
        fmt = {5126: "f", 5125: "I", 5123: "H", 5121: "B"}[a["componentType"]]
        n = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
        size = struct.calcsize("<" + fmt)
        stride = v.get("byteStride", size * n)
        buf = self.buffers[v["buffer"]]
        base = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        out = []
        for i in range(a["count"]):
            vals = struct.unpack_from(f"<{n}{fmt}", buf, base + i * stride)
            out.append(vals if n > 1 else vals[0])
        return out

    def walk(self):
        """(node index, node, world matrix) for every node of the default scene."""
        scene = self.doc["scenes"][self.doc.get("scene", 0)]
        stack = [(i, [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
                 for i in reversed(scene["nodes"])]
        while stack:
            i, parent = stack.pop()
            node = self.doc["nodes"][i]
            world = _mat_mul(parent, _node_matrix(node))
            yield i, node, world
            for c in reversed(node.get("children", [])):
                stack.append((c, world))


def _reflectance(material):
    ext = material.get("extensions", {}).get("LUXBAKE_material", {})
    rho = ext.get("reflectance")
    if rho is None:  # luxbake's fallback: baseColorFactor x (1 - metallic)
        pbr = material.get("pbrMetallicRoughness", {})
        base = pbr.get("baseColorFactor", [1, 1, 1, 1])[:3]
        metal = pbr.get("metallicFactor", 1.0)
        rho = [c * (1 - metal) for c in base]
    if isinstance(rho, (int, float)):
        rho = [rho] * 3
    return rho


def _area(tri):
    u = [tri[1][i] - tri[0][i] for i in range(3)]
    v = [tri[2][i] - tri[0][i] for i in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    return 0.5 * math.sqrt(sum(x * x for x in n))


def _unit_normal(tri):
    u = [tri[1][i] - tri[0][i] for i in range(3)]
    v = [tri[2][i] - tri[0][i] for i in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    length = math.sqrt(sum(x * x for x in n)) or 1.0
    return [x / length for x in n]


def _same_plane(a, b):
    """Whether triangles a and b (sharing the edge a0-a2 = b0-b1) face the same way: then
    a0 a1 a2 b2 is one planar quad, wound as they are."""
    na, nb = _unit_normal(a), _unit_normal(b)
    return sum(x * y for x, y in zip(na, nb)) > 1 - 1e-9


def _emits(material):
    em = material.get("extensions", {}).get("LUXBAKE_material", {}).get("emission") or {}
    return em.get("luminance", 0) > 0 or em.get("luminousFlux", 0) > 0


def _emission(material, area):
    """(luminance cd/m^2, RGB normalised to Y = 1) of a LUXBAKE_material emission, or None for
    a non-emitting material. RADIANCE's `light` emits from the front side only (a polygon's
    back looks black and sends nothing: source.c m_light and srcray) and reflects nothing, like
    a single-sided black emitter in luxbake; what it cannot express is refused."""
    ext = material.get("extensions", {}).get("LUXBAKE_material", {})
    em = ext.get("emission")
    name = material.get("name", "?")
    if em is None:
        if any(material.get("emissiveFactor", [0, 0, 0])):
            raise SystemExit(f"radiance: material '{name}': emission without LUXBAKE_material "
                             "is not converted")
        return None
    if "luminance" in em:
        luminance = em["luminance"]
    else:
        if area <= 0:
            raise SystemExit(f"radiance: material '{name}': luminousFlux on no area")
        luminance = em["luminousFlux"] / (math.pi * area)
    if luminance == 0:
        return None
    if "profile" in em or material.get("doubleSided") or any(_reflectance(material)):
        raise SystemExit(f"radiance: material '{name}': only single-sided black Lambertian "
                         "emitters are converted (RADIANCE `light`)")
    c = em.get("color", [1, 1, 1])
    y = _luminance_y(c)
    return luminance, [x / y for x in c]


def _luminance_y(c):
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]


def _euler_xyz(r):
    """Angles (deg) a, b, c with r = Rz(c) Ry(b) Rx(a): `xform -rx a -ry b -rz c`."""
    b = math.asin(max(-1.0, min(1.0, -r[2][0])))
    if abs(math.cos(b)) > 1e-9:
        a = math.atan2(r[2][1], r[2][2])
        c = math.atan2(r[1][0], r[0][0])
    else:  # gimbal lock: put everything into a
        a = math.atan2(-r[1][2], r[1][1])
        c = 0.0
    return [math.degrees(v) for v in (a, b, c)]


# ---------------------------------------------------------------- conversion

def convert(gltf_path, out_dir, bin_dir, ldt_to_ies=None):
    """Write out_dir/scene.rad (materials, geometry, luminaires) for the glTF at gltf_path.

    bin_dir: RADIANCE's binaries (ies2rad, xform); ldt_to_ies: {profile name: IES path} for
    EULUMDAT profiles. Returns a dict describing what was converted."""
    ldt_to_ies = ldt_to_ies or {}
    g = Gltf(gltf_path)
    doc = g.doc
    os.makedirs(out_dir, exist_ok=True)
    lines = ["# written by luxbake bench/radiance.py from " + os.path.basename(gltf_path),
             "# units: metres; glTF axes (+Y up); plastic = Lambertian reflectance; "
             "light = Lambertian emitter (front side only)", ""]
    mat_area = {}  # material index -> world area of its triangles (for luminousFlux)

    # luminaire profiles: (kind, index) -> (bytes or path, mime, name)
    ies_lights = doc.get("extensions", {}).get("EXT_lights_ies", {}).get("lights", [])
    lux_profiles = doc.get("extensions", {}).get("LUXBAKE_luminaire", {}).get("profiles", [])

    def profile_source(entry):
        name = entry.get("name", "")
        mime = entry.get("mimeType", "")
        if "bufferView" in entry:
            data = g.view_bytes(entry["bufferView"])
        else:
            data = g._uri_bytes(entry["uri"])
            if entry["uri"].lower().endswith(".ldt"):
                mime = "application/x-eulumdat"
        if "eulumdat" in mime:
            if name not in ldt_to_ies:
                raise SystemExit(f"radiance: no IES file given for EULUMDAT profile '{name}'")
            with open(ldt_to_ies[name], "rb") as f:
                data = f.read()
        return name, data

    triangles = 0
    polys = []
    luminaires = []
    ies_made = {}
    for idx, node, world in g.walk():
        if "mesh" in node:
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                if prim.get("mode", 4) != 4:
                    continue
                pos = g.accessor(prim["attributes"]["POSITION"])
                ind = g.accessor(prim["indices"]) if "indices" in prim else list(range(len(pos)))
                mat = f"mat{prim['material']}" if "material" in prim else "mat_default"
                wp = [_apply(world, p) for p in pos]
                emits = "material" in prim and _emits(doc["materials"][prim["material"]])
                merged = False
                for t in range(0, len(ind), 3):
                    tri = [wp[ind[t]], wp[ind[t + 1]], wp[ind[t + 2]]]
                    if "material" in prim:
                        mat_area[prim["material"]] = mat_area.get(prim["material"], 0.0) + \
                            _area(tri)
                    triangles += 1
                    if merged:  # second half of the quad written with the previous triangle
                        merged = False
                        continue
                    # An emitting quad stays one polygon: RADIANCE samples a long thin
                    # triangular source poorly ("triangular source with poor aspect": its -ab 0
                    # working plane came out 0.36 % high, 0.7 % RMS, on office-panels' halves).
                    if emits and t + 5 < len(ind) and ind[t + 3] == ind[t] and \
                            ind[t + 4] == ind[t + 2] and \
                            _same_plane(tri, [wp[ind[t]], wp[ind[t + 2]], wp[ind[t + 5]]]):
                        tri = tri + [wp[ind[t + 5]]]
                        merged = True
                    name = f"n{idx}_t{t // 3}"
                    coords = " ".join(f"{c:.7g}" for p in tri for c in p)
                    polys.append(f"{mat} polygon {name}\n0\n0\n{3 * len(tri)} {coords}\n")
        exts = node.get("extensions", {})
        ies = exts.get("EXT_lights_ies")
        lux = exts.get("LUXBAKE_luminaire")
        if ies is None and (lux is None or "profile" not in lux):
            continue
        if ies is not None:
            key = ("ies", ies["light"])
            entry = ies_lights[ies["light"]]
            mult = ies.get("multiplier", 1.0) * _luminance_y(ies.get("color", [1, 1, 1]))
        else:
            key = ("lux", lux["profile"])
            entry = lux_profiles[lux["profile"]]
            mult = 1.0
        if lux is not None:
            mult *= lux.get("multiplier", 1.0) * lux.get("maintenanceFactor", 1.0)
            mult *= _luminance_y(lux.get("color", [1, 1, 1]))
        if key not in ies_made:
            pname, data = profile_source(entry)
            base = f"lum_{key[0]}{key[1]}"
            with open(os.path.join(out_dir, base + ".ies"), "wb") as f:
                f.write(data)
            ies_made[key] = (base, pname)
        base, pname = ies_made[key]
        # one ies2rad output per (profile, multiplier): the multiplier is baked into the file
        tag = f"{base}_m{mult:.6g}".replace(".", "p")
        if not os.path.exists(os.path.join(out_dir, tag + ".rad")):
            subprocess.run([os.path.join(bin_dir, "ies2rad"), "-dm", "-t", "default",
                            "-m", f"{mult:.9g}", "-o", tag, base + ".ies"],
                           cwd=out_dir, check=True)
            with open(os.path.join(out_dir, tag + ".rad"), encoding="utf-8") as f:
                text = f.read()
            # light -> illum (no alternate material: invisible to non-shadow rays)
            text = text.replace(f"'{tag}_dist' light '{tag}_light'",
                                f"'{tag}_dist' illum '{tag}_light'")
            if f"illum '{tag}_light'" not in text:
                raise SystemExit(f"radiance: unexpected ies2rad output for {tag}")
            with open(os.path.join(out_dir, tag + ".rad"), "w", encoding="utf-8") as f:
                f.write(text)
        rot = [[world[i][j] for j in range(3)] for i in range(3)]
        for j in range(3):  # remove scale (luxbake: node scale changes neither intensity nor shape)
            n = math.sqrt(sum(rot[i][j] ** 2 for i in range(3)))
            for i in range(3):
                rot[i][j] /= n
        a, b, c = _euler_xyz(rot)
        t = [world[i][3] for i in range(3)]
        args = ["-n", f"L{idx}", "-rx", f"{a:.9g}", "-ry", f"{b:.9g}", "-rz", f"{c:.9g}",
                "-t"] + [f"{v:.9g}" for v in t]
        placed = subprocess.run([os.path.join(bin_dir, "xform")] + args + [tag + ".rad"],
                                cwd=out_dir, check=True, capture_output=True, text=True).stdout
        luminaires.append({"node": node.get("name", str(idx)), "profile": pname,
                           "multiplier": mult, "position": t, "xform": " ".join(args),
                           "nadir": [-rot[i][2] for i in range(3)],
                           "c0": [rot[i][0] for i in range(3)]})
        polys.append(placed)
    emitters = []
    for k, m in enumerate(doc.get("materials", [])):
        em = _emission(m, mat_area.get(k, 0.0))
        if em is None:
            r, gg, b = _reflectance(m)
            lines += [f"void plastic mat{k}", "0", "0", f"5 {r:.6g} {gg:.6g} {b:.6g} 0 0", ""]
            continue
        luminance, rgb = em
        # RADIANCE radiance (W/(sr m^2)) = luminance / 179 lm/W (as ies2rad converts candela)
        r, gg, b = (luminance * c / EFFICACY for c in rgb)
        lines += [f"void light mat{k}", "0", "0", f"3 {r:.9g} {gg:.9g} {b:.9g}", ""]
        emitters.append({"material": m.get("name", str(k)), "luminance": luminance,
                         "area": mat_area.get(k, 0.0), "radiance": [r, gg, b]})
    lines.append("void plastic mat_default\n0\n0\n5 0.5 0.5 0.5 0 0\n")
    with open(os.path.join(out_dir, "scene.rad"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n" + "\n".join(polys))
    return {"triangles": triangles, "luminaires": luminaires, "emitters": emitters,
            "profiles": sorted({p for _, p in ies_made.values()})}


def run_rtrace(bin_dir, lib_dir, octree, points, options, workdir, threads=2, timeout=None,
               weights=RADIANCE_WEIGHTS):
    """Irradiance at points [(x, y, z, dx, dy, dz)] -> (illuminances in lx, measurement, command).

    One rtrace process (-n threads) for all points, run in the octree's folder (where the
    luminaires' .dat files are); points, output and messages go to workdir. With -aa 0 (as the
    harness runs it) there is no ambient cache: every point is path traced on its own."""
    import measure
    scene_dir = os.path.dirname(os.path.abspath(octree))
    env = dict(os.environ)
    env["RAYPATH"] = os.pathsep.join([scene_dir, lib_dir])
    env["PATH"] = bin_dir + os.pathsep + env.get("PATH", "")
    pts = os.path.join(workdir, "points.txt")
    with open(pts, "w", encoding="ascii") as f:
        f.write("".join(" ".join(f"{v:.9g}" for v in p) + "\n" for p in points))
    out_path = os.path.join(workdir, "rtrace.out")
    err_path = os.path.join(workdir, "rtrace.err")
    cmd = [os.path.join(bin_dir, "rtrace"), "-h", "-I", "-ov", "-n", str(threads)] + options + [
        os.path.basename(octree)]
    m = measure.run(cmd, cwd=scene_dir, env=env, stdin_path=pts, stdout_path=out_path,
                    stderr_path=err_path, timeout=timeout)
    if m["returncode"] != 0:
        with open(err_path, encoding="utf-8", errors="replace") as f:
            raise SystemExit(f"rtrace failed ({m['returncode']}): {f.read()[-500:]}")
    values = []
    with open(out_path, encoding="ascii") as f:
        for line in f:
            parts = line.split()
            if len(parts) >= 3:
                values.append(illuminance([float(v) for v in parts[:3]], weights))
    if len(values) != len(points):
        raise SystemExit(f"rtrace returned {len(values)} values for {len(points)} points")
    return values, m, cmd
