"""Boxes as quads and a one-material room with a point light as an input glTF (Y up, metres):
shared by bench/shelf_scene.py and bench/desk_scene.py."""
import json, math, struct


def box_quads(quads, lo, hi, inward, skip=()):
    """Append an axis box's faces (-x +x -y +y -z +z) to `quads`, counter-clockwise seen from
    outside, or from inside when `inward`; faces whose index is in `skip` are left out."""
    x0, y0, z0 = lo; x1, y1, z1 = hi
    f = [
      [(x0,y0,z0),(x0,y0,z1),(x0,y1,z1),(x0,y1,z0)],
      [(x1,y0,z0),(x1,y1,z0),(x1,y1,z1),(x1,y0,z1)],
      [(x0,y0,z0),(x1,y0,z0),(x1,y0,z1),(x0,y0,z1)],
      [(x0,y1,z0),(x0,y1,z1),(x1,y1,z1),(x1,y1,z0)],
      [(x0,y0,z0),(x0,y1,z0),(x1,y1,z0),(x1,y0,z0)],
      [(x0,y0,z1),(x1,y0,z1),(x1,y1,z1),(x0,y1,z1)],
    ]
    for k, q in enumerate(f):
        if k in skip: continue
        quads.append(q[::-1] if inward else q)


def write(out_dir, name, quads, lumens, rho, light_at):
    """Write OUT_DIR/NAME.gltf and .bin: one mesh of `quads` in one grey material of reflectance
    `rho` (LUXBAKE_material) and an isotropic point light of `lumens` at `light_at`."""
    pos = []; idx = []
    for q in quads:
        b = len(pos); pos += q; idx += [b, b+1, b+2, b, b+2, b+3]
    bp = b''.join(struct.pack('<3f', *p) for p in pos); bi = b''.join(struct.pack('<I', i) for i in idx)
    buf = bp + bi
    mn = [min(p[i] for p in pos) for i in range(3)]; mx = [max(p[i] for p in pos) for i in range(3)]
    doc = {"asset": {"version": "2.0", "generator": f"luxbake bench {name}"},
     "extensionsUsed": ["KHR_lights_punctual", "LUXBAKE_material"],
     "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": lumens/(4*math.pi), "name": "bulb"}]}},
     "scene": 0, "scenes": [{"nodes": [0, 1]}],
     "nodes": [{"mesh": 0, "name": "room"}, {"name": "bulb", "translation": list(light_at), "extensions": {"KHR_lights_punctual": {"light": 0}}}],
     "materials": [{"name": "walls", "pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, 1]}, "extensions": {"LUXBAKE_material": {"reflectance": [rho, rho, rho]}}}],
     "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
     "buffers": [{"byteLength": len(buf), "uri": f"{name}.bin"}],
     "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(bp), "target": 34962}, {"buffer": 0, "byteOffset": len(bp), "byteLength": len(bi), "target": 34963}],
     "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": mn, "max": mx}, {"bufferView": 1, "componentType": 5125, "count": len(idx), "type": "SCALAR"}]}
    open(f"{out_dir}/{name}.bin", 'wb').write(buf)
    json.dump(doc, open(f"{out_dir}/{name}.gltf", 'w'), indent=1)
