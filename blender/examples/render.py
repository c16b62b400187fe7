"""Render a luxbake bake imported by the LuxBake add-on, from one of its camera nodes.

Usage: PYTHON blender/examples/render.py LIT.gltf OUT.png [--camera NAME] [--size WxH]
       [--samples N] [--false-colour illuminance|luminance --range LO:HI [--log]]
       [--no-openings] [--plain]
PYTHON is a Python 3.11 with PyPI `bpy` 5.0.1 (or `blender -b -P ... -- ARGS`). The bake is
imported with the add-on (display materials, Standard view transform), then rendered with Cycles
on the CPU (default 16 samples: the materials are pure emission, so samples only antialias).
--no-openings hides the luminaires' openings the add-on draws (to compare with `bake view
--display`, which draws none); --plain imports with Blender's glTF importer alone (add-on not
enabled, Blender's default view transform), to show what the add-on changes.
`blender/make_pictures.sh` makes docs/blender-office-*.png with it.
"""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def opt(argv, name, default=None):
    return argv[argv.index(name) + 1] if name in argv else default


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    lit, out = os.path.abspath(argv[0]), os.path.abspath(argv[1])
    camera = opt(argv, "--camera", "camera_interior")
    width, height = (int(v) for v in opt(argv, "--size", "900x600").split("x"))
    import bpy
    import addon_utils

    bpy.ops.wm.read_factory_settings(use_empty=True)
    if "--plain" in argv:
        bpy.ops.import_scene.gltf(filepath=lit)
    else:
        sys.path.insert(0, os.path.dirname(HERE))
        addon_utils.enable("luxbake", default_set=True, handle_error=None)
        from luxbake import operators

        operators.import_bake(lit)
    openings = bpy.data.collections.get("LuxBake luminaires")
    if openings is not None and "--no-openings" in argv:
        openings.hide_render = True
    scene = bpy.context.scene
    scene.camera = bpy.data.objects[camera]
    quantity = opt(argv, "--false-colour")
    if quantity:
        s = scene.luxbake_settings
        lo, hi = (float(v) for v in opt(argv, "--range").split(":"))
        s.display = quantity.upper()
        s.log_scale = "--log" in argv
        s.range_min, s.range_max = lo, hi
    render = scene.render
    render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = int(opt(argv, "--samples", "16"))
    scene.cycles.use_denoising = False
    render.resolution_x, render.resolution_y = width, height
    render.resolution_percentage = 100
    render.dither_intensity = 0.0  # no noise added: the PNGs compress (and compare) better
    render.image_settings.file_format = "PNG"
    render.image_settings.compression = 100
    render.image_settings.color_mode = "RGB"
    render.filepath = out
    bpy.ops.render.render(write_still=True)
    return 0


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    sys.exit(main(args))
