#!/usr/bin/env python3
"""The 10^4-triangle open-plan floor's working plane against RADIANCE (issue 29's accuracy check).

    python3 bench/floor_accuracy.py [--bake PATH] [--work DIR] [--out FILE.json]
                                    [--stride K] [--ad N] [--threads N] [--reference FILE]

Writes `bake generate openplan --size small`, and a copy whose emitting LED panels reflect
nothing (RADIANCE's `light` cannot also reflect; radiance.py refuses such emitters otherwise; their
reflected light is under 1 % of their own luminance). Bakes that copy with luxbake at draft,
default and high quality (and high with `--uniform-patches`, the issue's "converged reference")
with a working plane at 0.75 m, converts it to RADIANCE (radiance.py) and runs `rtrace -I` at
every K-th working-plane point facing up (+Y, glTF's up axis) with pure Monte Carlo (-aa 0
-ab 16 -ad N -lw 1e-7 -ds 0.01 -dj 1: -ab 8 -lw 1e-4 stopped 0.5 % of the inter-reflected light
short), then at -ab 0 (direct light alone, the mean of 32 runs).
RADIANCE's values at every point are kept in bench/data/openplan_small_plane_radiance.json
and read from there while the scene's bytes, -ad and the options are unchanged (--reference).
Each point's RADIANCE value is one Monte Carlo sample: its noise (estimated from two repeats at
137 points when it was written, bench/results/floor-accuracy/README.md) is reported beside the
errors.

Prints and writes per luxbake run: the working plane's mean against RADIANCE's, the relative
RMS of the per-point differences, their p95 and max, and the same for the direct light alone.
Python standard library only; RADIANCE comes from PyPI pyradiance (bench/.venv, as run.py).
"""

import argparse
import json
import math
import os
import struct
import subprocess
import sys

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)

import measure  # noqa: E402
import radiance  # noqa: E402
from run import ensure_venv  # noqa: E402

# Jittered direct light (-dj 1) is averaged over this many runs (each a few seconds).
DIRECT_REPEATS = 32

RUNS = {
    "draft": ["--quality", "draft"],
    "default": [],
    "high": ["--quality", "high"],
    "high-uniform": ["--quality", "high", "--uniform-patches"],
}


def glb_json(path):
    with open(path, "rb") as f:
        b = f.read()
    n = struct.unpack("<I", b[12:16])[0]
    return json.loads(b[20:20 + n])


def working_plane(path):
    """{probe name: (position, E(+y), direct E(+y))} of a bake's working-plane probes."""
    out = {}
    for node in glb_json(path)["nodes"]:
        e = node.get("extras", {}).get("luxbake", {})
        if e.get("probe", {}).get("origin", {}).get("kind") == "workingPlane":
            out[node["name"]] = (e["probe"]["position"], e["faces"]["+y"],
                                 e["facesDirect"]["+y"])
    return out


def stats(ours, ref):
    """Mean of both, relative error of the mean, RMS / p95 / max of per-point relative errors
    (points where the reference is above 1 lx)."""
    rel = sorted(abs(a - b) / b for a, b in zip(ours, ref) if b > 1.0)
    mean_a, mean_b = sum(ours) / len(ours), sum(ref) / len(ref)
    return {"mean": mean_a, "refMean": mean_b, "meanRel": (mean_a - mean_b) / mean_b,
            "rms": math.sqrt(sum(r * r for r in rel) / len(rel)),
            "p95": rel[int(0.95 * (len(rel) - 1))], "max": rel[-1], "points": len(rel)}


def black_panel_floor(bake, work):
    """`bake generate openplan --size small` with its emitting panels' reflectance set to 0,
    written to WORK/small-black-panels.gltf; returns that path."""
    floor = os.path.join(work, "small.gltf")
    subprocess.run([bake, "generate", "openplan", "--size", "small", "-o", floor], check=True)
    with open(floor, encoding="utf-8") as f:
        doc = json.load(f)
    for m in doc["materials"]:
        ext = m.get("extensions", {}).get("LUXBAKE_material", {})
        if "emission" in ext:
            ext["reflectance"] = [0.0, 0.0, 0.0]
    scene = os.path.join(work, "small-black-panels.gltf")
    with open(scene, "w", encoding="utf-8") as f:
        json.dump(doc, f)
    return scene


