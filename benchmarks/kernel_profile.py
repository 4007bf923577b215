"""Where the compiled kernel's time goes: the section "Compiled kernel: where the time
goes" of docs/performance.md.

The four-bar's kernel of all 71 results (``analyze(..., backend="numba")``, ``out=``, the
report's example) is timed by itself, its arguments captured from one call:

* **in cache** (``N_CACHE`` positions, whose 71 output rows fit a core's L2 cache) and
  over 10^6 positions, staged (the chunked kernel's choice for 71 outputs) and written
  straight (``engine/kernel.py``'s ``STAGE_FROM`` raised past 71), both with
  ``engine/compiled.py``'s ``STREAMED`` off; and over 10^6 positions the streamed kernel
  (the backend's choice there): its first run, of whole runs of positions;
* **knocked out**: the kernel compiled again with one of its transcendentals replaced by
  a multiply-add of its arguments (wrong answers; timing only): atan2's octant
  reduction and polynomial (``kernel_math._half_turn``), the mod-360 reduction
  (``_mod360``), sine and cosine (``_sincos``).  What the kernel saves without it is that
  function's cost, as far as its removal leaves the rest's registers alone;
* **its vector loop's instructions** (x86-64 only): from numba's assembly of the straight
  kernel, the loop with the most packed instructions: its size, the vector width, and
  its stores to and loads from the stack (values spilled out of the 16 or 32 vector
  registers and read back), per position.

Each configuration runs beside the full kernel in each round (CPU and wall time, median
and range; ``benchmarks/timing.py``).  Kernels are compiled in memory
(``SIELAFF_KERNEL_DIR=off``): a knocked-out kernel has the full one's text, and the kernel
cache, which keys on the text, would hand back the full one.

Usage: ``python benchmarks/kernel_profile.py [--rounds N] [--no-write]``
"""

from __future__ import annotations

import argparse
import os
import re
import statistics
import sys
from pathlib import Path
from typing import Any

os.environ["SIELAFF_KERNEL_DIR"] = "off"  # before sielaff: see the module's doc

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(ROOT / "benchmarks"))

from sielaff import engine  # noqa: E402
from sielaff.emulator.cards import parse_deck  # noqa: E402
from timing import machine, publish, rounds, table  # noqa: E402

DOC = ROOT / "docs" / "performance.md"
HEADING = "## Compiled kernel: where the time goes"
N_CACHE = 512  # 71 rows of 512 floats: 290 KiB
N_BIG = 10**6


def _half_turn(y, x):  # atan2 knocked out: a multiply-add, no reduction, no polynomial
    return abs(y) * 0.5 + x


def _mod360(x):  # mod 360 knocked out
    return x * 0.5


def _sincos(x):  # sine and cosine knocked out
    return x * 0.5, x * 0.25


KNOCKOUTS = {
    "atan2 (kernel_math._half_turn)": ("_half_turn", _half_turn),
    "mod 360 (kernel_math._mod360)": ("_mod360", _mod360),
    "sine and cosine (kernel_math._sincos)": ("_sincos", _sincos),
}


def _mechanism() -> Any:
    deck = (ROOT / "decks" / "example.dat").read_text()
    return parse_deck(deck, "decks/example.dat").mechanism


def _fresh_compiler() -> None:
    """Forget every compiled form, so that the next request compiles from kernel_math as
    it is now."""
    from sielaff.engine import kernel as K

    K._FORMS.clear()
    K._ONE.clear()
    K._KERNELS.clear()
    K._ARRAY_CODE.clear()


