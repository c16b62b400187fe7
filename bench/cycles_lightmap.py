"""Lightmaps against Blender Cycles: the empty seed office (`office-panels`) at 5 cm texels, time
and per-texel error against a converged reference, in one run.

    .venv-bpy/bin/python bench/cycles_lightmap.py [--samples 16,64,256,1024] [--work DIR]
        → bench/results/lightmaps/cycles.md (and DIR/results.json; --write-only rewrites the
          table from it)       about 6 min on 2 cores, 5 of them Cycles at 1024 samples

Needs numpy and bpy (the venv `.ci/run` makes: `.venv-bpy`). Bakes office-panels with
`--lightmaps --texel-size 0.05` at default quality (three runs, the fastest kept) and, as the
reference, at `--quality high --lightmap-tolerance 0` (every texel gathered). Cycles (CPU, the
same threads) bakes the default bake's atlas layout (`cycles_bake_bpy.py`: DIFFUSE pass, direct +
indirect + colour, no bounce limit, clamping or light threshold) at each sample count; its time
is the bake call's alone (import and set-up excluded; luxbake's is the whole process). Errors
are over the interior texels of reflecting surfaces (footprint a whole texel; emitters left
out): per texel |x − ref| / ref, RMS and 99th percentile, and the ratio of the sums. Two Cycles
seeds at the lowest sample count give its noise without any reference, and Cycles' highest
sample count against the reference checks that reference: its difference is its noise.
"""

import argparse
import glob
import json
import math
import os
import subprocess
import sys

import struct
import zlib

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cargo_example  # noqa: E402
import exr_read  # noqa: E402
import measure  # noqa: E402
import scenes  # noqa: E402

BENCH = cargo_example.BENCH
ROOT = cargo_example.ROOT
OFFICE = os.path.join(ROOT, "samples", "office", "office.gltf")
TEXEL = 0.05


def bake(binary, scene, out, args, repeats):
    """The fastest of `repeats` bakes (wall, CPU) and the atlas's channels."""
    best = None
    for _ in range(repeats):
        m = measure.run([binary, scene, "-o", out, "-q", "--lightmaps", "--texel-size",
                         str(TEXEL)] + args, timeout=1800)
        if m["returncode"] != 0:
            raise SystemExit(f"bake {' '.join(args)} failed")
        best = m if best is None or m["wall"] < best["wall"] else best
    stem = os.path.splitext(out)[0]
    exrs = glob.glob(stem + ".lightmap*.exr")
    if len(exrs) != 1:
        raise SystemExit(f"{out}: expected one atlas, found {len(exrs)}")
    e = exr_read.read(exrs[0])
    ch = {k: np.array(v, dtype=np.float64) for k, v in e["channels"].items()}
    return best, ch


