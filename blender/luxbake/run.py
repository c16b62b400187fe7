"""The `bake` command line the add-on runs (no bpy here): where the binary is, its arguments from
the scene's LuxBake settings, and a run that streams its standard error line by line.

bake's stderr carries warnings, errors (one line, exit 1 or 2) and, at the end, its summary;
its progress bars are drawn only on a terminal, so the add-on shows the lines and the elapsed
time as progress.
"""

import os
import shlex
import shutil
import subprocess
import threading


class BakeError(Exception):
    pass


def find_bake(configured=""):
    """The `bake` binary: the preferences' path when set, else `bake` on PATH."""
    if configured:
        path = os.path.abspath(os.path.expanduser(configured))
        if not (os.path.isfile(path) and os.access(path, os.X_OK)):
            raise BakeError(f"bake executable {path} (add-on preferences) is not an executable file")
        return path
    found = shutil.which("bake")
    if found is None:
        raise BakeError("no `bake` on PATH: install luxbake (cargo install --path .) or set "
                        "its path in the LuxBake add-on preferences")
    return found


def command(bake, scene_path, output_path, quality="default", working_plane=None,
            spacing=None, lightmaps=False, probe_glyphs=False, extra=""):
    """The argument list of one bake (working_plane: height in m or None)."""
    args = [bake, scene_path, "-o", output_path, "--quality", quality]
    if working_plane is not None:
        args += ["--working-plane", repr(float(working_plane))]
        if spacing is not None:
            args += ["--working-plane-spacing", repr(float(spacing))]
    if lightmaps:
        args.append("--lightmaps")
    if probe_glyphs:
        args.append("--probe-glyphs")
    args += shlex.split(extra)
    return args


class Run:
    """A bake running in the background; `lines` collects its stderr as it comes."""

    def __init__(self, args):
        self.args = args
        self.lines = []
        self.process = subprocess.Popen(
            args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors="replace")
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self):
        for line in self.process.stderr:
            self.lines.append(line.rstrip("\n"))
        self.process.stdout.read()

    def poll(self):
        """None while running, else the exit code (after all of stderr is read)."""
        code = self.process.poll()
        if code is None:
            return None
        self._reader.join()
        return code

    def wait(self):
        self.process.wait()
        self._reader.join()
        return self.process.returncode

    def cancel(self):
        if self.process.poll() is None:
            self.process.terminate()
        self.wait()

    def error(self):
        """The error line of a failed run (bake prints one), else its last line."""
        for line in reversed(self.lines):
            if line.startswith("error"):
                return line
        return self.lines[-1] if self.lines else f"bake exited with {self.process.returncode}"
