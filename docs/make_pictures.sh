#!/bin/sh
# Makes the pictures of README.md and the manual (docs/) from samples/office: a bake at default quality with
# lightmaps and a working plane, the seed's three viewpoints (the office's camera nodes, at the
# seed's image sizes: its Appendix C) as EXR (cd/m², ZIP), tone-mapped PNG and log false colour,
# and the working plane's isolux plan as SVG and PNG; the designer's report (bake report --format html)
# of a vertex bake with a working plane and a probe grid, printed to PDF and shot as a PNG by headless
# Chromium (Debian `chromium`). Deterministic: run again, same bytes (the PDF aside: Chromium dates it).
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
# The report: a bake of its own, with a probe grid at 1.2 m for the cubic illuminance (figures
# from vertices).
mkdir "$work/report"
$bake samples/office/office.gltf -o "$work/report/office-lit.gltf" --working-plane 0.8 \
    --probe-grid 1.5 --probe-height 1.2 -q
$bake report "$work/report/office-lit.gltf" --format html --targets samples/office/targets.json \
    --border 0.5 -o docs/report-office.html
page="file://$PWD/docs/report-office.html"
chromium="chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --no-pdf-header-footer"
$chromium --print-to-pdf=docs/report-office.pdf "$page" 2>/dev/null
$chromium --window-size=900,1300 --screenshot=docs/report-office.png "$page" 2>/dev/null
ls -l docs/office-* docs/plan-office-* docs/report-office.*