def cycles(lit, job, work, tag):
    path = os.path.join(work, f"job-{tag}.json")
    json.dump(job, open(path, "w"))
    out = os.path.join(work, f"cycles-{tag}.npy")
    p = subprocess.run([sys.executable, os.path.join(BENCH, "cycles_bake_bpy.py"), lit, path,
                        out], capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"Cycles bake {tag} failed:\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    info = json.loads([ln for ln in p.stdout.splitlines() if ln.startswith("{")][-1])
    return info["bakeSeconds"], np.load(out).astype(np.float64)


def errors(x, ref, mask):
    rel = np.abs(x[mask] - ref[mask]) / ref[mask]
    return {"rms": float(np.sqrt((rel ** 2).mean())), "p99": float(np.percentile(rel, 99)),
            "median": float(np.median(rel)), "over5": float((rel > 0.05).mean()),
            "sum": float(x[mask].sum() / ref[mask].sum() - 1.0)}


def pictures(folder, lux, cycles, ref, mask):
    """The per-texel relative error of luxbake default and of Cycles' highest sample count
    against the reference, as atlases (3 × 3 pixels a texel, row 0 at the top): red brighter,
    blue darker, saturated at ±5 %, grey outside the texels compared."""
    for name, x in (("cycles-error-luxbake.png", lux), ("cycles-error-cycles.png", cycles)):
        rel = np.where(mask, (x - ref) / np.where(mask, ref, 1.0), 0.0)
        v = np.clip(rel / 0.05, -1.0, 1.0)
        rgb = np.stack([np.where(v > 0, 1.0, 1.0 + v), 1.0 - np.abs(v),
                        np.where(v < 0, 1.0, 1.0 - v)], axis=-1)
        rgb[~mask] = 0.25
        px = np.repeat(np.repeat((rgb * 255).astype(np.uint8), 3, 0), 3, 1)
        write_png(os.path.join(folder, name), px)


def write_png(path, px):
    """An 8-bit RGB PNG of the H × W × 3 array `px`."""
    h, w = px.shape[:2]
    raw = b"".join(b"\x00" + px[y].tobytes() for y in range(h))

    def chunk(kind, data):
        crc = zlib.crc32(kind + data) & 0xFFFFFFFF
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", crc)

    open(path, "wb").write(b"\x89PNG\r\n\x1a\n"
                           + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                           + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def pct(x):
    return f"{100 * x:.3f} %"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", default="16,64,256,1024")
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--work", default=os.path.join(BENCH, "work", "cycles-lightmap"))
    ap.add_argument("--out", default=os.path.join(BENCH, "results", "lightmaps", "cycles.md"))
    ap.add_argument("--write-only", action="store_true",
                    help="rewrite --out from the work folder's results.json (no runs)")
    a = ap.parse_args()
    if a.write_only:
        data = json.load(open(os.path.join(a.work, "results.json")))
        write(a.out, data, cargo_example.build_bake())
        return
    samples = [int(s) for s in a.samples.split(",")]
    os.makedirs(a.work, exist_ok=True)
    binary = cargo_example.build_bake()
    scene = os.path.join(a.work, "scene.gltf")
    text, info = scenes.office_panels_gltf(OFFICE)
    open(scene, "w").write(text)
    threads = ["--threads", str(a.threads)]

    print("luxbake default", flush=True)
    lit = os.path.join(a.work, "default.gltf")
    m_def, lux = bake(binary, scene, lit, threads, 3)
    print("luxbake reference (high, every texel gathered)", flush=True)
    m_ref, ref_ch = bake(binary, scene, os.path.join(a.work, "reference.gltf"),
                         threads + ["--quality", "high", "--lightmap-tolerance", "0"], 1)
    if ref_ch["R"].shape != lux["R"].shape:
        raise SystemExit("the reference's atlas differs in size from the default bake's")
    ref = ref_ch["R"]
    # Interior texels of reflecting surfaces: a whole texel of surface in both bakes (their
    # meshes differ, so a chart's edge texels may differ a little), and not an emitter (whose R
    # holds its own luminance, above ρE/π < E/π).
    whole = 0.999 * TEXEL * TEXEL
    mask = ((lux["footprint"] >= whole) & (ref_ch["footprint"] >= whole) & (ref > 0)
            & (ref <= ref_ch["illuminance"] / math.pi))

    g = json.load(open(lit))
    rho = {}
    for mat in g["materials"]:
        r = mat["extras"]["luxbake"]["reflectance"]
        rho[mat["name"]] = sum(r) / 3
    # Lambertian panels: luminance = flux / (π × area).
    emit = info["panelFluxLm"] / (math.pi * info["panelSize"][0] * info["panelSize"][1])
    atlas = next(iter(m["extensions"]["LUXBAKE_lightmap"] for m in g["materials"]
                      if "LUXBAKE_lightmap" in m.get("extensions", {})))
    base = {"threads": a.threads, "width": atlas["width"], "height": atlas["height"],
            "reflectance": rho, "emitters": {"panel": emit}}
    runs, top = [], None
    for k, s in enumerate(samples):
        seeds = [1, 2] if k == 0 else [1]
        vals = []
        for seed in seeds:
            print(f"Cycles {s} samples, seed {seed}", flush=True)
            t, v = cycles(lit, dict(base, samples=s, seed=seed), a.work, f"{s}-{seed}")
            vals.append(v)
            top = v
            runs.append({"samples": s, "seed": seed, "seconds": t, **errors(v, ref, mask)})
        if len(vals) == 2:
            d = (vals[0][mask] - vals[1][mask]) / ref[mask]
            noise = float(np.sqrt((d ** 2).mean() / 2))
            runs[-1]["noiseFromSeeds"] = noise
    data = {"luxbakeDefault": {"wall": m_def["wall"], "cpu": m_def["cpu"],
                               **errors(lux["R"], ref, mask)},
            "reference": {"wall": m_ref["wall"]}, "cycles": runs, "texels": int(mask.sum()),
            "atlas": [atlas["width"], atlas["height"]], "panelLuminance": emit,
            "threads": a.threads, "blender": bpy_version(), "commit": commit()}
    json.dump(data, open(os.path.join(a.work, "results.json"), "w"), indent=1)
    pictures(os.path.dirname(a.out), lux["R"], top, ref, mask)
    write(a.out, data, binary)



def write(out, d, binary):
    lux, runs = d["luxbakeDefault"], d["cycles"]
    t_lux, e_lux = lux["wall"], lux["rms"]
    L = cargo_example.header("Lightmaps against Blender Cycles (office-panels, 5 cm texels)",
                             ".venv-bpy/bin/python bench/cycles_lightmap.py", binary,
                             section="all",
                             at=f"{d['commit'][:7]} (measured at)" if "commit" in d else None)
    if "commit" in d:
        L += [f"The runs: at commit {d['commit']}, with `bench/cycles_lightmap.py` (this file is "
              "rewritten from their `results.json` by `--write-only`).", ""]
    L += [f"Atlas {d['atlas'][0]} × {d['atlas'][1]} texels; errors over the {d['texels']} "
          "interior texels of reflecting surfaces, per texel against the reference (luxbake "
          "`--quality high --lightmap-tolerance 0`, every texel gathered: "
          f"{d['reference']['wall']:.1f} s wall). Panels: Lambertian, "
          f"{d['panelLuminance']:.1f} cd/m². Cycles {d['blender']}, CPU, {d['threads']} "
          "threads; its seconds are the bake call's only (import and set-up excluded), "
          "luxbake's the whole process.", "",
          "| run | seconds | per-texel RMS | p99 | Σ against the reference |",
          "| --- | ---: | ---: | ---: | ---: |",
          f"| luxbake default (fastest of 3) | {t_lux:.2f} | {pct(e_lux)} | "
          f"{pct(lux['p99'])} | {pct(lux['sum'])} |"]
    for r in runs:
        L.append(f"| Cycles {r['samples']} samples, seed {r['seed']} | {r['seconds']:.1f} | "
                 f"{pct(r['rms'])} | {pct(r['p99'])} | {pct(r['sum'])} |")
    first = next(r for r in runs if "noiseFromSeeds" in r)
    s0, n0 = first["samples"], first["noiseFromSeeds"]
    L += ["", f"Cycles' own noise from two seeds at {s0} samples: {pct(n0)} per texel (RMS).",
          "", "**At equal per-texel error (RMS)**, luxbake default: "
          f"{pct(e_lux)} in {t_lux:.2f} s."]
    if "median" in lux:
        L[-1] += (f" (median {pct(lux['median'])}; {pct(lux['over5'])} of the texels off by "
                  "more than 5 %: the RMS is theirs)")
    worse = [r for r in runs if r["rms"] > e_lux]
    better = [r for r in runs if r["rms"] <= e_lux]
    if worse:
        w = max(worse, key=lambda r: r["seconds"])
        L.append(f"- Cycles' slowest run that is still less accurate ({w['samples']} samples, "
                 f"{w['seconds']:.1f} s, {pct(w['rms'])}): Cycles needs more than that, "
                 f"**> {w['seconds'] / t_lux:.0f}×**.")
    if better:
        b = min(better, key=lambda r: r["seconds"])
        L.append(f"- Cycles' fastest run at least as accurate ({b['samples']} samples, "
                 f"{b['seconds']:.1f} s, {pct(b['rms'])}): {b['seconds'] / t_lux:.0f}× "
                 "at equal or better error.")
    # Noise falls as 1/√samples and time grows linearly with them (fitted on the runs): the
    # samples and seconds Cycles needs for luxbake's per-texel error.
    need = s0 * (n0 / e_lux) ** 2
    xs = np.array([r["samples"] for r in runs], dtype=float)
    slope, icpt = np.polyfit(xs, np.array([r["seconds"] for r in runs]), 1)
    t_need = icpt + slope * need
    L += [f"- Interpolated: about {need:,.0f} samples (the seeds' noise × √({s0}/samples)) "
          f"and {t_need:,.0f} s (time linear in samples, fitted on these runs: "
          f"{slope:.3f} s a sample {icpt:+.1f} s): about {t_need / t_lux:,.0f}×.", ""]
    top = max(runs, key=lambda r: r["samples"])
    noise = n0 * math.sqrt(s0 / top["samples"])
    L += ["The reference checked against Cycles: its highest sample count differs from it by "
          f"{pct(top['rms'])} RMS per texel and {pct(top['sum'])} in the sum, where that run's "
          f"noise alone is {pct(noise)} (the seeds' at {s0} samples scaled by √(samples)): no "
          "difference beyond Cycles' noise.", ""]
    L += ["Where the errors are (red: brighter than the reference, blue: darker, saturated at "
          "±5 %; grey: not compared), luxbake default and Cycles at its highest sample count, "
          "the atlas as written (row 0 at the top):", "",
          "![luxbake default against the reference](cycles-error-luxbake.png)",
          "![Cycles against the reference](cycles-error-cycles.png)", ""]
    cargo_example.write(out, L)


def commit():
    p = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                       text=True)
    return p.stdout.strip() or "?"


def bpy_version():
    p = subprocess.run([sys.executable, "-c", "import bpy; print(bpy.app.version_string)"],
                       capture_output=True, text=True)
    return "Blender " + (p.stdout.strip().splitlines() or ["?"])[-1]


if __name__ == "__main__":
    main()
