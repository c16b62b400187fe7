#!/usr/bin/env python3
"""The building floor's working planes against a converged RADIANCE reference (issue 55, 6).

    python3 bench/building.py [--bake PATH] [--work DIR] [--threads N] [--recompute]
                              [--ab N] [--ad N] [--batch R] [--max-repeats R] [--target-se F]
                              [--run TAG=ARGS ...]

Inputs: `bake generate building` (src/fixtures/building_floor.rs), whose `extras.generator`
lists the working planes (0.8 m above the floor, +Y up, glTF axes): the corridor, a lit office
(S1), an unlit office lit only through its open door (S2) and an unlit office behind a shut door
(N2, must read 0 lx).

Reference (bench/results/building/reference.json, reused while the scene's bytes, the options
and the points are unchanged; `--recompute` forces it): RADIANCE `rtrace -I` (pyradiance, as
bench/radiance.py converts the glTF) at every point of the lit planes facing +Y, pure Monte Carlo
(-aa 0, no irradiance cache: every point path traced on its own; -as 0, no ambient
super-sampling, which biases dim rooms low; -dj 1 jittered sources), the
points listed R times per rtrace run (each ray its own sample index: independent repeats), runs
added until the standard error of every plane's mean over the repeats is below --target-se
(0.2 %) with at least 8 repeats; then the direct light alone (-ab 0, 32 repeats). The shut
office's plane is traced once at the same options (expected exactly 0).

Outputs: bench/results/building/results.md and results.json: per plane and luxbake run (default
quality unless --run), the plane's mean against RADIANCE's (signed %), the RMS of the per-point
relative differences (%), the same for the direct part, and the dark plane's largest value (lx).
Python standard library only; RADIANCE from PyPI pyradiance in bench/.venv (as run.py).
"""

import argparse
import datetime
import hashlib
import json
import math
import os
import shlex
import subprocess
import sys
import time

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)

import measure  # noqa: E402
import provenance  # noqa: E402
import radiance  # noqa: E402
from floor_accuracy import file_sha256, radiance_octree  # noqa: E402
from run import PYRADIANCE, ensure_venv, machine  # noqa: E402

OUT = os.path.join(BENCH, "results", "building")
# -as 0: rtrace's default ambient super-sampling (-as 128) spends extra rays where a division's
# first samples varied and averages them in with the rest, which is not unbiased: in S2, lit
# through its door, it read the inter-reflected light 8.6 % low (63 points, -ad 1024, 16
# repeats each way; the corridor and S1 moved by -0.1 % and +0.4 %).
COMMON = ["-ds", "0.01", "-dt", "0", "-dc", "1", "-dj", "1", "-aa", "0", "-as", "0"]
DIRECT_REPEATS = 32
MIN_REPEATS = 8
RUNS = {"default": []}


def generate(bake, work):
    """`bake generate building -o WORK/building.gltf`; returns (path, the generator extras)."""
    path = os.path.join(work, "building.gltf")
    subprocess.run([bake, "generate", "building", "-q", "-o", path], check=True)
    with open(path, encoding="utf-8") as f:
        doc = json.load(f)
    return path, doc["scenes"][doc.get("scene", 0)]["extras"]["generator"]


def plane_points(gen):
    """[(plane name, point name, (x, y, z), expect zero)] in the generator's order."""
    return [(p["name"], f"{p['name']}_{i}", tuple(q), p["expectZero"])
            for p in gen["workingPlanes"] for i, q in enumerate(p["points"])]


def write_csv(points, path):
    """The points as a `bake --probes` CSV (x,y,z,name)."""
    with open(path, "w", encoding="utf-8") as f:
        f.write("x,y,z,name\n")
        f.writelines(f"{x:.9g},{y:.9g},{z:.9g},{n}\n" for _, n, (x, y, z), _ in points)


def plane_stats(values_by_repeat, planes):
    """Per plane: mean over its points of each repeat, their mean and standard error."""
    out = {}
    for plane, idx in planes.items():
        means = [sum(rep[i] for i in idx) / len(idx) for rep in values_by_repeat]
        m = sum(means) / len(means)
        r = len(means)
        se = math.sqrt(sum((x - m) ** 2 for x in means) / (r - 1) / r) if r > 1 else math.inf
        out[plane] = {"mean": m, "se": se, "seRel": se / m if m else math.inf,
                      "repeatMeans": means}
    return out