def captured(m: Any, n: int, straight: bool = False, knock: tuple[str, Any] | None = None,
             streamed: bool = False) -> tuple[Any, tuple[Any, ...]]:
    """The kernel of all results for ``n`` crank angles into reused arrays, and the
    arguments the backend calls it with first: (kernel, args).  The chunked kernel, or
    with ``streamed`` the streamed one (engine/compiled.py's STREAMED) and its first run,
    the one of whole runs of positions."""
    from sielaff.engine import compiled
    from sielaff.engine import kernel as K
    from sielaff.engine import kernel_math as KM

    saved_stage, saved_for = K.STAGE_FROM, K.kernel_for
    saved_fn = getattr(KM, knock[0]) if knock else None
    got: dict[str, Any] = {}

    def kernel_for(*a: Any, **k: Any) -> Any:
        kernel = saved_for(*a, **k)

        def call(*args: Any) -> Any:
            got.setdefault("kernel", kernel)
            got.setdefault("args", args)
            return kernel(*args)
        if K.streamed(kernel):
            K._STREAMED.add(call)
        return call

    if knock or straight:
        _fresh_compiler()
    try:
        compiled.STREAMED = streamed
        if straight:
            K.STAGE_FROM = 10**9
        if knock:
            setattr(KM, knock[0], knock[1])
        K.kernel_for = kernel_for
        th = np.arange(n) * (360.0 / n)
        out = {name: np.empty(n) for name in engine.RESULTS}
        engine.analyze(m, th, out=out, backend="numba")
    finally:
        K.kernel_for, K.STAGE_FROM, compiled.STREAMED = saved_for, saved_stage, True
        if knock:
            setattr(KM, knock[0], saved_fn)
    if knock or straight:
        _fresh_compiler()
    return got["kernel"], got["args"]


def repeated(kernel: Any, args: tuple[Any, ...], reps: int) -> Any:
    def run() -> None:
        for _ in range(reps):
            kernel(*args)
    return run


_STORE = re.compile(r"^\s+vmov\w*\s+%[xyz]mm\d+, -?\d*\(%rsp\)")
_LOAD = re.compile(r"^\s+vmov\w*\s+-?\d*\(%rsp\), %[xyz]mm\d+")
_OPERAND = re.compile(r"^\s+v(?!mov)\w+\s+-?\d*\(%rsp\),")
_OUT = re.compile(r"^\s+vmov\w*\s+%[yz]mm\d+, \(%r\w+,%r\w+(,8)?\)")