def radiance_octree(scene, rd, rad_bin, rad_lib):
    """The glTF converted to RADIANCE in folder rd and compiled; returns the octree's path."""
    os.makedirs(rd, exist_ok=True)
    radiance.convert(scene, rd, rad_bin)
    env = dict(os.environ, RAYPATH=os.pathsep.join([".", rad_lib]))
    oct_path = os.path.join(rd, "scene.oct")
    m = measure.run([os.path.join(rad_bin, "oconv"), "scene.rad"], cwd=rd, env=env,
                    stdout_path=oct_path, stderr_path=os.path.join(rd, "oconv.err"))
    if m["returncode"] != 0:
        raise SystemExit("oconv failed")
    return oct_path


def rtrace_total_and_direct(rad_bin, rad_lib, oct_path, rays, ad, threads,
                            weights=radiance.RADIANCE_WEIGHTS, direct_repeats=DIRECT_REPEATS):
    """RADIANCE `rtrace -I` at rays [(x, y, z, dx, dy, dz)], pure Monte Carlo (-aa 0 -ab 16
    -ad AD -lw 1e-7) and direct light alone (-ab 0, the mean of DIRECT_REPEATS runs), each in a
    folder beside the octree. Sources are sampled with jitter (-dj 1): at -dj 0 RADIANCE reads
    each source partition at its centre, and in a soft shadow that is a staircase (a point 3.5 cm
    beside a screen, seeing the end of a 1.5 m fitting over it: 27.1 lx at -dj 0 for any -ds,
    13.8 lx jittered, 13.9 lx integrated on a 4 mm grid).
    Returns ({"total": lx, "direct": lx}, {"total": wall s, "direct": wall s})."""
    common = ["-ds", "0.01", "-dt", "0", "-dc", "1", "-dj", "1", "-aa", "0"]
    ref, walls = {}, {}
    for tag, opts, repeats in [("total", ["-ab", "16", "-ad", str(ad), "-lw", "1e-7"], 1),
                               ("direct", ["-ab", "0"], direct_repeats)]:
        wd = os.path.join(os.path.dirname(oct_path), tag)
        os.makedirs(wd, exist_ok=True)
        values, m, _ = radiance.run_rtrace(rad_bin, rad_lib, oct_path, rays * repeats,
                                           common + opts, wd, threads=threads, weights=weights)
        n = len(rays)
        ref[tag] = [sum(values[i + k * n] for k in range(repeats)) / repeats for i in range(n)]
        walls[tag] = m["wall"]
        print(f"RADIANCE {tag}: {m['wall']:.1f} s wall", flush=True)
    return ref, walls


def file_sha256(path):
    """SHA-256 of a glTF and the buffers it names beside it (hex)."""
    import hashlib
    h = hashlib.sha256()
    with open(path, "rb") as f:
        doc = f.read()
    h.update(doc)
    for b in json.loads(doc).get("buffers", []):
        if "uri" in b and not b["uri"].startswith("data:"):
            with open(os.path.join(os.path.dirname(path), b["uri"]), "rb") as f:
                h.update(f.read())
    return h.hexdigest()


def cached_reference(path, key):
    """RADIANCE's {"total", "direct"} at key["names"] from the file at path when it was
    computed for this scene (its bytes), -ad and options at those points (or more), else None."""
    try:
        with open(path, encoding="utf-8") as f:
            c = json.load(f)
    except (OSError, ValueError):
        return None
    at = {n: i for i, n in enumerate(c.get("names", []))}
    if any(c.get(k) != key[k] for k in ("sceneSha256", "ad", "options")) or any(
            n not in at for n in key["names"]):
        print("reference", path, "is for another scene, -ad or set of points: recomputing")
        return None
    return {t: [c[t][at[n]] for n in key["names"]] for t in ("total", "direct")}


