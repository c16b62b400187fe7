"""Load one image file with Blender (`bpy.data.images.load`) and print its pixels as JSON.

Usage: PYTHON blender_image.py FILE
PYTHON is a Python 3.11 with the PyPI `bpy` module (5.0.1), e.g. `.venv-bpy/bin/python`.
Stdout receives {"size": [W, H], "channels", "is_float", "colorspace", "file_format",
"rows": [[[R, G, B, A], ...], ...]}, rows as Blender stores them: rows[0] is the BOTTOM row of
the image. Exit status 0 on success, 1 when loading fails.
"""

import json
import os
import sys


def main(argv):
    if len(argv) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    stdout_fd = os.dup(1)
    os.dup2(2, 1)  # Blender logs to fd 1
    try:
        import bpy

        image = bpy.data.images.load(os.path.abspath(argv[0]))
        w, h = image.size
        c = image.channels
        pixels = list(image.pixels)
        report = {
            "size": [w, h],
            "channels": c,
            "is_float": image.is_float,
            "colorspace": image.colorspace_settings.name,
            "file_format": image.file_format,
            "rows": [
                [pixels[c * (y * w + x) : c * (y * w + x) + c] for x in range(w)]
                for y in range(h)
            ],
        }
    except Exception as error:
        os.dup2(stdout_fd, 1)
        print(f"blender could not load {argv[0]}: {error!r}", file=sys.stderr)
        return 1
    sys.stdout.flush()
    os.dup2(stdout_fd, 1)
    json.dump(report, sys.stdout)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
