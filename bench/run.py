#!/usr/bin/env python3
"""luxbake benchmark harness: one command, see bench/README.md.

    python3 bench/run.py            # the full run (~20 min on 2 cores), writes bench/results/
    python3 bench/run.py --quick    # a quick subset (~3 min), writes bench/work/quick-results/

Runs `bake` on a set of scenes at several quality settings and records wall time, CPU time, peak
memory, patch/link/ray counts and the error against a reference (closed form where one exists,
else a converged high-quality bake), runs RADIANCE's rtrace on the office and on office-panels
(the office with Lambertian panels, against a converged RADIANCE reference) at the same points
at several -ab/-ad settings, and writes results.md, results.json, time_vs_error.svg and
scaling.svg. Python standard library only; RADIANCE comes from PyPI `pyradiance`, installed into
bench/.venv by this script when missing.
"""

import argparse
import datetime
import hashlib
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import time

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)

import measure  # noqa: E402
import provenance  # noqa: E402
import radiance  # noqa: E402
import scenes  # noqa: E402
import svgplot  # noqa: E402

PYRADIANCE = "pyradiance==1.3.1"
FACES = ["+x", "-x", "+y", "-y", "+z", "-z"]
FACE_DIRS = {"+x": (1, 0, 0), "-x": (-1, 0, 0), "+y": (0, 1, 0), "-y": (0, -1, 0),
             "+z": (0, 0, 1), "-z": (0, 0, -1)}

OFFICE = os.path.join(ROOT, "samples", "office", "office.gltf")
OFFICE_IES = {"CNS70 1/50W": os.path.join(ROOT, "samples", "office", "profiles",
                                          "cns70_50w.ies"),
              "Miral 1/58W louvred": os.path.join(ROOT, "samples", "office", "profiles",
                                                  "miral_58w.ies")}
OFFICE_PROBES = os.path.join(BENCH, "data", "office_probes.csv")
OFFICE_WP = ["--working-plane", "0.8", "--working-plane-spacing", "0.5"]
# office-panels (scenes.office_panels_gltf): the seed office as its HELIOS run modelled it
PANELS_GAP = 0.01  # m between the ceiling and the panels' emitting faces
PANELS_REF_CACHE = os.path.join(BENCH, "data", "office_panels_radiance_ref.json")
CORNELL = os.path.join(ROOT, "samples", "cornell-box", "cornell-box.obj")
CORNELL_WP = ["--working-plane", "0.05", "--working-plane-spacing", "0.05"]
OPENPLAN_WP = ["--working-plane", "0.8", "--working-plane-spacing", "0.5"]

# RADIANCE: direct part computed the same way in every run (fine source subdivision, every
# source tested), only the indirect settings -ab/-ad vary; -aa 0: no irradiance caching (each
# point is path traced: unbiased apart from the bounce limit, and nothing to tune besides -ab/-ad).
RAD_COMMON = ["-ds", "0.05", "-dt", "0", "-dc", "1", "-dj", "0", "-aa", "0"]
# Ray weight limit of the sweep: small enough that -ab, not -lw, ends the paths (with the common
# rule -lw = 1/-ad the mean stayed 0.25 % low at -ab 10 -ad 2048; at 1e-4 the bias is < 0.03 %).
RAD_SWEEP_LW = "1e-4"

# Settings of a full and of a quick run.
PLANS = {
    "full": {
        "office_runs": ["draft", "default", "high"],
        "office_ref": ["--quality", "high", "--patch-size", "0.1"],
        "office_ref_name": "high, patch 0.1 m",
        "rad_sweep": [(2, 128), (4, 256), (6, 256), (8, 512), (12, 512), (12, 1024),
                      (12, 2048)],
        "rad_ref": (12, 4096, "1e-5"),
        "panels_runs": ["draft", "default", "high"],
        "panels_rad_sweep": [(2, 128), (4, 128), (4, 256), (6, 128), (6, 256), (8, 256),
                             (8, 512), (12, 512), (12, 1024), (12, 2048)],
        "cie_rhos": [0.5, 0.9, 0.99],
        "cie_runs": ["draft", "default", "high"],
        "cornell_runs": ["draft", "default", "high"],
        "cornell_ref": ["--quality", "high", "--patch-size", "0.011"],
        "cornell_ref_name": "high, patch 0.011 m",
        "openplan_sizes": ["small", "medium", "large"],
        "openplan_runs": ["draft", "default", "high"],
        "openplan_ref": ["--quality", "high"],
        "openplan_ref_name": "high",
    },
    "quick": {
        "office_runs": ["draft", "default"],
        "office_ref": ["--quality", "high"],
        "office_ref_name": "high (quick: not converged)",
        "rad_sweep": [(2, 128), (4, 256)],
        "rad_ref": (8, 512, "1e-5"),
        "panels_runs": ["draft", "default"],
        "panels_rad_sweep": [(2, 128), (4, 256), (6, 256)],
        "cie_rhos": [0.5, 0.99],
        "cie_runs": ["draft", "default"],
        "cornell_runs": ["draft"],
        "cornell_ref": ["--quality", "default"],
        "cornell_ref_name": "default (quick: not converged)",
        "openplan_sizes": ["small"],
        "openplan_runs": ["draft"],
        "openplan_ref": ["--quality", "default"],
        "openplan_ref_name": "default (quick: not converged)",
    },
}

# office-panels' RADIANCE reference (both plans: it is cached in PANELS_REF_CACHE): pure Monte
# Carlo (RAD_COMMON has -aa 0), the working-plane points listed PANELS_REF_REPEATS times in one
# rtrace run, which gives independent estimates (each ray its own sample index: rtrace has no
# seed option) and their spread the reference's statistical error.
PANELS_REF = (16, 512, "1e-5")
PANELS_REF_REPEATS = 16

# Time limits (s): a run longer than this is stopped and reported as such (the harness must
# finish in ~20 minutes; a 10^6-triangle bake five times over its 60 s target is a miss anyway).
TIMEOUT_DEFAULT = 900
# Issue 56's targets: default quality on the 2-core machine, each floor within 2 GiB; the limits
# stop a bake just past its target, which decides it either way.
FLOOR_TARGETS = {"small": 3.0, "medium": 30.0, "large": 300.0}
FLOOR_MEMORY_MIB = 2048
SPEEDUP_GOAL = 10
TIMEOUT_OPENPLAN = {"small": 600, "medium": 150, "large": 330}


def log(msg):
    print(msg, flush=True)


# ------------------------------------------------------------------ environment

def sh(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, **kw)


def ensure_venv(venv):
    """bench/.venv with pyradiance (RADIANCE binaries); created on first use. Returns the
    pyradiance package directory (bin/ and lib/ inside it)."""
    py = os.path.join(venv, "bin", "python")
    probe = [py, "-c", "import os, pyradiance; print(os.path.dirname(pyradiance.__file__))"]
    if os.path.exists(py):
        r = sh(probe)
        if r.returncode == 0:
            return r.stdout.strip()
    log(f"creating {os.path.relpath(venv, ROOT)} with {PYRADIANCE} (RADIANCE binaries)")
    subprocess.run([sys.executable, "-m", "venv", venv], check=True)
    subprocess.run([py, "-m", "pip", "install", "--quiet", PYRADIANCE], check=True)
    r = sh(probe)
    if r.returncode != 0:
        raise SystemExit("pyradiance did not install: " + r.stderr.strip())
    return r.stdout.strip()


def build_bake():
    """cargo build --release (honours CARGO_TARGET_DIR); returns the binary's path."""
    log("cargo build --release")
    subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    target = os.environ.get("CARGO_TARGET_DIR") or os.path.join(ROOT, "target")
    if not os.path.isabs(target):
        target = os.path.join(ROOT, target)
    return os.path.join(target, "release", "bake")


def has_subcommand(bake, name):
    """Whether `bake --help` lists the subcommand (asking `bake NAME --help` would not do:
    NAME would be taken as the input file and --help answered anyway)."""
    text = sh([bake, "--help"]).stdout
    if "Commands:" not in text:
        return False
    section = text.split("Commands:", 1)[1].split("\n\n", 1)[0]
    return any(line.split()[0] == name for line in section.splitlines() if line.strip())


def machine(bake, rad):
    info = {}
    model = None
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    info["cpu"] = model or platform.processor() or platform.machine()
    info["cores"] = os.cpu_count()
    try:
        with open("/proc/meminfo", encoding="utf-8") as f:
            kib = int(f.readline().split()[1])
        info["ramGiB"] = round(kib / 1024 ** 2, 1)
    except (OSError, ValueError, IndexError):
        info["ramGiB"] = None
    osname = platform.platform()
    try:
        with open("/etc/os-release", encoding="utf-8") as f:
            for line in f:
                if line.startswith("PRETTY_NAME="):
                    osname = line.split("=", 1)[1].strip().strip('"') + ", Linux " + \
                        platform.release()
    except OSError:
        pass
    info["os"] = osname
    virt = []
    if shutil.which("systemd-detect-virt"):
        v = sh(["systemd-detect-virt"]).stdout.strip()
        if v and v != "none":
            virt.append(v)
    if shutil.which("lscpu"):
        lscpu = dict(line.split(":", 1) for line in sh(["lscpu"]).stdout.splitlines()
                     if ":" in line)
        lscpu = {k.strip(): v.strip() for k, v in lscpu.items()}
        if lscpu.get("Hypervisor vendor"):
            virt.append(f"{lscpu['Hypervisor vendor']} virtual machine")
        fam, mod = lscpu.get("CPU family"), lscpu.get("Model")
        if fam and mod:
            info["cpu"] += f" (family {fam}, model {mod}; {lscpu.get('Thread(s) per core', '?')}"\
                           f" thread(s) per core; L3 {lscpu.get('L3 cache', '?')})"
    info["virtualisation"] = ", ".join(virt) or "none detected"
    info["rustc"] = sh(["rustc", "--version"]).stdout.strip()
    info["python"] = platform.python_version()
    commit = sh(["git", "rev-parse", "HEAD"], cwd=ROOT).stdout.strip()
    dirty = sh(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT).stdout.strip()
    info["gitCommit"] = commit + (" (with uncommitted changes)" if dirty else "")
    info["gitBranch"] = sh(["git", "rev-parse", "--abbrev-ref", "HEAD"], cwd=ROOT).stdout.strip()
    info["luxbake"] = sh([bake, "--version"]).stdout.strip()
    if rad:
        env = dict(os.environ, RAYPATH=rad[1])
        info["radiance"] = sh([os.path.join(rad[0], "rtrace"), "-version"],
                              env=env).stdout.strip()
        info["pyradiance"] = PYRADIANCE
    else:
        info["radiance"] = "not used"
        info["pyradiance"] = "—"
    with open(os.path.join(ROOT, "Cargo.lock"), "rb") as f:
        info["cargoLockSha256"] = hashlib.sha256(f.read()).hexdigest()[:16]
    return info


