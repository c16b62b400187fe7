"""The provenance line every results page carries under its title (issue 58, item 2).

    Provenance: commit HASH (measured at); date YYYY-MM-DD; machine: N cores, M GiB (CPU);
    regenerate: `COMMAND` (`sh bench/regenerate.sh SECTION`).

tests/results_provenance.rs checks it on every Markdown file under bench/results/: the commit
must exist in `git log`, the file must be named in bench/regenerate.sh. Python standard library
only.
"""

import datetime
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def commit():
    """HEAD's short hash, and whether the tracked files differ from it."""
    def git(*args):
        return subprocess.run(["git", *args], cwd=ROOT, capture_output=True,
                              text=True).stdout.strip()
    head = git("rev-parse", "--short", "HEAD") or "unknown"
    dirty = git("status", "--porcelain", "--untracked-files=no")
    return head + (" (measured at, with uncommitted changes)" if dirty else " (measured at)")


def machine():
    """N cores, M GiB (CPU model): what the pages compare across."""
    cpu = None
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            cpu = next((l.split(":", 1)[1].strip() for l in f if l.startswith("model name")),
                       None)
    except OSError:
        pass
    ram = "?"
    try:
        with open("/proc/meminfo", encoding="utf-8") as f:
            ram = f"{int(f.readline().split()[1]) / 1024 ** 2:.1f}"
    except (OSError, ValueError, IndexError):
        pass
    return f"{os.cpu_count()} cores, {ram} GiB" + (f" ({cpu})" if cpu else "")


def line(command, section, at=None, date=None, machine_text=None):
    """The provenance line. `at`: a commit text (default HEAD now); `date`: YYYY-MM-DD (today)."""
    return (f"Provenance: commit {at or commit()}; date "
            f"{date or datetime.date.today().isoformat()}; machine: "
            f"{machine_text or machine()}; regenerate: `{command}` "
            f"(`sh bench/regenerate.sh {section}`).")


if __name__ == "__main__":
    # For the shell generators: python3 bench/provenance.py SECTION COMMAND...; AT=HASH names
    # the commit the measured binary was built at when it is not HEAD's.
    import sys
    at = os.environ.get("AT")
    print(line(" ".join(sys.argv[2:]), sys.argv[1], at=f"{at} (measured at: the binary's build)"
               if at else None))
