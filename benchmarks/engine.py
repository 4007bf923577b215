"""Throughput of the modern engine, side by side with the 1966 program compiled by gfortran.

Run from the repository root::

    python benchmarks/engine.py              # 10^6 positions; writes docs/performance.md
    python benchmarks/engine.py --no-write   # print only

What is timed (``benchmarks/timing.py``: rounds, the reference beside each
configuration, CPU time and wall time, median and range; one process, one core):

* **gfortran -O2** (the reference): ``decks/sielaff.f`` built by the test harness
  (``tests/fortran.py``, REAL*8) from a generated copy whose WRITE statements
  inside the loop are replaced by a running checksum of every value the sheet
  would print (and a sheet counter), printed once at the end: the program
  computes everything it prints, but does no formatted output.  The deck is
  the report's example with one range card (0, 0.00036, 359.9996): 10^6
  positions.  CPU time of the child process (start-up and card reading are
  well under a millisecond).
* **the engine**: all results with fresh arrays, and into reused arrays
  (``analyze(..., out=...)``); kinematics only; positions and rates; the crossed
  branch; the effects (crank acceleration, gravity, two loads).

As a check that the compiled program and the engine computed the same
thing, the engine's sum of the printed quantities is compared with the
program's checksum.

The table goes to stdout and, under the heading ``## Engine``, into
``docs/performance.md`` (only that section is replaced; the file is created
if missing).
"""

from __future__ import annotations

import argparse
import importlib.util
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
from timing import machine, rounds, table, write_section  # noqa: E402

DOC = ROOT / "docs" / "performance.md"
HEADING = "## Engine"
THZERO, DELTA, THMAX = 0.0, 0.00036, 359.9996  # 10^6 positions, 0 .. 359.99964
POSITIONS_AND_RATES = ["ATH3", "ATH4", "TH3D", "TH4D"]


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


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=5, help="rounds of each configuration")
    ap.add_argument("--no-write", action="store_true", help="do not touch docs/performance.md")
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
    Path(work, "fort.1").write_text(deck_text)
    answer = {}

    def gfortran():
        proc = subprocess.run([str(exe)], cwd=work, capture_output=True, text=True,
                              stdin=subprocess.DEVNULL, check=True)
        answer["stdout"] = proc.stdout

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
    from sielaff.engine.compiled import available

    if available():
        engine.analyze(m, ath2[:10], backend="numba")  # compile once, outside the timing
        configs.append(("engine, all results, `backend='numba'` (optional extra)",
                        lambda: engine.analyze(m, ath2, backend="numba")))
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
    lines = [
        HEADING, "",
        f"Measured by `python benchmarks/engine.py` on {machine()}.", "",
        f"The report's example at {n:,} crank angles (range card {THZERO!r}, {DELTA!r}, "
        f"{THMAX!r}), one process, one core.  The reference is `decks/sielaff.f` built by "
        "`tests/fortran.py` with `-O2` (REAL*8) from a copy whose in-loop WRITEs are "
        "replaced by a checksum of every printed value: it computes everything and formats "
        "nothing (a whole process, under a millisecond of start-up).  It runs beside each "
        f"configuration in each of {args.rounds} rounds; median (range).", "",
        *table(series), "",
        f"* All results into reused arrays: **{med[1]:.2f}x gfortran** in CPU time (goal "
        f">= 1.5x: {'met' if med[1] >= 1.5 else 'not met'}); with fresh arrays "
        f"{med[0]:.2f}x, the difference being the kernel's fresh pages and the caches.",
        f"* Kinematics only: {med[2] / med[1]:.2f}x the full analysis (goal >= 1.4x: "
        f"{'met' if med[2] / med[1] >= 1.4 else 'not met'}); positions and rates "
        f"{med[3]:.1f}x gfortran (goal >= 5x: {'met' if med[3] >= 5 else 'not met'}).",
        f"* Throughput against the open branch (all results, `out=`): the crossed branch "
        f"{med[4] / med[1]:.2f}x; crank acceleration, gravity and two loads together "
        f"{med[5] / med[1]:.2f}x (with three more outputs).",
        *([f"* The compiled loop (numba, one core): {med[6]:.2f}x gfortran (goal >= 3x: "
           f"{'met' if med[6] >= 3 else 'not met'}); it calls libm's atan2 and sqrt per "
           "position (18 and 16 times), which LLVM does not vectorise: a branch-free "
           "polynomial atan2 is what a prototype needed for 2.6x."] if len(med) > 6 else
          ["* The compiled loop: numba is not installed here."]),
        f"* Check: the sum of every printed value over the {n:,} positions, gfortran "
        f"{chk:.10e}, engine {eng_chk:.10e} (relative difference {rel:.1e}).", "",
        "What bounds the engine (cProfile of `analyze(..., out=...)`, all results, 10^6 "
        "positions, 0.38 s under the profiler): the 15 directions (atan2) 15%, the 15 "
        "magnitudes (sqrt) 9%, copying each block into the caller's arrays 17%, the fixed "
        "cost of 62 blocks (plan, checks, seeding) about 10%, positions (cos, sin, the loop "
        "closure, ATH3 and ATH4 by atan2) 13%, the rest the arithmetic of rates, "
        "accelerations and forces.  The velocities of VA, VG2, VB and VG4 now take no sqrt or "
        "atan2 (r |w|, the line's angle +- 90 degrees); the rest of the algebraic minimum "
        "(AA, AG2, AB, AG4 and three more directions from ATH2 or ATH4) and steps that write "
        "into the caller's arrays directly (no copy) are not done.  The machine is shared: "
        "the same work measured 1.24x to 1.43x on one afternoon.", "",
    ]
    text = "\n".join(lines)
    print(text)
    if not args.no_write:
        write_section(DOC, HEADING, text)
        print(f"wrote the '{HEADING}' section of {DOC.relative_to(ROOT)}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
