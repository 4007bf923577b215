"""What accuracy costs for pin friction, and what friction and springs cost beside 1966.

    python benchmarks/friction.py            # prints the markdown tables
    python benchmarks/friction.py --write    # and puts them into docs/effects.md

``tolerance_table()``: for each tolerance of the friction fixed point, analyze() on the
1966 example (10^4 positions, friction mu r = 0.1 in each pin), CPU and wall time
(median and range over rounds, the frictionless 1966 scene timed beside it in each
round) and the error read from an independent quantity: the power identity of
friction, ``TORQ_FRICTION TH2D = sum over pins of mu r |F| |relative rotation|`` with F
the reported pin forces (exact at the fixed point; the iteration's own torques do not
enter), its largest residual over the revolution relative to the largest loss.
``cost_table()``: springs and dampers, and friction at the default tolerance, against
the 1966 scene on 10^5 positions.  The functions are reusable (``sielaff bench`` may
call them).
"""

from __future__ import annotations

import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from sielaff import EXAMPLE, Damper, PinFriction, Scene, Spring, analyze

TOLERANCES = (1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-13)
PLOSS = ("PLOSS_O2", "PLOSS_A", "PLOSS_B", "PLOSS_O4")
ELEMENTS = (Spring((1, 6.0, 90.0), (3, 8.0, 0.0), 30.0, 5.0),
            Damper((1, 12.0, 60.0), (4, 6.0, 0.0), 0.5))


def machine() -> str:
    cpu = next((ln.split(":", 1)[1].strip() for ln in open("/proc/cpuinfo")
                if ln.startswith("model name")), platform.machine())
    return (f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, "
            f"numpy {np.__version__}")


def timed(th, outputs, scene):
    c0, w0 = time.process_time(), time.perf_counter()
    r = analyze(EXAMPLE, th, outputs, scene=scene)
    return time.process_time() - c0, time.perf_counter() - w0, r


def spread(xs) -> str:
    return f"{statistics.median(xs):.1f} ({min(xs):.1f}-{max(xs):.1f})"


def power_error(r, th2d=EXAMPLE.TH2D) -> float:
    """max |TORQ_FRICTION TH2D - sum of losses| / max loss: the friction power identity."""
    loss = sum(r[p] for p in PLOSS)
    return float(np.nanmax(np.abs(r["TORQ_FRICTION"] * th2d - loss)) / np.nanmax(loss))


def tolerance_table(n: int = 10_000, rounds: int = 5, mur: float = 0.1) -> list[tuple]:
    """Rows (tol, median iterations, max iterations, CPU ms, wall ms, 1966 CPU ms,
    power error) for each tolerance in TOLERANCES."""
    th = np.linspace(0.0, 360.0, n, endpoint=False)
    out = ["TORQ", "TORQ_FRICTION", "FRICTION_ITERATIONS", *PLOSS]
    rows = []
    timed(th, ["TORQ"], Scene())  # warm up
    for tol in TOLERANCES:
        sc = Scene(friction=PinFriction(mur, 1.0, tol=tol))
        cpu, wall, ref = [], [], []
        for _ in range(rounds):
            rc, _, _ = timed(th, ["TORQ"], Scene())
            c, w, r = timed(th, out, sc)
            cpu.append(c * 1e3)
            wall.append(w * 1e3)
            ref.append(rc * 1e3)
        it = r["FRICTION_ITERATIONS"]
        rows.append((f"{tol:.0e}", f"{np.median(it):.0f}", f"{it.max():.0f}", spread(cpu),
                     spread(wall), spread(ref), f"{power_error(r):.1e}"))
    return rows


def cost_table(n: int = 100_000, rounds: int = 5) -> list[tuple]:
    """Rows (configuration, CPU ms, wall ms, 1966 CPU ms, CPU ratio) for TORQ and the
    pin forces."""
    th = np.linspace(0.0, 360.0, n, endpoint=False)
    out = ["TORQ", "FA32", "FB34", "FOA", "FOB"]
    configs = {"springs and dampers (one each)": Scene(elements=ELEMENTS),
               "pin friction (mu r = 0.1, tol 1e-13)": Scene(friction=PinFriction(0.1, 1.0)),
               "both": Scene(elements=ELEMENTS, friction=PinFriction(0.1, 1.0))}
    timed(th, out, Scene())
    rows = []
    for name, sc in configs.items():
        cpu, wall, ref, ratio = [], [], [], []
        for _ in range(rounds):
            rc, _, _ = timed(th, out, Scene())
            c, w, _ = timed(th, out, sc)
            cpu.append(c * 1e3)
            wall.append(w * 1e3)
            ref.append(rc * 1e3)
            ratio.append(c / rc)
        rows.append((name, spread(cpu), spread(wall), spread(ref),
                     f"{statistics.median(ratio):.2f} ({min(ratio):.2f}-{max(ratio):.2f})"))
    return rows


def markdown() -> str:
    lines = [f"Measured by `python benchmarks/friction.py` on {machine()}; median (range) "
             "over 5 rounds, the 1966 scene timed beside each in every round.", "",
             "Accuracy against time, the 1966 example with PinFriction(0.1, 1.0) in every "
             "pin, 10,000 positions (TORQ, TORQ_FRICTION, the iterations, the four losses); "
             "the error is the largest residual of TORQ_FRICTION TH2D = sum of mu r |F| "
             "|relative rotation| (reported F) over the largest loss:", "",
             "| tol | iterations, median | iterations, max | CPU ms | wall ms | "
             "1966 scene, CPU ms | power error |", "|---|---:|---:|---:|---:|---:|---:|"]
    lines += ["| " + " | ".join(r) + " |" for r in tolerance_table()]
    lines += ["", "Cost beside the 1966 scene, 100,000 positions, TORQ and the four pin "
              "forces:", "", "| scene | CPU ms | wall ms | 1966 scene, CPU ms | CPU ratio |",
              "|---|---:|---:|---:|---:|"]
    lines += ["| " + " | ".join(r) + " |" for r in cost_table()]
    return "\n".join(lines) + "\n"


BEGIN, END = "<!-- friction bench begin -->", "<!-- friction bench end -->"


def main(argv: list[str]) -> int:
    text = markdown()
    print(text)
    if "--write" in argv:
        doc = Path(__file__).resolve().parent.parent / "docs" / "effects.md"
        old = doc.read_text()
        head, rest = old.split(BEGIN, 1)
        tail = rest.split(END, 1)[1]
        doc.write_text(head + BEGIN + "\n" + text + END + tail)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
