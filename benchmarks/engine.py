"""Throughput of the modern engine, side by side with the 1966 program compiled by gfortran.

Run from the repository root::

    python benchmarks/engine.py              # 10^6 positions; writes docs/performance.md
    python benchmarks/engine.py --no-write   # print only

What is timed (median of several repeats, one process, one core):

* **gfortran -O2**: ``decks/sielaff.f`` built by the test harness
  (``tests/fortran.py``, REAL*8) from a generated copy whose WRITE statements
  inside the loop are replaced by a running checksum of every value the sheet
  would print (and a sheet counter), printed once at the end: the program
  computes everything it prints, but does no formatted output.  The deck is
  the report's example with one range card (0, 0.00036, 359.9996): 10^6
  positions.  Wall time of the whole process (start-up and card reading are
  well under a millisecond).
* **engine, all results**: ``analyze(mechanism, ath2)`` (``RESULTS``, 71
  arrays) at the same 10^6 crank angles, computed as the program computes
  them (TH + I*DELTA).
* **engine, kinematics only**: ``outputs=KINEMATIC_OUTPUTS`` (48 arrays,
  what ``sielaff table --only kinematics`` asks for).
* **engine, positions and rates**: ``outputs=["ATH3", "ATH4", "TH3D", "TH4D"]``.
* **the port** (``Program(Float64()).MAIN``, no printing), for scale, on fewer
  positions.

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
import os
import platform
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "src"))

from sielaff import engine  # noqa: E402
from sielaff.emulator.cards import Deck, Range, parse_deck  # noqa: E402
from sielaff.emulator.program import SHEET_FIELDS, Program  # noqa: E402

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


def median_time(fn, repeats: int) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), result


def machine() -> dict[str, str]:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            names = [x.split(":", 1)[1].strip() for x in f if x.startswith("model name")]
        if names:
            cpu = names[0]
    except OSError:
        pass
    try:
        gfortran = subprocess.run(["gfortran", "--version"], capture_output=True, text=True,
                                  check=True).stdout.splitlines()[0]
    except (OSError, subprocess.CalledProcessError, IndexError):
        gfortran = "not installed"
    affinity = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None
    return {
        "CPU": cpu,
        "cores": f"{os.cpu_count()} logical" + (f" ({affinity} usable)" if affinity else ""),
        "OS": f"{platform.system()} {platform.release()}",
        "Python": platform.python_version(),
        "numpy": np.__version__,
        "gfortran": gfortran,
    }


def run_gfortran(exe: Path, deck_text: str, repeats: int) -> tuple[float, float, int]:
    with tempfile.TemporaryDirectory(prefix="sielaff-bench-") as work:
        Path(work, "fort.1").write_text(deck_text)

        def once():
            proc = subprocess.run([str(exe)], cwd=work, capture_output=True, text=True,
                                  stdin=subprocess.DEVNULL, check=True)
            return proc.stdout

        seconds, stdout = median_time(once, repeats)
    chk, npos = stdout.split()
    return seconds, float(chk.replace("D", "E")), int(npos)


def engine_checksum(result: dict[str, np.ndarray]) -> float:
    """The engine's sum of what the program prints (its CHK), in the same quantities."""
    return float(sum(np.sum(result[name], dtype=np.float64)
                     for group in SHEET_FIELDS for name in group))


def section(rows, info, n, checks) -> str:
    fortran_rate = rows[0][3]
    full_rate = rows[1][3]
    lines = [
        HEADING,
        "",
        "Written by `python benchmarks/engine.py` "
        f"({time.strftime('%Y-%m-%d')}); median of repeated runs in one process, "
        "one core.",
        "",
        "Machine: " + "; ".join(f"{k} {v}" for k, v in info.items()) + ".",
        "",
        f"The report's example mechanism at {n:,} crank angles "
        f"(range card {THZERO!r}, {DELTA!r}, {THMAX!r}).  The compiled program is "
        "`decks/sielaff.f` built by `tests/fortran.py` with `-O2` (REAL*8) from a copy "
        "whose in-loop WRITEs are replaced by a checksum of every printed value, so it "
        "computes everything and formats nothing.",
        "",
        "| run | positions | median time (s) | positions/s | ratio |",
        "|---|---:|---:|---:|---|",
    ]
    for label, count, seconds, rate, ratio in rows:
        lines.append(f"| {label} | {count:,} | {seconds:.3f} | {rate:,.0f} | {ratio} |")
    ok_a = full_rate >= fortran_rate
    ok_b = rows[2][3] >= 2.0 * full_rate
    lines += [
        "",
        f"* Engine (all results) against gfortran: {full_rate / fortran_rate:.2f}x "
        f"the compiled program's throughput; goal >= 1x: **{'met' if ok_a else 'not met'}**.",
        f"* Kinematics only against the full engine: {rows[2][3] / full_rate:.2f}x; "
        f"goal >= 2x: **{'met' if ok_b else 'not met'}**.",
        "",
    ]
    if not ok_b:
        lines += [
            "  The force analysis is cheap arithmetic on arrays the kinematics already",
            "  made; the transcendental work is kinematic (cos and sin of the crank",
            "  angle, atan2 for ATH3, ATH4, GAMMA and for 10 of the 15 printed",
            "  directions; square roots for 10 of the 15 magnitudes).  So skipping the",
            "  forces saves only their share of the time.  Asking for less does pay:",
            "  positions and rates alone (the acceptance test's four outputs) run",
            f"  {rows[3][3] / full_rate:.1f}x faster than the full analysis.",
            "",
        ]
    lines += [f"* Check: {checks}", ""]
    return "\n".join(lines)