def loadavg():
    try:
        return [round(v, 2) for v in os.getloadavg()]
    except OSError:
        return None


# ------------------------------------------------------------------ running bake

class Ctx:
    def __init__(self, bake, work, threads):
        self.bake = bake
        self.work = work
        self.threads = threads
        self.has_diff = has_subcommand(bake, "diff")
        # adaptive patches became the default with --uniform-patches to turn them off
        self.has_uniform = "--uniform-patches" in sh([bake, "--help"]).stdout

    def uniform(self):
        """References use one patch size everywhere (when the bake has the choice), so they do
        not depend on the adaptive refinement criterion being measured."""
        return ["--uniform-patches"] if self.has_uniform else []


def bake_run(ctx, scene, tag, inp, args, repeats=1, timeout=TIMEOUT_DEFAULT, probes=False):
    """One bake of inp with args (plus the measuring options). Returns a record: settings,
    measured resources (the fastest of `repeats` runs if the first is under 3 s), counts,
    stage timings and the report/probe values the errors are computed from."""
    d = os.path.join(ctx.work, scene, tag)
    os.makedirs(d, exist_ok=True)
    out = os.path.join(d, "out.gltf")
    summary = os.path.join(d, "summary.json")
    report = os.path.join(d, "report.json")
    cmd = [ctx.bake, inp, "-o", out, "-q", "--summary-json", summary, "--report", "json",
           "--report-out", report] + args
    if ctx.threads:
        cmd += ["--threads", str(ctx.threads)]
    probes_path = os.path.join(d, "probes.json")
    if probes:
        cmd += ["--probes-out", probes_path]
    samples = []
    for k in range(max(1, repeats)):
        la = loadavg()
        m = measure.run(cmd, stderr_path=os.path.join(d, "stderr.txt"), timeout=timeout)
        m["loadavgBefore"] = la
        samples.append(m)
        if m["timedOut"] or m["returncode"] != 0 or m["wall"] > 3.0:
            break
    best = min(samples, key=lambda s: s["wall"])
    rec = {"scene": scene, "tag": tag, "tool": "luxbake", "outDir": d,
           "command": " ".join(os.path.relpath(c, ROOT) if os.path.isabs(c) else c
                               for c in cmd),
           "wall": best["wall"], "cpu": best["cpu"], "user": best["user"], "sys": best["sys"],
           "peakMiB": best["peakMiB"], "wallSamples": [round(s["wall"], 4) for s in samples],
           "loadavgBefore": best["loadavgBefore"], "timedOut": best["timedOut"],
           "returncode": best["returncode"]}
    if best["timedOut"]:
        log(f"  {scene}/{tag}: stopped after {timeout} s")
        return rec
    if best["returncode"] != 0:
        with open(os.path.join(d, "stderr.txt"), encoding="utf-8", errors="replace") as f:
            rec["error"] = f.read()[-2000:]
        log(f"  {scene}/{tag}: bake failed ({best['returncode']}): {rec['error'][-300:]}")
        return rec
    with open(summary, encoding="utf-8") as f:
        s = json.load(f)
    with open(report, encoding="utf-8") as f:
        r = json.load(f)
    rec["patchSize"] = s.get("patchSize")
    rec["counts"] = s.get("counts")
    rec["solver"] = s.get("solver")
    rec["threads"] = s.get("threads")
    rec["stageSeconds"] = s.get("timingsSeconds")
    rec["balanceErrorRelative"] = s.get("energy", {}).get("balanceErrorRelative")
    rec["report"] = {"byMaterial": r.get("byMaterial"), "byNode": r.get("byNode"),
                     "workingPlane": r.get("workingPlane")}
    if probes:
        with open(probes_path, encoding="utf-8") as f:
            p = json.load(f)
        rec["workingPlanePoints"] = [
            {"position": x["probe"]["position"], "E": x["faces"]["+y"],
             "direct": x["facesDirect"]["+y"]}
            for x in p if x["probe"]["origin"]["kind"] == "workingPlane"]
        rec["probes"] = {x["probe"]["name"]: {"position": x["probe"]["position"],
                                              "faces": x["faces"],
                                              "facesDirect": x["facesDirect"]}
                         for x in p if x["probe"]["origin"]["kind"] != "workingPlane"}
    c = rec["counts"] or {}
    log(f"  {scene}/{tag}: {rec['wall']:.2f} s wall, {rec['cpu']:.2f} s CPU, "
        f"{rec['peakMiB']:.0f} MiB, {c.get('patches')} patches, {c.get('rays')} rays")
    return rec


def quality_args(q):
    return ["--quality", q]


# ------------------------------------------------------------------ errors

def rel(a, b):
    return (a - b) / b if b else float("nan")


def wp_errors(run, ref):
    """Working-plane errors of run against ref (same grid): the mean's signed relative error,
    and RMS and max over points of the per-point relative error."""
    a = run["workingPlanePoints"]
    b = ref["workingPlanePoints"]
    if len(a) != len(b):
        raise SystemExit(f"working planes differ: {len(a)} vs {len(b)} points")
    ma = sum(p["E"] for p in a) / len(a)
    mb = sum(p["E"] for p in b) / len(b)
    e = [rel(p["E"], q["E"]) for p, q in zip(a, b)]
    return {"wpMean": ma, "wpMeanRef": mb, "wpMeanErr": rel(ma, mb),
            "wpRms": math.sqrt(sum(x * x for x in e) / len(e)),
            "wpMax": max(abs(x) for x in e), "wpPoints": len(a)}


def probe_errors(run, ref):
    """Largest relative error over every face of every probe; and per probe."""
    worst, where, per = 0.0, None, {}
    for name, p in ref["probes"].items():
        q = run["probes"][name]
        e = max(abs(rel(q["faces"][f], p["faces"][f])) for f in FACES)
        per[name] = e
        for f in FACES:
            x = abs(rel(q["faces"][f], p["faces"][f]))
            if x > worst:
                worst, where = x, f"{name} {f}"
    return {"probeMax": worst, "probeWorst": where, "probePerProbe": per}


def surface_errors(run, ref):
    """Largest relative error of the area-weighted mean illuminance over the report's nodes."""
    rb = {x["name"]: x for x in ref["report"]["byNode"]}
    worst, where = 0.0, None
    for x in run["report"]["byNode"]:
        y = rb.get(x["name"])
        if y and y["eAvg"] > 0:
            e = abs(rel(x["eAvg"], y["eAvg"]))
            if e > worst:
                worst, where = e, x["name"]
    return {"surfaceMax": worst, "surfaceWorst": where}


def strip(rec):
    """The record without the bulky per-point values (kept for references only)."""
    return {k: v for k, v in rec.items()
            if k not in ("workingPlanePoints", "probes", "report", "outDir")}


def bake_diff(ctx, run, ref):
    """`bake diff RUN REF --mode means --json` when this bake has the subcommand (branch diff):
    its figures are kept in results.json beside the harness's own probe comparison."""
    if not ctx.has_diff or "outDir" not in run or "outDir" not in ref:
        return
    r = sh([ctx.bake, "diff", os.path.join(run["outDir"], "out.gltf"),
            os.path.join(ref["outDir"], "out.gltf"), "--mode", "means", "--json"])
    if r.returncode in (0, 1):
        try:
            d = json.loads(r.stdout)
        except ValueError:
            run["bakeDiff"] = {"unparsed": r.stdout[-2000:]}
            return
        run["bakeDiff"] = {k: d.get(k) for k in ("mode", "rtol", "floor", "pass", "values",
                                                 "failed", "worstFailure")}
        run["bakeDiff"]["overall"] = {
            q.get("quantity"): {"relMax": q.get("overall", {}).get("rel", {}).get("max"),
                                "relMean": q.get("overall", {}).get("rel", {}).get("mean")}
            for q in d.get("quantities", [])}
    else:
        run["bakeDiff"] = {"error": r.stderr.strip()[-500:]}


# ------------------------------------------------------------------ scenes

def bench_office(ctx, plan, rad, results):
    log("office (samples/office/office.gltf)")
    probe_args = OFFICE_WP + ["--probes", OFFICE_PROBES]
    ref = bake_run(ctx, "office", "reference", OFFICE,
                   plan["office_ref"] + ctx.uniform() + probe_args, probes=True)
    if "workingPlanePoints" not in ref:
        results["notes"].append("office: the luxbake reference failed; office skipped")
        return
    runs = []
    variants = [("", [])] + ([("-uniform", ["--uniform-patches"])] if ctx.has_uniform else [])
    for q, (suffix, extra) in [(q, v) for v in variants for q in plan["office_runs"]]:
        r = bake_run(ctx, "office", q + suffix, OFFICE, quality_args(q) + extra + probe_args,
                     repeats=3, probes=True)
        r["variant"] = suffix.lstrip("-")
        if "workingPlanePoints" in r:
            r["errors"] = {**wp_errors(r, ref), **probe_errors(r, ref),
                           **surface_errors(r, ref)}
            r["plotError"] = r["errors"]["wpRms"]
            bake_diff(ctx, r, ref)
        runs.append(r)
    office = {"reference": {**strip(ref), "name": plan["office_ref_name"] +
                            (", uniform patches" if ctx.has_uniform else ""),
                            "workingPlane": ref["report"]["workingPlane"],
                            "probes": ref["probes"]},
              "runs": [strip(r) for r in runs],
              "errorMeasure": "RMS over the working-plane points of the relative error"}
    results["scenes"]["office"] = office
    if rad is not None:
        office["radiance"] = bench_radiance(ctx, plan, rad, ref)


