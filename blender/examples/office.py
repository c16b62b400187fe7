"""samples/office rebuilt in Blender with the LuxBake add-on, from the numbers of
samples/office/make_office.py (imported, not copied), and exported as glTF for luxbake.

Usage: PYTHON blender/examples/office.py OUT_DIR [--blend FILE.blend]
PYTHON is a Python 3.11 with PyPI `bpy` 5.0.1 (or run it inside Blender with the add-on
enabled: `blender -b -P blender/examples/office.py -- OUT_DIR`). Writes OUT_DIR/office.gltf
(+ office.bin and the two profiles) through the add-on's export, and with --blend the .blend.
Prints {"gltf": path} on stdout.

What the add-on carries: materials' reflectances (LuxBake material panel, "Value"), the six
fluorescents (an Empty under each luminaire mesh with miral_58w.ies, a 1.5 × 0.2 m opening, C0
along the luminaire's length), the spotlight (an Empty with cns70_50w.ldt aimed at the picture),
glTF node names that repeat (each desk's `top`, `leg_1` …) through the objects' glTF node name,
and the seed's three cameras. Axes: make_office.py's glTF coordinates (+Y up) become Blender's
(+Z up) by (x, y, z) → (x, −z, y); an object's local axes are turned the same way, so a
luminaire's nadir (glTF node −Z) is its Empty's −Z and C0 its local +X.
"""

import importlib.util
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
OFFICE = os.path.join(REPO, "samples", "office")