def write_doc(text: str) -> None:
    """Replace (or add) the '## Engine' section of docs/performance.md."""
    if DOC.exists():
        old = DOC.read_text()
        m = re.search(rf"^{re.escape(HEADING)}\s*$", old, re.M)
        if m:
            nxt = re.search(r"^## ", old[m.end():], re.M)
            end = m.end() + nxt.start() if nxt else len(old)
            new = old[:m.start()] + text + ("\n" if nxt else "") + old[end:]
        else:
            new = old.rstrip("\n") + "\n\n" + text
    else:
        new = "# Performance\n\n" + text
    tmp = DOC.with_name(f".{DOC.name}.tmp")
    tmp.write_text(new)
    os.replace(tmp, DOC)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=7, help="timed runs of each (median)")
    ap.add_argument("--port-positions", type=int, default=20_000)
    ap.add_argument("--no-write", action="store_true", help="do not touch docs/performance.md")
    args = ap.parse_args(argv)

    fortran = load_harness()
    example = (ROOT / "decks" / "example.dat").read_text().splitlines()
    deck_text = "\n".join(example[:6] + [fortran.format_card(THZERO, DELTA, THMAX)]) + "\n"
    deck = parse_deck(deck_text, "<benchmark>")
    m = deck.mechanism
    n = int(np.floor((THMAX - THZERO) / DELTA)) + 2  # the 1966 loop: one past THMAX
    ath2 = (THZERO - DELTA) + np.arange(1, n + 1, dtype=np.float64) * DELTA  # TH + ZZZ*DELTA
    assert ath2[-2] <= THMAX < ath2[-1]

    rows = []
    info = machine()
    if not shutil.which("gfortran"):
        print("gfortran is not installed: cannot time the compiled program", file=sys.stderr)
        return 1
    with tempfile.TemporaryDirectory(prefix="sielaff-src-") as src:
        source = Path(src, "sielaff_silent.f")
        source.write_text(silent_source(fortran.DECK_SOURCE.read_text()))
        exe = fortran.build(opt="-O2", source=source)
    print(f"gfortran -O2 ({exe}) ...", file=sys.stderr)
    t_f, chk, npos = run_gfortran(exe, deck_text, max(3, args.repeats // 2 + 1))
    assert npos == n, (npos, n)
    rows.append(["gfortran -O2, output suppressed", n, t_f, n / t_f, "1.00 (reference)"])

    print("engine ...", file=sys.stderr)
    engine.analyze(m, ath2[:1000])  # warm-up (plans are cached)
    t_full, full = median_time(lambda: engine.analyze(m, ath2), args.repeats)
    eng_chk = engine_checksum(full)
    del full
    r0 = resource.getrusage(resource.RUSAGE_SELF)
    engine.analyze(m, ath2)
    r1 = resource.getrusage(resource.RUSAGE_SELF)
    cpu = (r1.ru_utime - r0.ru_utime, r1.ru_stime - r0.ru_stime)
    t_kin, _ = median_time(lambda: engine.analyze(m, ath2, engine.KINEMATIC_OUTPUTS),
                           args.repeats)
    t_pr, _ = median_time(lambda: engine.analyze(m, ath2, POSITIONS_AND_RATES), args.repeats)
    rows.append([f"engine, all results ({len(engine.RESULTS)} arrays)", n, t_full, n / t_full,
                 f"{t_f / t_full:.2f}x gfortran"])
    rows.append([f"engine, kinematics only ({len(engine.KINEMATIC_OUTPUTS)} arrays)", n, t_kin,
                 n / t_kin, f"{t_full / t_kin:.2f}x full engine"])
    rows.append(["engine, ATH3 ATH4 TH3D TH4D", n, t_pr, n / t_pr,
                 f"{t_full / t_pr:.2f}x full engine"])

    print("port ...", file=sys.stderr)
    k = args.port_positions
    port_deck = Deck(mechanism=m, ranges=[Range(THZERO, DELTA, THZERO + (k - 2) * DELTA)],
                     range_cards=[7], path="<benchmark>")
    from sielaff.emulator.arithmetic import Float64

    t_port, sheets = median_time(lambda: Program(Float64()).MAIN(port_deck, lambda *a: None),
                                 3)
    rows.append(["the port (Python, float64), no printing", sheets, t_port, sheets / t_port,
                 f"{(sheets / t_port) / (n / t_f):.3f}x gfortran"])

    rel = abs(eng_chk - chk) / abs(chk)
    checks = (f"sum of all printed values over the {n:,} sheets: gfortran {chk:.10e}, "
              f"engine {eng_chk:.10e} (relative difference {rel:.1e}).")
    if rel > 1e-5:
        print(f"checksums disagree: {checks}", file=sys.stderr)
        return 1
    checks += (f"\n* One full engine run: {cpu[0]:.2f} s user, {cpu[1]:.2f} s system; the "
               "system time is the kernel handing out fresh pages for the result arrays "
               f"({len(engine.RESULTS)} x {n * 8 / 1e6:.0f} MB).")
    text = section(rows, info, n, checks)
    print(text)
    if not args.no_write:
        write_doc(text)
        print(f"wrote the '{HEADING}' section of {DOC.relative_to(ROOT)}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