def rad_options(ab, ad, lw):
    return RAD_COMMON + ["-ab", str(ab), "-ad", str(ad), "-lw", str(lw)]


def bench_radiance(ctx, plan, rad, lux_ref):
    """RADIANCE on the office at luxbake's working-plane points (upward) and probe faces."""
    rad_bin, rad_lib = rad
    log("office in RADIANCE (pyradiance rtrace -I)")
    d = os.path.join(ctx.work, "office", "radiance")
    if os.path.exists(d):
        shutil.rmtree(d)
    os.makedirs(d)
    t0 = time.perf_counter()
    conv = radiance.convert(OFFICE, d, rad_bin, {"CNS70 1/50W": OFFICE_IES["CNS70 1/50W"]})
    m_oconv = measure.run([os.path.join(rad_bin, "oconv"), "scene.rad"], cwd=d,
                          env=dict(os.environ, RAYPATH=os.pathsep.join([".", rad_lib])),
                          stdout_path=os.path.join(d, "scene.oct"),
                          stderr_path=os.path.join(d, "oconv.err"))
    if m_oconv["returncode"] != 0:
        raise SystemExit("oconv failed: see " + os.path.join(d, "oconv.err"))
    conv_seconds = time.perf_counter() - t0
    points, keys = [], []
    for i, p in enumerate(lux_ref["workingPlanePoints"]):
        points.append(tuple(p["position"]) + (0.0, 1.0, 0.0))
        keys.append(("wp", i))
    for name, p in lux_ref["probes"].items():
        for f in FACES:
            points.append(tuple(p["position"]) + FACE_DIRS[f])
            keys.append(("probe", name, f))

    def run(tag, options):
        wd = os.path.join(d, tag)
        os.makedirs(wd)
        vals, m, cmd = radiance.run_rtrace(rad_bin, rad_lib, os.path.join(d, "scene.oct"),
                                          points, options, wd, threads=ctx.threads or
                                          os.cpu_count())
        rec = {"scene": "office", "tag": tag, "tool": "RADIANCE", "options": " ".join(options),
               "command": "rtrace " + " ".join(cmd[1:-1]) + " scene.oct < points",
               "wall": m["wall"] + m_oconv["wall"], "cpu": m["cpu"] + m_oconv["cpu"],
               "rtraceWall": m["wall"], "oconvWall": m_oconv["wall"],
               "peakMiB": max(m["peakMiB"], m_oconv["peakMiB"]), "points": len(points)}
        wp = [None] * len(lux_ref["workingPlanePoints"])
        probes = {name: {"position": p["position"], "faces": {}}
                  for name, p in lux_ref["probes"].items()}
        for k, v in zip(keys, vals):
            if k[0] == "wp":
                wp[k[1]] = {"position": lux_ref["workingPlanePoints"][k[1]]["position"], "E": v}
            else:
                probes[k[1]]["faces"][k[2]] = v
        rec["workingPlanePoints"] = wp
        rec["probes"] = probes
        log(f"  radiance/{tag}: {rec['wall']:.1f} s wall, {rec['cpu']:.1f} s CPU, "
            f"WP mean {sum(p['E'] for p in wp) / len(wp):.2f} lx")
        return rec

    # direct only (-ab 0): to compare the two tools' direct parts
    direct = run("ab0", RAD_COMMON + ["-ab", "0"])
    ref_ab, ref_ad, ref_lw = plan["rad_ref"]
    ref = run(f"ab{ref_ab}_ad{ref_ad}", rad_options(ref_ab, ref_ad, ref_lw))
    runs = []
    for ab, ad in plan["rad_sweep"]:
        r = run(f"ab{ab}_ad{ad}", rad_options(ab, ad, RAD_SWEEP_LW))
        r["errors"] = {**wp_errors(r, ref), **probe_errors(r, ref)}
        r["errorsVsLuxbakeReference"] = {**wp_errors(r, lux_ref), **probe_errors(r, lux_ref)}
        r["plotError"] = r["errors"]["wpRms"]
        runs.append(r)
    # agreement of the two references, total and direct parts
    lux_direct = {"workingPlanePoints": [{"E": p["direct"]} for p in
                                         lux_ref["workingPlanePoints"]],
                  "probes": {n: {"faces": p["facesDirect"]} for n, p in lux_ref["probes"].items()}}
    agreement = {
        "total": {**wp_errors(ref, lux_ref), **probe_errors(ref, lux_ref)},
        "direct": {**wp_errors(direct, lux_direct), **probe_errors(direct, lux_direct)},
    }
    wp_ind_rad = sum(a["E"] - b["E"] for a, b in zip(ref["workingPlanePoints"],
                                                   direct["workingPlanePoints"]))
    wp_ind_lux = sum(p["E"] - p["direct"] for p in lux_ref["workingPlanePoints"])
    agreement["indirectWpMean"] = {"radiance": wp_ind_rad / len(ref["workingPlanePoints"]),
                                   "luxbake": wp_ind_lux / len(ref["workingPlanePoints"])}
    agreement["indirectWpMean"]["relDiff"] = rel(agreement["indirectWpMean"]["radiance"],
                                                 agreement["indirectWpMean"]["luxbake"])
    return {"conversion": {**conv, "seconds": conv_seconds},
            "reference": {**strip(ref), "name": f"-ab {ref_ab} -ad {ref_ad} -lw {ref_lw}",
                          "workingPlaneMean": sum(p["E"] for p in ref["workingPlanePoints"])
                          / len(ref["workingPlanePoints"]),
                          "probes": ref["probes"]},
            "directOnly": {**strip(direct),
                           "workingPlaneMean": sum(p["E"] for p in direct["workingPlanePoints"])
                           / len(direct["workingPlanePoints"])},
            "runs": [strip(r) for r in runs],
            "referenceAgreement": agreement,
            "errorMeasure": "RMS over the working-plane points of the relative error against "
                            "RADIANCE's own reference"}


def wp_means(points):
    """Mean of the working-plane points' E, and of their direct part when they carry one."""
    n = len(points)
    m = {"wpMean": sum(p["E"] for p in points) / n}
    if all("direct" in p for p in points):
        m["wpDirectMean"] = sum(p["direct"] for p in points) / n
    return m


def panels_errors(run, ref, direct_mean):
    """Errors of a working plane against office-panels' RADIANCE reference: the mean's, its
    inter-reflected part's (mean minus direct_mean, the run's own direct part, against the
    reference's mean minus RADIANCE's -ab 0 mean) and the per-point RMS and max."""
    a, b = run["workingPlanePoints"], ref["workingPlanePoints"]
    if len(a) != len(b):
        raise SystemExit(f"office-panels: {len(a)} points against the reference's {len(b)}")
    mean, ref_mean = wp_means(a)["wpMean"], ref["wpMean"]
    ind, ref_ind = mean - direct_mean, ref_mean - ref["wpDirectMean"]
    e = [rel(p["E"], q["E"]) for p, q in zip(a, b)]
    return {"wpMean": mean, "wpMeanRef": ref_mean, "wpMeanErr": rel(mean, ref_mean),
            "wpIndirect": ind, "wpIndirectRef": ref_ind, "wpIndirectErr": rel(ind, ref_ind),
            "wpRms": math.sqrt(sum(x * x for x in e) / len(e)),
            "wpMax": max(abs(x) for x in e), "wpPoints": len(a)}


def panels_reference(rd, run, options, points, radiance_version):
    """office-panels' converged RADIANCE reference: read from PANELS_REF_CACHE when it was
    computed for the same scene.rad, options, repeats, points and RADIANCE, else computed (the
    points listed PANELS_REF_REPEATS times in one rtrace run) and written there."""
    with open(os.path.join(rd, "scene.rad"), "rb") as f:
        scene_sha = hashlib.sha256(f.read()).hexdigest()
    key = hashlib.sha256(json.dumps({
        "sceneRad": scene_sha, "options": options, "repeats": PANELS_REF_REPEATS,
        "points": [[f"{v:.9g}" for v in p] for p in points], "radiance": radiance_version},
        sort_keys=True).encode()).hexdigest()
    try:
        with open(PANELS_REF_CACHE, encoding="utf-8") as f:
            cached = json.load(f)
    except (OSError, ValueError):
        cached = None
    if cached and cached.get("key") == key:
        log(f"  radiance/reference: cached in {os.path.relpath(PANELS_REF_CACHE, ROOT)} "
            f"({cached['date']}, {cached['wall']:.0f} s wall then)")
        ref = {k: cached[k] for k in ("tag", "options", "command", "wall", "cpu", "repeats",
                                      "repeatMeans", "wpMean", "date")}
        ref["workingPlanePoints"] = [{"position": p, "E": e, "se": se} for p, e, se in
                                     zip(cached["points"], cached["E"], cached["seE"])]
        ref["cached"] = True
        return ref
    old = "stale (other scene, options, points or RADIANCE)" if cached else "missing"
    log(f"  radiance/reference: cache {old}: computing it ({PANELS_REF_REPEATS} repeats; "
        "several minutes)")
    ref = run("reference", options, PANELS_REF_REPEATS)
    ref["cached"] = False
    ref["date"] = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    with open(PANELS_REF_CACHE, "w", encoding="utf-8") as f:
        json.dump({"what": "office-panels' RADIANCE reference at the working-plane points "
                           "(bench/run.py bench_office_panels; E in lx, seE = standard error "
                           "over the repeats)",
                   "key": key, "sceneRadSha256": scene_sha, "radiance": radiance_version,
                   **{k: ref[k] for k in ("tag", "options", "command", "wall", "cpu",
                                          "repeats", "repeatMeans", "wpMean", "date")},
                   "points": [p["position"] for p in ref["workingPlanePoints"]],
                   "E": [p["E"] for p in ref["workingPlanePoints"]],
                   "seE": [p["se"] for p in ref["workingPlanePoints"]]}, f, indent=1)
        f.write("\n")
    log(f"  radiance/reference: written to {os.path.relpath(PANELS_REF_CACHE, ROOT)}")
    return ref


