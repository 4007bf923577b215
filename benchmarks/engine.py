"""Throughput of the modern engine, side by side with the 1966 program compiled by gfortran.

Run from the repository root::

    python benchmarks/engine.py              # 10^6 positions; writes docs/performance.md
    python benchmarks/engine.py --no-write   # print only
    python benchmarks/engine.py --section compiled   # only the compiled backend's section

What is timed (``benchmarks/timing.py``: rounds, the reference beside each
configuration, CPU time and wall time, median and range; one process, one core):

* **gfortran -O2** (the reference): ``decks/sielaff.f`` built by the test harness
  (``tests/fortran.py``, REAL*8) from a generated copy whose WRITE statements
  inside the loop are replaced by a running checksum of every value the sheet
  would print (and a sheet counter), printed once at the end: the program
  computes everything it prints, but does no formatted output.  The deck is
  the report's example with one range card (0, 0.00036, 359.9996): 10^6
  positions.  CPU time of the child process (its start-up and card reading, measured
  on a deck of one position, are in the section).
* **the engine**: all results with fresh arrays, and into reused arrays
  (``analyze(..., out=...)``); kinematics only; positions and rates; the crossed
  branch; the effects (crank acceleration, gravity, two loads).
* **the compiled backend** (``analyze(..., backend="numba")``; its own section, ``##
  Compiled backend``): all results into reused and fresh arrays, kinematics, the effects
  (springs and dampers too), two threads, the floors (the arrays' fill and allocation),
  the numpy engine beside it; and its largest difference from the numpy engine.

As a check that the compiled program and the engine computed the same
thing, the engine's sum of the printed quantities is compared with the
program's checksum.

The table goes to stdout and, under the heading ``## Engine``, into
``docs/performance.md`` (only that section is replaced; the file is created
if missing).
"""

from __future__ import annotations

import argparse
import atexit
import importlib.util
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "src"))

from sielaff import engine  # noqa: E402
from sielaff.emulator.cards import parse_deck  # noqa: E402
from sielaff.emulator.program import SHEET_FIELDS  # noqa: E402

sys.path.insert(0, str(ROOT / "benchmarks"))
from timing import machine, publish, rounds, table, touch_memory  # noqa: E402

DOC = ROOT / "docs" / "performance.md"
HEADING = "## Engine"
THZERO, DELTA, THMAX = 0.0, 0.00036, 359.9996  # 10^6 positions, 0 .. 359.99964
POSITIONS_AND_RATES = ["ATH3", "ATH4", "TH3D", "TH4D"]
TOUCH_GIB = 4.0  # written once before the compiled section's rounds (timing.touch_memory)


