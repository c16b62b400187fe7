#!/usr/bin/env python3
"""Write the office's two photometric profiles, each as IES LM-63-2002 (.ies) and
EULUMDAT (.ldt) holding the SAME distribution (see README.md in this folder):

  miral_58w.ies / .ldt  surface-mounted louvred linear fluorescent, 1 x 58 W T8/T26, 5200 lm
  cns70_50w.ies / .ldt  low-voltage spotlight, 1 x 50 W QR-CBC51, 990 lm, ~10 deg beam

Both are ANALYTIC MODELS written by us, plausible for the seed paper's Zumtobel Miral RAL 1/58W
and CNS70 1/50W; they are not manufacturer data.

Python 3 standard library only; the output is byte-for-byte deterministic.
Run from anywhere:  python3 samples/office/profiles/make_profiles.py
(`--check` recomputes everything and fails if a file on disk differs.)

Conventions (type C photometry, relative photometry):
  gamma = vertical angle from nadir (photometric -Z), C = horizontal angle, counter-clockwise
  seen from above, C = 0 along photometric +X, C = 90 along +Y.  The luminaire's LENGTH lies
  along C = 0 (the 0-180 plane): IES "length" and EULUMDAT "length of luminous area" are measured
  along C0-C180, "width" along C90-C270.
  EULUMDAT intensities are cd/klm; the IES candela values are exactly (as decimals)
  cd/klm x lamp flux / 1000, so the two files encode the same candela values.
"""

import math
import os
import sys
from decimal import Decimal, ROUND_HALF_EVEN

HERE = os.path.dirname(os.path.abspath(__file__))
ISSUE_DATE = "2026-11-22"          # fixed, so the files are deterministic
CRLF = "\r\n"                      # LM-63 and EULUMDAT lines end in CR LF


# ------------------------------------------------------------------ numerics


def simpson(f, a, b, n):
    """Composite Simpson's rule on [a, b] with n (even) intervals."""
    if n % 2:
        n += 1
    h = (b - a) / n
    s = f(a) + f(b)
    for k in range(1, n):
        s += (4 if k % 2 else 2) * f(a + k * h)
    return s * h / 3.0


def simpson_pieces(f, breaks, n_per_degree=200):
    """Simpson over consecutive pieces [breaks[i], breaks[i+1]] (radians); splitting at the
    kinks of a piecewise model keeps the rule at full order."""
    total = 0.0
    for a, b in zip(breaks, breaks[1:]):
        n = max(2, int(round(math.degrees(b - a) * n_per_degree)))
        total += simpson(f, a, b, n)
    return total


D = math.radians


def quantize(x, places):
    """Round a float to `places` decimals, half-even, as an exact Decimal."""
    return Decimal(x).quantize(Decimal(1).scaleb(-places), rounding=ROUND_HALF_EVEN)


# ------------------------------------------------------------ Miral 1/58W


