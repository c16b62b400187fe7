#!/usr/bin/env python3
"""Write a desk on four legs in a room as an input glTF: python3 bench/desk_scene.py OUT_DIR."""
# The desk of the furnished_room fixture (src/fixtures/contacts.rs) as an input glTF: a 4 x 3 x 5 m
# room (inward faces, reflectance 0.8), a 1.6 x 0.8 m desk top 3 cm thick at 0.72-0.75 m on four
# 5 cm square legs (their tops against its underside, their feet on the floor: contacts too small
# to cut along), and an isotropic point light of 2000 lm at (2, 2.2, 2.5). Y up, metres.
import json, struct, math, sys
quads = []
def box_quads(lo, hi, inward, skip=()):
    x0,y0,z0 = lo; x1,y1,z1 = hi
    # faces: -x +x -y +y -z +z, each listed counter-clockwise seen from outside
    f = [
      [(x0,y0,z0),(x0,y0,z1),(x0,y1,z1),(x0,y1,z0)],
      [(x1,y0,z0),(x1,y1,z0),(x1,y1,z1),(x1,y0,z1)],
      [(x0,y0,z0),(x1,y0,z0),(x1,y0,z1),(x0,y0,z1)],
      [(x0,y1,z0),(x0,y1,z1),(x1,y1,z1),(x1,y1,z0)],
      [(x0,y0,z0),(x0,y1,z0),(x1,y1,z0),(x1,y0,z0)],
      [(x0,y0,z1),(x1,y0,z1),(x1,y1,z1),(x0,y1,z1)],
    ]
    for k,q in enumerate(f):
        if k in skip: continue
        quads.append(q[::-1] if inward else q)
box_quads((0,0,0),(4,3,5),True)
box_quads((2.2,0.72,3.5),(3.8,0.75,4.3),False)
for x,z in [(2.2,3.5),(3.75,3.5),(2.2,4.25),(3.75,4.25)]:
    box_quads((x,0,z),(x+0.05,0.72,z+0.05),False)
pos=[]; idx=[]
for q in quads:
    b=len(pos); pos+=q; idx+=[b,b+1,b+2,b,b+2,b+3]
bp=b''.join(struct.pack('<3f',*p) for p in pos); bi=b''.join(struct.pack('<I',i) for i in idx)
buf=bp+bi
mn=[min(p[i] for p in pos) for i in range(3)]; mx=[max(p[i] for p in pos) for i in range(3)]
doc={"asset":{"version":"2.0","generator":"luxbake bench desk"},
 "extensionsUsed":["KHR_lights_punctual","LUXBAKE_material"],
 "extensions":{"KHR_lights_punctual":{"lights":[{"type":"point","intensity":2000/(4*math.pi),"name":"bulb"}]}},
 "scene":0,"scenes":[{"nodes":[0,1]}],
 "nodes":[{"mesh":0,"name":"room"},{"name":"bulb","translation":[2,2.2,2.5],"extensions":{"KHR_lights_punctual":{"light":0}}}],
 "materials":[{"name":"walls","pbrMetallicRoughness":{"baseColorFactor":[0.8,0.8,0.8,1]},"extensions":{"LUXBAKE_material":{"reflectance":[0.8,0.8,0.8]}}}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],
 "buffers":[{"byteLength":len(buf),"uri":"desk.bin"}],
 "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":len(bp),"target":34962},{"buffer":0,"byteOffset":len(bp),"byteLength":len(bi),"target":34963}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":len(pos),"type":"VEC3","min":mn,"max":mx},{"bufferView":1,"componentType":5125,"count":len(idx),"type":"SCALAR"}]}
open(sys.argv[1]+'/desk.bin','wb').write(buf); json.dump(doc,open(sys.argv[1]+'/desk.gltf','w'),indent=1)