def bench_office_panels(ctx, plan, rad, results):
    """office-panels: luxbake at every quality, and RADIANCE at the same working-plane points
    (a converged pure Monte Carlo reference, its -ab 0 direct part and an -ab/-ad sweep); errors
    of the working-plane mean and of its inter-reflected part against RADIANCE's reference."""
    log(f"office-panels (samples/office's shell, six Lambertian panels {PANELS_GAP} m below "
        "the ceiling)")
    d = os.path.join(ctx.work, "office-panels")
    os.makedirs(d, exist_ok=True)
    inp = os.path.join(d, "scene.gltf")
    text, info = scenes.office_panels_gltf(OFFICE, gap=PANELS_GAP)
    with open(inp, "w", encoding="utf-8") as f:
        f.write(text)
    runs = []
    for q in plan["panels_runs"]:
        r = bake_run(ctx, "office-panels", q, inp, quality_args(q) + OFFICE_WP, repeats=3,
                     probes=True)
        if "workingPlanePoints" in r:
            r.update(wp_means(r["workingPlanePoints"]))
        runs.append(r)
    scene = {"scene": info, "reference": {"name": "not run"},
             "errorMeasure": "relative error of the working-plane mean against RADIANCE's "
                             "converged reference"}
    results["scenes"]["office-panels"] = scene
    done = [r for r in runs if "workingPlanePoints" in r]
    scene["runs"] = [strip(r) for r in runs]
    if not done or rad is None:
        results["notes"].append("office-panels: " + ("every bake failed" if not done else
                                "RADIANCE not run (--no-radiance): no errors"))
        return
    grid = [p["position"] for p in done[0]["workingPlanePoints"]]
    for r in done[1:]:
        other = [p["position"] for p in r["workingPlanePoints"]]
        if len(other) != len(grid) or any(abs(u - v) > 1e-6 for a, b in zip(grid, other)
                                           for u, v in zip(a, b)):
            raise SystemExit(f"office-panels: {r['tag']}'s working plane differs from "
                             f"{done[0]['tag']}'s")

    rad_bin, rad_lib = rad
    log("office-panels in RADIANCE (pyradiance rtrace -I)")
    rd = os.path.join(d, "radiance")
    if os.path.exists(rd):
        shutil.rmtree(rd)
    os.makedirs(rd)
    t0 = time.perf_counter()
    conv = radiance.convert(inp, rd, rad_bin)
    m_oconv = measure.run([os.path.join(rad_bin, "oconv"), "scene.rad"], cwd=rd,
                          env=dict(os.environ, RAYPATH=os.pathsep.join([".", rad_lib])),
                          stdout_path=os.path.join(rd, "scene.oct"),
                          stderr_path=os.path.join(rd, "oconv.err"))
    if m_oconv["returncode"] != 0:
        raise SystemExit("oconv failed: see " + os.path.join(rd, "oconv.err"))
    conv_seconds = time.perf_counter() - t0
    points = [tuple(p) + (0.0, 1.0, 0.0) for p in grid]

    def run(tag, options, repeats=1):
        wd = os.path.join(rd, tag)
        os.makedirs(wd)
        vals, m, cmd = radiance.run_rtrace(rad_bin, rad_lib, os.path.join(rd, "scene.oct"),
                                          points * repeats, options, wd,
                                          threads=ctx.threads or os.cpu_count())
        n = len(points)
        reps = [vals[k * n:(k + 1) * n] for k in range(repeats)]
        pts = []
        for i, p in enumerate(grid):
            v = [x[i] for x in reps]
            e = sum(v) / repeats
            pt = {"position": p, "E": e}
            if repeats > 1:
                pt["se"] = math.sqrt(sum((x - e) ** 2 for x in v) / (repeats - 1) / repeats)
            pts.append(pt)
        rec = {"scene": "office-panels", "tag": tag, "tool": "RADIANCE",
               "options": " ".join(options),
               "command": "rtrace " + " ".join(cmd[1:-1]) + " scene.oct < points" +
                          (f" (the {n} points listed {repeats} times)" if repeats > 1 else ""),
               "wall": m["wall"] + m_oconv["wall"], "cpu": m["cpu"] + m_oconv["cpu"],
               "rtraceWall": m["wall"], "oconvWall": m_oconv["wall"],
               "peakMiB": max(m["peakMiB"], m_oconv["peakMiB"]), "points": n,
               "repeats": repeats, "workingPlanePoints": pts,
               "repeatMeans": [sum(x) / n for x in reps], **wp_means(pts)}
        log(f"  radiance/{tag}: {rec['wall']:.1f} s wall, {rec['cpu']:.1f} s CPU, "
            f"WP mean {rec['wpMean']:.3f} lx")
        return rec

    direct = run("ab0", RAD_COMMON + ["-ab", "0"])
    ref_ab, ref_ad, ref_lw = PANELS_REF
    ref = panels_reference(rd, run, rad_options(ref_ab, ref_ad, ref_lw), points,
                           results["machine"].get("radiance"))
    ref["wpDirectMean"] = direct["wpMean"]
    rm = ref["repeatMeans"]
    se = math.sqrt(sum((x - ref["wpMean"]) ** 2 for x in rm) / (len(rm) - 1) / len(rm))
    ref_ind = ref["wpMean"] - direct["wpMean"]
    ref["statError"] = {
        "repeats": len(rm), "wpMeanSe": se, "wpMeanSeRel": se / ref["wpMean"],
        "wpIndirectSeRel": se / ref_ind,
        "pointSeRelRms": math.sqrt(sum((p["se"] / p["E"]) ** 2 for p in
                                       ref["workingPlanePoints"]) / len(grid))}
    sweep = []
    for ab, ad in plan["panels_rad_sweep"]:
        r = run(f"ab{ab}_ad{ad}", rad_options(ab, ad, RAD_SWEEP_LW))
        r["errors"] = panels_errors(r, ref, direct["wpMean"])
        r["plotError"] = abs(r["errors"]["wpMeanErr"])
        sweep.append(r)
    for r in runs:
        if "workingPlanePoints" not in r:
            continue
        r["errors"] = panels_errors(r, ref, r["wpDirectMean"])
        r["errors"]["wpDirectErr"] = rel(r["wpDirectMean"], direct["wpMean"])
        r["plotError"] = abs(r["errors"]["wpMeanErr"])
        r["speedup"] = {k: speedup(r, sweep, k) for k in ("wpMeanErr", "wpIndirectErr",
                                                          "wpRms")}
    scene["runs"] = [strip(r) for r in runs]
    scene["reference"] = {
        "name": f"RADIANCE rtrace -I {ref['options']}, {ref['repeats']} independent repeats",
        **{k: v for k, v in ref.items() if k not in ("workingPlanePoints", "tag")},
        "wpIndirectMean": ref_ind}
    scene["radiance"] = {
        "conversion": {**conv, "seconds": conv_seconds},
        "directOnly": {**strip(direct), "wpMean": direct["wpMean"]},
        "runs": [strip(r) for r in sweep],
        "errorMeasure": "relative error of the working-plane mean against the same reference"}


def bench_cie(ctx, plan, results):
    for rho in plan["cie_rhos"]:
        name = f"cie5.8_rho{rho}"
        log(f"{name} (CIE 171 test 5.8, closed form)")
        d = os.path.join(ctx.work, name)
        os.makedirs(d, exist_ok=True)
        inp = os.path.join(d, "scene.gltf")
        with open(inp, "w", encoding="utf-8") as f:
            f.write(scenes.cie_5_8_gltf(rho))
        exact = scenes.cie_5_8_indirect(rho)
        runs = []
        for q in plan["cie_runs"]:
            r = bake_run(ctx, name, q, inp, quality_args(q), repeats=3)
            if "report" in r:
                walls = [x for x in r["report"]["byMaterial"] if x["name"] == "walls"][0]
                r["errors"] = {"meanIndirect": walls["eIndirectAvg"], "exact": exact,
                               "meanIndirectErr": rel(walls["eIndirectAvg"], exact)}
                r["plotError"] = abs(r["errors"]["meanIndirectErr"])
            runs.append(strip(r))
        results["scenes"][name] = {
            "reference": {"name": "closed form rho*PHI/(S(1-rho))", "value": exact},
            "runs": runs,
            "errorMeasure": "relative error of the area-weighted mean indirect illuminance"}


def bench_cornell(ctx, plan, results):
    log("cornell-box (samples/cornell-box)")
    ref = bake_run(ctx, "cornell-box", "reference", CORNELL,
                   plan["cornell_ref"] + ctx.uniform() + CORNELL_WP, probes=True)
    if "workingPlanePoints" not in ref:
        results["notes"].append("cornell-box: the reference failed; scene skipped")
        return
    runs = []
    for q in plan["cornell_runs"]:
        r = bake_run(ctx, "cornell-box", q, CORNELL, quality_args(q) + CORNELL_WP, repeats=3,
                     probes=True)
        if "workingPlanePoints" in r:
            r["errors"] = {**wp_errors(r, ref), **surface_errors(r, ref)}
            r["plotError"] = r["errors"]["wpRms"]
            bake_diff(ctx, r, ref)
        runs.append(strip(r))
    results["scenes"]["cornell-box"] = {
        "reference": {**strip(ref), "name": plan["cornell_ref_name"] +
                      (", uniform patches" if ctx.has_uniform else ""),
                      "workingPlane": ref["report"]["workingPlane"]},
        "runs": runs,
        "errorMeasure": "RMS over the working-plane points (5 cm above the floor, 5 cm grid) "
                        "of the relative error"}