class Miral:
    """Surface-mounted louvred linear fluorescent, one 58 W T8/T26 lamp of 5200 lm.

    I(C, g) = I0 * [cos^2 C * f0(g) + sin^2 C * f90(g)]   for 0 <= g <= 90 deg, 0 above
      f0(g)  = cos g                     C0 plane (along the lamp): the projected length of a
                                         long source falls as cos g
      f90(g) = sqrt(cos g) * T(g)        C90 plane (across the lamp): broad, then cut off by
                                         the louvre blades and side reflectors
      T(g)   = 1 for g <= 55 deg; (1 + cos(pi (g - 55)/10))/2 for 55..65 deg; 0 beyond 65 deg
    I0 is set so the model's flux is LOR x lamp flux = 0.65 x 5200 = 3380 lm.
    Quadrant symmetric (mirror in the C0-C180 and C90-C270 planes)."""

    key = "miral_58w"
    name = "Miral 1/58W louvred"
    lamp_flux = 5200.0
    lor = 0.65
    cut_start, cut_end = 55.0, 65.0          # deg, C90 louvre cut-off taper
    gammas = [5.0 * i for i in range(19)]    # 0..90 every 5 deg
    cs = [15.0 * i for i in range(7)]        # 0..90 every 15 deg (quadrant symmetry)
    length, width, height = 1.5, 0.2, 0.0    # luminous opening (m): length along C0
    housing_mm = (1500, 200, 80)             # the glTF housing box (length, width, height)

    @classmethod
    def taper(cls, g):
        gd = math.degrees(g)
        if gd <= cls.cut_start:
            return 1.0
        if gd >= cls.cut_end:
            return 0.0
        return 0.5 * (1.0 + math.cos(math.pi * (gd - cls.cut_start)
                                     / (cls.cut_end - cls.cut_start)))

    @classmethod
    def f0(cls, g):
        return math.cos(g) if g < math.pi / 2 else 0.0

    @classmethod
    def f90(cls, g):
        return math.sqrt(math.cos(g)) * cls.taper(g) if g < math.pi / 2 else 0.0

    @classmethod
    def shape(cls, c, g):
        """Relative intensity (peak 1 at nadir), c and g in radians."""
        if g >= math.pi / 2:
            return 0.0
        return math.cos(c) ** 2 * cls.f0(g) + math.sin(c) ** 2 * cls.f90(g)

    @classmethod
    def flux_per_cd(cls):
        """Phi / I0 = integral over the sphere of shape(C, g) sin g dg dC, numerically
        (Simpson in g split at the taper's kinks, Simpson in C over a quadrant, x 4)."""
        brk = [0.0, D(cls.cut_start), D(cls.cut_end), D(90.0)]

        def over_g(c):
            return simpson_pieces(lambda g: cls.shape(c, g) * math.sin(g), brk, 100)
        quadrant = simpson(over_g, 0.0, math.pi / 2, 90)
        return 4.0 * quadrant

    @classmethod
    def flux_per_cd_semi_analytic(cls):
        """Same, with the C integral done by hand (mean of cos^2 and sin^2 is 1/2):
        Phi/I0 = pi * (int f0 sin dg + int f90 sin dg) = pi * (1/2 + int f90 sin dg)."""
        brk = [0.0, D(cls.cut_start), D(cls.cut_end), D(90.0)]
        i90 = simpson_pieces(lambda g: cls.f90(g) * math.sin(g), brk, 400)
        return math.pi * (0.5 + i90)


# -------------------------------------------------------------- CNS70 1/50W