def load_make_office():
    spec = importlib.util.spec_from_file_location("make_office", os.path.join(OFFICE, "make_office.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def g2b(p):
    """glTF (+Y up) → Blender (+Z up)."""
    return (p[0], -p[2], p[1])


def basis(mo, q):
    """Blender rotation (quaternion w, x, y, z) whose local axes are those of the glTF rotation
    q = [x, y, z, w], turned into Blender's axes."""
    from mathutils import Matrix

    cols = [g2b(mo.rotate(q, e)) for e in ((1.0, 0, 0), (0, 1.0, 0), (0, 0, 1.0))]
    return Matrix([[cols[c][r] for c in range(3)] for r in range(3)]).to_quaternion()


def mesh(bpy, name, faces_by_material):
    """A mesh of quads (glTF corners, counter-clockwise seen from the front), each quad with its
    own four vertices and cut into the triangles (0, 1, 2), (0, 2, 3) as make_office writes
    them (Blender's exporter would choose its own diagonals), one material slot per list."""
    data = bpy.data.meshes.new(name)
    verts, polys, mats = [], [], []
    for slot, (faces, _material) in enumerate(faces_by_material):
        for corners, _normal in faces:
            base = len(verts)
            polys += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
            verts.extend(g2b(c) for c in corners)
            mats += [slot, slot]
    data.from_pydata(verts, [], polys)
    for _faces, material in faces_by_material:
        data.materials.append(material)
    data.polygons.foreach_set("material_index", mats)
    return data


def mo_r6(x):
    """make_office's r6: 1 µm rounding (its node translations are written so)."""
    v = round(x, 6)
    return 0.0 if v == 0 else v


def new_object(bpy, name, data=None, parent=None, location=(0, 0, 0), node_name=""):
    obj = bpy.data.objects.new(name, data)
    bpy.context.scene.collection.objects.link(obj)
    obj.parent = parent
    obj.location = g2b([mo_r6(c) for c in location])  # rounded as make_office writes them
    obj.luxbake_settings.node_name = node_name
    return obj


def build(bpy, mo):
    materials = {}
    for name, refl in (("floor", 0.3), ("ceiling", 0.7), ("wall", 0.5), ("wall_back", 0.6),
                       ("desk_dark", 0.2), ("desk_light", 0.6), ("picture", 0.5),
                       ("luminaire_housing", 0.7), ("luminaire_diffuser", 0.5)):
        m = bpy.data.materials.new(name)
        m.use_backface_culling = True  # single-sided, as make_office writes them
        m.diffuse_color = (refl, refl, refl, 1.0)
        m.luxbake_settings.reflectance_mode = "VALUE"
        m.luxbake_settings.reflectance = refl
        materials[name] = m

    W, H, L = mo.ROOM_W, mo.ROOM_H, mo.ROOM_L
    X, Y, Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
    room = [
        ("floor", "floor", mo.quad((0, 0, 0), (0, 0, L), (W, 0, 0), Y)),
        ("ceiling", "ceiling", mo.quad((0, H, 0), (W, 0, 0), (0, 0, L), mo.scale(Y, -1))),
        ("wall_left", "wall", mo.quad((0, 0, 0), (0, H, 0), (0, 0, L), X)),
        ("wall_right", "wall", mo.quad((W, 0, 0), (0, 0, L), (0, H, 0), mo.scale(X, -1))),
        ("wall_front", "wall", mo.quad((0, 0, 0), (W, 0, 0), (0, H, 0), Z)),
        ("wall_back", "wall_back", mo.quad((0, 0, L), (0, H, 0), (W, 0, 0), mo.scale(Z, -1))),
    ]
    for name, mname, face in room:
        new_object(bpy, name, mesh(bpy, name, [([face], materials[mname])]))

    top_faces = list(mo.box_faces((0.0, 0.0, 0.0), (mo.DESK_TOP_X, mo.DESK_TOP_T, mo.DESK_TOP_Z)).values())
    leg_faces = list(mo.box_faces((0.0, 0.0, 0.0), (mo.LEG_X, mo.LEG_Y, mo.LEG_Z)).values())
    top_y = mo.WORKING_PLANE - mo.DESK_TOP_T / 2.0
    leg_y = mo.LEG_Y / 2.0
    lx = mo.DESK_TOP_X / 2.0 - mo.LEG_INSET
    lz = mo.DESK_TOP_Z / 2.0 - mo.LEG_INSET
    for dname, _refl, cx, cz in mo.DESKS:
        desk = new_object(bpy, dname, None, location=(cx, 0.0, cz))
        top = mesh(bpy, dname + "_top", [(top_faces, materials[dname])])
        leg = mesh(bpy, dname + "_leg", [(leg_faces, materials[dname])])
        new_object(bpy, f"{dname}.top", top, desk, (0.0, top_y, 0.0), node_name="top")
        for i, (px, pz) in enumerate([(-lx, -lz), (lx, -lz), (lx, lz), (-lx, lz)], 1):
            new_object(bpy, f"{dname}.leg_{i}", leg, desk, (px, leg_y, pz), node_name=f"leg_{i}")

    hp = mo.PIC_SIZE / 2.0
    pic = mo.quad((hp, -hp, 0.0), (-mo.PIC_SIZE, 0.0, 0.0), (0.0, mo.PIC_SIZE, 0.0), mo.scale(Z, -1))
    new_object(bpy, "picture", mesh(bpy, "picture", [([pic], materials["picture"])]),
               location=mo.PIC_CENTRE)

    lf = mo.box_faces((0.0, -mo.LUM_Y / 2.0, 0.0), (mo.LUM_X, mo.LUM_Y, mo.LUM_Z))
    housing = [lf[k] for k in ("+x", "-x", "+y", "+z", "-z")]
    lum_mesh = mesh(bpy, "luminaire", [(housing, materials["luminaire_housing"]),
                                       ([lf["-y"]], materials["luminaire_diffuser"])])
    miral = os.path.join(OFFICE, "profiles", mo.MIRAL[0] + ".ies")
    n = 0
    for x in mo.LUM_ROWS_X:
        for z in mo.LUM_ZS:
            n += 1
            lum = new_object(bpy, f"luminaire_{n}", lum_mesh, location=(x, H, z))
            light = new_object(bpy, f"luminaire_{n}_light", None, lum,
                               (0.0, -mo.LUM_Y - mo.LIGHT_DROP, 0.0))
            light.rotation_mode = "QUATERNION"
            light.rotation_quaternion = basis(mo, mo.LIGHT_ROTATION)
            s = light.luxbake_settings
            s.profile = miral
            s.maintenance_factor = mo.MAINTENANCE_FACTOR
            s.use_opening = True
            s.opening = (mo.LUM_Z, mo.LUM_X, 0.0)

    aim = mo.norm(mo.sub(mo.SPOT_TARGET, mo.SPOT_POS))
    spot = new_object(bpy, "spotlight", None, location=mo.SPOT_POS)
    spot.rotation_mode = "QUATERNION"
    spot.rotation_quaternion = basis(mo, mo.look_rotation_minus_z(aim))
    spot.luxbake_settings.profile = os.path.join(OFFICE, "profiles", mo.CNS70[0] + ".ldt")
    spot.luxbake_settings.maintenance_factor = mo.MAINTENANCE_FACTOR

    scene = bpy.context.scene
    for cname, vd, _front, xs, ys, eye_s, focus_s, znear in mo.SEED_CAMERAS:
        eye, focus = mo.seed_to_gltf(eye_s), mo.seed_to_gltf(focus_s)
        cam = bpy.data.cameras.new(cname)
        params = mo.seed_camera(vd, xs, ys, znear)
        cam.sensor_fit = "VERTICAL"
        cam.angle_y = params["yfov"]
        cam.clip_start = znear
        obj = new_object(bpy, cname, cam, location=eye)
        obj.rotation_mode = "QUATERNION"
        obj.rotation_quaternion = basis(mo, mo.look_at_rotation(eye, focus))
        if cname == "camera_interior":
            scene.camera = obj
            scene.render.resolution_x, scene.render.resolution_y = xs, ys

    s = scene.luxbake_settings
    s.use_working_plane = True
    s.working_plane_height = mo.WORKING_PLANE
    s.working_plane_spacing = 0.25


def main(argv):
    if not argv or argv[0].startswith("-"):
        print(__doc__, file=sys.stderr)
        return 2
    out = os.path.abspath(argv[0])
    blend = os.path.abspath(argv[argv.index("--blend") + 1]) if "--blend" in argv else None
    stdout_fd = os.dup(1)
    os.dup2(2, 1)
    import bpy

    if "luxbake" not in bpy.context.preferences.addons.keys() and not any(
            k.endswith(".luxbake") for k in bpy.context.preferences.addons.keys()):
        import addon_utils
        sys.path.insert(0, os.path.dirname(HERE))
        bpy.ops.wm.read_factory_settings(use_empty=True)
        addon_utils.enable("luxbake", default_set=True, handle_error=None)
    # the add-on's operators module: `luxbake.operators`, or `bl_ext.<repo>.luxbake.operators`
    # when installed as an extension
    ops = next(module for name, module in sys.modules.items() if name.endswith("luxbake.operators"))
    mo = load_make_office()
    build(bpy, mo)
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "office.gltf")
    ops.export_scene(path)
    if blend:
        bpy.ops.wm.save_as_mainfile(filepath=blend)
    sys.stdout.flush()
    os.dup2(stdout_fd, 1)
    print(json.dumps({"gltf": path}))
    return 0


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    sys.exit(main(args))