def converge(rad, oct_path, rays, planes, options, a):
    """Repeats of `rays` in runs of a.batch until every plane's mean has a relative standard
    error below a.target_se (and at least MIN_REPEATS), or a.max_repeats. Returns (repeats
    [[lx per ray]], wall s, cpu s, command)."""
    reps, wall, cpu, cmd = [], 0.0, 0.0, None
    wd = os.path.join(os.path.dirname(oct_path), "total")
    os.makedirs(wd, exist_ok=True)
    while True:
        values, m, cmd = radiance.run_rtrace(rad[0], rad[1], oct_path, rays * a.batch, options,
                                             wd, threads=a.threads)
        n = len(rays)
        reps += [values[k * n:(k + 1) * n] for k in range(a.batch)]
        wall, cpu = wall + m["wall"], cpu + m["cpu"]
        st = plane_stats(reps, planes)
        worst = max(s["seRel"] for s in st.values())
        print(f"  {len(reps)} repeats, {wall:.0f} s: " + ", ".join(
            f"{k} {s['mean']:.3f} lx ± {s['seRel']:.3%}" for k, s in st.items()), flush=True)
        if (worst < a.target_se and len(reps) >= MIN_REPEATS) or len(reps) >= a.max_repeats:
            return reps, wall, cpu, cmd


def mean_of(reps):
    n = len(reps)
    return [sum(r[i] for r in reps) / n for i in range(len(reps[0]))]


def point_se(reps):
    """Standard error of each point's mean over the repeats."""
    n, mu = len(reps), mean_of(reps)
    return [math.sqrt(sum((r[i] - mu[i]) ** 2 for r in reps) / (n - 1) / n)
            for i in range(len(mu))]


def compute_reference(scene, points, key, rad, a):
    """RADIANCE at every point: converged total (lit planes), direct (-ab 0), dark planes once."""
    oct_path = radiance_octree(scene, os.path.join(a.work, "radiance"), rad[0], rad[1])
    lit = [i for i, p in enumerate(points) if not p[3]]
    dark = [i for i, p in enumerate(points) if p[3]]
    rays = [points[i][2] + (0.0, 1.0, 0.0) for i in range(len(points))]
    planes = {}
    for k, i in enumerate(lit):
        planes.setdefault(points[i][0], []).append(k)
    options = COMMON + ["-ab", str(a.ab), "-ad", str(a.ad), "-lw", a.lw]
    print(f"RADIANCE reference: rtrace -I {' '.join(options)}, {len(lit)} points", flush=True)
    t0 = time.time()
    reps, wall, cpu, cmd = converge(rad, oct_path, [rays[i] for i in lit], planes, options, a)
    wd = os.path.join(os.path.dirname(oct_path), "direct")
    os.makedirs(wd, exist_ok=True)
    dvals, dm, dcmd = radiance.run_rtrace(rad[0], rad[1], oct_path, rays * DIRECT_REPEATS,
                                          COMMON + ["-ab", "0"], wd, threads=a.threads)
    wd = os.path.join(os.path.dirname(oct_path), "dark")
    os.makedirs(wd, exist_ok=True)
    zvals, zm, _ = radiance.run_rtrace(rad[0], rad[1], oct_path, [rays[i] for i in dark],
                                       options, wd, threads=a.threads)
    n = len(points)
    total, se = [0.0] * n, [0.0] * n
    for k, (mu, s) in enumerate(zip(mean_of(reps), point_se(reps))):
        total[lit[k]], se[lit[k]] = mu, s
    for k, v in enumerate(zvals):
        total[dark[k]] = v
    direct = [sum(dvals[i + r * n] for r in range(DIRECT_REPEATS)) / DIRECT_REPEATS
              for i in range(n)]
    st = plane_stats(reps, planes)
    return dict(key, names=[p[1] for p in points], planes=[p[0] for p in points],
                points=[list(p[2]) for p in points], lux=total, luxSe=se, direct=direct,
                repeats=len(reps), planeStats=st, darkMax=max(zvals) if zvals else None,
                command="RAYPATH=.:<pyradiance>/lib " + " ".join(
                    [os.path.basename(cmd[0])] + cmd[1:]) +
                f" < points.txt (the {len(lit)} lit-plane points listed {a.batch} times per run,"
                f" runs until every plane's standard error < {a.target_se:.1%}, at least "
                f"{MIN_REPEATS} repeats); direct: rtrace -h -I -ov -n {a.threads} "
                f"{' '.join(COMMON)} -ab 0, {DIRECT_REPEATS} repeats; dark plane: one run of "
                "the total's options",
                wall={"total": wall, "direct": dm["wall"], "dark": zm["wall"],
                      "elapsed": time.time() - t0},
                cpu={"total": cpu, "direct": dm["cpu"], "dark": zm["cpu"]},
                commit=machine_commit(), date=datetime.datetime.now().isoformat(
                    timespec="seconds"), radiance=PYRADIANCE)


def machine_commit():
    r = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                       text=True)
    dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT,
                           capture_output=True, text=True).stdout.strip()
    return r.stdout.strip() + (" (with uncommitted changes)" if dirty else "")