class Cns70:
    """Low-voltage recessed spotlight, one 50 W QR-CBC51 lamp of 990 lm, narrow beam.

    I(g) = I0 * [(1 - k) * 2^(-(g/a)^p) + k * cos^m g]   for 0 <= g <= 90 deg, 0 above
      beam: a generalised Gaussian; spill: a broad cos^m halo (k = 0.02 of the peak, m = 6)
      a, p solved in closed form so that I(5 deg) = 0.5 I0 and I(10 deg) = 0.1 I0 exactly:
      beam angle (50 %) 10 deg, field angle (10 %) 20 deg.
    Tabulated every 1 deg to 30 deg, then every 2.5 deg to 90 deg.
    I0 is set so the model's flux is LOR x lamp flux = 0.8 x 990 = 792 lm.  Axially symmetric."""

    key = "cns70_50w"
    name = "CNS70 1/50W"
    lamp_flux = 990.0
    lor = 0.80
    k, m = 0.02, 6
    beam_half, field_half = 5.0, 10.0                          # deg
    gammas = [float(i) for i in range(31)] + [30.0 + 2.5 * i for i in range(1, 25)]
    length = width = 0.05                                      # round opening, diameter (m)
    height = 0.0
    housing_mm = (70, 0, 0)                                    # assumed, round (no glTF mesh)

    @classmethod
    def beam_params(cls):
        r1 = (0.5 - cls.k * math.cos(D(cls.beam_half)) ** cls.m) / (1.0 - cls.k)
        r2 = (0.1 - cls.k * math.cos(D(cls.field_half)) ** cls.m) / (1.0 - cls.k)
        l1, l2 = -math.log2(r1), -math.log2(r2)
        p = math.log2(l2 / l1) / math.log2(cls.field_half / cls.beam_half)
        a = cls.beam_half / l1 ** (1.0 / p)                    # deg
        return a, p

    @classmethod
    def shape_g(cls, g):
        if g >= math.pi / 2:
            return 0.0
        a, p = cls.beam_params()
        gd = math.degrees(g)
        return ((1.0 - cls.k) * 2.0 ** (-(gd / a) ** p)
                + cls.k * math.cos(g) ** cls.m)

    @classmethod
    def shape(cls, c, g):
        return cls.shape_g(g)

    @classmethod
    def flux_per_cd(cls):
        """Phi / I0 = 2 pi * integral_0^90 shape(g) sin g dg (Simpson, fine near the beam)."""
        brk = [0.0, D(10.0), D(30.0), D(90.0)]
        return 2.0 * math.pi * simpson_pieces(lambda g: cls.shape_g(g) * math.sin(g), brk, 400)

    @classmethod
    def flux_per_cd_semi_analytic(cls):
        """The spill term in closed form, 2 pi k/(m+1); the beam term by Simpson."""
        a, p = cls.beam_params()
        brk = [0.0, D(10.0), D(30.0), D(90.0)]
        beam = simpson_pieces(
            lambda g: (1.0 - cls.k) * 2.0 ** (-(math.degrees(g) / a) ** p) * math.sin(g),
            brk, 400)
        return 2.0 * math.pi * (beam + cls.k / (cls.m + 1))


# -------------------------------------------------------------- tabulation


def tabulate(lum):
    """Returns a dict with the model's peak I0 (cd), the cd/klm table (Decimal, 2 places) and
    the IES candela table (Decimal, exact = cd/klm x lamp flux / 1000); tables are
    [c index][g index]."""
    k = lum.flux_per_cd()
    k2 = lum.flux_per_cd_semi_analytic()
    assert abs(k - k2) < 1e-9 * k, (k, k2)
    target = lum.lor * lum.lamp_flux
    i0 = target / k
    klm = Decimal(repr(lum.lamp_flux)) / Decimal(1000)       # 5.2, 0.99 (exact decimals)
    per_klm = []
    cd = []
    cs = getattr(lum, "cs", [0.0])
    for c in cs:
        row_klm, row_cd = [], []
        for g in lum.gammas:
            v = i0 * lum.shape(D(c), D(g)) * 1000.0 / lum.lamp_flux
            q = quantize(v, 2)
            row_klm.append(q)
            row_cd.append(q * klm)                              # exact decimal product
        per_klm.append(row_klm)
        cd.append(row_cd)
    return {"i0": i0, "flux_per_cd": k, "target": target, "cs": cs,
            "per_klm": per_klm, "cd": cd, "klm": klm}


