"""Listing throughput: ``sielaff run`` beside the 1966 program compiled with gfortran -O2.

    python benchmarks/listing.py                 # print the report
    python benchmarks/listing.py --write-docs    # and its section of docs/performance.md

The deck is the report's mechanism with THETA 2 from 0.01 to 360 degrees in steps of
0.01: 36,001 sheets (one past THMAX).  Each configuration runs in rounds with the
compiled deck (``decks/sielaff.f`` built by ``tests/fortran.py``, ``-O2``, unit 3 linked
to /dev/null) run beside it, which of the two goes first alternating from round to
round; both are whole processes writing the listing to /dev/null, start-up included.
The ratio is of CPU times (user + sys, ``getrusage`` of the child processes; of this
process for the in-process row), since the machine may be shared: wall times are shown
beside them.  Configurations: the float64 listing many sheets at a time
(``emulator.vector``, the default), the same in process (no start-up), the port alone
(``--port``), and the IBM 1410's decimal model on fewer sheets (its cost per sheet).

Everything the section says is measured here: the start-up (a one-sheet deck, Python
alone, ``import numpy``, numpy's BLAS with its thread pool), where the in-process time
goes (cProfile), that ``sielaff run`` and ``--port`` print the same bytes, and the peak
memory at 10^4-10^6 sheets.  The children run with sielaff's bytecode cached (in a
temporary PYTHONPYCACHEPREFIX, as after ``pip install``); one start-up row runs without.
"""

from __future__ import annotations

import argparse
import cProfile
import hashlib
import os
import pstats
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "benchmarks"))

import fortran  # noqa: E402  (tests/fortran.py: the gfortran harness)
from timing import Series, machine, spread, table, write_section  # noqa: E402

DOC = ROOT / "docs" / "performance.md"
HEADING = "## Listing throughput"
PARAMETERS = (ROOT / "decks" / "example.dat").read_text().splitlines()[:6]
RANGE = "    0.01    0.01   360.0"       # 36,001 sheets
SHORT = "    0.01    0.36   360.0"       # 1,001 sheets (the 1410 model)
ONE = "    0.01    0.01    0.01"         # 2 sheets: THMAX and the one past it
LONG_RANGE = "  0.0001  0.0001  1000.0"   # 10**7 sheets
BLAS_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "VECLIB_MAXIMUM_THREADS")


def deck(directory: Path, name: str, range_card: str) -> Path:
    path = directory / f"{name}.dat"
    path.write_text("\n".join([*PARAMETERS, range_card]) + "\n")
    return path


def children_env(cache: Path | None, **extra: str) -> dict[str, str]:
    """The environment of a ``sielaff`` child: this checkout's package, no BLAS setting
    of ours (the command makes its own), the bytecode cached in ``cache`` (None: none)."""
    env = {k: v for k, v in os.environ.items() if k not in BLAS_VARIABLES}
    env["PYTHONPATH"] = str(ROOT / "src")
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    if cache is None:
        env["PYTHONDONTWRITEBYTECODE"] = "1"
        env.pop("PYTHONPYCACHEPREFIX", None)
    else:
        env["PYTHONPYCACHEPREFIX"] = str(cache)
    env.update(extra)
    return env


def process(argv: list[str], env: dict[str, str] | None = None,
            cwd: Path | None = None) -> Callable[[], object]:
    return lambda: subprocess.run(argv, cwd=cwd, env=env, check=True,
                                  stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL)


def gfortran_runner(exe: Path, deck_path: Path, work: Path) -> Callable[[], object]:
    work.mkdir()
    shutil.copyfile(deck_path, work / "fort.1")
    os.symlink(os.devnull, work / "fort.3")
    return process([str(exe)], cwd=work)


def sielaff(deck_path: Path, env: dict[str, str], *extra: str) -> Callable[[], object]:
    return process([sys.executable, "-m", "sielaff", "run", str(deck_path), *extra], env)


def _cpu(who: int) -> float:
    r = resource.getrusage(who)
    return r.ru_utime + r.ru_stime


def measure(fn: Callable[[], object], who: int) -> tuple[float, float]:
    """(wall s, CPU s) of one call; CPU of the children (``who`` = RUSAGE_CHILDREN) or of
    this process (RUSAGE_SELF)."""
    c0, w0 = _cpu(who), time.perf_counter()
    fn()
    return time.perf_counter() - w0, _cpu(who) - c0


CHILD, SELF = resource.RUSAGE_CHILDREN, resource.RUSAGE_SELF


def paired(name: str, fn: Callable[[], object], who: int, reference: Callable[[], object],
           n: int) -> Series:
    """``n`` rounds of ``fn`` with the reference (a child process) beside it, which goes
    first alternating."""
    print(f"  {name} ...", file=sys.stderr)
    s = Series(name)
    for k in range(n):
        pair = [(reference, CHILD, s.ref_wall, s.ref_cpu), (fn, who, s.wall, s.cpu)]
        for f, w, walls, cpus in (pair if k % 2 == 0 else pair[::-1]):
            wall, cpu = measure(f, w)
            walls.append(wall)
            cpus.append(cpu)
    return s


