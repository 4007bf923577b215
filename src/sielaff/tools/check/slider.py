"""``sielaff check SPEC`` for a slider-crank (``[linkage] kind = "slider-crank"``).

The report has three parts:

Linkage
    Every field as the spec gives it, with its unit and meaning; each ``[[range]]`` and
    the positions ``sielaff table`` gives for it.
Geometry
    Whether the crank turns fully (R3 >= R2 + |offset|, with its margin), the rod/crank
    ratio, the dead centres and the stroke by their construction
    (:func:`sielaff.slider_crank.stroke`) and the time ratio of the two strokes.
One revolution (modern engine, the spec's scene)
    The greatest rod angle |ATH3|; the peak loads on the pins O2 (FOA), A (FA32) and B
    (FB34), the guide's force FN both ways, the driving torque both ways, the shaking
    force and its X and Y components' ranges, found on a 0.1 deg grid and refined to
    0.001 deg; and the cycle work (the integral of TORQ over a revolution, trapezoid
    rule on the 0.1 deg grid), zero when nothing dissipates or works from outside.

A crank that cannot turn fully is reported with the reason and exit 3; the spec's
faults (a missing key, a rod that cannot reach the slider's line) are exit 2 before
this report (:func:`sielaff.tools.common.other_kind`).
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from sielaff.tools.check.sections import CheckReport
from sielaff.tools.common import EXIT_NOT_CRANK_ROCKER, work_text

__all__ = ["check_slider", "slider_facts"]

#: Each field's words (its unit comes from sielaff.quantities).
_MEANING = {
    "W2": "weight of link 2 (crank)", "W3": "weight of link 3 (rod)",
    "W4": "weight of link 4 (slider)", "ZI2": "moment of inertia of the crank (about G2)",
    "ZI3": "moment of inertia of the rod (about G3)", "R2": "crank, O2 to A",
    "R3": "rod, A to B", "offset": "the slider's line, y = offset",
    "ADEL2": "line O2-G2, from the crank", "ADEL3": "line A-G3, from the rod",
    "RG2": "O2 to G2", "RG3": "A to G3", "TH2D": "crank speed (constant)",
}
_MASS = {"W2": "W2", "W3": "W3", "W4": "W4"}  # a weight in in-lb-sec, a mass in SI

#: Peaks: (label, output, how).
PEAKS = (("load on pin O2 (FOA)", "FOA", "max"), ("load on pin A (FA32)", "FA32", "max"),
         ("load on pin B (FB34)", "FB34", "max"), ("guide force FN, largest", "FN", "max"),
         ("guide force FN, most negative", "FN", "min"),
         ("driving torque, largest", "TORQ", "max"),
         ("driving torque, most negative", "TORQ", "min"),
         ("shaking force SHAK", "SHAK", "max"), ("rod angle |ATH3|", "ATH3", "maxabs"))
GRID = 0.1
FINE = 0.001


def _analyze(m: Any, th: Any, names: list[str], scene: Any) -> Any:
    from sielaff.engine import AssemblyWarning, analyze

    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", AssemblyWarning)
        return analyze(m, th, names, scene=scene)


def _score(v: np.ndarray, how: str) -> np.ndarray:
    return np.abs(v) if how == "maxabs" else -v if how == "min" else v


def peaks(m: Any, scene: Any) -> list[tuple[str, str, float, float]]:
    """(label, name, value, THETA 2 [deg]) for each of :data:`PEAKS`: the grid's best,
    refined on a 0.001 deg grid 0.1 deg either side of it."""
    th = np.arange(0.0, 360.0, GRID)
    names = sorted({p[1] for p in PEAKS})
    r = _analyze(m, th, names, scene)
    out = []
    for label, name, how in PEAKS:
        i = int(np.argmax(_score(np.asarray(r[name]), how)))
        fine = th[i] + np.arange(-GRID, GRID + FINE / 2, FINE)
        v = np.asarray(_analyze(m, np.mod(fine, 360.0), [name], scene)[name])
        j = int(np.argmax(_score(v, how)))
        out.append((label, name, float(v[j]), float(np.mod(fine[j], 360.0))))
    return out


def _fields(deck: Any, rep: CheckReport) -> None:
    from decimal import Decimal

    from sielaff.quantities import unit
    from sielaff.slider_crank import FIELD_NAMES

    m = deck.mechanism
    rep.add(f'Linkage: a slider-crank ([linkage] kind = "slider-crank"); units {m.units}')
    for name in FIELD_NAMES:
        value = deck.exact.get(name, Decimal(repr(float(getattr(m, name)))))
        u = unit(name, m.units)
        meaning = _MEANING[name]
        if m.units == "SI" and name in _MASS:
            meaning = meaning.replace("weight", "mass")
        rep.add(f"  {name:<6} = {str(value):>10} {u:<12} {meaning}")
    from sielaff.tools.kinds import count, exact_range

    for i, r in enumerate(deck.ranges):
        n = count(*exact_range(deck, i))
        rep.add(f"  [[range]] {i + 1}: start = {r.THZERO:g} deg, step = {r.DELTA:g} deg, stop = "
                f"{r.THMAX:g} deg: {n} position{'s' if n != 1 else ''} in sielaff table")


def check_slider(deck: Any, scene: Any) -> CheckReport:
    """The report for a slider-crank spec's ``deck`` in ``scene`` (see the module doc)."""
    from sielaff.quantities import unit
    from sielaff.slider_crank import full_turn_failure, stroke

    m = deck.mechanism
    system = m.units
    rep = CheckReport()
    rep.add(f"sielaff check: {deck.path}")
    rep.add()
    _fields(deck, rep)
    rep.add()
    L = unit("R2", system)
    R2, R3, e = float(m.R2), float(m.R3), float(m.offset)
    rep.add("Geometry")
    rep.add(f"  rod/crank ratio R3/R2 = {R3 / R2:.4g}")
    failure = full_turn_failure(m)
    if failure:
        rep.add(f"  the crank cannot turn fully: {failure}")
        rep.add()
        rep.status = EXIT_NOT_CRANK_ROCKER
        rep.error = f"{deck.path}: [lengths]: {failure}"
        rep.add("Verdict: the crank rocks between its limits; sielaff table gives the positions "
                "where it assembles (exit 3 here)")
        return rep
    rep.add(f"  the crank turns fully: R3 = {R3:g} {L} >= R2 + |offset| = {R2 + abs(e):g} {L} "
            f"(margin {R3 - R2 - abs(e):.4g} {L})")
    s = stroke(m)
    rep.add(f"  outer dead centre: XB = {s.xb_outer:.4f} {L} at THETA 2 = {s.at_outer:.3f} deg")
    rep.add(f"  inner dead centre: XB = {s.xb_inner:.4f} {L} at THETA 2 = {s.at_inner:.3f} deg")
    rep.add(f"  stroke {s.length:.4f} {L}; the crank turns {s.inward:.3f} deg on the inward "
            f"stroke, {s.outward:.3f} deg on the outward: time ratio {s.time_ratio:.4f}")
    rep.add()
    from sielaff.tools.common import describe_scene

    effects = describe_scene(scene, system)
    rep.add(f"One revolution (modern engine, {effects or 'no gravity, no loads'})")
    rep.add(f"  THETA 2 = 0 to 360 on a {GRID:g} deg grid, peaks refined to {FINE:g} deg")
    for label, name, value, at in peaks(m, scene):
        shown = f"{abs(value) if name == 'ATH3' else value:.4g} {unit(name, system)}"
        rep.add(f"  {label:<31} {shown:>18} at THETA 2 = {at:7.3f} deg")
    th = np.arange(0.0, 360.0, GRID)
    r = _analyze(m, th, ["SHAKX", "SHAKY"], scene)
    F = unit("SHAK", system)
    rep.add(f"  shaking force X from {float(np.min(r['SHAKX'])):.4g} to "
            f"{float(np.max(r['SHAKX'])):.4g} {F}, Y from {float(np.min(r['SHAKY'])):.4g} to "
            f"{float(np.max(r['SHAKY'])):.4g} {F} (on the grid)")
    work, abs_work = cycle_work(m, scene)
    rep.add(f"  cycle work, integral of TORQ d(THETA 2) over a revolution: "
            f"{work_text(work, abs_work, system)}")
    rep.add()
    rep.add("Verdict: usable (sielaff table, check); not a 1966 deck (sielaff run and punch "
            "take four-bars)")
    return rep


