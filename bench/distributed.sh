#!/usr/bin/env bash
# The distributed bake against the single-process bake on one generated floor:
#   bench/distributed.sh [SIZE] [WORK]     SIZE small|medium|large (default large, 10^6 triangles)
#                                          or a triangle count (bake generate openplan --triangles)
# Bakes SIZE once in one process, then with dask/dask_bake.py on a local Dask cluster of two
# workers (four tasks, TASKS=N for another count), each bake call under /usr/bin/time -v (wall, CPU, peak memory per process);
# compares the two outputs byte for byte. Needs target/release/bake (BAKE=path for another
# build) and dask/install.sh's venv. SINGLE=file.glb takes that file (baked by the same build,
# with its own timing) as the single-process output instead of baking it again.
set -euo pipefail
size="${1:-large}"
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="${2:-$repo/bench/work/distributed-$size}"
bake="${BAKE:-$repo/target/release/bake}"
mkdir -p "$work/times"
rm -f "$work"/times/*
cd "$work"
case "$size" in
  small|medium|large) scale=(--size "$size");;
  *) scale=(--triangles "$size");;
esac
[ -f "$size.gltf" ] || "$bake" generate openplan "${scale[@]}" -o "$size.gltf" -q
# Every bake call of the distributed run timed into times/STAGE-PID.txt.
cat > timed-bake <<SH
#!/usr/bin/env bash
stage=other
[ "\$1" = shard ] && stage=\$2
exec /usr/bin/time -v -o "$work/times/\$stage-\$\$.txt" "$bake" "\$@"
SH
chmod +x timed-bake
if [ -n "${SINGLE:-}" ]; then
  cp "$SINGLE" single.glb
else
  /usr/bin/time -v -o times/single.txt "$bake" "$size.gltf" -o single.glb -q
fi
"$repo/.venv-dask/bin/python" "$repo/dask/dask_bake.py" "$size.gltf" -o dask.glb \
  --local-workers 2 --tasks "${TASKS:-4}" --bake "$work/timed-bake" --timings dask-timings.json
cmp single.glb dask.glb && echo "byte-identical: single.glb dask.glb"
for f in times/*.txt; do
  printf '%-24s wall %-10s user %-9s sys %-7s peak %s KiB\n' "$(basename "$f" .txt)" \
    "$(grep 'Elapsed (wall' "$f" | awk '{print $NF}')" \
    "$(grep 'User time' "$f" | awk '{print $NF}')" \
    "$(grep 'System time' "$f" | awk '{print $NF}')" \
    "$(grep 'Maximum resident' "$f" | awk '{print $NF}')"
done
cat dask-timings.json
