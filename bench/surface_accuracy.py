#!/usr/bin/env python3
"""Where the 10^4 floor's inter-reflected light differs from RADIANCE, surface by surface.

    python3 bench/surface_accuracy.py [--bake PATH] [--work DIR] [--out FILE.json]
                                      [--spacing S] [--ad N] [--threads N] [-- BAKE ARGS...]

The scene of floor_accuracy.py (`bake generate openplan --size small`, emitting panels'
reflectance 0). Probes 15 mm off four surfaces, each read on the face toward the surface, so a
probe's illuminance is what that surface receives: the ceiling (facing down, -Y; glTF is +Y up),
the floor (facing up), the west wall (x = 0, facing +X) and the south wall (z = 0, facing +Z), on
an S-metre grid (walls at 0.3, 0.9, 1.5, 2.1 and 2.7 m). luxbake bakes them (`--probes`, default
quality, plus any BAKE ARGS); RADIANCE (`rtrace -I`, -aa 0 -ab 8 -ad N -lw 1e-4, and -ab 0 for
the direct light) measures the same points. Both RGB results are weighed with luxbake's luminance
weights (Rec. 709 Y), so colour weighting plays no part.

Prints per surface: direct light, ours against RADIANCE (mean); inter-reflected light (total -
direct), mean and per-point RMS of the relative differences (points where RADIANCE's is above
1 lx). A surface that receives too much here sends too much to the others: the ceiling's
irradiance is what the floor and the working plane gather most of.
Python standard library only; RADIANCE from PyPI pyradiance (bench/.venv, as run.py).
"""

import argparse
import json
import math
import os
import sys

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)

import floor_accuracy  # noqa: E402
import measure  # noqa: E402
import radiance  # noqa: E402
from run import ensure_venv  # noqa: E402

# (surface, luxbake face, RADIANCE direction)
SURFACES = {"ceiling": ("-y", (0, -1, 0)), "floor": ("+y", (0, 1, 0)),
            "west wall": ("+x", (1, 0, 0)), "south wall": ("+z", (0, 0, 1))}
OFF = 0.015
WALL_HEIGHTS = (0.3, 0.9, 1.5, 2.1, 2.7)


def probe_points(width, depth, height, s):
    """[(surface, x, y, z)] on the four surfaces' grids."""
    out = []
    def axis(length):  # cell centres along one side
        return [s / 2 + s * i for i in range(math.ceil((length - s / 2) / s))]
    xs, zs = axis(width), axis(depth)
    for x in xs:
        for z in zs:
            out.append(("ceiling", x, height - OFF, z))
            out.append(("floor", x, OFF, z))
    for y in WALL_HEIGHTS:
        out += [("west wall", OFF, y, z) for z in zs]
        out += [("south wall", x, y, OFF) for x in xs]
    return out


def compare(ours_direct, ours_total, rad_direct, rad_total):
    mean = lambda v: sum(v) / len(v)  # noqa: E731
    oi = [t - d for t, d in zip(ours_total, ours_direct)]
    ri = [t - d for t, d in zip(rad_total, rad_direct)]
    rel = [(a - b) / b for a, b in zip(oi, ri) if b > 1.0]
    return {"points": len(oi), "directOurs": mean(ours_direct), "directRadiance": mean(rad_direct),
            "indirectOurs": mean(oi), "indirectRadiance": mean(ri),
            "indirectMeanRel": mean(oi) / mean(ri) - 1,
            "indirectRms": math.sqrt(sum(r * r for r in rel) / len(rel)) if rel else 0.0}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bake", default=os.path.join(ROOT, "target", "release", "bake"))
    ap.add_argument("--work", default=os.path.join(BENCH, "work", "surface-accuracy"))
    ap.add_argument("--out", default=None, help="results JSON (default WORK/results.json)")
    ap.add_argument("--spacing", type=float, default=0.5)
    ap.add_argument("--ad", type=int, default=1024)
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("bake_args", nargs="*", help="more `bake` arguments (after --)")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    pkg = ensure_venv(os.path.join(BENCH, ".venv"))
    rad_bin, rad_lib = os.path.join(pkg, "bin"), os.path.join(pkg, "lib")

    scene = floor_accuracy.black_panel_floor(a.bake, a.work)
    with open(scene, encoding="utf-8") as f:
        gen = json.load(f)["scenes"][0]["extras"]["generator"]
    (width, depth), height = gen["floorPlate"], gen["ceilingHeight"]
    points = probe_points(width, depth, height, a.spacing)
    csv = os.path.join(a.work, "probes.csv")
    with open(csv, "w", encoding="ascii") as f:
        f.write("".join(f"{x:.4f},{y:.4f},{z:.4f},p{i}\n" for i, (_, x, y, z) in
                        enumerate(points)))
    probes_out = os.path.join(a.work, "probes.json")
    m = measure.run([a.bake, scene, "-o", os.path.join(a.work, "bake.glb"), "--probes", csv,
                     "--probes-out", probes_out, "-q", "--threads", str(a.threads)] + a.bake_args)
    if m["returncode"] != 0:
        raise SystemExit("bake failed")
    with open(probes_out, encoding="utf-8") as f:
        ours = {p["probe"]["name"]: p for p in json.load(f)}
    print(f"luxbake: {m['wall']:.1f} s wall", flush=True)

    oct_path = floor_accuracy.radiance_octree(scene, os.path.join(a.work, "radiance"),
                                              rad_bin, rad_lib)
    rays = [(x, y, z) + SURFACES[s][1] for s, x, y, z in points]
    ref, _ = floor_accuracy.rtrace_total_and_direct(rad_bin, rad_lib, oct_path, rays, a.ad,
                                                    a.threads, radiance.REC709_WEIGHTS)

    results = {"scene": "bake generate openplan --size small, emitters' reflectance 0",
               "bakeArgs": a.bake_args, "spacing": a.spacing, "offset": OFF,
               "radiance": f"-aa 0 -ab 8 -ad {a.ad} -lw 1e-4 (direct: -ab 0)", "surfaces": {}}
    for surface, (face, _) in SURFACES.items():
        idx = [i for i, p in enumerate(points) if p[0] == surface]
        r = compare([ours[f"p{i}"]["facesDirect"][face] for i in idx],
                    [ours[f"p{i}"]["faces"][face] for i in idx],
                    [ref["direct"][i] for i in idx], [ref["total"][i] for i in idx])
        results["surfaces"][surface] = r
        print(f"{surface:10s} {r['points']:4d} points: direct {r['directOurs']:.1f} vs "
              f"{r['directRadiance']:.1f} lx; inter-reflected {r['indirectOurs']:.2f} vs "
              f"{r['indirectRadiance']:.2f} lx ({r['indirectMeanRel']:+.2%}), per-point RMS "
              f"{r['indirectRms']:.2%}")
    floor_accuracy.write_results(a.out or os.path.join(a.work, "results.json"), results)


if __name__ == "__main__":
    main()