def cycle_work(m: Any, scene: Any) -> tuple[float, float]:
    """(integral of TORQ, of |TORQ|) d(THETA 2) [rad] over a revolution, trapezoid rule on
    the 0.1 deg grid, both ends."""
    th = np.linspace(0.0, 360.0, round(360.0 / GRID) + 1)
    torq = np.asarray(_analyze(m, th, ["TORQ"], scene)["TORQ"])
    x = np.radians(th)
    return float(np.trapezoid(torq, x)), float(np.trapezoid(np.abs(torq), x))


def slider_facts(deck: Any, rep: CheckReport, scene: Any) -> str:
    """``--format json``: the kind, the stroke, the peaks (each ``{"value", "unit",
    "at"}``), the cycle work, the status, the error and the report's lines."""
    import json

    from sielaff.quantities import unit, unit_of
    from sielaff.slider_crank import full_turn_failure, stroke

    m = deck.mechanism
    L = unit("R2", m.units)
    facts: dict[str, Any] = {"kind": "slider-crank", "units": m.units}
    if full_turn_failure(m) is None:
        s = stroke(m)
        facts["stroke"] = {"value": s.length, "unit": L}
        facts["dead_centres"] = {"outer": {"XB": s.xb_outer, "at": s.at_outer},
                                 "inner": {"XB": s.xb_inner, "at": s.at_inner}, "unit": L}
        facts["time_ratio"] = s.time_ratio
        facts["peaks"] = [{"label": label, "name": name, "value": value,
                           "unit": unit(name, m.units), "at": at}
                          for label, name, value, at in peaks(m, scene)]
        work, abs_work = cycle_work(m, scene)
        facts["cycle_work"] = {"value": work if math.isfinite(work) else None,
                               "abs": abs_work, "unit": unit_of("work", m.units)}
    facts.update(status=rep.status, error=rep.error, lines=rep.lines)
    return json.dumps(facts, indent=1) + "\n"
