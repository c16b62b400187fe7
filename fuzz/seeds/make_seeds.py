#!/usr/bin/env python3
"""Write the fuzz seed corpus (fuzz/corpus/<target>/seed-*) from tests/data, samples/ and the
bakes in fuzz/seeds/bakes (made by `bake`, see fuzz/README.md). Scene inputs hold their side files
after the separator of fuzz/src/targets.rs: main file, then `\\n%%LUXFUZZ%%\\nNAME\\nBYTES` each."""
import json, os, struct, sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
OUT = os.path.join(ROOT, "fuzz", "corpus")
SEP = b"\n%%LUXFUZZ%%\n"


def read(*p):
    with open(os.path.join(ROOT, *p), "rb") as f:
        return f.read()


def put(target, name, data):
    d = os.path.join(OUT, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "seed-" + name), "wb") as f:
        f.write(data)


def scene(main, sides):
    return main + b"".join(SEP + n.encode() + b"\n" + b for n, b in sides)


def glb(doc, bin_):
    j = json.dumps(doc, separators=(",", ":")).encode()
    j += b" " * (-len(j) % 4)
    bin_ = bin_ + b"\0" * (-len(bin_) % 4)
    total = 12 + 8 + len(j) + (8 + len(bin_) if bin_ else 0)
    out = b"glTF" + struct.pack("<II", 2, total) + struct.pack("<I", len(j)) + b"JSON" + j
    if bin_:
        out += struct.pack("<I", len(bin_)) + b"BIN\0" + bin_
    return out


# glTF JSON scenes with their buffers (and a profile referenced by URI).
room = read("tests/data/blender-room/room.gltf")
put("gltf", "room", scene(room, [("room.bin", read("tests/data/blender-room/room.bin"))]))
for name in ["office", "office-ldt"]:
    put("gltf", name, scene(read("samples/office", name + ".gltf"),
                            [(name + ".bin", read("samples/office", name + ".bin"))]))
office = json.loads(read("samples/office/office.gltf"))
office["extensions"]["EXT_lights_ies"]["lights"][0] = {"uri": "miral.ies", "name": "by URI"}
office["extensions"]["LUXBAKE_luminaire"]["profiles"][0] = {"uri": "cns.ldt", "name": "by URI"}
put("gltf", "office-uri-profiles", scene(json.dumps(office).encode(), [
    ("office.bin", read("samples/office/office.bin")),
    ("miral.ies", read("samples/office/profiles/miral_58w.ies")),
    ("cns.ldt", read("samples/office/profiles/cns70_50w.ldt"))]))

# GLB scenes: the Blender room, the office packed into one GLB, a bake read back as input.
put("glb", "room", read("tests/data/blender-room/room.glb"))
office = json.loads(read("samples/office/office.gltf"))
del office["buffers"][0]["uri"]
put("glb", "office", glb(office, read("samples/office/office.bin")))
put("glb", "cornell-baked", read("fuzz/seeds/bakes/cornell-plane.glb"))

# OBJ + MTL (the first byte '#' is odd: read +Z up; a copy starting with a newline: +Y up).
obj = read("samples/cornell-box/cornell-box.obj")
mtl = read("samples/cornell-box/cornell-box.mtl")
put("obj", "cornell-z", scene(obj, [("cornell-box.mtl", mtl)]))
put("obj", "cornell-y", scene(b"\n" + obj, [("cornell-box.mtl", mtl)]))
put("obj", "cornell-no-mtl", obj)

# Accessors: 16 header bytes (see accessor_glb in targets.rs) + the binary chunk.
tri = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<3I", 0, 1, 2)
quad = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1) + struct.pack("<6H", 0, 1, 2, 0, 2, 3)
# kind 5 (FLOAT) VEC3, count 3, view 0: 9 words; indices u32 at 36; mode 4; view 1 from 36.
put("accessors", "triangle", bytes([5, 3, 0, 0, 9, 0, 0, 0, 0, 3, 0, 4, 36, 3, 0, 0]) + tri)
put("accessors", "quad-u16", bytes([5, 4, 0, 0, 12, 0, 0, 0, 2, 6, 0, 4, 48, 3, 0, 2]) + quad)
put("accessors", "strided", bytes([5, 3, 0, 0, 9, 12, 0, 0, 0, 3, 0, 4, 36, 3, 0, 0]) + tri)
put("accessors", "sparse", bytes([5, 3, 0, 0, 9, 0, 1 | 4 << 3, 1, 0, 3, 0, 4, 36, 3, 0, 0]) + tri)
put("accessors", "no-view-sparse", bytes([5, 3, 0, 0, 9, 0, 1, 2, 0, 3, 0, 4, 36, 3, 0, 1]) + tri)
norm = struct.pack("<9h", 0, 0, 0, 32767, 0, 0, 0, 32767, 0) + b"\0\0" + struct.pack("<3B", 0, 1, 2)
put("accessors", "normalized-i16", bytes([2 | 8, 3, 0, 0, 5, 0, 0, 0, 1, 3, 20, 4, 5, 1, 0, 4]) + norm)
put("accessors", "strip-no-indices", bytes([5, 3, 0, 0, 9, 0, 0, 0, 0, 0, 0, 5, 0, 0, 5 | 0x10, 14]) + tri)

# Photometric files.
for d in ["tests/data/photometry", "samples/office/profiles"]:
    for f in sorted(os.listdir(os.path.join(ROOT, d))):
        ext = f.rsplit(".", 1)[-1]
        if ext in ("ies", "ldt"):
            put(ext, f.rsplit(".", 1)[0], read(d, f))

# Probe CSV files.
put("probes_csv", "header", b"x,y,z,name\n0.5,0.5,0.5,centre\n0.2,0.8,0.3\n")
put("probes_csv", "quoted", b"\xef\xbb\xbf# desk probes\n1,0.75,2,\"desk, left\"\n\n3,0.75,2 # right\n")
put("probes_csv", "spaces", b" 1.5 , 1e-3 , -2.25E+1 , a\r\n-0,+4,.5,b\r\n")

# Targets files (the office's and ones naming the Cornell bake of targets.rs).
put("targets_json", "office", read("samples/office/targets.json"))
put("targets_json", "cornell", json.dumps({
    "working_plane": 500, "floor": 300, "node:tall_block[+y]": 250, "material:white": 200,
    "material:red[-x]": 100, "left_wall": 120, "back_wall[-z]": 150}).encode())
put("targets_json", "unknown", b'{"nothing": 1}')

# Lightmap EXR files and bakes read back.
for f in sorted(os.listdir(os.path.join(ROOT, "fuzz/seeds/bakes"))):
    data = read("fuzz/seeds/bakes", f)
    if f.endswith(".exr"):
        put("exr", f[:-4], data)
    elif f.endswith(".glb"):
        put("baked", f[:-4], data)
