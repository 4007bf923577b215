"""Listing throughput: ``sielaff run`` next to the 1966 program compiled with gfortran -O2.

Both print the same sheets for the same deck (the report's mechanism,
THETA 2 from 0.01 to 360 degrees in steps of 0.01: 36,001 sheets with the
one past THMAX) to /dev/null: the emulator through ``sielaff run`` in a
subprocess, the compiled deck (``decks/sielaff.f``, built by
``tests/fortran.py`` with ``-std=legacy -fdefault-real-8 -fdefault-double-8
-O2``) with its unit 3 (``fort.3``) linked to /dev/null.  The two are run
alternately, ``--repeat`` times each, and the best wall time of each is
reported, so that both see the same machine load.

It also measures the peak resident memory (``wait4`` rusage) of
``sielaff run`` for 10**4, 10**5 and 10**6 sheets (``--max-sheets`` on a
range of 10**7), to show that memory does not grow with the run, and where
the emulator's time goes (the port's arithmetic alone, and the whole run,
in-process).

    python benchmarks/listing.py                 # print the report
    python benchmarks/listing.py --write-docs    # and update docs/performance.md

``--write-docs`` replaces only the "## Listing throughput" section of
docs/performance.md (creating the file if needed) and keeps other sections.
"""

from __future__ import annotations

import argparse
import io
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import fortran  # noqa: E402  (tests/fortran.py: the gfortran harness)

DOC = ROOT / "docs" / "performance.md"
HEADING = "## Listing throughput"
PARAMETERS = (ROOT / "decks" / "example.dat").read_text().splitlines()[:6]
RANGE = "    0.01    0.01   360.0"       # 36,001 sheets
LONG_RANGE = "  0.0001  0.0001  1000.0"   # 10**7 sheets


def write_deck(directory: Path, range_card: str) -> Path:
    path = directory / f"deck-{abs(hash(range_card))}.dat"
    path.write_text("\n".join([*PARAMETERS, range_card]) + "\n")
    return path


def time_gfortran(exe: Path, deck: Path) -> float:
    with tempfile.TemporaryDirectory(prefix="sielaff-bench-") as work:
        shutil.copyfile(deck, Path(work) / "fort.1")
        os.symlink(os.devnull, Path(work) / "fort.3")
        start = time.perf_counter()
        subprocess.run([str(exe)], cwd=work, check=True, stdin=subprocess.DEVNULL,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return time.perf_counter() - start


def time_sielaff(deck: Path) -> float:
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "sielaff", "run", str(deck)], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def peak_rss_mb(deck: Path, sheets: int) -> tuple[float, float]:
    """(peak RSS in MB, seconds) of ``sielaff run deck --max-sheets sheets`` to /dev/null."""
    start = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "sielaff", "run", str(deck),
                             "--max-sheets", str(sheets)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise RuntimeError(f"sielaff run failed ({proc.returncode})")
    return usage.ru_maxrss / 1024, time.perf_counter() - start


def in_process_split(deck_path: Path, repeat: int) -> tuple[float, float]:
    """Best CPU seconds of (the port alone with a WRITE that does nothing, the whole run)."""
    from sielaff.emulator.arithmetic import get_arithmetic
    from sielaff.emulator.cards import read_deck
    from sielaff.emulator.program import Program
    from sielaff.emulator.run import run

    deck = read_deck(deck_path)

    class Null(io.TextIOBase):
        def write(self, text: str) -> int:
            return len(text)

    def best(func) -> float:
        times = []
        for _ in range(repeat):
            start = time.process_time()
            func()
            times.append(time.process_time() - start)
        return min(times)

    port = best(lambda: Program(get_arithmetic("float64")).MAIN(deck, lambda *a: None))
    whole = best(lambda: run(deck, Null()))
    return port, whole


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def gfortran_version() -> str:
    out = subprocess.run(["gfortran", "--version"], capture_output=True, text=True).stdout
    return out.splitlines()[0] if out else "unknown"


