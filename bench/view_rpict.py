"""`bake view` against RADIANCE `rpict`: one office view (a camera node of samples/office),
1280 x 720, timed in the same run, with each image's luminance error against a converged
reference at the same pixels (issue 26's acceptance; results in bench/results/view/README.md).

    bench/.venv/bin/python bench/view_rpict.py [--bake target/release/bake]
        [--camera camera_interior] [--size 1280x720] [--step 32] [--repeats 3]
        [--rpict "label:-ab 2 -ad 512 ..." ...] [--out bench/work/view]

Needs bench/.venv with PyPI pyradiance 1.3.1 (RADIANCE binaries), numpy and OpenEXR:
    python3 -m venv bench/.venv && bench/.venv/bin/pip install pyradiance==1.3.1 numpy OpenEXR

What it does:
- luxbake: bakes samples/office/office.gltf at default quality, vertex-only and with
  --lightmaps (not timed here: bench/run.py times bakes), then times `bake view LIT -o V.exr
  --camera NAME --size WxH` (best and median of --repeats runs, wall and CPU).
- RADIANCE: bench/radiance.py converts the same glTF (the spot's EULUMDAT profile as the IES
  file with the same candela values; luminaires become ies2rad `illum`s, invisible to view rays,
  so RADIANCE sees their 0.5-reflectance diffuser where bake view shows their luminance: those
  pixels are left out). oconv + rpict with the same view: -vtv, -vp = the camera node's world
  position, -vd its local -Z, -vu its local +Y, -vv = yfov, -vh = 2 atan(tan(yfov/2) W/H),
  -x W -y H -pa 0. Each rpict setting is timed (oconv + rpict, wall and CPU).
- Reference: RADIANCE rtrace with no irradiance cache (-aa 0, pure path tracing, -ab 8 -ad 1024
  -lw 1e-4, fine direct sampling) at the centre ray of every STEP-th pixel in x and y, each ray
  twice (independent estimates: their spread gives the reference's own noise).
- Mask: a sampled pixel counts when its centre ray and those of its four neighbours hit the same
  glTF node and none is a luminaire (rtrace -os -om, polygon names carry the node index; the
  luminaires' ies2rad `illum`s are named L<node>.*), so edges (antialiasing, pixel-footprint
  averaging) and luminaires are left out.
- Error: per sampled pixel (L - L_ref) / L_ref on the luminance (cd/m^2: bake view's EXR
  `luminance` channel; RADIANCE 179 x (0.265 R + 0.670 G + 0.065 B)); RMS, mean and 95th
  percentile of |.|.
"""

import argparse
import hashlib
import json
import math
import os
import subprocess
import sys
import time

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)

import measure  # noqa: E402
import radiance  # noqa: E402

try:
    import numpy as np
    import OpenEXR
    import pyradiance
except ImportError as e:
    raise SystemExit(f"view_rpict.py: {e}: run it with bench/.venv/bin/python (see the module "
                     "docstring for the venv)")

OFFICE = os.path.join(ROOT, "samples", "office", "office.gltf")
SPOT_IES = {"CNS70 1/50W": os.path.join(ROOT, "samples", "office", "profiles", "cns70_50w.ies")}
DIRECT = ["-ds", "0.05", "-dt", "0", "-dc", "1", "-dj", "0"]
REFERENCE = ["-aa", "0", "-ab", "8", "-ad", "1024", "-lw", "1e-4"] + DIRECT
# rpict settings of the sweep (irradiance cache on, as rpict is normally run), cheap to dear
RPICT = [
    ("ab2", "-ab 2 -ad 512 -as 128 -aa 0.2 -ar 64"),
    ("ab3", "-ab 3 -ad 1024 -as 512 -aa 0.1 -ar 128"),
    ("ab5", "-ab 5 -ad 2048 -as 1024 -aa 0.05 -ar 256"),
]
LUMINAIRE_MATERIALS = {"luminaire_housing", "luminaire_diffuser"}


def log(msg):
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", flush=True)


# ---------------------------------------------------------------- camera

def quat_rotate(q, v):
    x, y, z, w = q
    u = (x, y, z)
    cross = lambda a, b: (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                          a[0] * b[1] - a[1] * b[0])
    t = [2 * c for c in cross(u, v)]
    c2 = cross(u, t)
    return tuple(v[i] + w * t[i] + c2[i] for i in range(3))


