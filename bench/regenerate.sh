#!/bin/sh
# Regenerates every results file under bench/results/ and the manual's pictures (issue 58,
# item 2). Every results page names, under its title, the commit its figures were measured at,
# the date, the machine and its command (a `Provenance:` line; tests/results_provenance.rs checks
# it, and that every page and picture is named here).
#
#   sh bench/regenerate.sh quick     # about 13 min on 2 cores (build included): the cheap generated pages
#   sh bench/regenerate.sh all       # quick + the long runs (the 10^6 floor, RADIANCE references,
#                                    # pictures): about 7 h on 2 cores
#   sh bench/regenerate.sh manual    # the measurements behind the hand-written pages (about 3.5 h);
#                                    # their raw output goes to bench/work/manual/, the prose and
#                                    # tables of those pages are edited from it by hand
#   sh bench/regenerate.sh list      # print every step (time, files, command), run nothing
#
# One step per line: `step TIME FILES COMMAND...`, TIME the estimate on the 2-core, 23.5 GiB
# machine (no other load), FILES what the command writes (relative to the repository root).
# Pages that compare with an older build (`before-*`, `2f737ca-*`) build that commit's `bake`
# first (`binary_at`, from `git archive`, into bench/work/bin-COMMIT; about 6 min each).
# Steps run in order and stop at the first failure (set -e). DRY=1 = `list`.
set -eu
cd "$(dirname "$0")/.."
bake=target/release/bake
W=bench/work/regenerate
section=${1:-list}
[ "$section" = list ] && DRY=1
DRY=${DRY:-}

step() {
    est=$1; files=$2; shift 2
    cmd=
    for a in "$@"; do
        case "$a" in *[[:space:]]*|'') cmd="$cmd '$a'" ;; *) cmd="$cmd $a" ;; esac
    done
    printf '== [%s]%s\n     -> %s\n' "$est" "$cmd" "$files"
    [ -n "$DRY" ] && return 0
    "$@"
}

# binary_at COMMIT: a release `bake` built from COMMIT's tree (no worktree, no checkout).
binary_at() {
    dir=bench/work/bin-$1
    if [ ! -x "$dir/target/release/bake" ]; then
        mkdir -p "$dir"
        git archive "$1" | tar -x -C "$dir"
        (cd "$dir" && cargo build --release --quiet --bin bake)
    fi
    echo "$dir/target/release/bake"
}

build() { step "3 min" "target/release/bake" cargo build --release --quiet --bin bake; }

quick() {
    step "4 min (+10 min for the first test build)" "bench/results/closed_forms.md" \
        python3 bench/closed_forms.py
    step "1 min" "bench/results/skips.md" \
        python3 bench/skips.py
    step "1 min" "bench/results/diff.md" \
        python3 bench/diff_timing.py
    step "20 s" "bench/results/intensity.md" \
        python3 bench/intensity_timing.py
    step "2 min" "bench/results/lightmaps/readback.md" \
        python3 bench/lightmap_readback.py
    step "1 min" "bench/results/building/results.md bench/results/building/results.json" \
        python3 bench/building.py --run default= --run "high=--quality high"
    step "1 min" "bench/results/office-panels-rerun.md (its first, comment line by hand)" \
        python3 bench/run.py --scenes office-panels --out "$W/office-panels" --work "$W/office-panels-work"
    step "0 s" "bench/results/office-panels-rerun.md" \
        cp "$W/office-panels/results.md" bench/results/office-panels-rerun.md
}

