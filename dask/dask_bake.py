#!/usr/bin/env python3
"""Run one bake with its links gather spread over a Dask cluster.

    python dask/dask_bake.py IN -o OUT [--scheduler ADDR | --local-workers W] [--tasks N]
        [--bake PATH] [--state DIR] [--keep-state] [--task-threads T] [--timings FILE.json]
        -- [extra bake options]

Three stages, each `bake shard STEP --dir DIR` with the bake's own command line:
  plan    (here)            bake shard plan --dir DIR IN -o OUT OPTS [--tasks N]
  gather  (a Dask task, K)  bake shard gather --dir DIR IN -o OUT OPTS --threads T --task K
  merge   (here)            bake shard merge --dir DIR IN -o OUT OPTS
OUT is byte-identical to `bake IN -o OUT OPTS`. On a real cluster IN, OUT's folder, DIR and
the bake binary must be at the same paths on every node (a shared filesystem); see
dask/README.md. Exit 0 on success, 1 when a stage failed, 2 on bad arguments.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from dataclasses import asdict, dataclass
from pathlib import Path

from distributed import Client, LocalCluster, as_completed, get_worker
from distributed.comm.addressing import get_address_host

REPO_BAKE = Path(__file__).resolve().parent.parent / "target" / "release" / "bake"
STDERR_TAIL = 4000  # characters of a failed task's stderr carried back to the coordinator


class StageFailed(Exception):
    """A bake stage exited non-zero (the message says which and why)."""


@dataclass
class TaskResult:
    task: int
    wall_s: float
    exit_code: int
    stderr_tail: str
    host: str
    threads: int


def gather_task(argv: list[str], task: int, threads: int | None, slots_per_host: dict[str, int]) -> TaskResult:
    """Run on a Dask worker: one `bake shard gather` task as a bake subprocess.

    `threads` None: this host's cores shared evenly among the Dask worker slots on it.
    Raises on a non-zero exit, so that Dask's retry runs the task once more.
    """
    host = get_address_host(get_worker().address)
    if threads is None:
        cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
        threads = max(1, cores // max(1, slots_per_host.get(host, 1)))
    cmd = [*argv, "--threads", str(threads), "--task", str(task)]
    env = {**os.environ, "RAYON_NUM_THREADS": str(threads)}
    start = time.perf_counter()
    try:
        proc = subprocess.run(
            cmd, check=False, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True, errors="replace"
        )
        code, stderr = proc.returncode, proc.stderr
    except OSError as e:  # binary missing or not executable on this node
        code, stderr = 127, f"cannot run {cmd[0]}: {e}"
    result = TaskResult(task, time.perf_counter() - start, code, stderr[-STDERR_TAIL:], socket.gethostname(), threads)
    if code != 0:
        raise StageFailed(
            f"gather task {task} failed on {result.host} (exit {code}, {result.wall_s:.1f} s):\n{result.stderr_tail}"
        )
    return result


def run_local(stage: str, cmd: list[str]) -> float:
    """Run a coordinator stage with the terminal's stdout/stderr; return its wall seconds."""
    start = time.perf_counter()
    try:
        code = subprocess.run(cmd, check=False, stdin=subprocess.DEVNULL).returncode
    except OSError as e:
        raise StageFailed(f"{stage}: cannot run {cmd[0]}: {e}") from e
    if code != 0:
        raise StageFailed(f"{stage} failed (exit {code}): {' '.join(cmd)}")
    return time.perf_counter() - start


def without_threads(opts: list[str]) -> list[str]:
    """The bake options less any --threads (each gather task gets its own)."""
    out: list[str] = []
    skip = False
    for o in opts:
        if skip:
            skip = False
        elif o == "--threads":
            skip = True
        elif not o.startswith("--threads="):
            out.append(o)
    return out


