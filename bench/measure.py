"""Run a command and measure it: wall time, CPU time (user + system) and peak resident memory
of the process and of every descendant it waited for (os.wait4 on this one child: exact, no
interference from other children). Python standard library only."""

import os
import signal
import subprocess
import threading
import time


def run(cmd, cwd=None, env=None, stdin_path=None, stdout_path=None, stderr_path=None,
        timeout=None):
    """Run cmd to completion. Returns {"wall", "user", "sys", "cpu", "peakMiB", "returncode",
    "timedOut"}.

    stdin/stdout/stderr go to files (default: /dev/null) so that no pipe can fill up while we
    wait. With timeout (s), the process group is killed (SIGKILL) when it runs longer; the
    figures are then those up to the kill and "timedOut" is true. Peak memory is the largest
    resident set of the process or of any descendant it waited for (Linux ru_maxrss)."""
    fin = open(stdin_path, "rb") if stdin_path else subprocess.DEVNULL
    fout = open(stdout_path, "wb") if stdout_path else subprocess.DEVNULL
    ferr = open(stderr_path, "wb") if stderr_path else subprocess.DEVNULL
    try:
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, cwd=cwd, env=env, stdin=fin, stdout=fout, stderr=ferr,
                                start_new_session=True)
        timed_out = []
        timer = None
        if timeout:
            def kill():
                timed_out.append(True)
                try:
                    os.killpg(proc.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            timer = threading.Timer(timeout, kill)
            timer.start()
        try:
            _, status, usage = os.wait4(proc.pid, 0)
        except BaseException:  # Ctrl-C: the child runs in its own session, stop it too
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            try:
                os.wait4(proc.pid, 0)
            except ChildProcessError:  # already reaped
                pass
            if timer:
                timer.cancel()
            raise
        wall = time.perf_counter() - t0
        if timer:
            timer.cancel()
        proc.returncode = os.waitstatus_to_exitcode(status)
    finally:
        for f in (fin, fout, ferr):
            if hasattr(f, "close"):
                f.close()
    return {
        "wall": wall,
        "user": usage.ru_utime,
        "sys": usage.ru_stime,
        "cpu": usage.ru_utime + usage.ru_stime,
        "peakMiB": usage.ru_maxrss / 1024.0,  # Linux: ru_maxrss in KiB
        "returncode": proc.returncode,
        "timedOut": bool(timed_out),
    }
