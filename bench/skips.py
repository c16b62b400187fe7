"""Skipping what a scene does not need, measured with and without (issue 5, scope 5).

    python3 bench/skips.py [--bake PATH]   → bench/results/skips.md

Each line bakes one scene twice, once with the saving and once with it turned off, and records
wall time, CPU time, rays, patches, links and the error against the closed form or a converged
reference (the same measures as bench/run.py):
- convex empty enclosure: CIE 171 test 5.8 (ρ = 0.9) with no visibility rays (the default) and
  with every ray traced (hidden flag --always-trace);
- adaptive patches: the office with adaptive meshing (the default) and with --uniform-patches,
  working-plane mean against the harness's converged reference when bench/results/results.json
  has it;
- outputs not asked for: the office without probes (the default) and with a 1 m probe grid and
  a working plane (probes cost only when asked);
- black surfaces: the office with its floor, dark desks and picture black (reflectance 0), and
  with every surface black, each without links to black surfaces (the default) and with them
  (hidden flag --gather-black); the error is `bake diff` of the two (their meshes are the same).
Short runs are repeated three times, the fastest kept. Python standard library only.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import measure  # noqa: E402
import provenance  # noqa: E402
import scenes  # noqa: E402

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)


def bake(binary, inp, out_dir, args, repeats=3, out="out.gltf"):
    best = None
    for _ in range(repeats):
        summary = os.path.join(out_dir, "summary.json")
        m = measure.run([binary, inp, "-o", os.path.join(out_dir, out), "-q",
                         "--summary-json", summary] + args)
        if m["returncode"] != 0:
            raise SystemExit(f"bake failed: {args}")
        m["summary"] = json.load(open(summary))
        if best is None or m["wall"] < best["wall"]:
            best = m
    return best


def black_office(tmp, name, black):
    """A copy of the sample office (its folder, for the profiles) whose materials named in
    `black` (all when None) reflect nothing."""
    src = os.path.join(ROOT, "samples", "office")
    dst = os.path.join(tmp, name)
    shutil.copytree(src, dst)
    doc = json.load(open(os.path.join(src, "office.gltf")))
    for mat in doc["materials"]:
        if black is None or mat["name"] in black:
            mat["extensions"]["LUXBAKE_material"]["reflectance"] = 0.0
    json.dump(doc, open(os.path.join(dst, "office.gltf"), "w"))
    return os.path.join(dst, "office.gltf")


def diff(binary, a, b, mode, quantity):
    """`bake diff a b --mode mode --json`: the overall relative error of `quantity` (B the
    reference)."""
    out = subprocess.run([binary, "diff", a, b, "--mode", mode, "--json"], capture_output=True,
                         text=True)
    if out.returncode == 2:
        raise SystemExit(f"bake diff could not compare: {out.stderr}")
    q = {x["quantity"]: x["overall"] for x in json.loads(out.stdout)["quantities"]}
    return q[quantity]


def row(name, variant, m, error):
    c = m["summary"]["counts"]
    return (f"| {name} | {variant} | {m['wall']:.3f} | {m['cpu']:.3f} | {c['patches']} | "
            f"{c['links']} | {c['rays']} | {error} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bake", default=os.path.join(ROOT, "target", "release", "bake"))
    ap.add_argument("--out", default=os.path.join(BENCH, "results", "skips.md"))
    a = ap.parse_args()
    lines = ["# Skipping what a scene does not need", "",
             provenance.line("python3 bench/skips.py", "quick"), "",
             "Written by `python3 bench/skips.py`; wall and CPU time in s (fastest of three), "
             "same machine notes as results.md.", "",
             "| scene | variant | wall s | CPU s | patches | links | rays | error |",
             "| --- | --- | ---: | ---: | ---: | ---: | ---: | --- |"]
    with tempfile.TemporaryDirectory() as tmp:
        # Convex empty enclosure.
        cie = os.path.join(tmp, "cie.gltf")
        open(cie, "w").write(scenes.cie_5_8_gltf(0.9))
        exact = scenes.cie_5_8_indirect(0.9)
        for variant, args in [("no rays (default)", []), ("every ray traced", ["--always-trace"])]:
            m = bake(a.bake, cie, tmp, args + ["--report", "json", "--report-out",
                                               os.path.join(tmp, "r.json")])
            rep = json.load(open(os.path.join(tmp, "r.json")))
            rows = rep["byMaterial"]
            area = sum(r["area"] for r in rows)
            e_ind = sum(r["eIndirectAvg"] * r["area"] for r in rows) / area
            off = (e_ind / exact - 1) * 100
            lines.append(row("CIE 5.8, ρ = 0.9", variant, m,
                             f"mean E_ind {e_ind:.3f} lx vs {exact:.3f} ({off:+.3f} %)"))
        # Adaptive patches and outputs not asked for, on the office.
        office = os.path.join(ROOT, "samples", "office", "office.gltf")
        ref = None
        res = os.path.join(BENCH, "results", "results.json")
        if os.path.exists(res):
            try:
                r = json.load(open(res))
                ref = r["scenes"]["office"]["reference"]["workingPlane"]["eAvg"]
            except (KeyError, TypeError):
                ref = None
        for variant, args in [("adaptive (default)", []), ("uniform patches", ["--uniform-patches"])]:
            m = bake(a.bake, office, tmp, args + ["--working-plane", "0.8",
                                                  "--working-plane-spacing", "0.5", "--report", "json",
                                                  "--report-out", os.path.join(tmp, "r.json")])
            wp = json.load(open(os.path.join(tmp, "r.json")))["workingPlane"]["eAvg"]
            err = f"working plane {wp:.2f} lx"
            if ref:
                err += f" ({(wp / ref - 1) * 100:+.3f} % vs converged {ref:.2f})"
            lines.append(row("office", variant, m, err))
        for variant, args in [("no probes (default)", []),
                              ("1 m probe grid + working plane",
                               ["--probe-grid", "1.0", "--probe-height", "1.2", "--working-plane", "0.8"])]:
            m = bake(a.bake, office, tmp, args)
            t = m["summary"].get("timingsSeconds", {})
            out = t.get("probes", 0.0) + t.get("output", 0.0)
            lines.append(row("office", variant, m, f"probes + output stages {out:.2f} s"))
        # Black surfaces: nobody gathers from them (the default), or every receiver does.
        for name, black in [("office, floor + dark desks + picture black", ("floor", "desk_dark", "picture")),
                            ("office, every surface black", None)]:
            scene = black_office(tmp, "black" if black else "allblack", black)
            runs = []
            for k, args in enumerate([[], ["--gather-black"]]):
                m = bake(a.bake, scene, tmp, args + ["--working-plane", "0.8",
                                                     "--working-plane-spacing", "0.5", "--report",
                                                     "json", "--report-out", os.path.join(tmp, "r.json")],
                         out=f"black-{k}.gltf")
                m["wp"] = json.load(open(os.path.join(tmp, "r.json")))["workingPlane"]["eAvg"]
                runs.append(m)
            skipped, gathered = runs
            pa, pb = (os.path.join(tmp, f"black-{k}.gltf") for k in range(2))
            v = diff(a.bake, pa, pb, "vertices", "illuminance")
            p = diff(a.bake, pa, pb, "probes", "probeFaces")
            err = (f"working plane {skipped['wp']:.2f} vs {gathered['wp']:.2f} lx "
                   f"({(skipped['wp'] / gathered['wp'] - 1) * 100:+.3f} %); vertices p95 "
                   f"{v['rel']['p95'] * 100:.2f} %, max {v['rel']['max'] * 100:.2f} %; "
                   f"working-plane probes' six faces max {p['rel']['max'] * 100:.2f} %")
            lines.append(row(name, "no links to black (default)", skipped, err))
            lines.append(row(name, "links to black", gathered, "the reference of the line above"))
    lines.append("")
    open(a.out, "w").write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
