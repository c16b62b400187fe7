#!/usr/bin/env python3
"""Markdown tables of bench/lightmaps.sh's cost and floor steps (standard library only).

  python3 bench/lightmap_tables.py cost WORK      # WORK/cost-Q.json (paired.py) + summaries
  python3 bench/lightmap_tables.py floor WORK     # WORK/floor-SIZE-Q-{vc,lm}.{time,summary.json},
                                                  # WORK/floor-SIZE.gen.txt (bake generate's line)

Stage times come from each bake's --summary-json (timingsSeconds), wall time and peak memory of
the floor bakes from /usr/bin/time -v.
"""
import glob
import json
import os
import re
import sys


def load(path):
    with open(path) as f:
        return json.load(f)


def rng(d, f="{:.2f}"):
    return f"{f.format(d['median'])} ({f.format(d['min'])}–{f.format(d['max'])})"


# Default --lightmap-tolerance per quality (src/settings.rs, Quality::lightmap_tolerance).
DEFAULT_TOLERANCE = {"draft": 0.03, "default": 0.01, "high": 0.0}


def cost(work):
    print("| quality | lightmap tolerance | texel size (m) | texels | atlases | charts | gathered "
          "texels | pairs | vertex-only wall s | with lightmaps wall s | ratio wall | ratio CPU | "
          "peak MiB vertex-only / lightmaps |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for path in sorted(glob.glob(os.path.join(work, "cost-*.json")),
                       key=lambda p: ["draft", "default", "high"].index(
                           os.path.basename(p)[5:-5].split("-")[0])):
        tag = os.path.basename(path)[5:-5]
        if tag.endswith(".summary"):
            continue
        r = load(path)
        s = load(os.path.join(work, f"cost-{tag}-lm.summary.json"))
        lm = s["lightmaps"]
        tol = s["settings"]["lightmaps"].get("tolerance")
        atl = " + ".join(f"{w}×{h}" for w, h in lm["atlases"])
        q = s["settings"]["quality"]
        tol = f"default ({DEFAULT_TOLERANCE[q]:g})" if tol is None else f"{tol:g}"
        print(f"| {q} | {tol} | "
              f"{lm['texelSizeM']:g} | {lm['texels']} | {atl} | {lm['charts']} | "
              f"{lm['gatheredTexels']} | {r['pairs']} | {rng(r['b_wall'])} | {rng(r['a_wall'])} | "
              f"**{rng(r['ratio_wall'])}** | {rng(r['ratio_cpu'])} | "
              f"{r['b_peakMiB']['median']:.0f} / {r['a_peakMiB']['median']:.0f} |")


def gnu_time(path):
    text = open(path).read()
    m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", text)
    parts = [float(x) for x in m.group(1).split(":")]
    wall = sum(p * 60 ** i for i, p in enumerate(reversed(parts)))
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1)) / 1024
    cpu = (float(re.search(r"User time \(seconds\): (\S+)", text).group(1))
           + float(re.search(r"System time \(seconds\): (\S+)", text).group(1)))
    return wall, cpu, rss


def floor(work):
    print("| floor | triangles | quality | texel size (m) | texels | atlases | charts | gathered "
          "texels | lightmap stage s | other stages s (with lightmaps) | vertex-only bake: stages s "
          "| wall s vertex-only / lightmaps | peak RSS MiB vertex-only / lightmaps |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    runs = [os.path.basename(p)[6:-len("-lm.summary.json")]
            for p in glob.glob(os.path.join(work, "floor-*-lm.summary.json"))]
    order = {"small": 0, "medium": 1, "large": 2, "default": 0, "draft": 1, "high": 2}
    for run in sorted(runs, key=lambda r: [order.get(x, 9) for x in r.split("-")]):
        size = run.split("-")[0]
        s = load(os.path.join(work, f"floor-{run}-lm.summary.json"))
        v = load(os.path.join(work, f"floor-{run}-vc.summary.json"))
        lm = s["lightmaps"]
        t = s["timingsSeconds"]
        other = sum(x for k, x in t.items() if k != "lightmaps")
        vstages = sum(v["timingsSeconds"].values())
        wv, _, rv = gnu_time(os.path.join(work, f"floor-{run}-vc.time"))
        wl, _, rl = gnu_time(os.path.join(work, f"floor-{run}-lm.time"))
        gen = os.path.join(work, f"floor-{size}.gen.txt")
        m = re.search(r"(\d+) triangles", open(gen).read()) if os.path.exists(gen) else None
        tris = m.group(1) if m else "?"
        atl = " + ".join(f"{w}×{h}" for w, h in lm["atlases"])
        print(f"| {size} | {tris} | {s['settings']['quality']} | {lm['texelSizeM']:g} | "
              f"{lm['texels']} | {atl} | {lm['charts']} | {lm['gatheredTexels']} | "
              f"{t['lightmaps']:.1f} | {other:.1f} | {vstages:.1f} | {wv:.0f} / {wl:.0f} | "
              f"{rv:.0f} / {rl:.0f} |")
        if lm.get("coarser"):
            print(f"\n{run}: coarser texels where the count passed the cap: {lm['coarser']}\n")


def main():
    if len(sys.argv) == 3 and sys.argv[1] in ("cost", "floor"):
        {"cost": cost, "floor": floor}[sys.argv[1]](sys.argv[2])
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
