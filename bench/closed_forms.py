"""The manual's table of tests against closed forms (docs/accuracy.md), with its measured column from a run.

    python3 bench/closed_forms.py   → bench/results/closed_forms.md

Runs `cargo test --release --test FILE -- --nocapture` for each test file behind the table (and
the library's unit test of a hall's coverage), collects the lines `oracle: KEY measured VALUE`
the tests print to stderr, and writes the table (docs/accuracy.md's columns) with the commit and date,
followed by every line collected. A row whose lines are missing says so. Any failing test stops
the script. Python standard library only (honours CARGO_TARGET_DIR through cargo).
"""

import argparse
import datetime
import math
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import provenance  # noqa: E402

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)

RUNS = [["--test", "analytic"], ["--test", "black"],
        ["--lib", "transport::gather::tests::tilted_receivers_in_a_long_hall"],
        ["--test", "luminaires"], ["--test", "direct_light"], ["--test", "photometry"],
        ["--test", "contacts"]]
LINE = re.compile(r"^oracle: (\S+) measured (\S+)\s*$")
SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def pct(v):
    """A relative error as a percentage with two significant digits: 0.0011 → 0.11 %; below
    10⁻⁶ in powers of ten (sci)."""
    if v == 0:
        return "0"
    if abs(v) < 1e-6:
        return sci(v)
    x = 100 * abs(v)
    return f"{x:.{max(0, 1 - math.floor(math.log10(x)))}f} %"


def sci(v):
    """Two significant digits in powers of ten: 0.000214 → 2.1·10⁻⁴."""
    if v == 0:
        return "0"
    e = math.floor(math.log10(abs(v)))
    m = v / 10 ** e
    if round(m, 1) >= 10:
        m, e = m / 10, e + 1
    return f"{m:.1f}·10{str(e).translate(SUPERSCRIPT)}"