def startup(runs: dict[str, Callable[[], object]], n: int) -> dict[str, list[float]]:
    """CPU s of each process in ``runs``, ``n`` rounds, run one after the other in each."""
    print("  start-up ...", file=sys.stderr)
    cpu: dict[str, list[float]] = {k: [] for k in runs}
    for k in range(n):
        for name in (list(runs) if k % 2 == 0 else list(runs)[::-1]):
            cpu[name].append(measure(runs[name], CHILD)[1])
    return cpu


def output_of(argv: list[str], env: dict[str, str]) -> tuple[str, int, int]:
    """(SHA-256, length in bytes, sheets) of the listing a command prints on stdout."""
    out = subprocess.run(argv, env=env, check=True, capture_output=True).stdout
    return hashlib.sha256(out).hexdigest(), len(out), out.count(b"THETA 2")


def peak_rss_mb(deck_path: Path, sheets: int, env: dict[str, str]) -> float:
    proc = subprocess.Popen([sys.executable, "-m", "sielaff", "run", str(deck_path),
                             "--max-sheets", str(sheets)], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError("sielaff run failed")
    return usage.ru_maxrss / 1024


def profile(in_process: Callable[[], object], sheets: int) -> tuple[list[str], float, float]:
    """Where the in-process listing's time goes: (shares as text, profiled s, fields a
    sheet sent to the printer's own editor)."""
    from sielaff.emulator import vector

    sent = [0]
    slow = vector._Listing._slow

    def counted(self, page, rows, *args):
        sent[0] += rows.size
        return slow(self, page, rows, *args)

    vector._Listing._slow = counted
    try:
        prof = cProfile.Profile()
        prof.runcall(in_process)
    finally:
        vector._Listing._slow = slow
    stats = pstats.Stats(prof).stats  # (file, line, name) -> (cc, nc, tottime, cumtime, ..)
    total = sum(v[2] for v in stats.values())

    def own(*names: str) -> float:
        return sum(v[2] for (f, _l, fn), v in stats.items()
                   if f.endswith("vector.py") and fn in names)

    def under(name: str) -> float:
        return sum(v[3] for (f, _l, fn), v in stats.items()
                   if f.endswith("vector.py") and fn == name)

    parts = [
        ("the arithmetic on arrays (`_sheets`, ARCCOS, VECTOR)",
         own("_sheets", "_arccos", "_vector")),
        ("E12.4 fields in bulk", own("_edit_e")),
        ("F12.1 fields in bulk", own("_edit_f")),
        ("fields near a digit boundary, by the printer's own editor", under("_slow")),
        ("sheets the port prints (the notices)", under("port_sheet")),
        ("writing the bytes", sum(v[2] for (_f, _l, fn), v in stats.items()
                                  if fn.startswith("<method 'write' of '_io.Buffered"))),
    ]
    parts.append(("the rest (gathering the values, copying fields into the page, the "
                  "interpreter)", total - sum(t for _, t in parts)))
    text = [f"{name} {100 * t / total:.0f}%" for name, t in parts]
    return text, total, sent[0] / sheets


def report(args: argparse.Namespace) -> str:
    load_before = os.getloadavg()
    exe = fortran.build(opt="-O2")
    with tempfile.TemporaryDirectory(prefix="sielaff-bench-") as tmp:
        t = Path(tmp)
        full, short, one = deck(t, "full", RANGE), deck(t, "short", SHORT), deck(t, "one", ONE)
        long_deck = deck(t, "long", LONG_RANGE)
        env = children_env(t / "pycache")
        env_pool = children_env(t / "pycache", OPENBLAS_NUM_THREADS=str(os.cpu_count() or 1))
        env_nocache = children_env(None)
        process([sys.executable, "-m", "sielaff", "run", str(one)], env)()  # fill the cache
        # first, while this process is small: a child's peak RSS counts its parent's
        # pages from before the exec
        memory = [(n, peak_rss_mb(long_deck, n, env)) for n in args.memory_sheets]
        g_full = gfortran_runner(exe, full, t / "g")
        g_short = gfortran_runner(exe, short, t / "gs")
        from sielaff.emulator.cards import read_deck
        from sielaff.emulator.run import run

        deck_full = read_deck(str(full))

        def in_process():
            with open(os.devnull, "w") as null:
                run(deck_full, null, binary=null.buffer)

        in_process()  # numpy's and the listing's first-use costs are start-up, not this
        series = [
            paired("the same in process (`emulator.run.run`, no start-up), 36,001 sheets",
                   in_process, SELF, g_full, args.rounds),
            paired("sielaff run (float64, many sheets at a time), 36,001 sheets",
                   sielaff(full, env), CHILD, g_full, args.rounds),
            paired("sielaff run --port (float64, the line-by-line port), 36,001 sheets",
                   sielaff(full, env, "--port"), CHILD, g_full, args.rounds),
            paired("sielaff run --arith ibm1410, 1,001 sheets",
                   sielaff(short, env, "--arith", "ibm1410"), CHILD, g_short, args.rounds),
        ]
        cpu = startup({
            "full": sielaff(full, env),
            "one": sielaff(one, env),
            "pool": sielaff(one, env_pool),
            "nocache": sielaff(one, env_nocache),
            "python": process([sys.executable, "-c", "pass"], env),
            "numpy": process([sys.executable, "-c", "import numpy"],
                             dict(env, OPENBLAS_NUM_THREADS="1")),
        }, args.rounds)
        fast_out = output_of([sys.executable, "-m", "sielaff", "run", str(full)], env)
        same = fast_out == output_of([sys.executable, "-m", "sielaff", "run", str(full),
                                      "--port"], env)
        shares, profiled, sent = profile(in_process, 36_001)
    load_after = os.getloadavg()
    inproc, fast, port, ibm = series

    def med(xs: list[float]) -> float:
        return statistics.median(xs)

    def ms(xs: list[float]) -> str:
        return spread([1000 * x for x in xs], "{:.0f}") + " ms"

    ratio = med(fast.ratio("cpu"))
    share = [o / f for o, f in zip(cpu["one"], cpu["full"])]
    per_sheet = [c / 1001 * 1e6 for c in ibm.cpu]
    lines = [
        HEADING, "",
        f"Measured by `python benchmarks/listing.py --write-docs` on {machine()}; load "
        f"average (1 min) {load_before[0]:.1f} before and {load_after[0]:.1f} after.", "",
        "The report's mechanism with THETA 2 from 0.01 to 360 in steps of 0.01 degree "
        f"({fast_out[2]:,} sheets, {fast_out[1] / 1e6:.0f} MB of listing), every program "
        "a whole process writing to /dev/null, start-up included (sielaff's bytecode "
        "cached, as after `pip install`); the compiled deck (`decks/sielaff.f`, gfortran "
        f"-O2, REAL*8) run beside each configuration in each of {args.rounds} rounds, "
        "which goes first alternating; median (range) over the rounds.  The ratios are "
        "of CPU times (user + sys from `getrusage` of the child processes, of the "
        "benchmark's own process for the in-process row): the machine is shared, and "
        "time spent waiting for a core counts in wall time, not in CPU time.", "",
        *table(series), "",
        f"* **`sielaff run`: {ratio:.2f}x gfortran's throughput in CPU time** (range "
        f"{min(fast.ratio('cpu')):.2f}-{max(fast.ratio('cpu')):.2f}x; goal >= 3x: "
        f"{'met' if ratio >= 3 else 'not met'}).  Its listing and `sielaff run --port`'s "
        f"are {'the same bytes' if same else 'NOT the same bytes'} (SHA-256 of the two "
        "outputs compared by this script).",
        f"* Without start-up (in process) the same listing runs at "
        f"{spread(inproc.ratio('cpu'), '{:.2f}')}x.",
        f"* Start-up, whole processes beside it in {args.rounds} rounds: `sielaff run` on a "
        f"deck of two sheets {ms(cpu['one'])} of CPU, "
        f"{spread([100 * x for x in share], '{:.0f}')}% of the 36,001-sheet run; the same "
        f"with numpy's OpenBLAS starting its thread pool (OPENBLAS_NUM_THREADS="
        f"{os.cpu_count()}; the command otherwise sets 1) {ms(cpu['pool'])}, and without "
        f"the bytecode cache (PYTHONDONTWRITEBYTECODE=1) {ms(cpu['nocache'])}.  For "
        f"comparison `python -c pass` takes {ms(cpu['python'])} and `python -c \"import "
        f"numpy\"` (one BLAS thread) {ms(cpu['numpy'])}.",
        f"* The port alone: {spread(port.ratio('cpu'), '{:.2f}')}x.",
        f"* The IBM 1410 model (8-digit decimal arithmetic in Python): "
        f"{spread(per_sheet, '{:,.0f}')} us of CPU per sheet, start-up included.", "",
        "Peak resident memory of `sielaff run` (`--max-sheets N` on a range of 10^7 "
        "sheets; `wait4` rusage): " + ", ".join(f"{n:,} sheets {rss:.0f} MB"
                                                 for n, rss in memory) + ".", "",
        f"Where the in-process listing's time goes (cProfile, one run of 36,001 sheets, "
        f"{profiled:.2f} s under the profiler; each function's own time, the printer's "
        f"editor and the port with what they call): " + ", ".join(shares) + f".  "
        f"{sent:.1f} fields a sheet go to the printer's own editor.", "",
    ]
    return "\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=11)
    ap.add_argument("--memory-sheets", type=int, nargs="*", default=[10_000, 100_000, 1_000_000])
    ap.add_argument("--write-docs", action="store_true")
    args = ap.parse_args()
    text = report(args)
    print(text)
    if args.write_docs:
        write_section(DOC, HEADING, text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