def parse_args(argv: list[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(
        prog="dask_bake.py",
        usage="%(prog)s IN -o OUT [--scheduler ADDR | --local-workers W] [--tasks N] [--bake PATH] "
        "[--state DIR] [--keep-state] [--task-threads T] [--timings FILE.json] -- [bake options]",
        description="Bake IN to OUT with the links gather spread over Dask workers "
        "(output byte-identical to a plain bake). Bake options go after '--'.",
    )
    p.add_argument("input", type=Path, help="input scene (.gltf, .glb, .obj)")
    p.add_argument("-o", "--output", type=Path, required=True, help="output file (.gltf or .glb)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDR", help="address of a running scheduler, e.g. tcp://host:8786")
    where.add_argument(
        "--local-workers",
        type=int,
        default=2,
        metavar="W",
        help="without --scheduler: worker processes of a LocalCluster here (default 2)",
    )
    p.add_argument("--tasks", type=int, metavar="N", help="gather tasks (default: the bake's choice)")
    p.add_argument(
        "--bake",
        metavar="PATH",
        help=f"bake binary, the same path on every node (default {REPO_BAKE} if built, else bake on PATH)",
    )
    p.add_argument(
        "--state",
        type=Path,
        metavar="DIR",
        help="shard state folder (default: a temporary folder beside OUT, removed on success)",
    )
    p.add_argument("--keep-state", action="store_true", help="keep the default state folder after success")
    p.add_argument(
        "--task-threads",
        type=int,
        metavar="T",
        help="bake threads per gather task (default: a host's cores / its Dask worker slots)",
    )
    p.add_argument("--timings", type=Path, metavar="FILE.json", help="also write the timings as JSON")
    p.epilog = "Everything after '--' is passed to every bake call (plan, each gather task, merge)."
    own, opts = (argv[: argv.index("--")], argv[argv.index("--") + 1 :]) if "--" in argv else (argv, [])
    args = p.parse_args(own)
    args.bake_options = opts
    if args.local_workers < 1:
        p.error("--local-workers must be at least 1")
    if args.tasks is not None and args.tasks < 1:
        p.error("--tasks must be at least 1")
    if args.task_threads is not None and args.task_threads < 1:
        p.error("--task-threads must be at least 1")
    return args


def resolve_bake(path: str | None) -> str:
    if path is not None:
        found = path if "/" in path else shutil.which(path)
    elif REPO_BAKE.is_file():
        found = str(REPO_BAKE)
    else:
        found = shutil.which("bake")
    if not found or not os.path.isfile(found) or not os.access(found, os.X_OK):
        raise StageFailed(f"bake binary not found: {path or REPO_BAKE} (build it, or pass --bake PATH)")
    return os.path.abspath(found)


def run(args: argparse.Namespace, bake: str, state: Path) -> dict[str, object]:
    t0 = time.perf_counter()
    inp, out = args.input.resolve(), args.output.resolve()
    job = [str(inp), "-o", str(out)]

    def step(name: str, options: list[str]) -> list[str]:
        return [bake, "shard", name, "--dir", str(state), *job, *options]


    gather_argv = step("gather", without_threads(args.bake_options))
    local = args.scheduler is None
    with (
        (
            LocalCluster(n_workers=args.local_workers, threads_per_worker=1, processes=True, dashboard_address=None)
            if local
            else contextlib.nullcontext()
        ) as cluster,
        Client(cluster if local else args.scheduler) as client,
    ):
        # Connect (and wait for a first worker) before the plan, so a wrong address costs no plan.
        if not local:
            client.wait_for_workers(1, timeout=120)
        plan_cmd = step("plan", args.bake_options)
        if args.tasks is not None:
            plan_cmd += ["--tasks", str(args.tasks)]
        plan_s = run_local("plan", plan_cmd)
        plan = json.loads((state / "plan.json").read_text())
        n_tasks = int(plan["tasks"])
        print(
            f"dask_bake: plan {plan_s:.2f} s, {n_tasks} tasks, {plan.get('receivers', '?')} receivers", file=sys.stderr
        )

        slots: dict[str, int] = {}  # worker slots (threads) per host, when the gather starts
        for addr, n in client.nthreads().items():
            slots[get_address_host(addr)] = slots.get(get_address_host(addr), 0) + n
        n_slots = sum(slots.values())
        where = "local cluster" if local else args.scheduler
        print(f"dask_bake: gather on {where}: {n_slots} worker slots on {len(slots)} host(s)", file=sys.stderr)

        g0 = time.perf_counter()
        futures = client.map(
            gather_task,
            [gather_argv] * n_tasks,
            range(n_tasks),
            threads=args.task_threads,
            slots_per_host=slots,
            pure=False,
            retries=1,
        )
        results: list[TaskResult] = []
        for fut in as_completed(futures):
            if fut.status != "finished":
                error = fut.exception()
                client.cancel(futures)
                raise StageFailed(str(error) if isinstance(error, StageFailed) else f"gather task failed: {error!r}")
            r: TaskResult = fut.result()
            results.append(r)
            print(
                f"dask_bake: task {r.task} done on {r.host} in {r.wall_s:.2f} s ({len(results)}/{n_tasks})",
                file=sys.stderr,
            )
        gather_s = time.perf_counter() - g0

    merge_s = run_local("merge", step("merge", args.bake_options))
    results.sort(key=lambda r: r.task)
    task_sum = sum(r.wall_s for r in results)
    workers = min(n_slots, n_tasks)
    ideal = task_sum / workers
    return {
        "tasks": n_tasks,
        "receivers": plan.get("receivers"),
        "workers": workers,
        "worker_slots": n_slots,
        "hosts": len(slots),
        "plan_s": plan_s,
        "gather_wall_s": gather_s,
        "task_wall_sum_s": task_sum,
        "task_wall_max_s": max(r.wall_s for r in results),
        "ideal_gather_s": ideal,
        "engine_overhead_s": gather_s - ideal,
        "merge_s": merge_s,
        "total_s": time.perf_counter() - t0,
        "per_task": [{k: v for k, v in asdict(r).items() if k != "stderr_tail"} for r in results],
    }


def main(argv: list[str]) -> int:
    args = parse_args(argv)
    try:
        bake = resolve_bake(args.bake)
    except StageFailed as e:
        print(f"dask_bake: {e}", file=sys.stderr)
        return 1
    if args.state is not None:
        state, owned = args.state.resolve(), False
        state.mkdir(parents=True, exist_ok=True)
    else:
        out_dir = args.output.resolve().parent
        state, owned = Path(tempfile.mkdtemp(prefix=f".{args.output.name}.shards-", dir=out_dir)), True
    try:
        timings = run(args, bake, state)
    except (StageFailed, OSError, ValueError, KeyError) as e:
        print(f"dask_bake: {e}", file=sys.stderr)
        if owned and not any(state.iterdir()):
            state.rmdir()
        else:
            print(f"dask_bake: state kept in {state}", file=sys.stderr)
        return 1
    if owned and not args.keep_state:
        shutil.rmtree(state)
    else:
        print(f"dask_bake: state kept in {state}", file=sys.stderr)
    t = timings
    print(
        f"dask_bake: plan {t['plan_s']:.2f} s | gather {t['gather_wall_s']:.2f} s "
        f"(tasks sum {t['task_wall_sum_s']:.2f} s over {t['workers']} workers, ideal {t['ideal_gather_s']:.2f} s, "
        f"engine overhead {t['engine_overhead_s']:.2f} s) | merge {t['merge_s']:.2f} s | total {t['total_s']:.2f} s"
    )
    if args.timings is not None:
        args.timings.write_text(json.dumps(timings, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