def bench_openplan(ctx, plan, results):
    if not has_subcommand(ctx.bake, "generate"):
        note = ("open-plan floors skipped: this bake has no `generate` subcommand (the "
                "generator `bake generate openplan` is not merged yet)")
        log(note)
        results["notes"].append(note)
        results["generatorMissing"] = True
        return
    scaling = []
    for size in plan["openplan_sizes"]:
        name = f"openplan-{size}"
        d = os.path.join(ctx.work, name)
        os.makedirs(d, exist_ok=True)
        inp = os.path.join(d, "scene.gltf")
        g = measure.run([ctx.bake, "generate", "openplan", "--size", size, "-o", inp],
                        stderr_path=os.path.join(d, "generate.txt"), timeout=600)
        if g["returncode"] != 0:
            results["notes"].append(f"{name}: `bake generate` failed; skipped")
            continue
        with open(os.path.join(d, "generate.txt"), encoding="utf-8", errors="replace") as f:
            gen_text = f.read().strip()
        triangles = count_triangles(inp)
        log(f"{name}: {triangles} triangles ({gen_text.splitlines()[-1] if gen_text else ''})")
        # the scaling point: a plain default-quality bake
        limit = ctx.openplan_limit if ctx.openplan_limit and size != "small" else \
            TIMEOUT_OPENPLAN[size]
        r = bake_run(ctx, name, "default-plain", inp, quality_args("default"), timeout=limit)
        r["timeLimit"] = limit
        r["triangles"] = triangles
        scaling.append(strip(r))
        if size != "small" or not ctx.openplan_errors:
            continue
        ref = bake_run(ctx, name, "reference", inp,
                       plan["openplan_ref"] + ctx.uniform() + OPENPLAN_WP, probes=True,
                       timeout=TIMEOUT_DEFAULT)
        if "workingPlanePoints" not in ref:
            results["notes"].append(f"{name}: the reference failed; error curve skipped")
            continue
        runs = []
        for q in plan["openplan_runs"]:
            rr = bake_run(ctx, name, q, inp, quality_args(q) + OPENPLAN_WP, probes=True,
                          timeout=TIMEOUT_DEFAULT)
            if "workingPlanePoints" in rr:
                rr["errors"] = {**wp_errors(rr, ref), **surface_errors(rr, ref)}
                rr["plotError"] = rr["errors"]["wpRms"]
                bake_diff(ctx, rr, ref)
            runs.append(strip(rr))
        results["scenes"][name] = {
            "triangles": triangles,
            "reference": {**strip(ref), "name": plan["openplan_ref_name"],
                          "workingPlane": ref["report"]["workingPlane"]},
            "runs": runs,
            "errorMeasure": "RMS over the working-plane points (0.8 m, 0.5 m grid) of the "
                            "relative error"}
    results["scaling"] = scaling


def count_triangles(path):
    g = radiance.Gltf(path)
    n = 0
    for _, node, _ in g.walk():
        if "mesh" in node:
            for prim in g.doc["meshes"][node["mesh"]]["primitives"]:
                if prim.get("mode", 4) == 4:
                    acc = prim.get("indices", prim["attributes"]["POSITION"])
                    n += g.doc["accessors"][acc]["count"] // 3
    return n


# ------------------------------------------------------------------ targets

def speedup(lux, rad_runs, key):
    """RADIANCE's time over luxbake's (wall, and CPU) for the cheapest RADIANCE run whose error
    (key) is no larger than luxbake's; lower bounds when no RADIANCE run of the sweep gets there.
    Met when both ratios reach SPEEDUP_GOAL (on a shared machine the two tools may not have had
    the same share of the cores, which the CPU ratio does not depend on); not met when neither
    does."""
    e = abs(lux["errors"][key])
    ok = [r for r in rad_runs if abs(r["errors"][key]) <= e]
    if ok:
        best = min(ok, key=lambda r: r["wall"])
        wall, cpu = best["wall"] / lux["wall"], best["cpu"] / lux["cpu"]
        goal = SPEEDUP_GOAL
        met = True if min(wall, cpu) >= goal else False if max(wall, cpu) < goal else None
        return {"ratio": wall, "cpuRatio": cpu, "lowerBound": False, "radiance": best["tag"],
                "met": met,
                "text": f"{wall:.1f}× wall, {cpu:.1f}× CPU (RADIANCE {best['tag']}: "
                        f"{best['wall']:.1f} s wall, {best['cpu']:.1f} s CPU at "
                        f"{100 * abs(best['errors'][key]):.3f} %; luxbake {lux['tag']}: "
                        f"{lux['wall']:.2f} s wall, {lux['cpu']:.2f} s CPU at {100 * e:.3f} %)"}
    slowest = max(rad_runs, key=lambda r: r["wall"])
    wall, cpu = slowest["wall"] / lux["wall"], slowest["cpu"] / lux["cpu"]
    best_e = min(abs(r["errors"][key]) for r in rad_runs)
    return {"ratio": wall, "cpuRatio": cpu, "lowerBound": True, "radiance": None,
            "met": True if min(wall, cpu) >= SPEEDUP_GOAL else None,
            "text": f"> {wall:.1f}× wall, > {cpu:.1f}× CPU: no RADIANCE run reached luxbake "
                    f"{lux['tag']}'s {100 * e:.3f} % (RADIANCE's best {100 * best_e:.3f} %; "
                    f"slowest {slowest['tag']} {slowest['wall']:.1f} s; luxbake "
                    f"{lux['wall']:.2f} s)"}


def targets(results):
    rows = []
    sc = results["scenes"]

    def find(scene, tag):
        for r in sc.get(scene, {}).get("runs", []):
            if r["tag"] == tag:
                return r
        return None

    o = find("office", "default")
    if o and "errors" in o:
        e = o["errors"]
        rows.append(["Office, default quality: working-plane mean within 1 % of the converged "
                     "reference", "≤ 1 %", f"{100 * e['wpMeanErr']:+.3f} %",
                     abs(e["wpMeanErr"]) <= 0.01])
        rows.append(["Office, default quality: every probe (each face) within 3 %", "≤ 3 %",
                     f"{100 * e['probeMax']:.3f} % (worst: {e['probeWorst']})",
                     e["probeMax"] <= 0.03])
        rows.append(["Office, default quality: wall time", "< 1 s",
                     f"{o['wall']:.2f} s ({o['cpu']:.2f} s CPU)", o["wall"] < 1.0])
    else:
        rows.append(["Office targets", "—", "not measured", None])
    c = find("cie5.8_rho0.99", "default")
    if c and "errors" in c:
        rows.append(["CIE 171 test 5.8, ρ = 0.99, default quality: mean indirect within 0.5 %",
                     "≤ 0.5 %", f"{100 * c['errors']['meanIndirectErr']:+.3f} %",
                     abs(c["errors"]["meanIndirectErr"]) <= 0.005])
        rows.append(["CIE 171 test 5.8, ρ = 0.99, default quality: wall time", "< 1 s",
                     f"{c['wall']:.2f} s", c["wall"] < 1.0])
    rad = sc.get("office", {}).get("radiance")
    if o and rad and "errors" in o:
        for key, label in (("wpRms", "per-point RMS"), ("wpMeanErr", "mean")):
            s = speedup(o, rad["runs"], key)
            rows.append([f"Office working plane ({label} error): luxbake default at least "
                         f"{SPEEDUP_GOAL}× faster than RADIANCE at equal or better error",
                         f"≥ {SPEEDUP_GOAL}×", s["text"], s["met"]])
    op = find("office-panels", "default")
    if op and "errors" in op:
        e = op["errors"]
        st = sc["office-panels"]["reference"].get("statError") or {}
        rows.append(["Office with Lambertian panels (the seed's HELIOS model), default quality: "
                     "working-plane mean within 0.5 % of RADIANCE's converged value", "≤ 0.5 %",
                     f"{100 * e['wpMeanErr']:+.3f} % (reference ± "
                     f"{100 * st.get('wpMeanSeRel', float('nan')):.3f} %)",
                     abs(e["wpMeanErr"]) <= 0.005])
        rows.append(["Office with Lambertian panels, default quality: inter-reflected part of "
                     "the working-plane mean within 1 %", "≤ 1 %",
                     f"{100 * e['wpIndirectErr']:+.3f} % (reference ± "
                     f"{100 * st.get('wpIndirectSeRel', float('nan')):.3f} %)",
                     abs(e["wpIndirectErr"]) <= 0.01])
        for key, label in (("wpMeanErr", "mean"), ("wpRms", "per-point RMS"),
                           ("wpIndirectErr", "inter-reflected part")):
            s = op["speedup"][key]
            rows.append([f"Office with Lambertian panels, working plane ({label} error): "
                         f"luxbake default at least {SPEEDUP_GOAL}× faster than RADIANCE at "
                         "equal or better error", f"≥ {SPEEDUP_GOAL}×", s["text"], s["met"]])
    elif "office-panels" in sc:
        rows.append(["Office with Lambertian panels: targets", "—",
                     "not measured (no RADIANCE reference or no default bake)", None])
    sc_rows = results.get("scaling") or []
    for size, label in (("small", "10⁴"), ("medium", "10⁵"), ("large", "10⁶")):
        r = next((r for r in sc_rows if r["scene"] == f"openplan-{size}"), None)
        goal = FLOOR_TARGETS[size]
        name = f"{label}-triangle floor, default quality: wall time and peak memory"
        need = f"≤ {goal:.0f} s, ≤ {FLOOR_MEMORY_MIB // 1024} GiB"
        if r is None:
            why = ("not measured (`bake generate` not available)"
                   if results.get("generatorMissing") else "not run (--quick or --scenes)")
            rows.append([name, need, why, None])
            continue
        gib = f"{r['peakMiB'] / 1024:.2f} GiB"
        if r.get("timedOut"):
            rows.append([name, need, f"> {r['wall']:.0f} s (stopped), {gib} until then",
                         False if r["wall"] > goal else None])
        else:
            rows.append([name, need, f"{r['wall']:.1f} s, {gib}",
                         r["wall"] <= goal and r["peakMiB"] <= FLOOR_MEMORY_MIB])
    done = [r for r in sc_rows if not r.get("timedOut") and r.get("returncode") == 0]
    stopped = [r for r in sc_rows if r.get("timedOut")]
    if len(done) == 1 and stopped:
        a = done[0]
        parts, exceeded = [], False
        for b in stopped:
            na, nb = a["triangles"], b["triangles"]
            nlogn = (nb * math.log(nb)) / (na * math.log(na))
            ratio = b["wall"] / a["wall"]
            exceeded |= ratio > 1.25 * nlogn
            parts.append(f"{nb} triangles: > {ratio:.1f}× (stopped at {b['wall']:.0f} s; "
                         f"about N log N allows {1.25 * nlogn:.1f}×, 1.25 × {nlogn:.1f}×)")
        rows.append([f"Time grows no worse than about N log N from {a['triangles']} triangles "
                     f"({a['wall']:.1f} s)", "about N log N (1.25 × N log N)", "; ".join(parts) +
                     ("" if exceeded else " — the lower bounds cannot decide it"),
                     False if exceeded else None])
    elif len(done) >= 2:
        a, b = done[0], done[-1]
        na, nb = a["triangles"], b["triangles"]
        nlogn = (nb * math.log(nb)) / (na * math.log(na))
        ratio = b["wall"] / a["wall"]
        slope = math.log(ratio) / math.log(nb / na)
        rows.append([f"Time from {na} to {nb} triangles grows no worse than about N log N",
                     f"≤ {1.25 * nlogn:.0f}× (\"about\": 1.25 × N log N's {nlogn:.0f}×)",
                     f"{ratio:.0f}× (log-log slope {slope:.2f})", ratio <= 1.25 * nlogn])
    else:
        why = ("not measured (`bake generate` not available)" if results.get("generatorMissing")
               else "fewer than two floor sizes finished" if results.get("scaling")
               else "not run (--quick or --scenes)")
        rows.append(["Time grows no worse than N log N from 10⁴ to 10⁶ triangles", "N log N",
                     why, None])
    return rows