def write_results(path, results):
    with open(path, "w", encoding="utf-8") as f:
        json.dump(results, f, indent=1)
    print("wrote", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bake", default=os.path.join(ROOT, "target", "release", "bake"))
    ap.add_argument("--work", default=os.path.join(BENCH, "work", "floor-accuracy"))
    ap.add_argument("--out", default=None, help="results JSON (default WORK/results.json)")
    ap.add_argument("--stride", type=int, default=1, help="every K-th working-plane point")
    ap.add_argument("--ad", type=int, default=1024)
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--reference",
                    default=os.path.join(BENCH, "data", "openplan_small_plane_radiance.json"),
                    help="RADIANCE's values at the plane's points, read when made for this scene, "
                         "--ad, options and points (else computed, and written here at stride 1)")
    ap.add_argument("--run", action="append", metavar="TAG=ARGS",
                    help="bake these runs instead of the standard four (ARGS: the bake's extra "
                         "arguments, space-separated); repeatable")
    a = ap.parse_args()
    runs = RUNS
    if a.run:
        runs = {t: v.split() for t, v in (r.split("=", 1) for r in a.run)}
        runs.setdefault("default", [])  # the plane's points are read from the default run
    os.makedirs(a.work, exist_ok=True)
    pkg = ensure_venv(os.path.join(BENCH, ".venv"))
    rad_bin, rad_lib = os.path.join(pkg, "bin"), os.path.join(pkg, "lib")

    scene = black_panel_floor(a.bake, a.work)

    results = {"scene": "bake generate openplan --size small, emitters' reflectance 0",
               "radiance": {"options": f"-aa 0 -ab 16 -ad {a.ad} -lw 1e-7 -ds 0.01 -dt 0 "
                                       "-dc 1 -dj 1", "directRepeats": DIRECT_REPEATS,
                            "stride": a.stride}, "runs": {}}
    planes = {}
    for tag, extra in runs.items():
        out = os.path.join(a.work, f"{tag}.glb")
        m = measure.run([a.bake, scene, "-o", out, "--working-plane", "0.75", "-q",
                         "--threads", str(a.threads)] + extra)
        if m["returncode"] != 0:
            raise SystemExit(f"bake {tag} failed")
        planes[tag] = working_plane(out)
        results["runs"][tag] = {"args": " ".join(extra), "wall": m["wall"], "cpu": m["cpu"]}
        print(f"{tag}: {m['wall']:.1f} s wall", flush=True)

    names = sorted(planes["default"])[::a.stride]
    points = [tuple(planes["default"][k][0]) + (0.0, 1.0, 0.0) for k in names]
    key = {"sceneSha256": file_sha256(scene), "ad": a.ad,
           "options": results["radiance"]["options"], "names": names}
    ref = cached_reference(a.reference, key)
    if ref is None:
        oct_path = radiance_octree(scene, os.path.join(a.work, "radiance"), rad_bin, rad_lib)
        ref, walls = rtrace_total_and_direct(rad_bin, rad_lib, oct_path, points, a.ad, a.threads)
        for tag, wall in walls.items():
            results["radiance"][tag + "Wall"] = wall
        if a.stride == 1:
            write_results(a.reference, dict(key, points=points, total=ref["total"],
                                             direct=ref["direct"], walls=walls))
    else:
        results["radiance"]["cached"] = os.path.relpath(a.reference, ROOT)
        print("RADIANCE's values read from", a.reference)

    for tag, plane in planes.items():
        r = results["runs"][tag]
        r["total"] = stats([plane[k][1] for k in names], ref["total"])
        r["direct"] = stats([plane[k][2] for k in names], ref["direct"])
        t, d = r["total"], r["direct"]
        print(f"{tag:13s} mean {t['mean']:.2f} vs {t['refMean']:.2f} lx ({t['meanRel']:+.2%}), "
              f"per-point RMS {t['rms']:.2%}, p95 {t['p95']:.2%}, max {t['max']:.1%}; "
              f"direct: mean {d['meanRel']:+.2%}, RMS {d['rms']:.2%}")
    write_results(a.out or os.path.join(a.work, "results.json"), results)


if __name__ == "__main__":
    main()
