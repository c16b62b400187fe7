#!/bin/sh
# Contact-geometry pictures: bakes the picture-wall scene (bench/picture_wall.py: box, quad and
# no picture) and the Cornell box with BINARY at default quality, renders them with
# bench/render/render.mjs and measures the wall beside the picture (bench/contact_profile.py).
#
#   sh bench/contacts.sh BINARY TAG [WORK_DIR]     # e.g. sh bench/contacts.sh target/release/bake after
#
# Writes bench/results/contacts/TAG-{picture-front,picture-grazing,picture-quad-front,cornell}.png
# and TAG-profile.md; bakes go to WORK_DIR (default bench/work/contacts-TAG, not committed).
# AT=HASH: the commit BINARY was built at, for TAG-profile.md's provenance line (default HEAD).
# Fixed exposures (50 lx picture wall, 900 lx Cornell box; near the auto values of the b517572
# bakes, 49.1 and 900.9 lx) so that images of two binaries share one scale.
set -eu
[ $# -ge 2 ] || { echo "usage: sh bench/contacts.sh BINARY TAG [WORK_DIR]" >&2; exit 2; }
bench=$(cd "$(dirname "$0")" && pwd)
bin=$(realpath "$1")
tag=$2
work=${3:-$bench/work/contacts-$tag}
out=$bench/results/contacts
render="nice -n 15 node $bench/render/render.mjs"
mkdir -p "$work" "$out"
sh "$bench/render/install.sh" >/dev/null

python3 "$bench/picture_wall.py" "$work" >/dev/null
for v in box quad none; do
    nice -n 15 "$bin" "$work/picture-wall-$v.gltf" -o "$work/baked-$v.gltf" -q --exposure 50 \
        --summary-json "$work/summary-$v.json"
done
nice -n 15 "$bin" "$bench/../samples/cornell-box/cornell-box.obj" -o "$work/baked-cornell.gltf" \
    -q --exposure 900 --summary-json "$work/summary-cornell.json"

# Head-on from z = 1.6 m: the picture (x 1.6..2.4, y 1.2..1.8) and >= 30 cm of wall around it
# (41.1 deg vertical: 1.2 m tall, 1.6 m wide at the wall). Grazing: from the left, about 14 deg.
$render "$work/baked-box.gltf" "$out/$tag-picture-front.png" --eye 2.0,1.5,1.6 \
    --target 2.0,1.5,0.0 --fov 41.1 --size 1000x750
$render "$work/baked-box.gltf" "$out/$tag-picture-grazing.png" --eye 0.4,1.6,0.4 \
    --target 2.0,1.5,0.0 --fov 40 --size 1000x750
$render "$work/baked-quad.gltf" "$out/$tag-picture-quad-front.png" --eye 2.0,1.5,1.6 \
    --target 2.0,1.5,0.0 --fov 41.1 --size 1000x750
# Cornell box from its open front, above Cornell's published camera ((0.278, 0.273, -0.8) m,
# 39.3 deg) and looking down a little, so that the whole floor and the blocks' shadows show.
$render "$work/baked-cornell.gltf" "$out/$tag-cornell.png" --eye 0.278,0.45,-0.75 \
    --target 0.278,0.2,0.28 --fov 42 --size 1000x750

{
    echo "# Wall illuminance beside the picture: $tag"
    echo
    python3 "$bench/provenance.py" all "sh bench/contacts.sh $1 $tag"
    echo
    echo "Binary: \`$1\` ($("$bin" --version), sha256 $(sha256sum "$bin" | cut -c1-16)...)," \
        "default quality. \`python3 bench/contact_profile.py --reference baked-none.gltf" \
        "baked-box.gltf baked-quad.gltf\`"
    echo
    python3 "$bench/contact_profile.py" --reference "$work/baked-none.gltf" \
        "$work/baked-box.gltf" "$work/baked-quad.gltf"
} > "$out/$tag-profile.md"
tail -n 4 "$out/$tag-profile.md"
ls -l "$out/$tag"-*