def load_harness():
    """tests/fortran.py, imported by path (it is not a package)."""
    spec = importlib.util.spec_from_file_location("fortran", ROOT / "tests" / "fortran.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["fortran"] = module
    spec.loader.exec_module(module)
    return module


def silent_source(text: str) -> str:
    """The deck with its in-loop WRITEs replaced by a checksum and a sheet counter.

    ``      WRITE(3,1)ATH2,ATH3,ATH4`` becomes ``      CHK=CHK+ATH2+ATH3+ATH4``;
    a WRITE of a heading becomes CONTINUE; the page eject (FORMAT 18) counts the
    sheet.  The labelled ``00052 WRITE(3,20)`` (not a crank-rocker) stays.  At
    statement 237 the program prints CHK and the count on unit 6.
    """
    out, started = [], False
    for line in text.splitlines():
        m = re.match(r"^      WRITE\(3,(\d+)\)(.*)$", line)
        if not started and re.match(r"^      READ\(1,19\)", line):
            out += ["      CHK=0.0", "      NPOS=0"]
            started = True
        if m:
            fmt, items = m.group(1), m.group(2).strip()
            if fmt == "18":
                line = "      NPOS=NPOS+1"
            elif items:
                line = "      CHK=CHK+" + items.replace(",", "+")
            else:
                line = "      CONTINUE"
            assert len(line) <= 72, line
        out.append(line)
        if line.startswith("00237 CONTINUE"):
            out.append("      WRITE(6,*) CHK, NPOS")
    assert started and any("WRITE(6,*)" in x for x in out)
    return "\n".join(out) + "\n"


def engine_checksum(result: dict[str, np.ndarray]) -> float:
    """The engine's sum of what the program prints (its CHK), in the same quantities."""
    return float(sum(np.sum(result[name], dtype=np.float64)
                     for group in SHEET_FIELDS for name in group))


#: What each of the engine's functions does, for the profile's sentence (others by name).
WHAT = {
    "outputs._direction": "the directions of vectors (arctan2)",
    "outputs._rotating_direction": "the directions of vectors turning with a link (mod 360)",
    "outputs._magnitude": "the magnitudes (hypot)",
    "outputs._rotating_magnitude": "the magnitudes of turning vectors",
    "analysis._analyze_into": "the blocks: seeding each and copying it into the caller's arrays",
    "registry.run": "running the plan of steps",
    "positions._loop_closure": "the loop closure",
    "positions._angle_deg": "the link angles (arctan2)",
    "positions._crank_angle": "the crank angle (mod 360, cos, sin)",
    "positions._transmission_angle": "the transmission angle",
    "accelerations._pivot_acc": "the pivots' accelerations",
    "velocities._pivot_vel": "the pivots' velocities",
    "forces._force_link4": "the pin forces of link 4",
    "forces._force_link3": "the pin forces of link 3",
}


def gfortran_startup(exe, deck_text: str, runs: int) -> float:
    """The reference's CPU time on a deck of one position [s], median of ``runs``: what
    its start-up and card reading cost, measured beside the rest."""
    import resource

    def _cpu() -> float:  # the children's alone: not this process's spawning of them
        kids = resource.getrusage(resource.RUSAGE_CHILDREN)
        return kids.ru_utime + kids.ru_stime

    one = "\n".join(deck_text.splitlines()[:6] + ["     0.0     1.0     0.0"]) + "\n"
    times = []
    with tempfile.TemporaryDirectory(prefix="sielaff-bench-one-") as work:
        Path(work, "fort.1").write_text(one)
        for _ in range(runs):
            before = _cpu()
            subprocess.run([str(exe)], cwd=work, capture_output=True, stdin=subprocess.DEVNULL,
                           check=True)
            times.append(_cpu() - before)
    return statistics.median(times)


def profile_paragraph(fn, n: int, top: int = 8) -> str:
    """Where the time of ``fn`` goes, measured now: cProfile, each function's own time
    (a numpy ufunc is not profiled on its own: its time counts in the engine function
    that calls it), the ``top`` largest shares and the rest."""
    import cProfile
    import pstats

    fn()  # warm
    prof = cProfile.Profile()
    prof.enable()
    fn()
    prof.disable()
    stats = pstats.Stats(prof).stats  # type: ignore[attr-defined]
    own: dict[str, float] = {}
    for (path, _, func), (_, _, tottime, _, _) in stats.items():
        name = (f"{Path(path).stem}.{func}" if "sielaff" in path
                else "numpy and Python outside the engine")
        own[name] = own.get(name, 0.0) + tottime
    total = sum(own.values())
    ranked = sorted(own.items(), key=lambda kv: -kv[1])
    parts = [f"{WHAT.get(k, '`' + k + '`')} {v / total:.0%}" for k, v in ranked[:top]]
    rest = sum(v for _, v in ranked[top:]) / total
    return ("What bounds the engine (cProfile of `analyze(..., out=...)`, all results, "
            f"{n:,} positions, {total:.2f} s under the profiler; each function's own time, "
            "a numpy call counted in the function that makes it): " + ", ".join(parts)
            + f", the rest {rest:.0%}.")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=5, help="rounds of each configuration")
    ap.add_argument("--no-write", action="store_true", help="do not touch docs/performance.md")
    ap.add_argument("--section", choices=("all", "numpy", "compiled"), default="all",
                    help="which sections to measure and write (default: all)")
    args = ap.parse_args(argv)

    fortran = load_harness()
    example = (ROOT / "decks" / "example.dat").read_text().splitlines()
    deck_text = "\n".join(example[:6] + [fortran.format_card(THZERO, DELTA, THMAX)]) + "\n"
    m = parse_deck(deck_text, "<benchmark>").mechanism
    n = int(np.floor((THMAX - THZERO) / DELTA)) + 2  # the 1966 loop: one past THMAX
    ath2 = (THZERO - DELTA) + np.arange(1, n + 1, dtype=np.float64) * DELTA  # TH + ZZZ*DELTA
    if not shutil.which("gfortran"):
        print("gfortran is not installed: cannot time the compiled program", file=sys.stderr)
        return 1
    with tempfile.TemporaryDirectory(prefix="sielaff-src-") as src:
        source = Path(src, "sielaff_silent.f")
        source.write_text(silent_source(fortran.DECK_SOURCE.read_text()))
        exe = fortran.build(opt="-O2", source=source)
    work = tempfile.mkdtemp(prefix="sielaff-bench-")
    atexit.register(shutil.rmtree, work, True)  # the deck and gfortran's units: nothing left
    Path(work, "fort.1").write_text(deck_text)
    answer = {}

    def gfortran():
        proc = subprocess.run([str(exe)], cwd=work, capture_output=True, text=True,
                              stdin=subprocess.DEVNULL, check=True)
        answer["stdout"] = proc.stdout

    if args.section in ("all", "compiled"):
        status = compiled_section(args, m, ath2, gfortran)
        if status or args.section == "compiled":
            return status
    outs = {name: np.empty(n) for name in engine.RESULTS}
    scene = dict(th2dd=-40.0, gravity="down",
                 loads=[engine.Load(3, r=8.0, angle=10.0, fx=80.0), engine.Load(4, torque=15.0)])
    more = {name: np.empty(n) for name in ("TORQ_INERTIA", "TORQ_GRAVITY", "TORQ_LOADS")}
    configs = [
        (f"engine, all {len(engine.RESULTS)} results, fresh arrays",
         lambda: engine.analyze(m, ath2)),
        ("engine, all results into reused arrays (`out=`)",
         lambda: engine.analyze(m, ath2, out=outs)),
        (f"engine, kinematics only ({len(engine.KINEMATIC_OUTPUTS)} arrays), `out=`",
         lambda: engine.analyze(m, ath2, out={k: outs[k] for k in engine.KINEMATIC_OUTPUTS})),
        ("engine, ATH3 ATH4 TH3D TH4D, `out=`",
         lambda: engine.analyze(m, ath2, out={k: outs[k] for k in POSITIONS_AND_RATES})),
        ("engine, all results, crossed branch, `out=`",
         lambda: engine.analyze(m, ath2, out=outs, branch="crossed")),
        ("engine, all results + TORQ parts, crank acceleration, gravity, two loads, `out=`",
         lambda: engine.analyze(m, ath2, out={**outs, **more}, **scene)),
    ]
    engine.analyze(m, ath2[:1000])  # warm-up
    series = []
    for name, fn in configs:
        print(f"  {name} ...", file=sys.stderr)
        series.append(rounds(name, fn, gfortran, args.rounds))
    chk, npos = answer["stdout"].split()
    chk = float(chk.replace("D", "E"))
    assert int(npos) == n
    eng_chk = engine_checksum(engine.analyze(m, ath2))
    rel = abs(eng_chk - chk) / abs(chk)
    if rel > 1e-5:
        print(f"checksums disagree: gfortran {chk}, engine {eng_chk}", file=sys.stderr)
        return 1
    med = [statistics.median(x.ratio("cpu")) for x in series]
    startup_ms = 1000.0 * gfortran_startup(exe, deck_text, args.rounds)
    lines = [
        HEADING, "",
        f"Measured by `python benchmarks/engine.py` on {machine()}.", "",
        f"The report's example at {n:,} crank angles (range card {THZERO!r}, {DELTA!r}, "
        f"{THMAX!r}), one process, one core.  The reference is `decks/sielaff.f` built by "
        "`tests/fortran.py` with `-O2` (REAL*8) from a copy whose in-loop WRITEs are "
        "replaced by a checksum of every printed value: it computes everything and formats "
        f"nothing (a whole process: on a deck of one position it takes {startup_ms:.1f} ms of "
        f"CPU, median of {args.rounds} runs).  It runs beside each "
        f"configuration in each of {args.rounds} rounds; median (range).", "",
        *table(series), "",
        f"* All results into reused arrays: **{med[1]:.2f}x gfortran** in CPU time (goal "
        f">= 1.5x: {'met' if med[1] >= 1.5 else 'not met'}); with fresh arrays "
        f"{med[0]:.2f}x (goal >= 1x: {'met' if med[0] >= 1 else 'not met'}).",
        f"* Kinematics only: {med[2] / med[1]:.2f}x the full analysis (goal >= 1.4x: "
        f"{'met' if med[2] / med[1] >= 1.4 else 'not met'}); positions and rates "
        f"{med[3]:.1f}x gfortran (goal >= 5x: {'met' if med[3] >= 5 else 'not met'}).",
        f"* Throughput against the open branch (all results, `out=`): the crossed branch "
        f"{med[4] / med[1]:.2f}x; crank acceleration, gravity and two loads together "
        f"{med[5] / med[1]:.2f}x (with three more outputs).",
        f"* Check: the sum of every printed value over the {n:,} positions, gfortran "
        f"{chk:.10e}, engine {eng_chk:.10e} (relative difference {rel:.1e}).", "",
        profile_paragraph(lambda: engine.analyze(m, ath2, out=outs), n), "",
    ]
    publish(DOC, HEADING, "\n".join(lines), not args.no_write)
    return 0


