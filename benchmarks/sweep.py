"""How a design sweep scales: designs per second against workers, and its memory.

    python benchmarks/sweep.py            # prints the markdown docs/design.md shows
    python benchmarks/sweep.py --quick    # a smaller grid, one round
    python benchmarks/sweep.py --default-malloc   # keep distributed's worker malloc setting

Needs the sweep extra (dask, distributed).  The grid is the report's linkage with the
rocker's length and the coupler's weight varied, 360 angles per design.  For each way of
running, several rounds, the in-process run beside it in each round (a noisy shared
machine moves both alike); CPU time is user + sys of this process *and* of every worker
process (psutil, which distributed installs), wall time as seen here; median (range).
Then one 10^5-design grid in process and on a two-worker LocalCluster: peak memory
(this process's peak RSS; the workers' largest RSS) and whether the results are
identical.
"""

from __future__ import annotations

import os
import platform
import resource
import statistics
import sys
import time
import tracemalloc

import numpy as np
import psutil

from sielaff import EXAMPLE
from sielaff.design.sweep import BLOCK, Grid, iter_blocks

QUICK = "--quick" in sys.argv
ROUNDS = 1 if QUICK else 3
ANGLES = 360


def grid(n_designs: int) -> Grid:
    r4 = 100 if n_designs >= 10_000 else 25
    return Grid(EXAMPLE, {"R4": np.linspace(9.0, 15.0, r4),
                          "W3": np.linspace(2.0, 12.0, n_designs // r4)})


def cpu_of(procs) -> float:
    total = 0.0
    for p in procs:
        try:
            t = p.cpu_times()
            total += t.user + t.system
        except psutil.Error:
            pass
    return total


def run(g: Grid, backend: str = "process", client=None, workers=()) -> tuple:
    me = psutil.Process()
    procs = [me, *workers]
    c0, w0 = cpu_of(procs), time.perf_counter()
    out = np.concatenate(list(iter_blocks(g, ANGLES, 0.05, {}, backend, client)))
    return cpu_of(procs) - c0, time.perf_counter() - w0, out


def spread(xs, fmt="{:.2f}") -> str:
    return f"{fmt.format(statistics.median(xs))} ({fmt.format(min(xs))}-{fmt.format(max(xs))})"


def block_memory() -> float:
    """Peak bytes numpy allocates for one block (tracemalloc sees numpy's buffers)."""
    g = grid(10_000)
    tracemalloc.start()
    next(iter_blocks(g, ANGLES, 0.05, {}))
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak


def main() -> int:
    import dask

    # distributed starts workers with MALLOC_TRIM_THRESHOLD_=65536; any explicit value
    # turns off glibc's adaptive mmap threshold, and then every large numpy temporary is
    # a fresh mmap: the engine runs 2x slower in such a worker (docs/design.md).  Unset it.
    if "--default-malloc" not in sys.argv:
        dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None})
    from distributed import Client, LocalCluster

    n = 2_000 if QUICK else 10_000
    g = grid(n)
    run(grid(200))  # warm up
    rows = []
    configs = [("in process", None), ("dask, local threads (2)", "threads"),
               ("LocalCluster, 1 worker", 1), ("LocalCluster, 2 workers", 2)]
    for name, how in configs:
        cluster = client = None
        workers: list = []
        if isinstance(how, int):
            cluster = LocalCluster(n_workers=how, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
            client = Client(cluster)
            pids = client.run(os.getpid).values()
            workers = [psutil.Process(p) for p in pids]
            run(grid(200), "dask", client, workers)  # warm the workers
        cpu, wall, ref_wall, rate = [], [], [], []
        for _ in range(ROUNDS):
            _, rw, _ = run(g)
            if how is None:
                c, w, _ = run(g)
            else:
                c, w, _ = run(g, "dask", client, workers)
            cpu.append(c)
            wall.append(w)
            ref_wall.append(rw)
            rate.append(g.size / w)
        rows.append((name, spread(cpu), spread(wall), spread(ref_wall),
                     spread(rate, "{:,.0f}")))
        if client is not None:
            client.close()
            cluster.close()

    big = Grid(EXAMPLE, {"R4": np.linspace(9.0, 15.0, 500 if not QUICK else 100),
                         "W3": np.linspace(2.0, 12.0, 200 if not QUICK else 50)})
    t0 = time.perf_counter()
    _, _, a = run(big)
    t_proc = time.perf_counter() - t0
    rss_here = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        workers = [psutil.Process(p) for p in client.run(os.getpid).values()]
        t0 = time.perf_counter()
        _, _, b = run(big, "dask", client, workers)
        t_cluster = time.perf_counter() - t0
        rss_workers = max(w.memory_info().rss for w in workers) / 2**20
    same = np.array_equal(a, b, equal_nan=True)

    cpu_name = next((ln.split(":", 1)[1].strip() for ln in open("/proc/cpuinfo")
                     if ln.startswith("model name")), platform.machine())
    print(f"Measured by `python benchmarks/sweep.py` on {cpu_name}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, numpy {np.__version__}: a grid of {g.size:,} "
          f"designs x {ANGLES} angles, blocks of {BLOCK} designs, {ROUNDS} rounds, "
          "median (range).\n")
    print("| how | CPU s (all processes) | wall s | in process beside it, wall s | "
          "designs / s |")
    print("|---|---:|---:|---:|---:|")
    for row in rows:
        print("| " + " | ".join(row) + " |")
    print(f"\nOne block ({BLOCK} designs x {ANGLES} angles) allocates at most "
          f"{block_memory() / 2**20:.0f} MB (tracemalloc).  A {big.size:,}-design grid: in "
          f"process {t_proc:.1f} s wall, peak RSS of this process {rss_here:.0f} MB; on a "
          f"two-worker LocalCluster {t_cluster:.1f} s wall, largest worker RSS "
          f"{rss_workers:.0f} MB; results identical: {'yes' if same else 'NO'}.")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