def sphere_integrals(cs, gammas, table):
    """Flux (lm) of a tabulated type C distribution, zero outside the table's gamma range:
    (a) the trapezoid rule in gamma on I sin g dg and in C;
    (b) exact integral of I linear between tabulated gammas (times sin g), trapezoid in C.
    `cs` covers a quadrant (0..90) or is [0] (axial)."""
    g = [D(x) for x in gammas]

    def trap_g(row):
        s = 0.0
        for i in range(len(g) - 1):
            h = g[i + 1] - g[i]
            s += 0.5 * h * (row[i] * math.sin(g[i]) + row[i + 1] * math.sin(g[i + 1]))
        return s

    def lin_g(row):
        s = 0.0
        for i in range(len(g) - 1):
            g0, g1 = g[i], g[i + 1]
            h = g1 - g0
            i0, i1 = row[i], row[i + 1]
            s += i0 * (math.cos(g0) - math.cos(g1))
            s += (i1 - i0) / h * (-h * math.cos(g1) + math.sin(g1) - math.sin(g0))
        return s

    def over_c(per_plane):
        if len(cs) == 1:
            return 2.0 * math.pi * per_plane[0]
        assert cs[0] == 0.0 and cs[-1] == 90.0
        s = 0.0
        for i in range(len(cs) - 1):
            s += 0.5 * D(cs[i + 1] - cs[i]) * (per_plane[i] + per_plane[i + 1])
        return 4.0 * s

    rows = [[float(v) for v in r] for r in table]
    return (over_c([trap_g(r) for r in rows]), over_c([lin_g(r) for r in rows]))


def crossing(gammas, values, level):
    """First gamma (deg) where `values` falls to `level`, linear interpolation."""
    for i in range(len(gammas) - 1):
        v0, v1 = values[i], values[i + 1]
        if v0 >= level > v1 or v0 > level >= v1:
            return gammas[i] + (gammas[i + 1] - gammas[i]) * (v0 - level) / (v0 - v1)
    return None


def model_crossing(f, level, lo=0.0, hi=90.0):
    """Angle (deg) where a decreasing model f(g in rad) equals level (bisection)."""
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f(D(mid)) > level:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


# ------------------------------------------------------------------ writers


def fmt(d):
    return format(d, "f")


def wrap(values, per_line=10):
    out = []
    for i in range(0, len(values), per_line):
        out.append(" ".join(values[i:i + per_line]))
    return out


def ies_text(lum, tab, info):
    cs = tab["cs"]
    if lum is Miral:
        lines = [
            "IESNA:LM-63-2002",
            "[TEST] none - computed from an analytic model, not a measurement",
            "[TESTLAB] none - luxbake samples/office/profiles/make_profiles.py",
            "[ISSUEDATE] " + ISSUE_DATE,
            "[MANUFAC] none - analytic model plausible for a Zumtobel Miral RAL 1/58W,"
            " NOT manufacturer data",
            "[LUMCAT] luxbake-miral-58w-model",
            "[LUMINAIRE] Surface-mounted louvred linear fluorescent, 1 x 58 W (model)",
            "[LAMPCAT] T8/T26 58W",
            "[LAMP] 1 x 58 W T8/T26 linear fluorescent, 5200 lm",
            "[OTHER] Light output ratio %.2f, luminaire flux %.0f lm (candela values are for"
            " the luminaire)" % (lum.lor, tab["target"]),
            "[MORE] Luminaire length 1.5 m along C0-C180 (IES length), width 0.2 m along"
            " C90-C270 (IES width)",
            "[MORE] Input watts = nominal lamp watts; ballast losses not modelled",
        ]
        dims = "%s %s %s" % (lum.width, lum.length, lum.height)      # width length height
        watts = "58"
    else:
        lines = [
            "IESNA:LM-63-2002",
            "[TEST] none - computed from an analytic model, not a measurement",
            "[TESTLAB] none - luxbake samples/office/profiles/make_profiles.py",
            "[ISSUEDATE] " + ISSUE_DATE,
            "[MANUFAC] none - analytic model plausible for a Zumtobel CNS70 1/50W,"
            " NOT manufacturer data",
            "[LUMCAT] luxbake-cns70-50w-model",
            "[LUMINAIRE] Low-voltage recessed spotlight, 1 x 50 W, narrow beam (model)",
            "[LAMPCAT] QR-CBC51 50W",
            "[LAMP] 1 x 50 W QR-CBC51 low-voltage tungsten halogen, 990 lm",
            "[OTHER] Light output ratio %.2f, luminaire flux %.0f lm; beam angle 10 deg (50 %%),"
            " field angle 20 deg (10 %%)" % (lum.lor, tab["target"]),
            "[MORE] Round luminous opening 0.05 m diameter (LM-63-2002: width = length ="
            " -diameter, height 0)",
            "[MORE] Input watts = nominal lamp watts; transformer losses not modelled",
        ]
        dims = "-%s -%s %s" % (lum.width, lum.length, lum.height)
        watts = "50"
    lines.append("TILT=NONE")
    # <#lamps> <lumens/lamp> <multiplier> <#vert> <#horiz> <type> <units> <w> <l> <h>
    lines.append("1 %d 1 %d %d 1 2 %s" % (int(lum.lamp_flux), len(lum.gammas), len(cs), dims))
    # <ballast factor> <future use> <input watts>
    lines.append("1 1 %s" % watts)
    lines += wrap([("%g" % g) for g in lum.gammas], 16)
    lines += wrap([("%g" % c) for c in cs], 16)
    for row in tab["cd"]:
        lines += wrap([fmt(v) for v in row], 8)
    return CRLF.join(lines) + CRLF