def reference(scene, points, rad, a):
    """The cached reference when it was made for this scene, these options and points, else
    computed and written (bench/results/building/reference.json)."""
    path = os.path.join(OUT, "reference.json")
    opts = " ".join(COMMON + ["-ab", str(a.ab), "-ad", str(a.ad), "-lw", a.lw])
    names = [p[1] for p in points]
    key = {"sceneSha256": file_sha256(scene), "options": opts, "targetSe": a.target_se,
           "pointsSha256": hashlib.sha256(json.dumps([list(p[2]) for p in points])
                                          .encode()).hexdigest()}
    if not a.recompute and os.path.exists(path):
        with open(path, encoding="utf-8") as f:
            ref = json.load(f)
        if all(ref.get(k) == v for k, v in key.items()) and ref.get("names") == names:
            print("RADIANCE reference read from", os.path.relpath(path, ROOT))
            return ref
        print("reference.json is for another scene, options or points: recomputing")
    ref = compute_reference(scene, points, key, rad, a)
    os.makedirs(OUT, exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        json.dump(ref, f, indent=1)
    print("wrote", os.path.relpath(path, ROOT))
    return ref


def bake_run(bake, scene, csv, tag, extra, a):
    """One luxbake bake with the points as probes; returns ({name: (E+y, direct E+y)}, measure)."""
    out = os.path.join(a.work, f"{tag}.glb")
    probes = os.path.join(a.work, f"{tag}-probes.json")
    cmd = [bake, scene, "-o", out, "--probes", csv, "--probes-out", probes, "-q",
           "--threads", str(a.threads)] + extra
    m = measure.run(cmd, stderr_path=os.path.join(a.work, f"{tag}.err"))
    if m["returncode"] != 0:
        raise SystemExit(f"bake {tag} failed: see {a.work}/{tag}.err")
    with open(probes, encoding="utf-8") as f:
        got = {p["probe"]["name"]: (p["faces"]["+y"], p["facesDirect"]["+y"])
               for p in json.load(f)}
    m["command"] = "bake building.gltf -o OUT.glb --probes points.csv --probes-out P.json " + \
        " ".join(["-q", "--threads", str(a.threads)] + extra)
    return got, m


def compare(ours, ref, ref_se=None):
    """Mean of each, signed relative error of the mean, RMS and max of the per-point relative
    differences (at points where the reference exceeds 1 lx: the direct light is 0 at many
    points of the office lit through its door), and the reference's own per-point noise (RMS of
    its relative standard errors)."""
    ma, mb = sum(ours) / len(ours), sum(ref) / len(ref)
    rel = [(x - y) / y for x, y in zip(ours, ref) if y > 1.0]
    out = {"mean": ma, "refMean": mb, "meanRel": (ma - mb) / mb if mb else None,
           "rms": math.sqrt(sum(r * r for r in rel) / len(rel)) if rel else None,
           "max": max(rel, key=abs) if rel else None, "points": len(rel)}
    if ref_se:
        out["refNoiseRms"] = math.sqrt(sum((s / y) ** 2 for s, y in zip(ref_se, ref)) / len(ref))
    return out


def evaluate(got, ref):
    """Per plane: total and direct compared (lit planes), or the largest value (dark planes)."""
    out = {}
    for plane in dict.fromkeys(ref["planes"]):
        idx = [i for i, p in enumerate(ref["planes"]) if p == plane]
        ours = [got[ref["names"][i]] for i in idx]
        tot = [ref["lux"][i] for i in idx]
        if max(tot) == 0.0:
            out[plane] = {"dark": True, "refMax": 0.0, "max": max(o[0] for o in ours),
                          "mean": sum(o[0] for o in ours) / len(ours), "points": len(idx)}
            continue
        out[plane] = {"total": compare([o[0] for o in ours], tot,
                                       [ref["luxSe"][i] for i in idx]),
                      "direct": compare([o[1] for o in ours], [ref["direct"][i] for i in idx]),
                      "indirectMean": sum(o[0] - o[1] for o in ours) / len(idx),
                      "refIndirectMean": sum(ref["lux"][i] - ref["direct"][i]
                                             for i in idx) / len(idx)}
    return out


def markdown(ref, runs, a, info):
    """results.md: the reference, then per run and plane the comparison."""
    L = [f"# Building floor: luxbake against converged RADIANCE", "",
         provenance.line("python3 bench/building.py" + "".join(" " + shlex.quote(x) for x in sys.argv[1:]), "quick"), "",
         f"Written by `python3 bench/building.py{a.argv}` on "
         f"{datetime.date.today().isoformat()} at commit {info['gitCommit']} "
         f"(`bake --version`: {info['luxbake']}); machine: {info['cpu']}, {info['cores']} cores.",
         "", "Scene: `bake generate building -o building.gltf` (src/fixtures/building_floor.rs): "
         "offices along a corridor, a meeting room, shared slabs, thick and zero-thickness "
         "partitions, doors open and shut. Working planes 0.8 m above the floor, 0.4 m grid, "
         "0.5 m from the walls, illuminance on the upward face (+Y).", "",
         "## Reference", "",
         f"RADIANCE ({ref['radiance']}), computed at commit {ref['commit']} on {ref['date']}: "
         f"`{ref['command']}`.", "",
         f"{ref['repeats']} independent repeats; time {ref['wall']['total']:.0f} s wall / "
         f"{ref['cpu']['total']:.0f} s CPU (total), {ref['wall']['direct']:.0f} s (direct), "
         f"{ref['wall']['dark']:.0f} s (dark plane).", "",
         "| plane | points | RADIANCE mean (lx) | standard error of the mean | "
         "per-point noise (RMS of relative SE) |", "| --- | --- | --- | --- | --- |"]
    for plane, s in ref["planeStats"].items():
        idx = [i for i, p in enumerate(ref["planes"]) if p == plane]
        noise = math.sqrt(sum((ref["luxSe"][i] / ref["lux"][i]) ** 2 for i in idx) / len(idx))
        L.append(f"| {plane} | {len(idx)} | {s['mean']:.3f} | {s['seRel']:.3%} | {noise:.2%} |")
    L.append(f"| office_dark (door shut, unlit) | "
             f"{sum(1 for p in ref['planes'] if p == 'office_dark')} | "
             f"max {ref['darkMax']:.3g} | — | — |")
    for tag, r in runs.items():
        L += ["", f"## luxbake `{tag}`", "", f"`{r['command']}`: {r['wall']:.1f} s wall, "
              f"{r['cpu']:.1f} s CPU.", "",
              "| plane | luxbake mean (lx) | RADIANCE mean (lx) | mean error | per-point RMS | "
              "per-point max | direct: mean error | direct: RMS | indirect mean luxbake / "
              "RADIANCE (lx) |", "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
        for plane, e in r["planes"].items():
            if e.get("dark"):
                L.append(f"| {plane} | {e['mean']:.3f} (max {e['max']:.3f}) | 0 (exactly) | "
                         "— | — | — | — | — | — |")
                continue
            t, d = e["total"], e["direct"]
            d_rms = "—" if d["rms"] is None else f"{d['rms']:.2%} ({d['points']} points > 1 lx)"
            L.append(f"| {plane} | {t['mean']:.3f} | {t['refMean']:.3f} | {t['meanRel']:+.2%} "
                     f"| {t['rms']:.2%} | {t['max']:+.1%} | {d['meanRel']:+.2%} | "
                     f"{d_rms} | {e['indirectMean']:.3f} / {e['refIndirectMean']:.3f} |")
    return L


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bake", default=os.path.join(ROOT, "target", "release", "bake"))
    ap.add_argument("--work", default=os.path.join(BENCH, "work", "building"))
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--recompute", action="store_true", help="recompute the RADIANCE reference")
    ap.add_argument("--ab", type=int, default=16)
    ap.add_argument("--ad", type=int, default=256)
    ap.add_argument("--lw", default="1e-7")
    ap.add_argument("--batch", type=int, default=4, help="repeats per rtrace run")
    ap.add_argument("--max-repeats", type=int, default=64)
    ap.add_argument("--target-se", type=float, default=0.002)
    ap.add_argument("--run", action="append", metavar="TAG=ARGS",
                    help="luxbake runs instead of `default` (ARGS: extra bake arguments)")
    a = ap.parse_args()
    a.argv = "".join(" " + x for x in sys.argv[1:])
    a.work = os.path.abspath(a.work)
    runs = {t: v.split() for t, v in (r.split("=", 1) for r in a.run)} if a.run else RUNS
    os.makedirs(a.work, exist_ok=True)
    pkg = ensure_venv(os.path.join(BENCH, ".venv"))
    rad = (os.path.join(pkg, "bin"), os.path.join(pkg, "lib"))
    scene, gen = generate(a.bake, a.work)
    points = plane_points(gen)
    csv = os.path.join(a.work, "points.csv")
    write_csv(points, csv)
    ref = reference(scene, points, rad, a)
    results = {}
    for tag, extra in runs.items():
        got, m = bake_run(a.bake, scene, csv, tag, extra, a)
        results[tag] = {"command": m["command"], "wall": m["wall"], "cpu": m["cpu"],
                        "planes": evaluate(got, ref)}
        print(f"luxbake {tag}: {m['wall']:.1f} s", flush=True)
    info = machine(a.bake, None)
    lines = markdown(ref, results, a, info)
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "results.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(OUT, "results.json"), "w", encoding="utf-8") as f:
        json.dump({"commit": info["gitCommit"], "runs": results}, f, indent=1)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
