#!/bin/sh
# The pictures of the manual's Blender chapter (docs/blender.md), by the round trip it describes: samples/office
# rebuilt in Blender (blender/examples/office.py), exported by the LuxBake add-on, baked, imported
# back by the add-on and rendered with Cycles from the seed's interior camera
# (blender/examples/render.py). Needs a Python with PyPI bpy 5.0.1 ($LUXBAKE_BPY_PYTHON, else
# .venv-bpy/bin/python) and a built bake (cargo build --release).
set -eu
cd "$(dirname "$0")/.."
py=${LUXBAKE_BPY_PYTHON:-.venv-bpy/bin/python}
bake=target/release/bake
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$py" blender/examples/office.py "$work/blender" >/dev/null 2>&1
"$bake" "$work/blender/office.gltf" -o "$work/office-lit.gltf" -q
"$bake" "$work/blender/office.gltf" -o "$work/office-lightmaps.gltf" --lightmaps -q
render() { "$py" blender/examples/render.py "$@" >/dev/null 2>&1; }
render "$work/office-lit.gltf" docs/blender-office-interior.png
render "$work/office-lightmaps.gltf" docs/blender-office-interior-lightmaps.png
render "$work/office-lit.gltf" docs/blender-office-interior-false-colour.png \
  --false-colour illuminance --range 0:1000
echo "wrote docs/blender-office-interior{,-lightmaps,-false-colour}.png"
