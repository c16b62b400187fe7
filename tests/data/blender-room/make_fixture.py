"""Build a small room in Blender and export it with Blender's own glTF exporter.

Run with the Blender Python module (bpy 5.0.1), from the repository root:

    python3 -m venv .venv-bpy && .venv-bpy/bin/pip install bpy==5.0.1
    .venv-bpy/bin/python tests/data/blender-room/make_fixture.py

Writes, next to this script: room.glb (GLB) and room.gltf + room.bin (GLTF_SEPARATE).
Blender works in Z-up; the exporter converts to glTF's Y-up (+Y up):
glTF (x, y, z) = Blender (x, z, -y). Units: Blender metres = glTF metres.
See README.md for what the files contain.
"""

import math
import os
import sys

import bpy  # must come before bmesh / mathutils
import bmesh
from mathutils import Vector

HERE = os.path.dirname(os.path.abspath(__file__))

ROOM = (4.0, 3.0, 2.5)          # x, y (Blender depth), z (height); centred on x/y, floor z = 0
BLOCK_SIZE = 0.5
BLOCK_LOC = (0.8, 0.5, 0.25)    # on the floor, rotated 30 deg about Blender +Z (vertical)
BLOCK_LINKED_LOC = (-1.0, 0.7, 0.25)
BLOCK_MIRRORED_LOC = (0.8, -0.7, 0.25)
PANEL_SIZE = 0.6
PANEL_LOC = (0.0, 0.0, 2.49)    # 1 cm below the ceiling, facing down
LAMP_LOC = (-1.2, -0.8, 2.0)
LAMP_WATTS = 100.0
SPOT_LOC = (1.6, -1.2, 2.3)
SPOT_WATTS = 200.0
SPOT_SIZE = math.radians(40.0)  # Blender spot_size is the FULL cone angle
SPOT_BLEND = 0.2
PROBE_LOC = (-1.0, 0.0, 0.8)


def principled(name, base, metallic=0.0, roughness=1.0, emission=None, strength=0.0):
    mat = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):  # always node based from Blender 5 on
        mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (base, base, base, 1.0)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    if emission is not None:
        bsdf.inputs["Emission Color"].default_value = (*emission, 1.0)
        bsdf.inputs["Emission Strength"].default_value = strength
    return mat


def box_mesh(name, lo, hi, inward=False):
    """Axis-aligned box with 6 quads; outward normals unless inward=True."""
    me = bpy.data.meshes.new(name)
    bm = bmesh.new()
    v = {}
    for ix, x in enumerate((lo[0], hi[0])):
        for iy, y in enumerate((lo[1], hi[1])):
            for iz, z in enumerate((lo[2], hi[2])):
                v[ix, iy, iz] = bm.verts.new((x, y, z))
    quads = [  # counter-clockwise seen from outside
        ((0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)),  # bottom (-z)
        ((0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)),  # top (+z)
        ((0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)),  # -y
        ((0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)),  # +y
        ((0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)),  # -x
        ((1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)),  # +x
    ]
    for q in quads:
        bm.faces.new([v[k] for k in (reversed(q) if inward else q)])
    bm.normal_update()
    for f in bm.faces:  # sanity: normals point the intended way
        c = f.calc_center_median()
        mid = Vector([(a + b) / 2 for a, b in zip(lo, hi)])
        assert (f.normal.dot(c - mid) < 0) == inward, (name, f.normal, c)
    bm.to_mesh(me)
    bm.free()
    return me


def link(obj):
    bpy.context.scene.collection.objects.link(obj)
    return obj


def build():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.unit_settings.system = "METRIC"
    scene.unit_settings.scale_length = 1.0

    m_walls = principled("walls", 0.5)
    m_block = principled("block", 0.3)
    m_panel = principled("panel_emitter", 0.8, emission=(1.0, 1.0, 1.0), strength=500.0)

    # room: one closed box, normals facing inward, object transform = identity
    hx, hy = ROOM[0] / 2, ROOM[1] / 2
    me_room = box_mesh("room", (-hx, -hy, 0.0), (hx, hy, ROOM[2]), inward=True)
    me_room.materials.append(m_walls)
    link(bpy.data.objects.new("room", me_room))

    # block: 0.5 m cube on the floor, rotated 30 deg about the vertical
    h = BLOCK_SIZE / 2
    me_block = box_mesh("block", (-h, -h, -h), (h, h, h))
    me_block.materials.append(m_block)
    block = link(bpy.data.objects.new("block", me_block))
    block.location = BLOCK_LOC
    block.rotation_euler = (0.0, 0.0, math.radians(30.0))

    # linked duplicate: a second object using the SAME mesh data
    block_linked = link(bpy.data.objects.new("block_linked", me_block))
    block_linked.location = BLOCK_LINKED_LOC

    # mirrored copy (also the same mesh data) with a negative scale
    block_mirrored = link(bpy.data.objects.new("block_mirrored", me_block))
    block_mirrored.location = BLOCK_MIRRORED_LOC
    block_mirrored.rotation_euler = (0.0, 0.0, math.radians(30.0))
    block_mirrored.scale = (-1.0, 1.0, 1.0)

    # emissive panel: a plane (normal +Z in its mesh) turned 180 deg about X to face down
    me_panel = bpy.data.meshes.new("panel")
    s = PANEL_SIZE / 2
    me_panel.from_pydata([(-s, -s, 0.0), (s, -s, 0.0), (s, s, 0.0), (-s, s, 0.0)], [],
                         [(0, 1, 2, 3)])
    me_panel.materials.append(m_panel)
    panel = link(bpy.data.objects.new("panel", me_panel))
    panel.location = PANEL_LOC
    panel.rotation_euler = (math.pi, 0.0, 0.0)

    # point light
    lamp_data = bpy.data.lights.new("lamp", type="POINT")
    lamp_data.energy = LAMP_WATTS
    lamp = link(bpy.data.objects.new("lamp", lamp_data))
    lamp.location = LAMP_LOC

    # spot light aimed at the block centre (lights shine down their local -Z)
    spot_data = bpy.data.lights.new("spot", type="SPOT")
    spot_data.energy = SPOT_WATTS
    spot_data.spot_size = SPOT_SIZE
    spot_data.spot_blend = SPOT_BLEND
    spot = link(bpy.data.objects.new("spot", spot_data))
    spot.location = SPOT_LOC
    aim = Vector(BLOCK_LOC) - Vector(SPOT_LOC)
    spot.rotation_mode = "QUATERNION"
    spot.rotation_quaternion = aim.to_track_quat("-Z", "Y")

    # probe: an Empty with a custom property
    probe = link(bpy.data.objects.new("probe_1", None))
    probe.empty_display_type = "PLAIN_AXES"
    probe.location = PROBE_LOC
    probe["probe"] = True

    bpy.context.view_layer.update()
    return aim


def export():
    common = dict(export_lights=True, export_extras=True, export_yup=True,
                  export_cameras=False, use_selection=False)
    bpy.ops.export_scene.gltf(filepath=os.path.join(HERE, "room.glb"),
                              export_format="GLB", **common)
    bpy.ops.export_scene.gltf(filepath=os.path.join(HERE, "room.gltf"),
                              export_format="GLTF_SEPARATE", **common)


def main():
    aim = build()
    export()
    print("Blender", bpy.app.version_string)
    print("spot aim (Blender, normalised):", tuple(round(c, 6) for c in aim.normalized()))
    for f in ("room.glb", "room.gltf", "room.bin"):
        print(f, os.path.getsize(os.path.join(HERE, f)), "bytes")


if __name__ == "__main__":
    sys.exit(main())