def camera(gltf_path, name, width, height):
    """(eye, forward, up, yfov rad, xfov rad) of a root camera node (world = its TRS)."""
    with open(gltf_path, encoding="utf-8") as f:
        doc = json.load(f)
    roots = set(doc["scenes"][doc.get("scene", 0)]["nodes"])
    for i, node in enumerate(doc["nodes"]):
        if node.get("name") == name and "camera" in node:
            if i not in roots:
                raise SystemExit(f"camera node {name} is not a root node: not supported here")
            cam = doc["cameras"][node["camera"]]["perspective"]
            q = node.get("rotation", [0, 0, 0, 1])
            yfov = cam["yfov"]
            xfov = 2 * math.atan(math.tan(yfov / 2) * width / height)
            return (node.get("translation", [0, 0, 0]), quat_rotate(q, (0, 0, -1)),
                    quat_rotate(q, (0, 1, 0)), yfov, xfov)
    raise SystemExit(f"no camera node {name} in {gltf_path}")


def pixel_rays(cam, width, height, pixels):
    """Centre rays (origin, direction) of pixels [(col, row)], row 0 at the top."""
    eye, fwd, up, yfov, xfov = cam
    right = (fwd[1] * up[2] - fwd[2] * up[1], fwd[2] * up[0] - fwd[0] * up[2],
             fwd[0] * up[1] - fwd[1] * up[0])
    tx, ty = math.tan(xfov / 2), math.tan(yfov / 2)
    rays = []
    for col, row in pixels:
        x = (2 * (col + 0.5) / width - 1) * tx
        y = (1 - 2 * (row + 0.5) / height) * ty
        d = [fwd[i] + x * right[i] + y * up[i] for i in range(3)]
        n = math.sqrt(sum(c * c for c in d))
        rays.append(list(eye) + [c / n for c in d])
    return rays


# ---------------------------------------------------------------- RADIANCE

def rad_env(bin_dir, lib_dir, scene_dir):
    env = dict(os.environ)
    env["RAYPATH"] = os.pathsep.join([scene_dir, lib_dir])
    env["PATH"] = bin_dir + os.pathsep + env.get("PATH", "")
    return env


def rtrace(bin_dir, env, scene_dir, octree, rays, options, out_spec, work, tag):
    pts = os.path.join(work, f"{tag}.rays")
    with open(pts, "w", encoding="ascii") as f:
        f.write("".join(" ".join(f"{v:.9g}" for v in r) + "\n" for r in rays))
    out = os.path.join(work, f"{tag}.out")
    cmd = [os.path.join(bin_dir, "rtrace"), "-h", out_spec, "-n", "2"] + options + [octree]
    m = measure.run(cmd, cwd=scene_dir, env=env, stdin_path=pts, stdout_path=out,
                    stderr_path=os.path.join(work, f"{tag}.err"))
    if m["returncode"] != 0:
        raise SystemExit(f"rtrace failed: see {work}/{tag}.err")
    with open(out, encoding="ascii") as f:
        lines = [ln.split() for ln in f if ln.strip()]
    if len(lines) != len(rays):
        raise SystemExit(f"rtrace gave {len(lines)} lines for {len(rays)} rays")
    return lines, m


def luminance(rgb):
    r, g, b = (float(c) for c in rgb)
    return radiance.EFFICACY * (0.265 * r + 0.670 * g + 0.065 * b)


def rpict_image(bin_dir, env, scene_dir, octree, cam, width, height, options, path):
    eye, fwd, up, yfov, xfov = cam
    view = ["-vtv", "-vp"] + [f"{c:.9g}" for c in eye] + ["-vd"] + [f"{c:.9g}" for c in fwd] + \
        ["-vu"] + [f"{c:.9g}" for c in up] + \
        ["-vh", f"{math.degrees(xfov):.9g}", "-vv", f"{math.degrees(yfov):.9g}"]
    cmd = [os.path.join(bin_dir, "rpict")] + view + ["-x", str(width), "-y", str(height),
                                                      "-pa", "0"] + options + [octree]
    m = measure.run(cmd, cwd=scene_dir, env=env, stdout_path=path,
                    stderr_path=path + ".err")
    if m["returncode"] != 0:
        raise SystemExit(f"rpict failed: see {path}.err")
    return m, cmd


def read_hdr_luminance(bin_dir, path, width, height):
    """Luminance (cd/m^2) of a RADIANCE picture, rows top first, exposure undone."""
    raw = subprocess.run([os.path.join(bin_dir, "pvalue"), "-o", "-h", "-H", "-df", path],
                         check=True, capture_output=True).stdout
    rgb = np.frombuffer(raw, dtype=np.float32).reshape(height, width, 3).astype(np.float64)
    return radiance.EFFICACY * (0.265 * rgb[..., 0] + 0.670 * rgb[..., 1] + 0.065 * rgb[..., 2])


