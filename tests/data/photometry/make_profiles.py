#!/usr/bin/env python3
"""Writes the photometry test profiles (IES LM-63 and EULUMDAT) and profiles.json.

Every profile samples an analytic intensity distribution I(d) (d a unit direction in the
photometric frame: -Z nadir, +X = C0, +Y = C90) whose flux is known in closed form:

  cos      I0 * max(0, -z)                          flux pi * I0
  cosn     I0 * max(0, -z)^n                        flux 2 pi I0 / (n + 1)
  iso      I0                                       flux 4 pi I0
  up       I0 * max(0, z)                           flux pi * I0
  bilat0   I0 * max(0, -z) * (1 + a x)              flux pi * I0   (symmetric about C0-C180)
  bilat90  I0 * max(0, -z) * (1 + a y)              flux pi * I0   (symmetric about C90-C270)
  quad     I0 * max(0, -z) * (1 + a (x^2 - y^2))    flux pi * I0   (both planes)
  none     I0 * max(0, -z) * (1 + a x + b y)        flux pi * I0   (no symmetry)

The declared lamp lumens equal the closed-form flux (or the file is absolute photometry).
Angles map to directions as src/photometry/frame.rs documents (type C: C, gamma; type B/A:
aim (0, 0) = -Z, V > 0 towards +X, H > 0 towards -Y). Standard library only; deterministic:
run `python3 make_profiles.py` in this folder to rewrite every file byte for byte.
"""

import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
A, B = 0.5, 0.3


def direction(ptype, h, v):
    h, v = math.radians(h), math.radians(v)
    if ptype == "C":
        return (math.sin(v) * math.cos(h), math.sin(v) * math.sin(h), -math.cos(v))
    if ptype == "B":
        return (math.cos(h) * math.sin(v), -math.sin(h), -math.cos(h) * math.cos(v))
    return (math.sin(v), -math.cos(v) * math.sin(h), -math.cos(v) * math.cos(h))


def shape(dist, n, d):
    x, y, z = d
    down = max(0.0, -z)
    return {
        "cos": down,
        "cosn": down ** n,
        "iso": 1.0,
        "up": max(0.0, z),
        "bilat0": down * (1 + A * x),
        "bilat90": down * (1 + A * y),
        "quad": down * (1 + A * (x * x - y * y)),
        "none": down * (1 + A * x + B * y),
    }[dist]


def flux_per_i0(dist, n):
    if dist == "cosn":
        return 2 * math.pi / (n + 1)
    if dist == "iso":
        return 4 * math.pi
    return math.pi


def steps(a, b, s):
    k = round((b - a) / s)
    return [a + i * s for i in range(k + 1)]


def num(v):
    if abs(v) < 1e-12:
        v = 0.0
    return repr(float(v))


def table(spec, hs, vs):
    i0 = spec["flux"] / flux_per_i0(spec["dist"], spec.get("n", 1))
    return [[i0 * shape(spec["dist"], spec.get("n", 1), direction(spec["type"], h, v)) for v in vs] for h in hs]


def chunks(values, k):
    return [values[i:i + k] for i in range(0, len(values), k)]


def write_ies(spec):
    hs, vs = spec["h"], spec["v"]
    sep = ", " if spec.get("commas") else " "
    factor = spec.get("multiplier", 1.0) * spec.get("ballast", 1.0) * spec.get("blpf", 1.0)
    out = list(spec["header"])
    out += spec.get("tilt", ["TILT=NONE"])
    lumens = -1 if spec.get("absolute") else spec["flux"] / spec["lamps"]
    code = {"C": 1, "B": 2, "A": 3}[spec["type"]]
    w, l, hgt = spec.get("opening", (0, 0, 0))
    out.append(sep.join(str(x) for x in [spec["lamps"], num(lumens), num(spec.get("multiplier", 1.0)),
                                          len(vs), len(hs), code, spec.get("units", 2), w, l, hgt]))
    out.append(sep.join([num(spec.get("ballast", 1.0)), num(spec.get("blpf", 1.0)), "50"]))
    out += [sep.join(num(a) for a in c) for c in chunks(vs, 10)]
    out += [sep.join(num(a) for a in c) for c in chunks(hs, 10)]
    for row in table(spec, hs, vs):
        out += [sep.join(num(x / factor) for x in c) for c in chunks(row, 10)]
    return "\r\n".join(out) + "\r\n"