# ------------------------------------------------------------------ output

def pct(x, digits=3):
    return "—" if x is None else f"{100 * x:.{digits}f}"


def rad_ref_name(results):
    rad = results["scenes"].get("office", {}).get("radiance")
    return f"rtrace {rad['reference']['name']}" if rad else "not run"


def write_plots(results, out):
    series = []
    sc = results["scenes"]
    for name, s in sc.items():
        for variant in sorted({r.get("variant", "") for r in s["runs"]}):
            pts = [(r["wall"], r["plotError"] * 100, r["tag"].replace("-" + variant, ""))
                   for r in s["runs"] if "plotError" in r and r.get("variant", "") == variant]
            label = f"{name} (luxbake" + (f", {variant} patches)" if variant else ")")
            if pts:
                series.append({"name": label, "points": pts, "dash": bool(variant)})
        if name in ("office", "office-panels") and s.get("radiance"):
            rp = sorted((r["wall"], r["plotError"] * 100, r["tag"].replace("_", " "))
                        for r in s["radiance"]["runs"])
            series.append({"name": f"{name} (RADIANCE rtrace)", "points": rp, "dash": True})
    if not series:
        return write_scaling(results, out)
    svgplot.plot(os.path.join(out, "time_vs_error.svg"), series,
                 "luxbake: wall time against error (one curve per scene)",
                 "wall time, s (log)", "error, % (log)",
                 caption=["office, Cornell box, open plan: RMS over the working-plane points of "
                          "the relative error against a converged bake;",
                          "RADIANCE: against its own reference "
                          f"({rad_ref_name(results)}), at the same points.",
                          "office-panels (luxbake and RADIANCE): relative error of the "
                          "working-plane mean against RADIANCE's converged reference.",
                          "CIE 171 test 5.8: relative error of the mean indirect illuminance "
                          "against the closed form. Hollow points lie below the axis floor.",
                          f"Machine: {results['machine']['cpu'].split(' (')[0]}, "
                          f"{results['machine']['cores']} cores (shared); see results.md."])
    write_scaling(results, out)


def write_scaling(results, out):
    sc_rows = [r for r in results.get("scaling") or [] if r.get("returncode") == 0 or
               r.get("timedOut")]
    if sc_rows:
        pts = [(r["triangles"], r["wall"], r["scene"].replace("openplan-", "") +
                (f" (stopped at {r['wall']:.0f} s)" if r.get("timedOut") else ""),
                bool(r.get("timedOut"))) for r in sc_rows]
        n0, t0 = pts[0][0], pts[0][1]
        n1 = max(p[0] for p in pts)
        ns = [n for n in (n0 * 10 ** (k / 4) for k in range(0, 13)) if n < n1] + [n1]
        guide = [(n, t0 * n * math.log(n) / (n0 * math.log(n0))) for n in ns]
        lin = [(n, t0 * n / n0) for n in ns]
        svgplot.plot(os.path.join(out, "scaling.svg"),
                     [{"name": "open-plan floor, default quality", "points": pts}],
                     "luxbake: wall time against triangle count",
                     "triangles (log)", "wall time, s (log)",
                     guides=[("N log N", guide), ("N", lin)],
                     caption=["Generated open-plan floors (bake generate openplan --size "
                              "small|medium|large), default quality, plain bake; guides N and "
                              "N log N through the first point.",
                              "Hollow points: the bake was stopped at its time limit (the time "
                              "is a lower bound)."])


def panels_markdown(s, results):
    """The office-panels section of results.md."""
    info, ref = s["scene"], s["reference"]
    c = info["panelCentres"]
    L = ["### office-panels", "",
         "The seed office modelled as the seed's HELIOS run modelled it: samples/office's room "
         "shell (5 × 8 × 3.2 m; floor, ceiling, walls, back wall" +
         (" and the picture" if info["picture"] else "") + " with their reflectances "
         f"{info['reflectances']}; no desks), its six louvred fluorescents replaced by "
         f"{info['panelSize'][0]} × {info['panelSize'][1]} m single-sided black Lambertian "
         f"panels of {info['panelFluxLm']:.0f} lm each (`LUXBAKE_material` emission "
         "`luminousFlux`; RADIANCE `light` polygons), facing down (−Y), their faces "
         f"{info['gapMetres']} m below the ceiling (y = {c[0][1]} m, +Y up), centres at the "
         f"luminaires' (x, z) = " + ", ".join(f"({p[0]:.2f}, {p[2]:.2f})" for p in c) +
         f", long side along {info['panelLongSide']}. Working plane 0.8 m, 0.5 m grid. "
         "Errors are against RADIANCE, for luxbake and RADIANCE alike; the inter-reflected "
         "part is total − direct (luxbake: its own direct part; RADIANCE: its `-ab 0` run).", ""]
    if "statError" not in ref:
        L += ["RADIANCE was not run: no errors.", ""]
        return L
    st = ref["statError"]
    L += [f"Reference: `{ref['name']}` ({ref['wall']:.0f} s wall, {ref['cpu']:.0f} s CPU" +
          (f"; cached in `bench/data/{os.path.basename(PANELS_REF_CACHE)}`, computed "
           f"{ref['date']}" if ref.get("cached") else f"; computed in this run, {ref['date']}")
          + f"): working-plane mean {ref['wpMean']:.3f} lx, direct (`-ab 0`) "
          f"{ref['wpDirectMean']:.3f} lx, inter-reflected {ref['wpIndirectMean']:.3f} lx. "
          f"Statistical error (standard error over the {st['repeats']} repeats): "
          f"{st['wpMeanSe']:.3f} lx = {100 * st['wpMeanSeRel']:.4f} % of the mean, "
          f"{100 * st['wpIndirectSeRel']:.4f} % of the inter-reflected part; per point "
          f"{100 * st['pointSeRelRms']:.3f} % (RMS).", "",
          "| run | wall s | CPU s | peak MiB | patches | wp mean lx | wp mean err % | "
          "inter-reflected lx | inter-reflected err % | wp RMS % | direct vs RADIANCE -ab 0 % "
          "| speed-up at equal mean error: wall / CPU | at equal inter-reflected error |",
          "| --- |" + " ---: |" * 10 + " --- | --- |"]
    for r in s["runs"]:
        e, c = r.get("errors"), r.get("counts") or {}
        if not e:
            L.append(f"| luxbake {r['tag']} | failed or stopped after {r['wall']:.0f} s |")
            continue
        cells = []
        for key in ("wpMeanErr", "wpIndirectErr"):
            x = r["speedup"][key]
            cells.append(f"> {x['ratio']:.1f}× / > {x['cpuRatio']:.1f}× (none reached)"
                         if x["lowerBound"] else
                         f"{x['ratio']:.1f}× / {x['cpuRatio']:.1f}× ({x['radiance']})")
        L.append(f"| luxbake {r['tag']} | {r['wall']:.2f} | {r['cpu']:.2f} | "
                 f"{r['peakMiB']:.0f} | {c.get('patches')} | {e['wpMean']:.3f} | "
                 f"{100 * e['wpMeanErr']:+.3f} | {e['wpIndirect']:.3f} | "
                 f"{100 * e['wpIndirectErr']:+.3f} | {pct(e['wpRms'])} | "
                 f"{100 * e['wpDirectErr']:+.4f} | {cells[0]} | {cells[1]} |")
    for r in s["radiance"]["runs"]:
        e = r["errors"]
        L.append(f"| RADIANCE {r['options'].split('-aa 0 ')[-1]} | {r['wall']:.2f} | "
                 f"{r['cpu']:.2f} | {r['peakMiB']:.0f} | | {e['wpMean']:.3f} | "
                 f"{100 * e['wpMeanErr']:+.3f} | {e['wpIndirect']:.3f} | "
                 f"{100 * e['wpIndirectErr']:+.3f} | {pct(e['wpRms'])} | | | |")
    conv = s["radiance"]["conversion"]
    L += ["", f"RADIANCE: {conv['triangles']} triangles converted, the panels as "
          f"{len(conv['emitters'])} `light` material(s) of radiance "
          f"{conv['emitters'][0]['radiance'][0]:.4f} W/(sr·m²) = "
          f"{conv['emitters'][0]['luminance']:.2f} cd/m² / 179 lm/W, one polygon per panel "
          "(a light polygon emits from its front only and looks black from behind, like a "
          "single-sided black emitter in luxbake). Options common to all runs: "
          f"`{' '.join(RAD_COMMON)}`; sweep `-lw {RAD_SWEEP_LW}`, one run each. Time = oconv + "
          f"rtrace (-n {results['radianceThreads']}). Speed-up: RADIANCE's cheapest run of the "
          "sweep with no larger error, over luxbake's time (as for the office).", ""]
    return L


