#!/bin/sh
# What a viewer shows (issue 57): bakes four scenes with the given `bake` binary and renders each
# as three.js (headless Chromium) and `bake view --display` show it, and in Blender (the add-on,
# Cycles) where the scene has a camera node. Used to commit before/after pictures:
#   sh bench/viewer_renders.sh BAKE OUT_DIR PREFIX
# Scenes: samples/office (vertex colours and lightmaps, camera_interior), the Cornell box
# (lightmaps, the published camera), bench/window_room.py's furnished room lit by a window
# panel (vertex colours and lightmaps, camera_room) and the 10^4 generated open-plan floor
# (vertex colours, from above a desk cluster). +Y up throughout. Needs node + npm three
# (bench/render), Debian chromium, and for Blender .venv-bpy.
set -eu
bake=$(realpath "$1"); out=$(realpath "$2"); prefix=$3
cd "$(dirname "$0")/.."
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
python3 bench/window_room.py "$work"
[ -f "$work/floor.gltf" ] || "$bake" generate openplan --size small -o "$work/floor.gltf" -q
three() { node bench/render/render.mjs "$@" >/dev/null 2>&1; }
shot() { # name lit view-args...
    name=$1; lit=$2; shift 2
    three "$lit" "$out/$prefix-$name-three.png" "$@" --size 900x600
    "$bake" view "$lit" -o "$work/v.exr" "$@" --size 900x600 --display "$out/$prefix-$name-view.png"
}
blender() { # name lit camera
    [ -x .venv-bpy/bin/python ] || return 0
    .venv-bpy/bin/python blender/examples/render.py "$2" "$out/$prefix-$1-blender.png" \
        --camera "$3" --size 900x600 --samples 16 >/dev/null 2>&1
}
for mode in vertex lightmaps; do
    flag=""; [ $mode = lightmaps ] && flag=--lightmaps
    mkdir -p "$work/office-$mode" "$work/window-$mode"
    "$bake" samples/office/office.gltf -o "$work/office-$mode/lit.gltf" $flag -q
    shot office-$mode "$work/office-$mode/lit.gltf" --camera camera_interior
    blender office-$mode "$work/office-$mode/lit.gltf" camera_interior
    "$bake" "$work/window_room.gltf" -o "$work/window-$mode/lit.gltf" $flag -q
    shot window-$mode "$work/window-$mode/lit.gltf" --camera camera_room
    blender window-$mode "$work/window-$mode/lit.gltf" camera_room
done
mkdir -p "$work/cornell" "$work/floor"
"$bake" samples/cornell-box/cornell-box.obj -o "$work/cornell/lit.gltf" --lightmaps -q
shot cornell-lightmaps "$work/cornell/lit.gltf" --eye 0.278,0.273,-0.8 --target 0.278,0.273,0 --fov 39.3
"$bake" "$work/floor.gltf" -o "$work/floor/lit.gltf" -q
shot floor-vertex "$work/floor/lit.gltf" --eye 3,4.5,-1.5 --target 5,0.5,3 --fov 60
ls "$out" | grep "^$prefix-"
