#!/bin/sh
# Makes the pictures of README.md and docs/ from samples/office: a bake at default quality with
# lightmaps and a working plane, the seed's three viewpoints (the office's camera nodes, at the
# seed's image sizes: its Appendix C) as EXR (cd/m², ZIP), tone-mapped PNG and log false colour,
# and the working plane's isolux plan as SVG and PNG. Deterministic: run again, same bytes.
set -eu
cd "$(dirname "$0")/.."
cargo build --release --quiet
bake=target/release/bake
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
$bake samples/office/office.gltf -o "$work/lit.gltf" --lightmaps --working-plane 0.8 -q
for view in front:820x530 side:800x380 interior:900x600; do
    name=${view%%:*}
    size=${view#*:}
    $bake view "$work/lit.gltf" --camera "camera_$name" --size "$size" --zip \
        -o "docs/office-$name.exr" --png "docs/office-$name.png" \
        --false-colour "docs/office-$name-false-colour.png" --log --steps 12 --contours
done
$bake plan "$work/lit.gltf" -o docs/plan-office-working-plane.svg
$bake plan "$work/lit.gltf" -o docs/plan-office-working-plane.png
ls -l docs/office-* docs/plan-office-*