def read_exr_luminance(path):
    with OpenEXR.File(path) as f:
        channels = f.channels()
        if "luminance" not in channels:
            raise SystemExit(f"{path}: no luminance channel (has {sorted(channels)})")
        return np.asarray(channels["luminance"].pixels, dtype=np.float64)


# ---------------------------------------------------------------- luxbake

def bake(bake_bin, out, extra, work):
    m = measure.run([bake_bin, OFFICE, "-o", out] + extra,
                    stderr_path=os.path.join(work, os.path.basename(out) + ".err"))
    if m["returncode"] != 0:
        raise SystemExit(f"bake failed: see {work}")
    return m


def bake_view(bake_bin, lit, exr, camera_name, size, work):
    m = measure.run([bake_bin, "view", lit, "-o", exr, "--camera", camera_name,
                     "--size", size], stderr_path=exr + ".err")
    if m["returncode"] != 0:
        with open(exr + ".err", encoding="utf-8", errors="replace") as f:
            raise SystemExit(f"bake view failed: {f.read()[-400:]}")
    return m


# ---------------------------------------------------------------- errors

def errors(image, samples, ref, lum):
    rel = np.array([(image[row, col] - r) / r
                    for (col, row), r, out in zip(samples, ref, lum) if not out])
    a = np.abs(rel)
    return {"rms": float(np.sqrt(np.mean(rel ** 2))), "mean": float(np.mean(rel)),
            "p95": float(np.percentile(a, 95)), "max": float(a.max())}


def fmt_pct(x):
    return f"{100 * x:.2f} %"


