#!/usr/bin/env python3
"""Write the shelf_on_wall fixture as an input glTF: python3 bench/shelf_scene.py OUT_DIR."""
# The shelf_on_wall fixture (src/fixtures/contacts.rs) as an input glTF: a 4 x 3 x 5 m room
# (inward faces), a 1.4 m x 3 cm x 0.3 m plank against the wall z = 0, open at the back, and an
# isotropic point light of 1000 lm (79.577 cd) at (2, 2.2, 2.5). Y up, metres.
import os, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from quad_room import box_quads, write

quads = []
box_quads(quads, (0,0,0), (4,3,5), True)
box_quads(quads, (1.3,1.5,0), (2.7,1.53,0.3), False, skip=(4,))
write(sys.argv[1], "shelf", quads, 1000, 0.5, (2, 2.2, 2.5))