def report(args: argparse.Namespace) -> str:
    with tempfile.TemporaryDirectory(prefix="sielaff-bench-") as tmp:
        tmpdir = Path(tmp)
        deck, long_deck = write_deck(tmpdir, RANGE), write_deck(tmpdir, LONG_RANGE)
        exe = fortran.build(opt="-O2")
        sheets = 36001
        g_times, s_times = [], []
        for _ in range(args.repeat):
            g_times.append(time_gfortran(exe, deck))
            s_times.append(time_sielaff(deck))
            print(f"  gfortran {g_times[-1]:.3f} s   sielaff {s_times[-1]:.3f} s", file=sys.stderr)
        g, s = min(g_times), min(s_times)
        port, whole = in_process_split(deck, args.repeat)
        memory = []
        for n in args.memory_sheets:
            rss, seconds = peak_rss_mb(long_deck, n)
            memory.append((n, rss, seconds))
            print(f"  {n} sheets: {rss:.1f} MB peak, {seconds:.1f} s", file=sys.stderr)

    ratio = (sheets / s) / (sheets / g)
    lines = [
        HEADING,
        "",
        "Measured by `python benchmarks/listing.py --write-docs` "
        f"on {time.strftime('%Y-%m-%d')}.",
        "",
        f"* Machine: {cpu_model()}, {os.cpu_count()} cores; "
        f"Python {platform.python_version()}; {gfortran_version()}.",
        "* Deck: the report's mechanism (`decks/example.dat`) with the range card "
        "THZERO = 0.01, DELTA = 0.01, THMAX = 360 (THETA 2 in steps of 0.01 degree), "
        f"{sheets:,} sheets (the 1966 loop prints one past THMAX), "
        f"{sheets * 59:,} records, both written to /dev/null.",
        "* gfortran: `decks/sielaff.f` built by `tests/fortran.py` with "
        "`-std=legacy -fdefault-real-8 -fdefault-double-8 -O2`, unit 3 linked to /dev/null.",
        "* sielaff: `python -m sielaff run DECK > /dev/null` (float64), start-up included.",
        f"* Best wall time of {args.repeat} runs each, run alternately in one session.",
        "",
        "| program | seconds | sheets per second |",
        "|---|---:|---:|",
        f"| gfortran -O2 | {g:.2f} | {sheets / g:,.0f} |",
        f"| sielaff run | {s:.2f} | {sheets / s:,.0f} |",
        "",
        f"**Ratio (sielaff / gfortran sheets per second): {ratio:.2f}** "
        f"(goal: at least 0.25; {'reached' if ratio >= 0.25 else 'NOT reached'}).",
        "",
        "Where the emulator's time goes (CPU seconds in-process, best of "
        f"{args.repeat}, no start-up):",
        "",
        "| part | seconds | share |",
        "|---|---:|---:|",
        f"| the port's arithmetic (`Program.MAIN`, WRITE doing nothing) | {port:.2f} | "
        f"{port / whole:.0%} |",
        f"| formatting and writing the listing | {whole - port:.2f} | "
        f"{(whole - port) / whole:.0%} |",
        f"| whole run (`emulator.run`) | {whole:.2f} | 100% |",
        "",
        "Peak resident memory of `sielaff run` (to /dev/null, `--max-sheets N` on a range "
        "of 10^7 sheets; `wait4` rusage):",
        "",
        "| sheets | peak RSS | seconds |",
        "|---:|---:|---:|",
        *[f"| {n:,} | {rss:.1f} MB | {sec:.1f} |" for n, rss, sec in memory],
        "",
        "The listing is streamed a sheet at a time, so memory does not grow with the run.",
        "",
        "Before the printer's fast path (commit 20668d5, same machine, same deck) the run "
        "took 4.7 s, 7,600 sheets per second, a ratio of about 0.3.  cProfile on 5,000 "
        "sheets put 83% of the time in the printer: `decimal_parts` (0.67 s of 2.80 s), "
        "`Format.records` (0.45 s), `edit_e` and `edit_f` (0.39 s), the WRITE wrapper "
        "with its per-value `isfinite` (0.23 s); the port itself (`MAIN`, `VECTOR`, "
        "`ARCCOS`) took 0.27 s.  The port is unchanged: its time is the listing's own "
        "arithmetic (per sheet about 160 assignment statements, 3 ARCCOS series of "
        "about 9 terms and 15 VECTOR calls); binding library names to locals in VECTOR "
        "measured under 2% of the run, not worth moving the code away from the listing.",
        "",
        "How the printer is made fast without changing a printed byte "
        "(`printer.fast_editor`, `Format.text_function`):",
        "",
        "* each FORMAT is compiled once into a Python function that builds all the records "
        "of one WRITE in a single expression of literals and field editors;",
        "* a field is edited by arithmetic (scale to d digits, `int()`), which is the "
        "truncation of `repr`'s digits except near a digit boundary; values within 1E-7 "
        "(E) or 1E-6 (F) of one after scaling (here four of the 41 fields of every sheet, "
        "crank velocities and accelerations that are exactly 100, 200, 5000, 10000, and "
        "one THETA 2 in ten) are edited from `repr`, and memoised since they recur;",
        "* the writer collects a whole sheet and hands it to the stream in one `write`.",
        "",
        "`tests/test_robust.py` checks that the fast editors print exactly what the "
        "reference editors (`edit_e`, `edit_f`) print, on arbitrary floats and on floats "
        "a few units in the last place from every digit boundary; the golden and "
        "differential tests guard the listing itself.",
        "",
    ]
    return "\n".join(lines)


def write_docs(section: str) -> None:
    text = DOC.read_text() if DOC.exists() else "# Performance\n\n"
    pattern = re.compile(rf"^{re.escape(HEADING)}\n.*?(?=^## |\Z)", re.MULTILINE | re.DOTALL)
    if pattern.search(text):
        text = pattern.sub(lambda _: section + "\n", text, count=1)
    else:
        text = text.rstrip("\n") + "\n\n" + section + "\n"
    DOC.parent.mkdir(exist_ok=True)
    DOC.write_text(text.rstrip("\n") + "\n")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs of each program (best kept)")
    parser.add_argument("--memory-sheets", type=int, nargs="+",
                        default=[10_000, 100_000, 1_000_000],
                        help="sheet counts for the peak-memory runs")
    parser.add_argument("--write-docs", action="store_true",
                        help=f"replace the '{HEADING}' section of docs/performance.md")
    args = parser.parse_args(argv)
    if not fortran.gfortran_available():
        print("gfortran is not installed", file=sys.stderr)
        return 1
    section = report(args)
    print(section)
    if args.write_docs:
        write_docs(section)
        print(f"updated {DOC.relative_to(ROOT)}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