def vector_loop(asm: str) -> dict[str, Any] | None:
    """The loop of numba's assembly with the most packed (ymm or zmm) instructions, among
    those that are mostly packed: its instruction counts."""
    lines = asm.splitlines()
    labels = {m.group(1): i for i, x in enumerate(lines)
              if (m := re.match(r"^(\.LBB\d+_\d+):", x))}
    best = None
    for i, x in enumerate(lines):
        m = re.match(r"^\s+j\w+\s+(\.LBB\d+_\d+)", x)
        if not m or labels.get(m.group(1), i) >= i:
            continue
        body = [y for y in lines[labels[m.group(1)]:i + 1]
                if y.startswith("\t") and not y.strip().startswith(".")]
        packed = sum(1 for y in body if "ymm" in y or "zmm" in y)
        if 2 * packed > len(body) and (best is None or packed > best[0]):
            best = (packed, body)
    if best is None:
        return None
    body = best[1]
    width = "zmm" if any("zmm" in y for y in body) else "ymm"
    return {"instructions": len(body), "lanes": 8 if width == "zmm" else 4, "width": width,
            "spill stores": sum(1 for y in body if _STORE.match(y)),
            "stack loads": sum(1 for y in body if _LOAD.match(y)),
            "stack operands": sum(1 for y in body if _OPERAND.match(y)),
            "output stores": sum(1 for y in body if _OUT.match(y))}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=5, help="rounds of each configuration")
    ap.add_argument("--no-write", action="store_true", help="do not touch docs/performance.md")
    args = ap.parse_args(argv)
    from sielaff.engine import compiled

    if not compiled.available():
        print("numba is not installed: nothing to profile", file=sys.stderr)
        return 1
    m = _mechanism()
    reps = max(1, 2 * N_BIG // N_CACHE)  # about as many positions in cache as out of it
    print("  compiling the kernels ...", file=sys.stderr)
    base_small = captured(m, N_CACHE)
    base_big = captured(m, N_BIG)
    straight_small = captured(m, N_CACHE, straight=True)
    straight_big = captured(m, N_BIG, straight=True)
    streamed_big = captured(m, N_BIG, streamed=True)
    knocked = {name: captured(m, N_CACHE, knock=k) for name, k in KNOCKOUTS.items()}
    ref_small = repeated(*base_small, reps)
    ref_big = repeated(*base_big, 2)
    configs = [
        ("the kernel, staged (the backend's choice), in cache", ref_small, ref_small,
         N_CACHE * reps),
        ("written straight, in cache", repeated(*straight_small, reps), ref_small,
         N_CACHE * reps),
        *((f"without {name}, in cache", repeated(*k, reps), ref_small, N_CACHE * reps)
          for name, k in knocked.items()),
        (f"the kernel, staged, {N_BIG:,} positions", ref_big, ref_big, 2 * N_BIG),
        (f"written straight, {N_BIG:,} positions", repeated(*straight_big, 2), ref_big,
         2 * N_BIG),
        (f"streamed (the backend's choice here), {N_BIG:,} positions",
         repeated(*streamed_big, 2), ref_big, 2 * streamed_big[1][0]),
    ]
    series, per = [], []
    for name, fn, ref, positions in configs:
        print(f"  {name} ...", file=sys.stderr)
        s = rounds(name, fn, ref, args.rounds)
        series.append(s)
        per.append((1e9 * statistics.median(s.cpu) / positions,
                    1e9 * statistics.median(s.ref_cpu) / positions))
    loop = None
    try:
        kernel = straight_small[0]
        loop = vector_loop(kernel.inspect_asm(kernel.signatures[0]))
    except Exception as e:  # noqa: BLE001 - the count is optional: say why it is missing
        print(f"no assembly count: {type(e).__name__}: {e}", file=sys.stderr)
    full = per[0][1]
    lines = [
        HEADING, "",
        f"Measured by `python benchmarks/kernel_profile.py` on {machine()}.", "",
        f"The four-bar's kernel of all {len(engine.RESULTS)} results "
        "(`analyze(..., backend='numba')`, `out=`, the report's example) timed by itself, "
        f"its arguments captured from one call: in cache ({N_CACHE} positions, called "
        f"{reps:,} times) and over {N_BIG:,} positions (called twice).  Each configuration "
        "runs beside the full kernel, staged as the backend runs it, in each of "
        f"{args.rounds} rounds; median (range).  A knocked-out function is replaced by a "
        "multiply-add of its arguments (wrong answers; timing only).", "",
        *table(series, "the full kernel"), "",
        "Per position (median CPU time over the positions computed):", "",
        "| configuration | ns per position | the full kernel beside it, ns | saved, ns |",
        "|---|---:|---:|---:|",
        *(f"| {s.name} | {a:.1f} | {b:.1f} | {b - a:.1f} |"
          for s, (a, b) in zip(series, per, strict=True)), "",
    ]
    knock_rows = [(name, per[2 + k]) for k, name in enumerate(knocked)]
    lines.append("* In cache, of the full kernel's " + f"{full:.1f} ns per position: " + "; ".join(
        f"{name.split(' (')[0]} {b - a:.1f} ns ({100 * (b - a) / b:.0f}%)"
        for name, (a, b) in knock_rows) + ".")
    big, big_straight, big_streamed = per[-3][0], per[-2][0], per[-1][0]
    lines.append(f"* Over {N_BIG:,} positions: staged {big:.1f} ns per position, written "
                 f"straight {big_straight:.1f} ns, streamed (each output's vectors stored "
                 f"around the caches straight from the loop) {big_streamed:.1f} ns; in cache "
                 f"staged {per[0][0]:.1f} ns, straight {per[1][0]:.1f} ns.")
    if loop:
        lanes = loop["lanes"]
        lines.append(
            f"* The straight kernel's vector loop ({loop['width']} registers, {lanes} "
            f"positions an iteration): {loop['instructions']:,} instructions, of which "
            f"{loop['spill stores']} store a vector register to the stack, "
            f"{loop['stack loads']} load one back and {loop['stack operands']} more take "
            f"an operand from the stack; {loop['output stores']} store an output.  Per "
            f"position: {loop['instructions'] / lanes:.0f} instructions, "
            f"{(loop['spill stores'] + loop['stack loads'] + loop['stack operands']) / lanes:.0f}"
            " of them spill traffic.")
    else:
        lines.append("* No count of the vector loop's instructions (not x86-64, or no "
                     "loop mostly of packed instructions found).")
    publish(DOC, HEADING, "\n".join(lines), not args.no_write)
    return 0


if __name__ == "__main__":
    sys.exit(main())
