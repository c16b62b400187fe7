"""Build the LuxBake extension zip: blender/dist/luxbake-<version>.zip.

Usage: python3 blender/build_extension.py [--output-dir DIR] [--blender BLENDER]

It runs Blender's own extension builder on blender/luxbake/ (the folder with
blender_manifest.toml): `BLENDER --command extension build --source-dir ... --output-dir ...`
when a `blender` executable is given or on PATH, else the same builder as a script,
`bl_pkg/cli/blender_ext.py build`, from the PyPI `bpy` module's bundled add-ons (run with the
Python that has bpy, e.g. .venv-bpy/bin/python). Both check the manifest and write the same zip.
Prints the zip's path.
"""

import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.join(HERE, "luxbake")


def builder(blender):
    """The command that builds, without its build arguments."""
    blender = blender or shutil.which("blender")
    if blender:
        return [blender, "--factory-startup", "--command", "extension", "build"]
    try:
        import bpy
    except ImportError:
        sys.exit("no `blender` on PATH and no bpy module in this Python: run it with "
                 ".venv-bpy/bin/python or pass --blender")
    scripts = bpy.utils.system_resource("SCRIPTS")
    return [sys.executable, os.path.join(scripts, "addons_core", "bl_pkg", "cli", "blender_ext.py"),
            "build"]


def main(argv):
    out = os.path.abspath(argv[argv.index("--output-dir") + 1]) if "--output-dir" in argv \
        else os.path.join(HERE, "dist")
    blender = argv[argv.index("--blender") + 1] if "--blender" in argv else None
    os.makedirs(out, exist_ok=True)
    for cache in ("__pycache__",):
        shutil.rmtree(os.path.join(SOURCE, cache), ignore_errors=True)
    command = builder(blender) + ["--source-dir", SOURCE, "--output-dir", out]
    subprocess.run(command, check=True, stdout=sys.stderr)
    version = next(line.split('"')[1] for line in open(os.path.join(SOURCE, "blender_manifest.toml"))
                   if line.startswith("version"))
    print(os.path.join(out, f"luxbake-{version}.zip"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
