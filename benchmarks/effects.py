"""What each effect costs: analyze() on 10^5 positions, each effect against the 1966 scene.

    python benchmarks/effects.py            # prints the markdown table docs/effects.md shows

For each configuration, several rounds; in each round the reference (no effect) runs
right beside it, so a noisy shared machine moves both alike.  CPU time (user + sys of
this process) and wall time, median and range over the rounds, all outputs (RESULTS plus
the TORQ breakdown).
"""

from __future__ import annotations

import os
import platform
import statistics
import sys
import time

import numpy as np

from sielaff import EXAMPLE, Load, analyze
from sielaff.engine import RESULTS

N, ROUNDS = 100_000, 7
TH = np.linspace(0.0, 360.0, N, endpoint=False)
OUT = list(RESULTS) + ["TORQ_INERTIA", "TORQ_GRAVITY", "TORQ_LOADS", "TORQ_TEX"]
CONFIGS = {
    "crank acceleration (th2dd=-40)": dict(th2dd=-40.0),
    "gravity": dict(gravity=(0.0, -386.088)),
    "two loads": dict(loads=[Load(3, r=8.0, angle=10.0, fx=80.0), Load(4, torque=15.0)]),
    "all three": dict(th2dd=-40.0, gravity=(0.0, -386.088),
                      loads=[Load(3, r=8.0, angle=10.0, fx=80.0), Load(4, torque=15.0)]),
}


def timed(**scene) -> tuple[float, float]:
    c0, w0 = time.process_time(), time.perf_counter()
    analyze(EXAMPLE, TH, OUT, **scene)
    return time.process_time() - c0, time.perf_counter() - w0


def spread(xs) -> str:
    return f"{statistics.median(xs):.1f} ({min(xs):.1f}-{max(xs):.1f})"


def main() -> int:
    timed()  # warm up
    rows = []
    for name, scene in CONFIGS.items():
        ref_c, ref_w, cpu, wall, ratio = [], [], [], [], []
        for _ in range(ROUNDS):
            rc, rw = timed()
            c, w = timed(**scene)
            ref_c.append(rc * 1e3)
            ref_w.append(rw * 1e3)
            cpu.append(c * 1e3)
            wall.append(w * 1e3)
            ratio.append(c / rc)
        rows.append((name, spread(cpu), spread(wall), spread(ref_c), spread(ref_w),
                     f"{statistics.median(ratio):.2f} ({min(ratio):.2f}-{max(ratio):.2f})"))
    cpu_name = next((ln.split(":", 1)[1].strip() for ln in open("/proc/cpuinfo")
                     if ln.startswith("model name")), platform.machine())
    print(f"Measured by `python benchmarks/effects.py` on {cpu_name}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, numpy {np.__version__}: analyze() on "
          f"{N:,} positions, {len(OUT)} outputs, {ROUNDS} rounds, median (range), ms.\n")
    print("| effect | CPU ms | wall ms | no effect, CPU ms | no effect, wall ms | "
          "CPU ratio |")
    print("|---|---:|---:|---:|---:|---:|")
    for row in rows:
        print("| " + " | ".join(row) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
