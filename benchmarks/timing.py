"""What the benchmarks share: timing that survives a noisy shared machine.

Every configuration is run in rounds, with the reference (the gfortran build) run right
beside it in each round, so that a load on the machine moves both alike.  Each run's wall
time and CPU time (user + sys, of this process and of the child processes it waited for)
are recorded; reports give the median and the range over the rounds, and the ratio
reference / configuration per round (its median and range).
"""

from __future__ import annotations

import os
import platform
import resource
import statistics
import subprocess
import time
from collections.abc import Callable
from dataclasses import dataclass, field


def _cpu() -> float:
    me = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def measure(fn: Callable[[], object]) -> tuple[float, float]:
    """(wall s, CPU s) of one call."""
    c0, w0 = _cpu(), time.perf_counter()
    fn()
    return time.perf_counter() - w0, _cpu() - c0


def touch_memory(gib: float) -> tuple[float, float]:
    """CPU seconds to write ``gib`` GiB of new arrays, the first time and again (each
    freed after).  On a virtual machine the first write of memory the guest has not used
    before can cost many times the second: done before the rounds, so that a round that
    allocates measures the program, not that."""
    import numpy

    n = int(gib * (1 << 27))  # floats

    def once() -> float:
        c = _cpu()
        a = numpy.empty(n)
        a.fill(1.0)
        del a
        return _cpu() - c

    return once(), once()


@dataclass
class Series:
    """Rounds of one configuration and of the reference beside it."""

    name: str
    wall: list[float] = field(default_factory=list)
    cpu: list[float] = field(default_factory=list)
    ref_wall: list[float] = field(default_factory=list)
    ref_cpu: list[float] = field(default_factory=list)

    def ratio(self, kind: str = "cpu") -> list[float]:
        mine, ref = (self.cpu, self.ref_cpu) if kind == "cpu" else (self.wall, self.ref_wall)
        return [r / m for r, m in zip(ref, mine)]


def rounds(name: str, fn: Callable[[], object], reference: Callable[[], object],
           n: int) -> Series:
    s = Series(name)
    for _ in range(n):
        w, c = measure(reference)
        s.ref_wall.append(w)
        s.ref_cpu.append(c)
        w, c = measure(fn)
        s.wall.append(w)
        s.cpu.append(c)
    return s


def spread(xs: list[float], fmt: str = "{:.3f}") -> str:
    return (f"{fmt.format(statistics.median(xs))} "
            f"({fmt.format(min(xs))}-{fmt.format(max(xs))})")


def machine() -> str:
    cpu = platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(x.split(":", 1)[1].strip() for x in f if x.startswith("model name"))
    except (OSError, StopIteration):
        pass
    try:
        gfortran = subprocess.run(["gfortran", "--version"], capture_output=True, text=True,
                                  check=True).stdout.splitlines()[0]
    except (OSError, subprocess.CalledProcessError, IndexError):
        gfortran = "gfortran not installed"
    import numpy

    return (f"{cpu}, {os.cpu_count()} cores (shared), {simd()}; {platform.system()} "
            f"{platform.release()}; Python {platform.python_version()}, numpy "
            f"{numpy.__version__}; {gfortran}")


def simd() -> str:
    """The widest vector instructions numpy found on this CPU (as ``numpy.show_runtime``):
    numpy's SVML loops (float64 arctan2, sin and cos among them) are built only for
    AVX-512 (``NPY_HAVE_AVX512_SKX`` in numpy's ``loops_umath_fp`` dispatch source), so
    the engine's ratios to gfortran differ between machines by this above all."""
    import numpy

    try:
        from numpy._core._multiarray_umath import __cpu_features__ as feats
    except ImportError:  # pragma: no cover - another numpy layout
        return "SIMD unknown"
    level = ("AVX-512 (X86_V4)" if feats.get("AVX512_SKX") else
             "AVX2, no AVX-512 (X86_V3)" if feats.get("AVX2") else "no AVX2")
    return f"numpy {numpy.__version__} sees {level}"


def table(series: list[Series], reference: str = "gfortran") -> list[str]:
    """The markdown table of ``series``, each beside the run of ``reference``."""
    lines = [f"| configuration | CPU s | wall s | {reference} beside it, CPU s | "
             f"ratio {reference} CPU / CPU | ratio of wall times |",
             "|---|---:|---:|---:|---:|---:|"]
    for s in series:
        lines.append(f"| {s.name} | {spread(s.cpu)} | {spread(s.wall)} | "
                     f"{spread(s.ref_cpu)} | {spread(s.ratio('cpu'), '{:.2f}')}x | "
                     f"{spread(s.ratio('wall'), '{:.2f}')}x |")
    return lines


def publish(doc, heading: str, text: str, write: bool) -> None:
    """Print ``text``; with ``write``, make it the section ``heading`` of ``doc`` and say
    so on stderr."""
    import sys

    print(text)
    if write:
        write_section(doc, heading, text)
        print(f"wrote the '{heading}' section of {doc.name}", file=sys.stderr)


def write_section(doc, heading: str, text: str) -> None:
    """Replace (or add) the section ``heading`` of the markdown file ``doc``."""
    import re

    if doc.exists():
        old = doc.read_text()
        m = re.search(rf"^{re.escape(heading)}\s*$", old, re.M)
        if m:
            nxt = re.search(r"^## ", old[m.end():], re.M)
            end = m.end() + nxt.start() if nxt else len(old)
            new = old[:m.start()] + text + ("\n" if nxt else "") + old[end:]
        else:
            new = old.rstrip("\n") + "\n\n" + text
    else:
        new = "# Performance\n\n" + text
    tmp = doc.with_name(f".{doc.name}.tmp")
    tmp.write_text(new)
    os.replace(tmp, doc)
