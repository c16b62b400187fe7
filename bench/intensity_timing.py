"""The cost of `Photometry::intensity` (one interpolated intensity), in ns per call.

    python3 bench/intensity_timing.py [--repeats N]   → bench/results/intensity.md

Builds the example `intensity_cost` (examples/intensity_cost.rs) and runs it on a few profiles
of tests/data/photometry (an EULUMDAT file with no symmetry and two lamp sets, an axial IES file,
a type B IES file): 4096 directions over the sphere, 250 times each, in N rounds (default 5);
the fastest and the median round are kept. Python standard library only.
"""

import argparse
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cargo_example  # noqa: E402

BENCH = cargo_example.BENCH
ROOT = cargo_example.ROOT
PROFILES = ["ldt_isym0_two_sets.ldt", "ies2019_axial_cosn_absolute.ies", "ies2002_typeB.ies"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", default=os.path.join(BENCH, "results", "intensity.md"))
    a = ap.parse_args()
    bake, example = cargo_example.build("intensity_cost")
    lines = cargo_example.header("Cost of `Photometry::intensity`",
                                 "python3 bench/intensity_timing.py", bake)
    lines += [f"Each profile: 4096 directions × 250 calls per round, {a.repeats} rounds, one "
              "thread; ns per call.", "",
              "| profile | fastest round | median round |", "| --- | ---: | ---: |"]
    for name in PROFILES:
        path = os.path.join(ROOT, "tests", "data", "photometry", name)
        out = subprocess.run([example, path, str(a.repeats)], capture_output=True, text=True,
                             check=True).stdout
        per = [float(line.split()[1]) for line in out.splitlines()
               if line.startswith("ns_per_call ")]
        fastest, median, _ = cargo_example.spread(per)
        lines.append(f"| `{name}` | {fastest:.0f} | {median:.0f} |")
    lines.append("")
    cargo_example.write(a.out, lines)


if __name__ == "__main__":
    main()
