#!/usr/bin/env python3
"""Write a desk on four legs in a room as an input glTF: python3 bench/desk_scene.py OUT_DIR."""
# The desk of the furnished_room fixture (src/fixtures/contacts.rs) as an input glTF: a 4 x 3 x 5 m
# room (inward faces, reflectance 0.8), a 1.6 x 0.8 m desk top 3 cm thick at 0.72-0.75 m on four
# 5 cm square legs (their tops against its underside, their feet on the floor: contacts too small
# to cut along), and an isotropic point light of 2000 lm at (2, 2.2, 2.5). Y up, metres.
import os, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from quad_room import box_quads, write

quads = []
box_quads(quads, (0,0,0), (4,3,5), True)
box_quads(quads, (2.2,0.72,3.5), (3.8,0.75,4.3), False)
for x, z in [(2.2,3.5), (3.75,3.5), (2.2,4.25), (3.75,4.25)]:
    box_quads(quads, (x,0,z), (x+0.05,0.72,z+0.05), False)
write(sys.argv[1], "desk", quads, 2000, 0.8, (2, 2.2, 2.5))
