"""Shared by the scripts that time a Cargo example or `bake` outside the harness
(diff_timing.py, intensity_timing.py): building, and the header of their results file naming
the date, machine (run.machine) and commit. Python standard library only."""

import datetime
import os
import subprocess
import sys

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)

import provenance  # noqa: E402
import run  # noqa: E402


def build(example):
    """cargo build --release of `bake` and the example (honours CARGO_TARGET_DIR); returns the
    paths of both binaries."""
    print(f"cargo build --release --bin bake --example {example}", flush=True)
    subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "bake", "--example",
                    example], cwd=ROOT, check=True)
    release = _release()
    return os.path.join(release, "bake"), os.path.join(release, "examples", example)


def build_bake():
    """cargo build --release of `bake` alone (honours CARGO_TARGET_DIR); returns its path."""
    subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "bake"], cwd=ROOT,
                   check=True)
    return os.path.join(_release(), "bake")


def _release():
    target = os.environ.get("CARGO_TARGET_DIR") or os.path.join(ROOT, "target")
    if not os.path.isabs(target):
        target = os.path.join(ROOT, target)
    return os.path.join(target, "release")


def header(title, command, bake, section="quick", at=None):
    """The opening lines of a results file: what wrote it, when, on which machine and commit
    (the provenance line first, bench/provenance.py; `at`: the commit the figures were measured
    at when it is not HEAD, as for a table rewritten from stored runs)."""
    m = run.machine(bake, None)
    load = " / ".join(f"{x:.2f}" for x in os.getloadavg())
    return [f"# {title}", "", provenance.line(command, section, at=at), "",
            f"Written by `{command}` on {datetime.date.today().isoformat()} at commit "
            f"{m['gitCommit']} (`bake --version`: {m['luxbake']}).", "",
            f"Machine: {m['cpu']}, {m['cores']} cores, {m['ramGiB']} GiB, {m['os']} "
            f"({m['virtualisation']}); {m['rustc']}. Load average before the runs (1 / 5 / 15 min): "
            f"{load}.", ""]


def spread(values):
    """min / median / max."""
    v = sorted(values)
    return v[0], v[len(v) // 2], v[-1]


def write(path, lines):
    """Write the result table to `path` (creating its folder) and print it."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    open(path, "w").write("\n".join(lines))
    print("\n".join(lines))