def ldt_text(lum, tab, info):
    miral = lum is Miral
    mc, dc = 24, 15                                     # C planes in the full circle
    g = lum.gammas
    dg = g[1] - g[0]
    equidistant = all(abs((g[i + 1] - g[i]) - dg) < 1e-9 for i in range(len(g) - 1))
    lines = [
        "luxbake analytic model (not manufacturer data)",            # 1 company / databank
        "2" if miral else "1",                                         # 2 Ityp
        "4" if miral else "1",                                         # 3 Isym
        str(mc),                                                       # 4 Mc
        "%g" % dc,                                                     # 5 Dc
        str(len(g)),                                                   # 6 Ng
        ("%g" % dg) if equidistant else "0",                           # 7 Dg (0: not equidistant)
        "none - computed from an analytic model",                      # 8 report number
        ("Miral 1/58W louvred (model, plausible for Zumtobel Miral RAL 1/58W)" if miral
         else "CNS70 1/50W spotlight (model, plausible for Zumtobel CNS70 1/50W)"),  # 9
        "luxbake-miral-58w-model" if miral else "luxbake-cns70-50w-model",       # 10
        lum.key + ".ldt",                                              # 11 file name
        ISSUE_DATE + " luxbake make_profiles.py",                      # 12 date / user
        "%d" % lum.housing_mm[0],                                      # 13 length/diameter
        "%d" % lum.housing_mm[1],                                      # 14 width (0: round)
        "%d" % lum.housing_mm[2],                                      # 15 height
        "%d" % round(lum.length * 1000),                               # 16 luminous length/diam.
        "%d" % (round(lum.width * 1000) if miral else 0),              # 17 luminous width
        "0", "0", "0", "0",                                            # 18-21 heights C0..C270
        "%.1f" % info["dff"],                                          # 22 DFF (%)
        "%.1f" % (lum.lor * 100.0),                                    # 23 LORL (%)
        "1",                                                           # 24 conversion factor
        "0",                                                           # 25 tilt
        "1",                                                           # 26 n lamp sets
        "1",                                                           # 26a number of lamps
        "T26 58W" if miral else "QR-CBC51 50W",                        # 26b lamp type
        "%d" % lum.lamp_flux,                                          # 26c lamp flux (lm)
        "unknown",                                                     # 26d colour
        "unknown",                                                     # 26e colour rendering
        "58" if miral else "50",                                       # 26f watts (lamp only)
    ]
    lines += ["0"] * 10                                                # 27 direct ratios
    lines += ["%g" % (dc * i) for i in range(mc)]                      # 28 C angles
    lines += ["%g" % x for x in g]                                     # 29 gamma angles
    for row in tab["per_klm"]:                                         # 30 cd/klm
        lines += [fmt(v) for v in row]
    return CRLF.join(lines) + CRLF