long() {
    step "15 min" "bench/results/results.md bench/results/results.json bench/results/time_vs_error.svg bench/results/scaling.svg" \
        python3 bench/run.py
    step "90 min" "bench/results/openplan-scaling/results.md bench/results/openplan-scaling/results.json bench/results/openplan-scaling/scaling.svg" \
        python3 bench/run.py --scenes openplan --openplan-sizes small,medium,large --openplan-limit 4500 \
        --out bench/results/openplan-scaling --work "$W/openplan-scaling"
    step "8 min" "bench/results/building/reference.json bench/results/building/results.md bench/results/building/results.json (bench/results/building/README.md by hand)" \
        python3 bench/building.py --recompute --run default= --run "high=--quality high"
    step "5 min" "bench/results/contacts/bench/results.md bench/results/contacts/bench/results.json bench/results/contacts/bench/time_vs_error.svg" \
        python3 bench/run.py --scenes office,office-panels --out bench/results/contacts/bench --work "$W/contacts-bench"
    step "3 min" "bench/results/contacts/after-*.png bench/results/contacts/after-profile.md (bench/results/contacts/README.md by hand)" \
        sh bench/contacts.sh "$bake" after
    if [ -z "$DRY" ]; then b=$(binary_at b517572); else b='$(binary_at b517572)'; fi
    step "9 min" "bench/results/contacts/before-*.png bench/results/contacts/before-profile.md" \
        env AT=b517572 sh bench/contacts.sh "$b" before
    if [ -z "$DRY" ]; then b=$(binary_at 2f737ca); else b='$(binary_at 2f737ca)'; fi
    step "9 min" "bench/results/contacts/2f737ca-*.png bench/results/contacts/2f737ca-profile.md" \
        env AT=2f737ca sh bench/contacts.sh "$b" 2f737ca
    step "30 min" "bench/results/lightmaps/cost.md bench/results/lightmaps/error.md bench/results/lightmaps/floor.md bench/results/lightmaps/*.png (bench/results/lightmaps/README.md by hand)" \
        sh bench/lightmaps.sh "$bake" "$W/lightmaps"
    step "6 min" "bench/results/lightmaps/cycles.md" \
        .venv-bpy/bin/python bench/cycles_lightmap.py --work "$W/cycles"
    step "5 min" "$W/view/results.json (bench/results/view/README.md by hand)" \
        bench/.venv/bin/python bench/view_rpict.py --repeats 5 \
        --rpict "ab7:-ab 7 -ad 256 -as 64 -aa 0.2 -ar 32 -lw 2e-3" --out "$W/view"
    step "0 s" "bench/results/view/results.json" \
        cp "$W/view/results.json" bench/results/view/results.json
    step "25 min" "bench/data/openplan_small_plane_radiance.json $W/floor-accuracy/results.json (bench/results/floor-accuracy/README.md by hand)" \
        python3 bench/floor_accuracy.py --work "$W/floor-accuracy"
    step "20 min" "bench/results/floor-accuracy/surfaces.json (bench/results/floor-accuracy/inter-reflection.md by hand)" \
        python3 bench/surface_accuracy.py --work "$W/surface-accuracy" --out bench/results/floor-accuracy/surfaces.json
    step "10 min" "bench/results/distributed/medium-dask-timings.json (bench/results/distributed/README.md by hand)" \
        bash bench/distributed.sh medium "$W/distributed-medium"
    step "0 s" "bench/results/distributed/medium-dask-timings.json" \
        cp "$W/distributed-medium/dask-timings.json" bench/results/distributed/medium-dask-timings.json
    step "25 min" "bench/results/distributed/3e5-dask-timings.json" \
        bash bench/distributed.sh 300000 "$W/distributed-3e5"
    step "0 s" "bench/results/distributed/3e5-dask-timings.json" \
        cp "$W/distributed-3e5/dask-timings.json" bench/results/distributed/3e5-dask-timings.json
    step "130 min" "bench/results/distributed/1e6-dask-timings.json (the 10^6-triangle floor: one single-process bake of about 68 min, then the distributed one)" \
        bash bench/distributed.sh large "$W/distributed-1e6"
    step "0 s" "bench/results/distributed/1e6-dask-timings.json" \
        cp "$W/distributed-1e6/dask-timings.json" bench/results/distributed/1e6-dask-timings.json
    step "2 min" "bench/results/lightmaps/packers.md's tables (bench/results/lightmaps/packers.md by hand)" \
        sh -c 'cd bench/packers && cargo run --release --quiet'
    # The manual's pictures.
    step "2 min" "docs/office-*.png docs/office-*.exr docs/plan-office-working-plane.svg docs/plan-office-working-plane.png docs/report-office.html docs/report-office.pdf docs/report-office.png" \
        sh docs/make_pictures.sh
    step "4 min" "docs/blender-office-interior.png docs/blender-office-interior-lightmaps.png docs/blender-office-interior-false-colour.png" \
        sh blender/make_pictures.sh
    step "6 min" "docs/renders/after-*.png" \
        sh bench/viewer_renders.sh "$bake" docs/renders after
    if [ -z "$DRY" ]; then b=$(binary_at 4c45b72); else b='$(binary_at 4c45b72)'; fi
    step "12 min" "docs/renders/before-*.png (the 4c45b72 build)" \
        sh bench/viewer_renders.sh "$b" docs/renders before
}