COMPILED_HEADING = "## Compiled backend"


def compiled_section(args, m, ath2, gfortran) -> int:
    """The compiled backend (``analyze(..., backend="numba")``) beside gfortran: its
    section of docs/performance.md."""
    from sielaff.engine import compiled
    from sielaff.engine.analysis import prepare
    from sielaff.engine.scene import Scene

    if not compiled.available():
        print("numba is not installed: no compiled section", file=sys.stderr)
        return 1
    n = ath2.size
    results, kin = engine.RESULTS, engine.KINEMATIC_OUTPUTS
    parts = ("TORQ_INERTIA", "TORQ_GRAVITY", "TORQ_LOADS", "TORQ_ELEMENTS")
    outs = {name: np.empty(n) for name in results + parts}
    effects = Scene(th2dd=-40.0, gravity="down",
                    loads=[engine.Load(3, r=8.0, angle=10.0, fx=80.0),
                           engine.Load(4, torque=15.0)],
                    elements=[engine.Spring((1, 6.0, 90.0), (4, 8.0, 0.0), 30.0, 5.0),
                              engine.Damper((2, 2.0, 0.0), (4, 6.0, 10.0), 0.5)])

    def numba(wanted, out=True, scene=None):
        if out:
            o = {k: outs[k] for k in wanted}
            return lambda: engine.analyze(m, ath2, out=o, scene=scene, backend="numba")
        return lambda: engine.analyze(m, ath2, list(wanted), scene=scene, backend="numba")

    two = prepare(m, ath2, list(results), Scene())
    from sielaff.engine import kernel as K

    def chunked(fn):
        """fn with the streamed kernel off (compiled.STREAMED): the chunked kernel, whose
        copy of each chunk streams, or for few outputs the loop with plain stores."""
        def run():
            compiled.STREAMED = False
            try:
                fn()
            finally:
                compiled.STREAMED = True
        return run

    def unkept(fn):
        """fn with no block of dropped results kept (compiled.KEEP_BYTES = 0): each fresh
        block new from the operating system."""
        def run():
            saved, compiled.KEEP_BYTES = compiled.KEEP_BYTES, 0
            compiled.release()
            try:
                fn()
            finally:
                compiled.KEEP_BYTES = saved
        return run

    def uncrowded(fn):
        """fn with the streamed kernel taken however crowded the outputs' offsets."""
        def run():
            saved, compiled.CROWD = compiled.CROWD, 1 << 30
            try:
                fn()
            finally:
                compiled.CROWD = saved
        return run

    spread = dict(zip(results, compiled._fresh(len(results), n)))

    def fresh_arrays(k):
        """What k fresh results cost without a kernel: the block the backend makes for them
        (compiled._fresh: one block aligned to a huge page), new, each row written once."""
        def make():
            for a in compiled._fresh(k, n):
                a.fill(0.0)
        return unkept(make)

    def streamed_fill(k):
        """The kernel's copy-out with no arithmetic: k reused arrays written from a staged
        chunk of zeros by the kernel's own non-temporal stores (kernel_math._streaming)."""
        import numba

        from sielaff.engine.kernel_math import _streaming

        copy_out, fence = _streaming()

        @numba.njit(nogil=True)
        def fill(arrays, n):
            buf = np.zeros((len(arrays), K.CHUNK))
            for c in range(0, n, K.CHUNK):
                m = min(K.CHUNK, n - c)
                for j in range(len(arrays)):
                    copy_out(arrays[j], buf[j], c, m, True)
            fence()

        arrays = tuple(outs[name] for name in results[:k])
        return lambda: fill(arrays, n)

    configs = [
        (f"`backend='numba'`, all {len(results)} results into reused arrays (`out=`)",
         numba(results)),
        (f"`backend='numba'`, all {len(results)} results, fresh arrays", numba(results, False)),
        (f"`backend='numba'`, kinematics ({len(kin)} results), fresh arrays",
         numba(kin, False)),
        (f"`backend='numba'`, kinematics ({len(kin)} results), `out=`", numba(kin)),
        ("`backend='numba'`, all results + TORQ parts, crank acceleration, gravity, two "
         "loads, a spring and a damper, `out=`", numba(results + parts, scene=effects)),
        ("the same, fresh arrays", numba(results + parts, False, scene=effects)),
        (f"`backend='numba'`, all {len(results)} results, `out=`, two threads",
         lambda: compiled.run(two, {k: outs[k] for k in results}, threads=2)),
        (f"no kernel: numpy fills the {len(results)} reused arrays (the memory traffic "
         "alone)", lambda: [outs[k].fill(0.0) for k in results]),
        (f"no kernel: the block of {len(results)} fresh results made and written once "
         "(the allocation)", fresh_arrays(len(results))),
        (f"the numpy engine, all {len(results)} results, fresh arrays",
         lambda: engine.analyze(m, ath2)),
        ("the numpy engine, all results, `out=`",
         lambda: engine.analyze(m, ath2, out={k: outs[k] for k in results})),
        ("the numpy engine, the same effects, `out=`",
         lambda: engine.analyze(m, ath2, out={k: outs[k] for k in results + parts},
                                scene=effects)),
        (f"no kernel: the block of {len(kin)} fresh results made and written once",
         fresh_arrays(len(kin))),
        (f"`backend='numba'`, all {len(results)} results into reused arrays, the chunked "
         "kernel (compiled.STREAMED off: staged, each chunk's copy streamed)",
         chunked(numba(results))),
        ("the same, fresh arrays", chunked(numba(results, False))),
        (f"`backend='numba'`, kinematics ({len(kin)} results), fresh arrays, plain stores "
         "(compiled.STREAMED off)", chunked(numba(kin, False))),
        (f"`backend='numba'`, all {len(results)} results, fresh arrays, each block new "
         "(compiled.KEEP_BYTES = 0: none kept of the dropped results)",
         unkept(numba(results, False))),
        (f"`backend='numba'`, kinematics ({len(kin)} results), fresh arrays, each block new",
         unkept(numba(kin, False))),
        (f"`backend='numba'`, all {len(results)} results into reused arrays, streamed "
         "whatever their offsets from a 4 KiB page (compiled.CROWD without limit)",
         uncrowded(numba(results))),
        (f"`backend='numba'`, all {len(results)} results into reused arrays on spread "
         "offsets from a 4 KiB page (the rows of one block, as fresh results are), `out=`",
         lambda: engine.analyze(m, ath2, out=spread, backend="numba")),
    ]
    # friction, springs and dampers on: compiled, or refused (then only said)
    rubbing = Scene(friction=engine.PinFriction(0.1, 0.2), elements=effects.elements)
    rubbing_out = results + ("TORQ_FRICTION", "TORQ_ELEMENTS")
    outs.update({k: np.empty(n) for k in rubbing_out if k not in outs})
    try:
        engine.analyze(m, ath2[:10], ["TORQ"], backend="numba", scene=rubbing)
        friction = "compiled"
        configs += [
            ("`backend='numba'`, all results + TORQ_FRICTION and TORQ_ELEMENTS, pin friction "
             "at the four pins, a spring and a damper, `out=`",
             numba(rubbing_out, scene=rubbing)),
            ("the numpy engine, the same friction scene, `out=`",
             lambda: engine.analyze(m, ath2, out={k: outs[k] for k in rubbing_out},
                                    scene=rubbing))]
    except ValueError as e:
        friction = f"refused: \"{e}\""
    floor = (f"no kernel: the {len(results)} reused arrays written by the kernel's streaming "
             "copy (non-temporal stores) from a staged chunk of zeros (the memory traffic "
             "alone, streamed)")
    configs.append((floor, streamed_fill(len(results))))
    first, again = touch_memory(TOUCH_GIB)
    for _, fn in configs:  # compile (or load the kernel cache) outside the timing
        fn()
    series, loads = [], []
    for name, fn in configs:
        print(f"  {name} ...", file=sys.stderr)
        before = os.getloadavg()[0]
        series.append(rounds(name, fn, gfortran, args.rounds))
        loads += [before, os.getloadavg()[0]]
    # the error against the numpy engine over this run, relative to each output's scale
    got = engine.analyze(m, ath2, backend="numba")
    ref = engine.analyze(m, ath2)
    worst = 0.0
    for name in results:
        a, b = got[name], ref[name]
        ok = np.isfinite(b)
        d = np.abs(a[ok] - b[ok])
        if (name[:1] == "D" and name[1:] in engine.VECTORS) or name in ("ATH2", "ATH3", "ATH4"):
            d = np.abs((a[ok] - b[ok] + 180.0) % 360.0 - 180.0)
        worst = max(worst, float(np.max(d)) / max(float(np.max(np.abs(b[ok]))), 1e-300))
    same_nan = all(np.array_equal(np.isnan(got[k]), np.isnan(ref[k])) for k in results)
    passes = float(np.mean(engine.analyze(m, ath2, ["FRICTION_ITERATIONS"], scene=rubbing)[
        "FRICTION_ITERATIONS"])) if friction == "compiled" else 0.0
    med = [statistics.median(x.ratio("cpu")) for x in series]
    wall = [statistics.median(x.ratio("wall")) for x in series]
    cpu = [statistics.median(x.cpu) for x in series]
    from collections import Counter

    crowd = Counter(outs[k].ctypes.data % 4096 for k in results).most_common(1)[0][1]
    if compiled.stream_start([outs[k] for k in results], [ath2]) is not None:
        kernel_used = "the streamed kernel ran"
    else:
        kernel_used = (f"the chunked kernel ran (more than compiled.CROWD = {compiled.CROWD} "
                       "on one offset and vector stores narrower than a cache line, "
                       "kernel_math.line_stores); streamed anyway "
                       f"{cpu[18]:.3f} s ({med[18]:.2f}x); the same kernel into the rows of "
                       f"one block, on spread offsets, {cpu[19]:.3f} s ({med[19]:.2f}x)")
    import numba as nb

    from sielaff.engine.kernel_math import line_stores

    def llvm_cpu() -> str:
        import llvmlite.binding as llvm

        return nb.config.CPU_NAME or llvm.get_host_cpu_name()

    def goal(x: float, g: float) -> str:
        return f"goal >= {g:g}x: {'met' if x >= g else 'not met'}"

    lines = [
        COMPILED_HEADING, "",
        f"Measured by `python benchmarks/engine.py --section compiled` on {machine()}; "
        f"numba {nb.__version__}, compiling for LLVM's CPU {llvm_cpu()} (vector stores of "
        f"a whole cache line: {'yes' if line_stores() else 'no'}).", "",
        f"`analyze(..., backend='numba')` on the report's example at {n:,} crank angles "
        "(the deck of the Engine section): the kernel generated from the four-bar model's "
        "own plan (engine/kernel.py).  The same gfortran -O2 reference runs beside each "
        f"configuration in each of {args.rounds} rounds; median (range).  The ratio is "
        "taken in CPU time; wall time beside it.  Every kernel is compiled (or loaded from "
        "the kernel cache) before the timing.  Load average (1 min) over the section: "
        f"{min(loads):.1f} to {max(loads):.1f} on this machine's {os.cpu_count()} cores.  "
        f"Before the rounds the script wrote {TOUCH_GIB:g} GiB of new arrays twice, freeing "
        f"them between: {first:.2f} s of CPU the first time, {again:.2f} s the second (a "
        "virtual machine's first write of memory its guest has not used yet; without this, "
        "a round that allocates can pay it).", "",
        *table(series), "",
        f"* All results into reused arrays: **{med[0]:.2f}x gfortran** in CPU time "
        f"({goal(med[0], 6)}); fresh arrays **{med[1]:.2f}x** ({goal(med[1], 3.5)}).  "
        f"The reused arrays are separate np.empty arrays, {crowd} of them on one offset "
        f"from a 4 KiB page: {kernel_used}.  "
        f"The fresh call's CPU time less `out=`'s: {cpu[1] - cpu[0]:+.3f} s; its block "
        "is one the caller's dropped results left (compiled.KEEP_BYTES; each round drops "
        "its results, as a loop over calls does).  With each block new from the operating "
        f"system (KEEP_BYTES = 0, as any first call) {med[16]:.2f}x ({cpu[16]:.3f} s); "
        f"making that block of {len(results)} fresh results and writing it once costs "
        f"{cpu[8]:.3f} s here (the first writes fault the block's pages in, which Linux "
        "zeroes).",
        f"* Kinematics, fresh arrays: **{med[2]:.2f}x gfortran** ({goal(med[2], 8)}); "
        f"`out=` {med[3]:.2f}x; each block new {med[17]:.2f}x ({cpu[17]:.3f} s), the "
        f"block of {len(kin)} fresh results alone, made new and written once, "
        f"{cpu[12]:.3f} s.",
        f"* Crank acceleration, gravity, two loads, a spring and a damper: **{med[4]:.2f}x "
        f"gfortran** with `out=` ({goal(med[4], 3)}), {med[5]:.2f}x with fresh arrays; "
        f"the numpy engine on the same scene {med[11]:.2f}x.",
        (f"* Pin friction at the four pins (mu r = 0.02 in), a spring and a damper, `out=`: "
         f"**{med[20]:.2f}x gfortran** ({goal(med[20], 3)}); the numpy engine on the same "
         f"scene {med[21]:.2f}x.  The fixed point takes {passes:.2f} iterations a position "
         "on average (FRICTION_ITERATIONS), run in the kernel as passes over each chunk "
         "(engine/iterate.py)." if friction == "compiled" else
         f"* Pin friction: {friction} (goal: compiled, >= 3x: not met)."),
        f"* The floor: numpy's fill of the {len(results)} reused arrays alone (plain "
        f"stores) is {med[7]:.2f}x gfortran ({cpu[7]:.3f} s against the kernel's "
        f"{cpu[0]:.3f} s); the kernel's streaming copy with no arithmetic "
        f"{med[-1]:.2f}x ({cpu[-1]:.3f} s).",
        f"* From {K.STREAM_FROM:,} values (engine/kernel.py's STREAM_FROM) the loop stores "
        "each output by a non-temporal store of whole vectors on 64-byte boundaries (the "
        "streamed kernel, engine/compiled.py's runs): all results into reused arrays "
        f"{cpu[18]:.3f} s (on one offset from a 4 KiB page; on spread offsets "
        f"{cpu[19]:.3f} s), fresh {cpu[1]:.3f} s, kinematics fresh {cpu[2]:.3f} s; the chunked "
        f"kernel instead (its outputs staged in chunks of {K.CHUNK} positions, each "
        f"chunk's copy streamed; kinematics by plain stores): {cpu[13]:.3f} s, "
        f"{cpu[14]:.3f} s and {cpu[15]:.3f} s.",
        f"* Two threads (the kernel releases the GIL): {wall[6]:.2f}x gfortran in wall time "
        f"against {wall[0]:.2f}x on one thread ({med[6]:.2f}x in CPU time, the threads' "
        "CPU added).",
        f"* The numpy engine: fresh arrays {med[9]:.2f}x gfortran ({goal(med[9], 1)}), "
        f"`out=` {med[10]:.2f}x ({goal(med[10], 1.5)}).",
        f"* Against the numpy engine over these {n:,} positions: the largest difference, "
        f"relative to each output's largest magnitude, {worst:.1e} (each engine is within "
        "engine/accuracy.py's bound of the exact answer, tested against 40 digits in "
        f"tests/test_error_bound.py); NaN in the same places: {same_nan}.", "",
    ]
    publish(DOC, COMPILED_HEADING, "\n".join(lines), not args.no_write)
    return 0


if __name__ == "__main__":
    sys.exit(main())