def write_ldt(spec):
    isym, cs, gs = spec["isym"], spec["c"], spec["g"]
    mc = len(cs)
    stored = {0: cs, 1: [0.0], 2: cs[: mc // 2 + 1], 3: cs[mc // 4: mc // 4 + mc // 2 + 1], 4: cs[: mc // 4 + 1]}[isym]
    total = sum(s[2] for s in spec["sets"])
    comma = spec.get("decimal_comma", False)

    def f(v):
        s = num(v)
        return s.replace(".", ",") if comma else s

    la, wa = spec.get("area", (500, 250))
    lines = ["luxbake test profiles", "1" if isym == 1 else "3", str(isym), str(mc), f(cs[1] - cs[0]), str(len(gs)),
             f(gs[1] - gs[0]), "make_profiles.py", spec["name"], spec["number"], spec["file"][:8],
             "2025-01-01 generator", "600", "600", "80", str(la), str(wa), "0", "0", "0", "0", "100", "100",
             f(1.0), f(0.0), str(len(spec["sets"]))]
    for lamps, kind, flux, watts in spec["sets"]:
        lines += [str(lamps), kind, f(flux), "3000 K", "80", f(watts)]
    lines += [f(0.5 + 0.04 * k) for k in range(10)]
    lines += [f(c) for c in cs] + [f(g) for g in gs]
    spec_c = dict(spec, type="C")
    for row in table(spec_c, stored, gs):
        lines += [f(x * 1000.0 / total) for x in row]
    return "\r\n".join(lines) + "\r\n"


def header(version, name, extra=()):
    out = [version] if version else []
    out += ["[TEST] make_profiles.py", "[MANUFAC] luxbake tests", f"[LUMCAT] {name.upper()}",
            f"[LUMINAIRE] {name}", "[LAMP] analytic"]
    return out + list(extra)


C15, C15_90, C15_180, C15_90_270 = steps(0, 360, 15), steps(0, 90, 15), steps(0, 180, 15), steps(90, 270, 15)
G5, G5_UP, G25 = steps(0, 90, 5), steps(90, 180, 5), steps(0, 90, 2.5)
AB, AB_HALF = steps(-90, 90, 5), steps(0, 90, 5)
LDT_C = steps(0, 345, 15)

IES = [
    dict(file="ies1986_axial_commas.ies", dist="cos", flux=1000.0, lamps=1, type="C", h=[0.0], v=G5, commas=True,
         units=1, opening=(1, 2, 0),
         header=["Free-form LM-63-1986 header: no version line, no keywords", "Cosine downlight, comma separated"]),
    dict(file="ies1991_quadrant.ies", dist="quad", flux=1500.0, lamps=2, type="C", h=C15_90, v=G5,
         multiplier=0.5, ballast=0.95, blpf=0.9, header=header("IESNA91", "quadrant")),
    dict(file="ies1995_bilateral_90_270.ies", dist="bilat90", flux=2000.0, lamps=1, type="C", h=C15_90_270, v=G5,
         header=header("IESNA:LM-63-1995", "bilateral 90-270")),
    dict(file="ies2002_bilateral.ies", dist="bilat0", flux=1200.0, lamps=1, type="C", h=C15_180, v=G5,
         opening=(-0.2, -0.2, 0),
         header=header("IESNA:LM-63-2002", "bilateral", ["[OTHER] a keyword", "[MORE] continued"])),
    dict(file="ies2002_none_tilt.ies", dist="none", flux=3000.0, lamps=1, type="C", h=C15, v=G5,
         header=header("IESNA:LM-63-2002", "no symmetry"),
         tilt=["TILT=INCLUDE", "1", "7", "0 15 30 45 60 75 90", "1.0 0.98 0.95 0.9 0.85 0.8 0.75"]),
    dict(file="ies2019_axial_cosn_absolute.ies", dist="cosn", n=10, flux=800.0, lamps=1, type="C", h=[0.0], v=G25,
         absolute=True, header=header("IES:LM-63-2019", "cos^10 spot", ["[TESTLAB] tests", "[ISSUEDATE] 2025-01-01"])),
    dict(file="ies2019_uplight.ies", dist="up", flux=500.0, lamps=1, type="C", h=[0.0], v=G5_UP,
         header=header("IES:LM-63-2019", "uplight")),
    dict(file="ies2002_isotropic.ies", dist="iso", flux=400 * math.pi, lamps=1, type="C", h=[0.0],
         v=steps(0, 180, 10), header=header("IESNA:LM-63-2002", "isotropic")),
    dict(file="ies2002_typeB.ies", dist="none", flux=1000.0, lamps=1, type="B", h=AB, v=AB,
         header=header("IESNA:LM-63-2002", "type B flood")),
    dict(file="ies2002_typeB_lateral.ies", dist="bilat0", flux=1000.0, lamps=1, type="B", h=AB_HALF, v=AB,
         header=header("IESNA:LM-63-2002", "type B lateral symmetry")),
    dict(file="ies2019_typeA.ies", dist="none", flux=1000.0, lamps=1, type="A", h=AB, v=AB,
         header=header("IES:LM-63-2019", "type A")),
    dict(file="ies1995_typeA_quadrant.ies", dist="quad", flux=1000.0, lamps=1, type="A", h=AB_HALF, v=AB_HALF,
         header=header("IESNA:LM-63-1995", "type A quadrant")),
]

LDT = [
    dict(file="ldt_isym1.ldt", dist="cosn", n=10, flux=800.0, isym=1, c=LDT_C, g=G25, area=(300, 0),
         sets=[(1, "LED", 800.0, 10.0)], name="cos^10 spot", number="ISYM1"),
    dict(file="ldt_isym2.ldt", dist="bilat0", flux=1200.0, isym=2, c=LDT_C, g=G5,
         sets=[(1, "LED", 1200.0, 12.0)], name="bilateral", number="ISYM2"),
    dict(file="ldt_isym3.ldt", dist="bilat90", flux=2000.0, isym=3, c=LDT_C, g=G5,
         sets=[(1, "LED", 2000.0, 20.0)], name="bilateral 90-270", number="ISYM3"),
    dict(file="ldt_isym4_commas.ldt", dist="quad", flux=1500.0, isym=4, c=LDT_C, g=G5, decimal_comma=True,
         sets=[(2, "T16 14W", 1500.0, 30.5)], name="quadrant", number="ISYM4"),
    dict(file="ldt_isym0_two_sets.ldt", dist="none", flux=3000.0, isym=0, c=LDT_C, g=G5,
         sets=[(2, "T16 28W", 1800.0, 60.0), (1, "T16 35W", 1200.0, 38.0)], name="no symmetry", number="ISYM0"),
    dict(file="ldt_absolute.ldt", dist="cos", flux=1000.0, isym=1, c=[0.0, 180.0], g=G5, absolute=True,
         sets=[(-1, "LED module", 1000.0, 9.0)], name="absolute cosine", number="ABS"),
]

PAIRS = [("ies2019_axial_cosn_absolute.ies", "ldt_isym1.ldt"), ("ies2002_bilateral.ies", "ldt_isym2.ldt"),
         ("ies1995_bilateral_90_270.ies", "ldt_isym3.ldt"), ("ies1991_quadrant.ies", "ldt_isym4_commas.ldt"),
         ("ies2002_none_tilt.ies", "ldt_isym0_two_sets.ldt"), ("ies1986_axial_commas.ies", "ldt_absolute.ldt")]


def main():
    manifest = []
    for spec in IES + LDT:
        ies = spec["file"].endswith(".ies")
        text = write_ies(spec) if ies else write_ldt(spec)
        with open(os.path.join(HERE, spec["file"]), "w", newline="") as fh:
            fh.write(text)
        manifest.append(dict(file=spec["file"], dist=spec["dist"], n=spec.get("n", 1), a=A, b=B,
                             i0=spec["flux"] / flux_per_i0(spec["dist"], spec.get("n", 1)), flux=spec["flux"],
                             type=spec.get("type", "C"), absolute=bool(spec.get("absolute")),
                             h=spec.get("h", spec.get("c")), v=spec.get("v", spec.get("g"))))
    with open(os.path.join(HERE, "profiles.json"), "w", newline="\n") as fh:
        json.dump(dict(a=A, b=B, profiles=manifest, pairs=PAIRS), fh, indent=1)
        fh.write("\n")


if __name__ == "__main__":
    main()