manual() {
    m=bench/work/manual
    [ -n "$DRY" ] || mkdir -p "$m"
    for size in small medium large; do
        step "1 min" "$m/openplan-$size.gltf" \
            "$bake" generate openplan --size "$size" -o "$m/openplan-$size.gltf" -q
    done
    step "80 min" "$m/openplan-*.glb $m/openplan-*.summary.json (bench/results/floor-stages.md by hand, with the builds it names: binary_at COMMIT)" \
        sh -c "for s in small medium large; do $bake $m/openplan-\$s.gltf -o $m/openplan-\$s.glb -q --summary-json $m/openplan-\$s.summary.json; done"
    step "10 min" "$m/direct-floor.txt (bench/results/direct-floor.md by hand)" \
        sh -c "for s in small medium large; do cargo run --release --quiet --example direct_floor -- $m/openplan-\$s.gltf 1 $m/openplan-\$s.glb; done > $m/direct-floor.txt"
    step "5 min" "$m/direct-budget.txt (bench/results/direct-budget.md by hand)" \
        sh -c "for p in small:1 medium:4 large:200; do cargo run --release --quiet --example direct_budget -- $m/openplan-\${p%:*}.gltf \${p#*:} 0.01 0.03 0.1; done > $m/direct-budget.txt"
    step "10 min" "$m/ray-speed.txt (bench/results/ray-speed.md by hand)" \
        sh -c "for p in small:4 medium:16 large:64; do cargo run --release --quiet --example ray_speed -- $m/openplan-\${p%:*}.gltf \${p#*:} 256; done > $m/ray-speed.txt"
    step "3 min" "$m/fit.txt (bench/results/fit/README.md by hand)" \
        sh -c "farm-bench -n 5 'target/release/bake fit samples/office/office.gltf --design samples/office/table1.csv -o $m/f.gltf -q' 'target/release/bake samples/office/office.gltf -o $m/plain.gltf -q' > $m/fit.txt"
    step "10 min" "$m/receiver-sharing.txt (bench/results/receiver-sharing/README.md by hand)" \
        sh -c "farm-bench -n 5 '$bake $m/openplan-small.gltf -o $m/a.glb -q' '$bake $m/openplan-small.gltf -o $m/b.glb -q --receiver-tolerance 0' > $m/receiver-sharing.txt; $bake diff $m/b.glb $m/a.glb >> $m/receiver-sharing.txt || true"
    step "10 min" "$m/light-hierarchy.txt (bench/results/light-hierarchy/README.md by hand)" \
        sh -c "for f in 0 0.01; do /usr/bin/time -v $bake $m/openplan-medium.gltf -o $m/cut-\$f.glb -q --light-cut-fraction \$f; done > $m/light-hierarchy.txt 2>&1"
    step "10 min" "$m/limits.txt (bench/results/limits.md by hand: its table's scenes and settings)" \
        sh -c "for s in small medium; do /usr/bin/time -v $bake $m/openplan-\$s.gltf -o $m/lim-\$s.glb -q --threads 1; $bake $m/openplan-\$s.gltf -o $m/lim-\$s.glb --threads 1 --max-patches 1 || true; done > $m/limits.txt 2>&1"
    step "60 min" "$m/fuzz.txt (bench/results/fuzz/README.md by hand; cargo fuzz on nightly, see fuzz/README.md)" \
        sh -c "cd fuzz && for t in \$(ls fuzz_targets | sed 's/\.rs\$//'); do cargo +nightly fuzz run \$t -- -max_total_time=360 -timeout=10 -rss_limit_mb=4096 -malloc_limit_mb=4096; done > ../$m/fuzz.txt 2>&1"
}

case "$section" in
    quick) build; quick ;;
    all) build; quick; long ;;
    manual) build; manual ;;
    list) echo "# quick"; quick; echo "# all = quick +"; long; echo "# manual"; manual ;;
    *) echo "usage: sh bench/regenerate.sh quick|all|manual|list" >&2; exit 2 ;;
esac