def save(work, results):
    with open(os.path.join(work, "results.json"), "w", encoding="utf-8") as f:
        json.dump(results, f, indent=1)
    log(f"wrote {work}/results.json")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bake", default=os.path.join(ROOT, "target", "release", "bake"))
    ap.add_argument("--camera", default="camera_interior")
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--step", type=int, default=32)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--rpict", action="append", help="label:options (replaces the sweep)")
    ap.add_argument("--out", default=os.path.join(BENCH, "work", "view"))
    a = ap.parse_args()
    width, height = (int(v) for v in a.size.split("x"))
    work = os.path.abspath(a.out)
    os.makedirs(work, exist_ok=True)
    pkg = os.path.dirname(pyradiance.__file__)
    bin_dir, lib_dir = os.path.join(pkg, "bin"), os.path.join(pkg, "lib")
    results = {"camera": a.camera, "size": a.size, "step": a.step, "loadavg_start":
               os.getloadavg(), "nproc": os.cpu_count()}

    cam = camera(OFFICE, a.camera, width, height)
    results["view"] = {"eye": cam[0], "dir": cam[1], "up": cam[2],
                       "yfov_deg": math.degrees(cam[3]), "xfov_deg": math.degrees(cam[4])}

    # ---- RADIANCE scene and the sampled pixels' reference
    rd = os.path.join(work, "rad")
    radiance.convert(OFFICE, rd, bin_dir, SPOT_IES)
    env = rad_env(bin_dir, lib_dir, rd)
    m_oconv = measure.run([os.path.join(bin_dir, "oconv"), "scene.rad"], cwd=rd, env=env,
                          stdout_path=os.path.join(rd, "scene.oct"),
                          stderr_path=os.path.join(rd, "oconv.err"))
    if m_oconv["returncode"] != 0:
        raise SystemExit("oconv failed")
    samples = [(c, r) for r in range(a.step // 2, height, a.step)
               for c in range(a.step // 2, width, a.step)]
    offsets = [(0, 0), (-1, 0), (1, 0), (0, -1), (0, 1)]
    probe = [(min(max(c + dc, 0), width - 1), min(max(r + dr, 0), height - 1))
             for c, r in samples for dc, dr in offsets]
    lines, _ = rtrace(bin_dir, env, rd, "scene.oct", pixel_rays(cam, width, height, probe),
                      ["-ab", "0"], "-osm", work, "mask")
    with open(OFFICE, encoding="utf-8") as f:
        materials = json.load(f)["materials"]
    lum_mods = {f"mat{k}" for k, m in enumerate(materials) if m["name"] in LUMINAIRE_MATERIALS}
    keep, seen_lum = [], []
    for k in range(len(samples)):
        hits = lines[5 * k:5 * k + 5]
        nodes = {h[0].split("_t")[0] if len(h) == 2 else "void" for h in hits}
        if len(nodes) == 1 and "void" not in nodes:
            keep.append(k)
            # a luminaire: its housing or diffuser, or the ies2rad `illum` in front of it
            # (xform names it L<node>.…; it passes view rays on to the diffuser)
            seen_lum.append(any(h[1] in lum_mods or (h[0].startswith("L") and "." in h[0])
                                for h in hits))
    samples = [samples[k] for k in keep]
    log(f"{len(samples)} sampled pixels off edges of {len(probe) // 5}, "
        f"{sum(seen_lum)} of them luminaires (left out of the errors)")
    rays = pixel_rays(cam, width, height, samples)
    # the reference is dear (minutes): reused when the work folder holds one for the same
    # scene, rays and options (ref.rays, ref.key, ref.out)
    ray_text = "".join(" ".join(f"{v:.9g}" for v in r) + "\n" for r in rays + rays)
    with open(os.path.join(rd, "scene.rad"), "rb") as f:
        key = hashlib.sha256(f.read() + " ".join(REFERENCE).encode()).hexdigest()
    paths = {k: os.path.join(work, f"ref.{k}") for k in ("rays", "key", "out", "wall")}
    try:
        with open(paths["rays"], encoding="ascii") as f, open(paths["key"]) as g:
            reuse = f.read() == ray_text and g.read().strip() == key
    except OSError:
        reuse = False
    if reuse:
        log(f"reference: reused {paths['out']}")
        with open(paths["out"], encoding="ascii") as f:
            lines = [ln.split() for ln in f if ln.strip()]
        with open(paths["wall"]) as f:
            ref_wall = float(f.read())
    else:
        log(f"reference: rtrace {' '.join(REFERENCE)} x 2 at {len(rays)} pixel centres")
        lines, m_ref = rtrace(bin_dir, env, rd, "scene.oct", rays + rays, REFERENCE, "-ov",
                              work, "ref")
        ref_wall = m_ref["wall"]
        with open(paths["key"], "w") as f:
            f.write(key + "\n")
        with open(paths["wall"], "w") as f:
            f.write(f"{ref_wall}\n")
    est = np.array([luminance(ln[:3]) for ln in lines]).reshape(2, len(rays))
    ref = est.mean(axis=0)
    on = ~np.array(seen_lum)
    ref_noise = float(np.sqrt(np.mean(((est[0] - est[1])[on] / 2 / ref[on]) ** 2)))
    results["reference"] = {"options": " ".join(REFERENCE), "pixels": len(rays),
                            "pixelsCompared": len(rays) - sum(seen_lum),
                            "wall": ref_wall, "relNoiseRms": ref_noise,
                            "meanLuminance": float(ref[on].mean())}
    log(f"reference: {ref_wall:.0f} s, its own noise {fmt_pct(ref_noise)} RMS")

    # ---- rpict sweep
    sweep = [tuple(s.split(":", 1)) for s in a.rpict] if a.rpict else RPICT
    results["rpict"] = []
    for label, opts in sweep:
        path = os.path.join(work, f"rpict-{label}.hdr")
        m, cmd = rpict_image(bin_dir, env, rd, "scene.oct", cam, width, height,
                             opts.split() + DIRECT, path)
        image = read_hdr_luminance(bin_dir, path, width, height)
        err = errors(image, samples, ref, seen_lum)
        rec = {"label": label, "options": opts, "wall": m["wall"] + m_oconv["wall"],
               "cpu": m["cpu"] + m_oconv["cpu"], "rpictWall": m["wall"],
               "peakMiB": m["peakMiB"], **err}
        results["rpict"].append(rec)
        log(f"rpict {label}: {rec['wall']:.1f} s, RMS {fmt_pct(err['rms'])}, "
            f"mean {fmt_pct(err['mean'])}")
    save(work, results)

    # ---- luxbake
    results["bake"] = []
    for tag, extra in (("vertex", []), ("lightmaps", ["--lightmaps"])):
        lit = os.path.join(work, f"lit-{tag}.gltf")
        mb = bake(a.bake, lit, extra, work)
        runs = []
        for k in range(a.repeats):
            exr = os.path.join(work, f"view-{tag}.exr")
            if os.path.exists(exr):
                os.remove(exr)
            runs.append(bake_view(a.bake, lit, exr, a.camera, a.size, work))
        image = read_exr_luminance(exr)
        err = errors(image, samples, ref, seen_lum)
        walls = sorted(r["wall"] for r in runs)
        rec = {"bake": tag, "bakeWall": mb["wall"], "viewWallBest": walls[0],
               "viewWallMedian": walls[len(walls) // 2],
               "viewCpuMedian": sorted(r["cpu"] for r in runs)[len(runs) // 2],
               "viewPeakMiB": max(r["peakMiB"] for r in runs), **err}
        results["bake"].append(rec)
        log(f"bake view ({tag}): {walls[0]:.3f} s best, RMS {fmt_pct(err['rms'])}, "
            f"mean {fmt_pct(err['mean'])}")

    results["loadavg_end"] = os.getloadavg()
    save(work, results)


if __name__ == "__main__":
    main()
