"""`bake diff` on two 10⁶-vertex outputs: wall time, CPU time and peak memory.

    python3 bench/diff_timing.py [--repeats N] [--work DIR]   → bench/results/diff.md

Builds `bake` and the example `diff_pair` (examples/diff_pair.rs), which writes the two outputs
with the library: a 1000 × 1000 vertex floor as A.glb and B.glb, B 1 % higher on one vertex in
1000 (so the diff fails, exit 1, having compared every value). Then runs `bake diff A.glb B.glb`
and `bake diff A.glb B.glb --json` N times each (default 5), each run measured by measure.py
(wall, user + system CPU, peak resident memory), and writes the figures. Python standard
library only.
"""

import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cargo_example  # noqa: E402
import measure  # noqa: E402

BENCH = cargo_example.BENCH


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--work", default=os.path.join(BENCH, "work", "diff"))
    ap.add_argument("--out", default=os.path.join(BENCH, "results", "diff.md"))
    a = ap.parse_args()
    bake, example = cargo_example.build("diff_pair")
    os.makedirs(a.work, exist_ok=True)
    made = measure.run([example, a.work])
    if made["returncode"] != 0:
        raise SystemExit("diff_pair failed")
    pa, pb = (os.path.join(a.work, f"{x}.glb") for x in "ab")
    lines = cargo_example.header("`bake diff` on two 10⁶-vertex outputs",
                                 "python3 bench/diff_timing.py", bake)
    size = os.path.getsize(pa) / 1e6
    lines += [f"Inputs: `examples/diff_pair.rs` (a 1000 × 1000 vertex floor, 1 996 002 triangles; "
              f"B 1 % higher on one vertex in 1000), two .glb files of {size:.1f} MB each, "
              f"written in {made['wall']:.1f} s. Each command ran {a.repeats} times, one after "
              "the other; times in s, peak resident memory in MiB (largest of the runs).", "",
              "| command | exit | wall min / median / max | CPU min / median / max | peak MiB |",
              "| --- | ---: | --- | --- | ---: |"]
    for args in [[], ["--json"]]:
        cmd = [bake, "diff", pa, pb] + args
        out = os.path.join(a.work, "out.txt")
        runs = [measure.run(cmd, stdout_path=out) for _ in range(a.repeats)]
        codes = {r["returncode"] for r in runs}
        if codes != {1}:
            raise SystemExit(f"bake diff {' '.join(args)} exited {codes}, not 1")
        if args:
            ill = next(q for q in json.load(open(out))["quantities"]
                       if q["quantity"] == "illuminance")
            if ill["overall"]["values"] != 1000 * 1000:
                raise SystemExit(f"compared {ill['overall']['values']} values, not 10^6")
        wall = cargo_example.spread([r["wall"] for r in runs])
        cpu = cargo_example.spread([r["cpu"] for r in runs])
        peak = max(r["peakMiB"] for r in runs)
        shown = " ".join(["bake", "diff", "A.glb", "B.glb"] + args)
        lines.append(f"| `{shown}` | 1 | {' / '.join(f'{x:.2f}' for x in wall)} | "
                     f"{' / '.join(f'{x:.2f}' for x in cpu)} | {peak:.0f} |")
    lines.append("")
    cargo_example.write(a.out, lines)


if __name__ == "__main__":
    main()
