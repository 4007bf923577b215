"""Friction in every joint of the other linkage kinds, compiled and not.

Run from the repository root::

    python benchmarks/kinds_friction.py              # writes its section of docs/performance.md
    python benchmarks/kinds_friction.py --no-write   # print only

For each kind's example (slider-crank, inverted slider-crank, Watt and Stephenson
six-bars): Coulomb friction in every pin (mu r = 0.02 in) and slide (mu = 0.1), gravity
and a crank acceleration, every output of the kind but ASSEMBLED, into reused arrays
(``out=``) over a revolution of crank angles.  The reference beside each configuration
is the numpy engine on the same request (``benchmarks/timing.py``: rounds, CPU and wall
time, median and range); the ratio is the numpy engine's CPU time over the
configuration's.  Every kernel is compiled (or loaded from the kernel cache) before the
timing.  The section also says each kind's mean Newton iterations a position
(FRICTION_ITERATIONS), its positions by FRICTION_STATUS and the largest difference
between the two engines (``difference``), all measured in this run.
"""

from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "src"))

from sielaff import (  # noqa: E402
    INVERTED_EXAMPLE,
    SLIDER_EXAMPLE,
    STEPHENSON_EXAMPLE,
    WATT_EXAMPLE,
    PinFriction,
    analyze,
    scene_for,
)
from sielaff.engine import model_for  # noqa: E402
from sielaff.engine.compiled import NOT_GIVEN, available  # noqa: E402
from sielaff.quantities import unit  # noqa: E402

sys.path.insert(0, str(ROOT / "benchmarks"))
from timing import machine, publish, rounds, table  # noqa: E402

DOC = ROOT / "docs" / "performance.md"
HEADING = "## Friction on every linkage kind"
KINDS = (("slider-crank", SLIDER_EXAMPLE), ("inverted slider-crank", INVERTED_EXAMPLE),
         ("Watt six-bar", WATT_EXAMPLE), ("Stephenson six-bar", STEPHENSON_EXAMPLE))
MUR, MU_SLIDE = 0.02, 0.1  # [in], [-]


def scene(m):
    """Friction in every joint of ``m``'s kind, gravity down, the crank slowing."""
    from sielaff.engine.joint_friction import _names

    joints = _names(model_for(m).topology)[2]
    friction = {j: PinFriction(MU_SLIDE, 0.0) if j.startswith("slide")
                else PinFriction(MUR / 0.5, 0.5) for j in joints}
    return scene_for(m)(gravity="down", th2dd=-15.0, friction=friction)


def difference(name, got, ref) -> float:
    """The largest difference of output ``name`` between the two engines, relative to its
    scale: an angle's modulo 360 deg; a vector's x or y component against the vector's
    largest magnitude (a component that is zero by the geometry differs by rounding
    only); any other output against its own largest magnitude."""
    ok = np.isfinite(ref[name])
    if not ok.any():
        return 0.0
    d = got[name][ok] - ref[name][ok]
    try:
        if unit(name) == "deg":
            d = (d + 180.0) % 360.0 - 180.0
    except KeyError:
        pass
    pair = name[:-1] + ("Y" if name[-1] == "X" else "X")
    if name[-1] in "XY" and pair in ref:
        scale = float(np.max(np.hypot(ref[name][ok], ref[pair][ok])))
    else:
        scale = float(np.max(np.abs(ref[name][ok])))
    return float(np.max(np.abs(d))) / max(scale, 1e-300)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=5, help="rounds of each configuration")
    ap.add_argument("--positions", type=int, default=100_000, help="crank angles a run")
    ap.add_argument("--no-write", action="store_true", help="do not touch docs/performance.md")
    args = ap.parse_args(argv)
    if not available():
        print("numba is not installed: nothing to compare", file=sys.stderr)
        return 1
    n = args.positions
    th = np.arange(n) * (360.0 / n)
    rows, notes = [], []
    for kind, m in KINDS:
        wanted = [k for k in model_for(m).outputs if k not in NOT_GIVEN]
        sc = scene(m)
        outs = {k: np.empty(n) for k in wanted}

        def numba(out=True, m=m, sc=sc, outs=outs, wanted=wanted):
            if out:
                return lambda: analyze(m, th, out=outs, scene=sc, backend="numba")
            return lambda: analyze(m, th, wanted, scene=sc, backend="numba")

        def numpy(m=m, sc=sc, wanted=wanted):
            mine = {k: np.empty(n) for k in wanted}  # not the arrays numba writes
            return lambda: analyze(m, th, out=mine, scene=sc)

        print(f"  {kind}: compiling ...", file=sys.stderr)
        numba(False)()  # both paths' kernels compiled (or loaded) outside the timing
        numba()()
        got = {k: v.copy() for k, v in outs.items()}
        ref = analyze(m, th, wanted, scene=sc)
        for name, fn in ((f"{kind}, `backend='numba'`, `out=`", numba()),
                         (f"{kind}, `backend='numba'`, fresh arrays", numba(False))):
            print(f"  {name} ...", file=sys.stderr)
            rows.append(rounds(name, fn, numpy(), args.rounds))
        worst = max(difference(k, got, ref) for k in wanted)
        same_nan = all(np.array_equal(np.isnan(got[k]), np.isnan(ref[k])) for k in wanted)
        status = ref["FRICTION_STATUS"]
        notes.append(
            f"* {kind}: {len(wanted)} outputs; Newton iterations a position, mean "
            f"{float(np.mean(ref['FRICTION_ITERATIONS'])):.2f} (numpy) and "
            f"{float(np.mean(got['FRICTION_ITERATIONS'])):.2f} (numba); positions where a "
            f"joint is at rest to within roundoff (FRICTION_STATUS 1): "
            f"{int(np.count_nonzero(status == 1.0))}, without a solution (2): "
            f"{int(np.count_nonzero(status == 2.0))}; the largest difference between the "
            f"engines {worst:.1e} of the output's scale; NaN in the same places: "
            f"{same_nan}.")
    lines = [
        HEADING, "",
        f"Measured by `python benchmarks/kinds_friction.py` on {machine()}.", "",
        f"Each kind's example with Coulomb friction in every pin (mu r = {MUR} in) and slide "
        f"(mu = {MU_SLIDE}), gravity and a crank acceleration of -15 rad/sec^2, at {n:,} "
        "crank angles over a revolution; every output but ASSEMBLED.  The reference beside "
        "each configuration, in each of "
        f"{args.rounds} rounds, is the numpy engine on the same request into reused arrays; "
        "median (range); the ratio is the numpy engine's CPU time over the "
        "configuration's.", "",
        *table(rows, "numpy engine"), "",
        *notes, "",
    ]
    med = [statistics.median(s.ratio("cpu")) for s in rows]
    lines.insert(-1, f"* The compiled kernel against the numpy engine, `out=`: "
                 f"{min(med[0::2]):.2f}x to {max(med[0::2]):.2f}x over the four kinds.")
    publish(DOC, HEADING, "\n".join(lines), not args.no_write)
    return 0


if __name__ == "__main__":
    sys.exit(main())