# ------------------------------------------------- read-back (independent)


def parse_ies(data):
    """Minimal LM-63-2002 reader for our own files: (lamp lumens, gammas, cs, cd[c][g], opening)."""
    text = data.decode("ascii")
    assert "\n" not in text.replace("\r\n", ""), "bare LF"
    lines = text.split("\r\n")
    i = next(k for k, ln in enumerate(lines) if ln.startswith("TILT="))
    assert lines[i] == "TILT=NONE"
    nums = " ".join(lines[i + 1:]).split()
    n_lamps, lumens, mult = int(nums[0]), float(nums[1]), Decimal(nums[2])
    nv, nh, ptype, units = int(nums[3]), int(nums[4]), int(nums[5]), int(nums[6])
    w, ln_, h = float(nums[7]), float(nums[8]), float(nums[9])
    assert (n_lamps, ptype, units) == (1, 1, 2)
    rest = nums[13:]
    gam = [float(x) for x in rest[:nv]]
    cs = [float(x) for x in rest[nv:nv + nh]]
    vals = [Decimal(x) * mult for x in rest[nv + nh:]]
    assert len(vals) == nv * nh
    return lumens, gam, cs, [vals[k * nv:(k + 1) * nv] for k in range(nh)], (w, ln_, h)


def parse_ldt(data):
    """Minimal EULUMDAT reader for our own files: (lamp flux, LORL %, isym, gammas,
    stored cs, cd/klm[c][g], luminous length/width mm)."""
    lines = data.decode("ascii").split("\r\n")
    isym, mc, ng = int(lines[2]), int(lines[3]), int(lines[5])
    lum_len, lum_wid = float(lines[15]), float(lines[16])
    lorl = float(lines[22])
    n_sets = int(lines[25])
    assert n_sets == 1
    flux = float(lines[28])
    k = 26 + 6 * n_sets + 10                       # first C angle (0-based line index)
    call = [float(x) for x in lines[k:k + mc]]
    gam = [float(x) for x in lines[k + mc:k + mc + ng]]
    stored = {1: 1, 4: mc // 4 + 1}[isym]
    first = k + mc + ng
    vals = [Decimal(x) for x in lines[first:first + stored * ng]]
    assert lines[first + stored * ng:] == [""], "trailing data"
    cs = call[:stored]
    return flux, lorl, isym, gam, cs, [vals[j * ng:(j + 1) * ng] for j in range(stored)], \
        (lum_len, lum_wid)


def verify(files):
    """Parse the written files back and check: same grids, LDT cd/klm x flux/1000 == IES cd
    exactly, the opening, and the flux of the data against LOR x lamp flux (< 0.5 %)."""
    out = []
    for lum in (Miral, Cns70):
        lm, gi, ci, cd, opening = parse_ies(files[lum.key + ".ies"])
        flux, lorl, isym, gl, cl, klm, lum_area = parse_ldt(files[lum.key + ".ldt"])
        assert lm == flux == lum.lamp_flux and gi == gl and ci == cl, lum.key
        scale = Decimal(repr(flux)) / Decimal(1000)
        same = all(a * scale == b for ra, rb in zip(klm, cd) for a, b in zip(ra, rb))
        assert same, lum.key
        if lum is Miral:
            assert opening == (0.2, 1.5, 0.0) and lum_area == (1500.0, 200.0) and isym == 4
        else:
            assert opening == (-0.05, -0.05, 0.0) and lum_area == (50.0, 0.0) and isym == 1
        trap, lin = sphere_integrals(ci, gi, cd)
        target = lorl / 100.0 * flux
        assert abs(trap / target - 1) < 0.005 and abs(lin / target - 1) < 0.005, lum.key
        out.append("read back %s: IES == LDT x %s exactly (%d values); data flux %.2f lm"
                   " (trapezoid) vs LORL x lamp = %.1f lm" % (
                       lum.key, scale, sum(len(r) for r in cd), trap, target))
    return out


# -------------------------------------------------------------------- main


def build(lum):
    tab = tabulate(lum)
    cs = tab["cs"]
    # both formats hold the same candela values, as exact decimals
    for rk, rc in zip(tab["per_klm"], tab["cd"]):
        for vk, vc in zip(rk, rc):
            assert vk * tab["klm"] == vc
    trap, lin = sphere_integrals(cs, lum.gammas, tab["cd"])
    err = trap / tab["target"] - 1.0
    assert abs(err) < 0.005, (lum.key, trap, tab["target"])
    # downward flux fraction: all tabulated gammas are <= 90 deg, zero above -> 100 %
    assert max(lum.gammas) <= 90.0
    dff = 100.0
    peak_cd = max(max(r) for r in tab["cd"])
    info = {"trap": trap, "lin": lin, "err": err, "dff": dff, "peak_cd": peak_cd,
            "peak_klm": max(max(r) for r in tab["per_klm"])}
    # beam (50 %) and field (10 %) half-angles per stored plane, from the table and the model
    angles = {}
    for ci, c in enumerate(cs):
        vals = [float(v) for v in tab["cd"][ci]]
        pk = max(vals)
        angles[c] = (crossing(lum.gammas, vals, 0.5 * pk), crossing(lum.gammas, vals, 0.1 * pk),
                     model_crossing(lambda gg: lum.shape(D(c), gg), 0.5),
                     model_crossing(lambda gg: lum.shape(D(c), gg), 0.1))
    info["angles"] = angles
    return tab, info


def outputs():
    files = {}
    report = []
    for lum in (Miral, Cns70):
        tab, info = build(lum)
        files[lum.key + ".ies"] = ies_text(lum, tab, info).encode("ascii")
        files[lum.key + ".ldt"] = ldt_text(lum, tab, info).encode("ascii")
        report.append("%s (%s): lamp %.0f lm, LOR %.2f -> model flux %.1f lm; I0 %.2f cd"
                      " (%.2f cd/klm); Phi/I0 = %.9f sr" % (
                          lum.key, lum.name, lum.lamp_flux, lum.lor, tab["target"], tab["i0"],
                          tab["i0"] * 1000.0 / lum.lamp_flux, tab["flux_per_cd"]))
        report.append("  tabulated: trapezoid %.2f lm (%+.3f %%), piecewise-linear %.2f lm"
                      " (%+.3f %%); peak %s cd = %s cd/klm; DFF %.1f %%" % (
                          info["trap"], 100 * info["err"], info["lin"],
                          100 * (info["lin"] / tab["target"] - 1), fmt(info["peak_cd"]),
                          fmt(info["peak_klm"]), info["dff"]))
        for c, (b, f, bm, fm) in info["angles"].items():
            if lum is Miral and c not in (0.0, 45.0, 90.0):
                continue
            report.append("  C%g: beam (50 %%) %.2f deg, field (10 %%) %.2f deg full angle"
                          " from the table; model %.2f / %.2f" % (c, 2 * b, 2 * f, 2 * bm, 2 * fm))
        if lum is Cns70:
            a, p = lum.beam_params()
            report.append("  beam parameters a = %.6f deg, p = %.6f" % (a, p))
    return files, report


def main():
    check = "--check" in sys.argv[1:]
    files, report = outputs()
    bad = []
    for name, data in files.items():
        path = os.path.join(HERE, name)
        if check:
            with open(path, "rb") as f:
                if f.read() != data:
                    bad.append(name)
        else:
            with open(path, "wb") as f:
                f.write(data)
    report += verify(files)
    for line in report:
        print(line)
    if check:
        if bad:
            sys.exit("differs from the generator: " + ", ".join(bad))
        print("all %d files match" % len(files))
    else:
        print("wrote " + ", ".join(sorted(files)))


if __name__ == "__main__":
    main()