# (test, closed form, tolerance, measured column from the oracle lines m: KEY → float)
ROWS = [
    ("closed box, emitting ceiling panel, ρ = 0.3 / 0.9 / 0.99", "mean E = Φ/(S(1−ρ))", "0.5 %",
     lambda m: " / ".join(pct(m[f"box/{r}"]) for r in ("0.3", "0.9", "0.99"))),
    ("closed 4 × 3 × 5 m box, ceiling panel, twelve tessellated balls 5 cm above the floor "
     "(curved clutter, seen as clusters), ρ = 0.5 / 0.9", "mean E = Φ/(S(1−ρ)), S with the balls",
     "0.5 %", lambda m: " / ".join(pct(m[f"balls/{r}"]) for r in ("0.5", "0.9"))),
    ("furnace, ρ = 0.9", "M = M_e/(1−ρ) at every vertex", "0.5 %",
     lambda m: f"{sci(m['furnace'])} worst"),
    ("inside a tessellated sphere (radius 2 m, 2 208 facets, point light at the centre), "
     "ρ = 0.5 / 0.8 / 0.99", "E_ind = ρΦ/(S(1−ρ)) at every vertex", "0.5 %",
     lambda m: " / ".join(sci(m[f"sphere/{r}"]) for r in ("0.5", "0.8", "0.99")) + " worst"),
    ("the same sphere, ρ = 0.8 with its lowest 40 % black, without and with links to black "
     "(`tests/black.rs`)", "E_ind = ρΦ(1−s₀)/(S(1−ρ(1−f₀))) at every vertex (f₀, s₀: black share "
     "of area and of flux)", "0.5 % mean, 3 % each vertex",
     lambda m: f"{pct(m['black-cap/without/mean'])} / {pct(m['black-cap/with/mean'])} mean, "
               f"{pct(max(m['black-cap/without/worst'], m['black-cap/with/worst']))} worst"),
    ("tilted receivers in an empty 60 × 45 × 3 m hall, far slivers on the horizon skipped (unit "
     "test in `transport::gather`)", "coverage before normalisation = 1", "10⁻³",
     lambda m: f"{sci(m['hall-coverage'])} worst"),
    ("closed 4 × 3 × 5 m room, 1 × 1 m panel in a 4 cm housing 0 / 1 mm / 1 cm / 3 cm / 10 cm "
     "under the ceiling, ρ = 0.5 and 0.9 (`tests/contacts.rs`)",
     "Σ(1−ρ)·E·A over the output's triangles = Φ; balance error", "0.5 %; 10⁻⁴",
     lambda m: f"{pct(m['contacts/panel-sumpner'])}; {sci(m['contacts/panel-balance'])} worst"),
    ("the same with a single-sided flat panel (its back absorbs) 1 mm to 10 cm under the ceiling",
     "balance error", "10⁻⁴", lambda m: f"{sci(m['contacts/flat-panel-balance'])} worst"),
    ("three 0.6 m cubes standing on the floor (and lifted 1 mm), point light, ρ = 0.5 / 0.9",
     "Σ(1−ρ)·E·A = Φ; balance error", "0.5 %; 10⁻⁴",
     lambda m: f"{pct(m['contacts/cubes-sumpner'])}; {sci(m['contacts/cubes-balance'])} worst"),
    ("a 1.2 × 2 × 0.5 m cabinet on the floor, back against a wall, ρ = 0.9",
     "Σ(1−ρ)·E·A = Φ; balance error", "0.5 %; 10⁻⁴",
     lambda m: f"{pct(m['contacts/cabinet-sumpner'])}; {sci(m['contacts/cabinet-balance'])}"),
    ("the wall 3 cm outside a 0.8 × 0.6 m picture 1 cm proud of it, two point lights; framed (a "
     "1 cm box) / a single-sided quad", "the bare wall / the bare wall less its inter-reflected "
     "light from the hemisphere share the quad's black back hides, ½(1 − x/√(x² + g²))", "3 %",
     lambda m: f"{pct(m['contacts/picture-framed'])} / {pct(m['contacts/picture-quad'])} worst"),
    ("CIE 171:2006 test 5.8, ρ = 0.2 / 0.5 / 0.9 / 0.95", "mean E_ind = ρΦ/(S(1−ρ))", "0.5 %",
     lambda m: " / ".join(pct(m[f"cie5.8/{r}"]) for r in ("0.2", "0.5", "0.9", "0.95"))),
    ("Lambertian panel over a floor", "Lambert's formula at every vertex", "0.5 %",
     lambda m: f"{pct(m['panel-floor'])} worst"),
    ("point light over a floor", "I·cos ξ/d² at every vertex", "0.2 %",
     lambda m: f"{pct(m['point-floor'])} worst"),
    ("opaque box between light and floor", "0 lx direct in the umbra", "exact",
     lambda m: "0" if m["umbra"] == 0 else f"{m['umbra']} lx"),
    ("1 vs 2 threads", "byte-identical", "—",
     lambda m: "identical" if m["threads"] == 0 else f"{m['threads']:.0f} values differ"),
    ("CIE 171:2006 test 5.2, cosine source from an IES file", "I₀h²/d⁴ at every vertex", "0.1 %",
     lambda m: f"{pct(m['cie5.2'])} worst"),
    ("576 cosine luminaires over a floor, far ones grouped; with a screen hiding part",
     "Σ I₀h²/d⁴ over the unhidden", "10⁻⁵",
     lambda m: f"{sci(m['grouped/open'])} / {sci(m['grouped/screen'])} worst"),
    ("the same 576 with the light cut at f = 1 % (`--light-cut-fraction 0.01`)",
     "Σ I₀h²/d⁴ over the unhidden", "f + 10⁻⁵",
     lambda m: f"{sci(m['grouped/open-cut'])} / {sci(m['grouped/screen-cut'])} worst"),
    ("the same 576 over a floor half under a table top whose slanted edge crosses columns of "
     "them", "each luminaire traced alone; Σ I₀h²/d⁴ over the unhidden", "10⁻¹² / 2·10⁻⁵",
     lambda m: f"{sci(m['grouped/slanted-traced'])} / {sci(m['grouped/slanted'])} worst"),
    ("CIE 171:2006 test 5.3, panel in a black room", "point-to-rectangle form factors (parallel "
     "and perpendicular, by superposition) at every vertex", "0.5 %",
     lambda m: f"{pct(m['cie5.3'])} worst"),
    ("KHR spot: inner cone, falloff, outside", "the spec's reference falloff",
     "10⁻⁵ / 2·10⁻⁴ (each + 10⁻⁵ of the on-axis E) / 0",
     lambda m: f"{sci(m['spot/inner'])} / {100 * m['spot/ramp']:.0f} % of the tolerance / "
               + ("0" if m["spot/outside"] == 0 else f"{m['spot/outside']} lx")),
    ("near field of a 1.5 × 0.2 m opening, 0.3 / 1 / 3 m", "fine integration over the opening",
     "0.5 %", lambda m: f"{pct(m['near-field'])} worst"),
    ("soft shadow of a 1.5 × 0.2 m opening behind a straight edge, across / along the fitting",
     "fine integration over the opening, the edge by geometry", "1 % of the unshadowed E",
     lambda m: f"{pct(m['soft-shadow/across'])} / {pct(m['soft-shadow/along'])} worst"),
    ("closed room lit by an IES luminaire, ρ = 0.8", "mean E = Φ/(S(1−ρ)); balance", "0.5 %",
     lambda m: f"{pct(m['ies-room/mean'])}; {sci(m['ies-room/balance'])}"),
    ("cosine-profiled emitting panel", "Lambert's formula", "0.5 %",
     lambda m: f"{pct(m['profiled-panel'])} worst"),
    (None, "closed forms", "0.5 %", lambda m: f"≤ {pct(m['profile-flux'])}"),
    ("same distribution as IES and as EULUMDAT", "equal intensities / illuminances", "0.1 %",
     lambda m: f"{pct(m['ies-ldt/intensity'])} / "
               + ("identical" if m["ies-ldt/illuminance"] == 0 else pct(m["ies-ldt/illuminance"]))
               + " worst"),
]