def provenance_line(results):
    """bench/provenance.py's line from the run's own record (so `--replot` keeps the commit,
    date and machine the figures were measured at)."""
    m = results["machine"]
    commit = m["gitCommit"].split()[0][:7]
    dirty = ", with uncommitted changes" if "uncommitted" in m["gitCommit"] else ""
    command = results["command"]
    section = "quick" if " --scenes office-panels " in command + " " else "all"
    return provenance.line(command, section, at=f"{commit} (measured at{dirty})",
                           date=results["date"][:10],
                           machine_text=f"{m['cores']} cores, {m['ramGiB']} GiB ({m['cpu']})")


def write_markdown(results, out, rows):
    m = results["machine"]
    L = ["# luxbake benchmark results", "", provenance_line(results), "",
         f"Written by `{results['command']}` on {results['date']} "
         f"(harness wall time {results['harnessSeconds'] / 60:.1f} min)." +
         (f" Tables, verdicts and plots rewritten from results.json (`--replot`, no new runs) "
          f"on {results['replotted']}." if results.get("replotted") else ""), "",
         "## Machine", "",
         "| | |", "| --- | --- |",
         f"| CPU | {m['cpu']} |", f"| cores | {m['cores']} |",
         f"| RAM | {m['ramGiB']} GiB |", f"| OS | {m['os']} |",
         f"| virtualisation | {m.get('virtualisation', '—')} |",
         f"| rustc | {m['rustc']} |", f"| luxbake | {m['luxbake']} |",
         f"| git commit | {m['gitCommit']} ({m['gitBranch']}) |",
         f"| RADIANCE | {m['radiance']} (PyPI {m['pyradiance']}) |",
         f"| Python | {m['python']} |",
         f"| load average (1, 5, 15 min) at start / end | {results['loadavgStart']} / "
         f"{results['loadavgEnd']} |", "",
         "The machine is shared: other work ran on the same two cores during the run (see the "
         "load averages), so wall times are pessimistic; CPU time (user + system, all threads) "
         "is given beside them. Short runs (< 3 s) are repeated three times and the fastest is "
         "kept.", "",
         "## Targets", "",
         "| target | required | measured | met? |", "| --- | --- | --- | --- |"]
    for t, req, meas, met in rows:
        L.append(f"| {t} | {req} | {meas} | "
                 f"{'yes' if met is True else 'no' if met is False else 'n/a'} |")
    if any("plotError" in r for s in results["scenes"].values() for r in s["runs"]):
        L += ["", "![time against error](time_vs_error.svg)", ""]
    else:
        L.append("")
    if results.get("scaling"):
        L += ["![scaling](scaling.svg)", ""]
    L += ["## Runs", "",
          "Wall and CPU time in s, peak resident memory in MiB; errors in % (signed for means, "
          "else magnitudes). `wp` = working plane, `probes` = largest error over the six faces "
          "of every probe, `surfaces` = largest error of a node's area-weighted mean "
          "illuminance.", ""]
    for name, s in results["scenes"].items():
        if name == "office-panels":
            L += panels_markdown(s, results)
            continue
        ref = s["reference"]
        L += [f"### {name}", "", f"Reference: {ref['name']}" +
              (f" ({ref['wall']:.1f} s wall, {ref['cpu']:.1f} s CPU, {ref['peakMiB']:.0f} MiB, "
               f"{ref['counts']['patches']} patches)" if "counts" in ref else
               f" = {ref['value']:.4f} lx") + ".", f"Error plotted: {s['errorMeasure']}.", ""]
        if name.startswith("cie"):
            L += ["| quality | wall s | CPU s | peak MiB | patches | links | rays | mean E_ind lx "
                  "| exact lx | error % |", "| --- | ---: | ---: | ---: | ---: | ---: | ---: | "
                  "---: | ---: | ---: |"]
            for r in s["runs"]:
                c, e = r.get("counts") or {}, r.get("errors") or {}
                L.append(f"| {r['tag']} | {r['wall']:.3f} | {r['cpu']:.3f} | {r['peakMiB']:.0f} "
                         f"| {c.get('patches')} | {c.get('links')} | {c.get('rays')} | "
                         f"{e.get('meanIndirect', 0):.3f} | {e.get('exact', 0):.3f} | "
                         f"{100 * e.get('meanIndirectErr', float('nan')):+.4f} |")
        else:
            probes = name == "office"
            head = ("| quality | wall s | CPU s | peak MiB | patches | links | rays | wp mean lx | "
                    "wp mean err % | wp RMS % | wp max % |" + (" probes max % |" if probes else "")
                    + " surfaces max % |")
            L += [head, "|" + " --- |" + " ---: |" * (head.count("|") - 2)]
            for r in s["runs"]:
                c, e = r.get("counts") or {}, r.get("errors") or {}
                if r.get("timedOut") or r.get("returncode"):
                    L.append(f"| {r['tag']} | stopped/failed after {r['wall']:.0f} s |")
                    continue
                L.append(f"| {r['tag']} | {r['wall']:.2f} | {r['cpu']:.2f} | {r['peakMiB']:.0f} "
                         f"| {c.get('patches')} | {c.get('links')} | {c.get('rays')} | "
                         f"{e['wpMean']:.2f} | {100 * e['wpMeanErr']:+.3f} | {pct(e['wpRms'])} | "
                         f"{pct(e['wpMax'])} |" +
                         (f" {pct(e['probeMax'])} ({e['probeWorst']}) |" if probes else "") +
                         f" {pct(e.get('surfaceMax'))} ({e.get('surfaceWorst')}) |")
        L.append("")
        diffs = [r for r in s["runs"] if (r.get("bakeDiff") or {}).get("overall")]
        if diffs:
            L += ["`bake diff RUN REFERENCE --mode means` (area-weighted means of every node and "
                  "material, and the probes; relative differences, values below its floor of "
                  "1 % of the reference's 99th percentile taken at the floor):", "",
                  "| quality | illuminance: max % | mean % | direct: max % | luminance: max % | "
                  "probe faces: max % | working plane: max % | values | outside 0.1 % |",
                  "| --- |" + " ---: |" * 8]
            for r in diffs:
                o = r["bakeDiff"]["overall"]

                def g(q, k):
                    v = (o.get(q) or {}).get(k)
                    return "—" if v is None else f"{100 * v:.3f}"
                L.append(f"| {r['tag']} | {g('illuminance', 'relMax')} | "
                         f"{g('illuminance', 'relMean')} | {g('illuminanceDirect', 'relMax')} | "
                         f"{g('luminance', 'relMax')} | {g('probeFaces', 'relMax')} | "
                         f"{g('workingPlane', 'relMax')} | {r['bakeDiff'].get('values')} | "
                         f"{r['bakeDiff'].get('failed')} |")
            L.append("")
        stages = [r for r in s["runs"] if r.get("stageSeconds")]
        if stages and not name.startswith("cie"):
            keys = list(stages[0]["stageSeconds"].keys())
            L += ["Stage wall times (s, from `--summary-json`):", "",
                  "| quality | " + " | ".join(keys) + " |",
                  "| --- |" + " ---: |" * len(keys)]
            for r in stages:
                L.append(f"| {r['tag']} | " + " | ".join(f"{r['stageSeconds'][k]:.2f}"
                                                       for k in keys) + " |")
            L.append("")
        rad = s.get("radiance")
        if rad:
            L += ["#### RADIANCE (rtrace -I) on the office", "",
                  f"Converted scene: {rad['conversion']['triangles']} triangles, "
                  f"{len(rad['conversion']['luminaires'])} luminaires "
                  f"(ies2rad + xform); {rad['runs'][0]['points']} rtrace points "
                  f"(the {s['reference']['workingPlane']['points']} working-plane points facing "
                  f"up, and six faces of each of the {len(s['reference']['probes'])} probes). "
                  f"Options common to all runs: `{' '.join(RAD_COMMON)}`; sweep `-lw {RAD_SWEEP_LW}`. "
                  f"Time = oconv + rtrace (-n {results['radianceThreads']}); conversion from "
                  f"glTF ({rad['conversion']['seconds']:.1f} s) not counted. "
                  f"Reference: `{rad['reference']['name']}` ({rad['reference']['wall']:.0f} s "
                  f"wall).", "",
                  "| settings | wall s | CPU s | peak MiB | wp mean lx | wp mean err % | wp RMS % | "
                  "wp max % | probes max % | vs luxbake ref: wp mean % | wp RMS % | probes max % |",
                  "| --- |" + " ---: |" * 11]
            for r in rad["runs"]:
                e, x = r["errors"], r["errorsVsLuxbakeReference"]
                L.append(f"| {r['options'].split('-aa 0 ')[-1]} | {r['wall']:.1f} | "
                         f"{r['cpu']:.1f} | {r['peakMiB']:.0f} | {e['wpMean']:.2f} | "
                         f"{100 * e['wpMeanErr']:+.3f} | {pct(e['wpRms'])} | {pct(e['wpMax'])} | "
                         f"{pct(e['probeMax'])} | {100 * x['wpMeanErr']:+.3f} | "
                         f"{pct(x['wpRms'])} | {pct(x['probeMax'])} |")
            L += ["", "Speed-up at equal or better error (RADIANCE's cheapest run of the sweep "
                  "with no larger error, against its own reference, over luxbake's time):", "",
                  "| luxbake run | wall s | CPU s | per-point RMS: speed-up wall / CPU | "
                  "mean: speed-up wall / CPU |", "| --- | ---: | ---: | --- | --- |"]
            for r in s["runs"]:
                if "errors" not in r:
                    continue
                cells = []
                for key in ("wpRms", "wpMeanErr"):
                    x = speedup(r, rad["runs"], key)
                    cells.append((f"> {x['ratio']:.1f}× / > {x['cpuRatio']:.1f}× (none reached "
                                  f"{100 * abs(r['errors'][key]):.3f} %)"
                                  if x["lowerBound"] else
                                  f"{x['ratio']:.1f}× / {x['cpuRatio']:.1f}× ({x['radiance']}; "
                                  f"{100 * abs(r['errors'][key]):.3f} %)"))
                L.append(f"| {r['tag']} | {r['wall']:.2f} | {r['cpu']:.2f} | {cells[0]} | "
                         f"{cells[1]} |")
            a = rad["referenceAgreement"]
            L += ["", "**The two references** (RADIANCE's against luxbake's):", "",
                  "| | wp mean (RADIANCE − luxbake) | wp RMS per point | wp max per point | "
                  "probes max (face) |", "| --- | ---: | ---: | ---: | ---: |",
                  f"| total | {100 * a['total']['wpMeanErr']:+.3f} % "
                  f"({a['total']['wpMean']:.2f} vs {a['total']['wpMeanRef']:.2f} lx) | "
                  f"{pct(a['total']['wpRms'])} % | {pct(a['total']['wpMax'])} % | "
                  f"{pct(a['total']['probeMax'])} % ({a['total']['probeWorst']}) |",
                  f"| direct only (RADIANCE -ab 0; luxbake's direct part) | "
                  f"{100 * a['direct']['wpMeanErr']:+.3f} % "
                  f"({a['direct']['wpMean']:.2f} vs {a['direct']['wpMeanRef']:.2f} lx) | "
                  f"{pct(a['direct']['wpRms'])} % | {pct(a['direct']['wpMax'])} % | "
                  f"{pct(a['direct']['probeMax'])} % ({a['direct']['probeWorst']}) |",
                  f"| indirect (wp mean) | {100 * a['indirectWpMean']['relDiff']:+.2f} % "
                  f"({a['indirectWpMean']['radiance']:.2f} vs "
                  f"{a['indirectWpMean']['luxbake']:.2f} lx) | | | |", ""]
    if results.get("scaling"):
        L += ["### Scaling (open-plan floors, default quality, plain bake)", "",
              "| scene | triangles | wall s | CPU s | peak MiB | patches | links | rays |",
              "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
        for r in results["scaling"]:
            c = r.get("counts") or {}
            wall = (f"> {r['wall']:.0f} (stopped)" if r.get("timedOut") else f"{r['wall']:.2f}")
            L.append(f"| {r['scene']} | {r['triangles']} | {wall} | {r['cpu']:.2f} | "
                     f"{r['peakMiB']:.0f} | {c.get('patches', '—')} | {c.get('links', '—')} | "
                     f"{c.get('rays', '—')} |")
        L.append("")
        staged = [r for r in results["scaling"]
                  if r.get("stageSeconds") and (r.get("counts") or {}).get("raysByStage")]
        if staged:
            L += ["Where the time and the shadow rays go (stage wall seconds; rays in millions, "
                  "per receiver in brackets):", "",
                  "| scene | mesh s | direct s | links s | solve s | rays: meshing | "
                  "direct at receivers | direct into patches | links |",
                  "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
            for r in staged:
                t, c = r["stageSeconds"], r["counts"]
                rays, n = c["raysByStage"], max(c.get("receivers") or 1, 1)
                cell = lambda k: f"{rays.get(k, 0) / 1e6:.1f} ({rays.get(k, 0) / n:.0f})"
                L.append(f"| {r['scene']} | {t.get('mesh', 0):.1f} | {t.get('direct', 0):.1f} | "
                         f"{t.get('links', 0):.1f} | {t.get('solve', 0):.1f} | "
                         f"{cell('meshing')} | {cell('directAtReceivers')} | "
                         f"{cell('directIntoPatches')} | {cell('links')} |")
            L.append("")
    if results["notes"]:
        L += ["## Notes", ""] + [f"- {n}" for n in results["notes"]] + [""]
    readme = os.path.relpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "README.md"),
                             os.path.abspath(out))
    L += [f"Reproduce: see [bench/README.md]({readme}). Raw figures: "
          "[results.json](results.json).", ""]
    with open(os.path.join(out, "results.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(L))


# ------------------------------------------------------------------ main

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true",
                    help="a quick subset: fewer settings, unconverged references, no large "
                         "floors; writes bench/work/quick-results unless --out")
    ap.add_argument("--scenes", default="office,office-panels,cie,cornell,openplan",
                    help="comma-separated subset of office,office-panels,cie,cornell,openplan")
    ap.add_argument("--no-radiance", action="store_true", help="skip the RADIANCE comparison")
    ap.add_argument("--openplan-limit", type=float, default=0, metavar="SECONDS",
                    help="time limit of the medium and large open-plan bakes (default 150 s "
                         "and 330 s: past their targets of 30 s and 300 s, so the run decides "
                         "them; the harness then takes about 15 min)")
    ap.add_argument("--openplan-sizes", default="", metavar="LIST",
                    help="comma-separated subset of small,medium,large (default: the plan's)")
    ap.add_argument("--openplan-errors", action="store_true",
                    help="also bake the small open-plan floor at every quality against a "
                         "high-quality reference (long: not part of the ~20 min budget)")
    ap.add_argument("--bake", help="use this bake binary instead of building one")
    ap.add_argument("--threads", type=int, default=0,
                    help="threads for bake and rtrace (default: all cores)")
    ap.add_argument("--out", help="results folder (default bench/results)")
    ap.add_argument("--work", default=os.path.join(BENCH, "work"),
                    help="scratch folder for scenes and outputs (default bench/work)")
    ap.add_argument("--replot", metavar="DIR",
                    help="only rewrite results.md and the plots from DIR/results.json (no runs)")
    a = ap.parse_args()
    if a.replot:
        with open(os.path.join(a.replot, "results.json"), encoding="utf-8") as f:
            results = json.load(f)
        rows = targets(results)
        results["targets"] = [{"target": t, "required": q, "measured": m, "met": ok}
                              for t, q, m, ok in rows]
        commit = sh(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT).stdout.strip()
        results["replotted"] = (datetime.datetime.now(datetime.timezone.utc)
                                .strftime("%Y-%m-%d %H:%M UTC") + f" by the harness at {commit}")
        with open(os.path.join(a.replot, "results.json"), "w", encoding="utf-8") as f:
            json.dump(results, f, indent=1, ensure_ascii=False)
            f.write("\n")
        write_plots(results, a.replot)
        write_markdown(results, a.replot, rows)
        log(f"rewrote {a.replot}/results.md and plots from results.json")
        return
    plan = dict(PLANS["quick" if a.quick else "full"])
    if a.openplan_sizes:
        plan["openplan_sizes"] = a.openplan_sizes.split(",")
    out = a.out or (os.path.join(BENCH, "work", "quick-results") if a.quick
                    else os.path.join(BENCH, "results"))
    wanted = set(a.scenes.split(","))
    t_start = time.perf_counter()
    bake = os.path.abspath(a.bake) if a.bake else build_bake()
    if not os.path.exists(bake):
        raise SystemExit(f"no bake binary at {bake}")
    rad_dir = None if a.no_radiance or not wanted & {"office", "office-panels"} else \
        ensure_venv(os.path.join(BENCH, ".venv"))
    rad = (os.path.join(rad_dir, "bin"), os.path.join(rad_dir, "lib")) if rad_dir else None
    work = os.path.join(a.work, "quick" if a.quick else "full")
    if os.path.exists(work):
        shutil.rmtree(work)
    os.makedirs(work)
    os.makedirs(out, exist_ok=True)
    cmdline = "python3 bench/run.py" + (" " + " ".join(sys.argv[1:]) if sys.argv[1:] else "")
    results = {
        "command": cmdline,
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "plan": "quick" if a.quick else "full",
        "machine": machine(bake, rad),
        "loadavgStart": loadavg(),
        "radianceThreads": a.threads or os.cpu_count(),
        "scenes": {},
        "notes": [],
    }
    log(f"machine: {results['machine']['cpu']}, {results['machine']['cores']} cores, "
        f"load {results['loadavgStart']}")
    ctx = Ctx(bake, work, a.threads)
    ctx.openplan_errors = a.openplan_errors
    ctx.openplan_limit = a.openplan_limit
    if not ctx.has_diff:
        results["notes"].append("`bake diff` is not in this bake (branch diff not merged): "
                                "bakes are compared at the working-plane points and probes "
                                "only (which is what the targets are phrased in)")
    results["bakeDiffUsed"] = ctx.has_diff
    if "cie" in wanted:
        bench_cie(ctx, plan, results)
    if "office" in wanted:
        bench_office(ctx, plan, rad, results)
    if "office-panels" in wanted:
        bench_office_panels(ctx, plan, rad, results)
    if "cornell" in wanted:
        bench_cornell(ctx, plan, results)
    if "openplan" in wanted:
        bench_openplan(ctx, plan, results)
    elif not a.quick:
        results["notes"].append("open-plan floors not run (--scenes)")
    if wanted & {"office", "office-panels"} and a.no_radiance:
        results["notes"].append("RADIANCE comparison not run (--no-radiance)")
    results["loadavgEnd"] = loadavg()
    results["harnessSeconds"] = time.perf_counter() - t_start
    rows = targets(results)
    results["targets"] = [{"target": t, "required": r, "measured": m, "met": ok}
                          for t, r, m, ok in rows]
    with open(os.path.join(out, "results.json"), "w", encoding="utf-8") as f:
        json.dump(results, f, indent=1, ensure_ascii=False)
        f.write("\n")
    write_plots(results, out)
    write_markdown(results, out, rows)
    log(f"wrote {os.path.relpath(out, ROOT)}/results.md, results.json, time_vs_error.svg"
        f" in {results['harnessSeconds'] / 60:.1f} min")
    for t, r, m, ok in rows:
        log(f"  [{'met' if ok is True else 'MISSED' if ok is False else 'n/a'}] {t}: {m}")


if __name__ == "__main__":
    main()
