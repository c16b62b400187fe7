"""Install the LuxBake extension zip as a user would (Blender's "Install from Disk":
`bpy.ops.extensions.package_install_files`) into the user repository, then export a plane with
Blender's plain glTF export (File > Export) and print what the add-on added, as JSON.

Usage: BLENDER_USER_RESOURCES=EMPTY_DIR PYTHON install_zip.py LUXBAKE.zip OUT_DIR
(BLENDER_USER_RESOURCES keeps the install out of the real user's Blender configuration.)
Then a spot light carrying a profile is exported with Punctual Lights off (the default): the
export must fail, saying so, and write nothing.
Stdout: {"modules": [enabled add-on modules], "operators": bool, "material": {...}, "probe": ...,
         "lights_off": the error's last line, "lights_off_written": bool}
"""

import json
import os
import sys


def main(zip_path, out):
    stdout_fd = os.dup(1)
    os.dup2(2, 1)
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    result = bpy.ops.extensions.package_install_files(
        filepath=zip_path, repo="user_default", enable_on_install=True)
    modules = [m for m in bpy.context.preferences.addons.keys() if "luxbake" in m]

    mesh = bpy.data.meshes.new("plane")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [], [(0, 1, 2, 3)])
    material = bpy.data.materials.new("grey")
    material.luxbake_settings.reflectance_mode = "VALUE"
    material.luxbake_settings.reflectance = 0.4
    mesh.materials.append(material)
    plane = bpy.data.objects.new("plane", mesh)
    bpy.context.scene.collection.objects.link(plane)
    probe = bpy.data.objects.new("probe", None)
    probe.location = (0.5, 0.5, 1.0)
    probe.luxbake_settings.probe = True
    bpy.context.scene.collection.objects.link(probe)
    path = os.path.join(out, "plane.gltf")
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLTF_SEPARATE")
    with open(path) as f:
        gltf = json.load(f)
    # a profile on a Light with the export's Punctual Lights off: the export fails, saying so
    lamp = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "SPOT"))
    lamp.luxbake_settings.profile = os.path.join(out, "any.ies")
    bpy.context.scene.collection.objects.link(lamp)
    try:
        bpy.ops.export_scene.gltf(filepath=os.path.join(out, "lamp.gltf"), export_format="GLTF_SEPARATE")
        refused = None
    except RuntimeError as error:
        refused = str(error).strip().splitlines()[-1]
    report = {
        "lights_off": refused,
        "lights_off_written": os.path.exists(os.path.join(out, "lamp.gltf")),
        "install": sorted(result),
        "modules": modules,
        "operators": hasattr(bpy.ops.luxbake, "bake"),
        "material": gltf["materials"][0],
        "probe": next(n.get("extras") for n in gltf["nodes"] if n["name"] == "probe"),
    }
    sys.stdout.flush()
    os.dup2(stdout_fd, 1)
    print(json.dumps(report))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