DEFAULT_OUT = os.path.join(BENCH, "results", "closed_forms.md")
MANUAL = os.path.join(ROOT, "docs", "accuracy.md")
BEGIN, END = "<!-- closed-forms table: bench/closed_forms.py writes it -->", "<!-- end of closed-forms table -->"


def write_manual(out, commit):
    """The same table into the manual (docs/accuracy.md) between its markers, with the commit;
    tests/docs_links.rs checks that the two tables are equal."""
    text = open(MANUAL, encoding="utf-8").read()
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    table = [l for l in out if l.startswith("|")]
    date = datetime.date.today().isoformat()
    block = [BEGIN, f"Measured at commit {commit[:7]}{commit[40:]} on {date} "
             "(`python3 bench/closed_forms.py`):", "", *table, END]
    open(MANUAL, "w", encoding="utf-8").write(head + "\n".join(block) + tail)


def git(*args):
    return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True).stdout.strip()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=DEFAULT_OUT)
    a = ap.parse_args()
    measured, lines = {}, []
    for args in RUNS:
        cmd = ["cargo", "test", "--release", "--quiet", *args, "--", "--nocapture"]
        print(" ".join(cmd), flush=True)
        run = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
        if run.returncode != 0:
            sys.stderr.write(run.stdout[-4000:] + run.stderr[-4000:])
            raise SystemExit(f"{' '.join(cmd)} failed")
        for line in (run.stderr + run.stdout).splitlines():
            hit = LINE.match(line)
            if hit:
                measured[hit[1]] = float(hit[2])
                lines.append(f"{' '.join(args)}: {hit[1]} {hit[2]}")
    commit = git("rev-parse", "HEAD")
    if git("status", "--porcelain", "--untracked-files=no"):
        commit += " (with uncommitted changes)"
    out = ["# Tests against closed forms, measured", "",
           provenance.line("python3 bench/closed_forms.py", "quick"), "",
           f"Written by `python3 bench/closed_forms.py` on {datetime.date.today().isoformat()} "
           f"at commit {commit}: `cargo test --release` of "
           + ", ".join(f"`{' '.join(r)}`" for r in RUNS) + " (default quality unless the "
           "test says otherwise). The measured column is what the tests print as "
           "`oracle: KEY measured VALUE`, listed below the table.", "",
           "| test | closed form | tolerance | measured |", "| --- | --- | --- | --- |"]
    missing = []
    for test, form, tol, cell in ROWS:
        if test is None:
            files = measured.get("profile-flux/files")
            test = f"profile files ({files:.0f}): integrated vs declared flux" if files else \
                "profile files: integrated vs declared flux"
        try:
            value = cell(measured)
        except KeyError as e:
            value = f"not measured: no `oracle: {e.args[0]}` line"
            missing.append(test)
        out.append(f"| {test} | {form} | {tol} | {value} |")
    out += ["", "Oracle lines (test binary: key value):", "", "```", *lines, "```", ""]
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    open(a.out, "w").write("\n".join(out))
    if a.out == DEFAULT_OUT:
        write_manual(out, commit)
    print("\n".join(out))
    if missing:
        print("rows not measured: " + "; ".join(missing), file=sys.stderr)


if __name__ == "__main__":
    main()
