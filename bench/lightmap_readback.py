"""`bake report` and `bake diff` of the office sample with lightmaps: wall time, CPU time and
peak memory, beside the same commands on its vertex-only bake.

    python3 bench/lightmap_readback.py [--repeats N] [--work DIR]
        → bench/results/lightmaps/readback.md

Builds `bake`, bakes samples/office/office.gltf without lightmaps and with `--lightmaps` at the
default texel size (5 cm), at 10 cm and at 2 cm (each bake once), then runs every command N
times (default 7), each run measured by measure.py. Report: from texels (the lightmapped bakes)
or vertices. Diff: a bake against itself (texel by texel, or vertex by vertex), 5 cm against
10 cm and against 2 cm (other layouts: sampled at vertices and triangle centroids). Python
standard library only.
"""

import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cargo_example  # noqa: E402
import measure  # noqa: E402

BENCH = cargo_example.BENCH
ROOT = cargo_example.ROOT



def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--work", default=os.path.join(BENCH, "work", "lightmap_readback"))
    ap.add_argument("--out",
                    default=os.path.join(BENCH, "results", "lightmaps", "readback.md"))
    a = ap.parse_args()
    bake = cargo_example.build_bake()
    os.makedirs(a.work, exist_ok=True)
    office = os.path.join(ROOT, "samples", "office", "office.gltf")
    bakes = {"vertices": [], "5cm": ["--lightmaps"],
             "10cm": ["--lightmaps", "--texel-size", "0.1"],
             "2cm": ["--lightmaps", "--texel-size", "0.02"]}
    texels = {}
    for name, extra in bakes.items():
        out = os.path.join(a.work, f"{name}.gltf")
        r = measure.run([bake, office, "-o", out, "-q"] + extra)
        if r["returncode"] != 0:
            raise SystemExit(f"bake {name} failed")
        lm = json.load(open(out))["scenes"][0]["extras"]["luxbake"].get("lightmaps")
        texels[name] = lm["texels"] if lm else 0
    p = {name: os.path.join(a.work, f"{name}.gltf") for name in bakes}
    commands = [
        ("report, vertex-only bake", [bake, "report", p["vertices"]], 0),
        ("report, 5 cm texels", [bake, "report", p["5cm"]], 0),
        ("report, 2 cm texels", [bake, "report", p["2cm"]], 0),
        ("diff, vertex-only bake against itself", [bake, "diff", p["vertices"], p["vertices"]], 0),
        ("diff, 5 cm against itself (texels)", [bake, "diff", p["5cm"], p["5cm"]], 0),
        ("diff, 2 cm against itself (texels)", [bake, "diff", p["2cm"], p["2cm"]], 0),
        ("diff, 5 cm against 10 cm (samples)", [bake, "diff", p["5cm"], p["10cm"]], 1),
        ("diff, 5 cm against 2 cm (samples)", [bake, "diff", p["5cm"], p["2cm"]], 1),
    ]
    lines = cargo_example.header("`bake report` and `bake diff` of lightmapped bakes",
                                 "python3 bench/lightmap_readback.py", bake)
    lines += [f"Inputs: `samples/office/office.gltf` baked without lightmaps and with "
              f"`--lightmaps` at 5 cm ({texels['5cm']} texels with a footprint), 10 cm "
              f"({texels['10cm']}) and 2 cm ({texels['2cm']}). Each command ran {a.repeats} "
              "times, one after the other; times in ms, peak resident memory in MiB (largest "
              "of the runs). A diff of other layouts fails (exit 1): the office has shadows "
              "and contacts, where texel sizes differ most.", "",
              "| command | exit | wall min / median / max | CPU min / median / max | peak MiB |",
              "| --- | ---: | --- | --- | ---: |"]
    for name, cmd, code in commands:
        runs = [measure.run(cmd) for _ in range(a.repeats)]
        codes = {r["returncode"] for r in runs}
        if codes != {code}:
            raise SystemExit(f"{name}: exit {codes}, not {code}")
        wall = cargo_example.spread([1000 * r["wall"] for r in runs])
        cpu = cargo_example.spread([1000 * r["cpu"] for r in runs])
        peak = max(r["peakMiB"] for r in runs)
        lines.append(f"| {name} | {code} | {' / '.join(f'{x:.0f}' for x in wall)} | "
                     f"{' / '.join(f'{x:.0f}' for x in cpu)} | {peak:.0f} |")
    lines.append("")
    cargo_example.write(a.out, lines)


if __name__ == "__main__":
    main()
