"""``sielaff check SPEC`` for a linkage of another kind than the four-bar (``[linkage] kind
= "slider-crank"``, ``"inverted-slider-crank"``, ``"watt"``, ``"stephenson"``).

The report has three parts:

Linkage
    Every field as the spec gives it, with its unit and where the spec gives it; each
    ``[[range]]`` and the positions ``sielaff table`` gives for it.
Geometry
    Whether the crank turns fully (and if not, the arcs where the linkage assembles), each
    dyad's least margin from its toggle (an RRR's least transmission angle), and the kind's
    own figures by construction: a slider-crank's rod/crank ratio, dead centres, stroke and
    time ratio (:func:`sielaff.slider_crank.stroke`); an inverted slider-crank's quick
    return (:func:`sielaff.inverted_slider_crank.quick_return`).
One revolution (modern engine, the spec's scene)
    The peak load on every pin and slide, the driving torque both ways and the shaking
    force, found on a 0.1 deg grid and refined to 0.001 deg; the cycle work (the
    integral of TORQ over a revolution, trapezoid rule on the 0.1 deg grid), zero when
    nothing dissipates or works from outside; each effect's own figures.

A crank that cannot turn fully is reported with the reason and exit 3; the spec's
faults (a missing key, a dyad that cannot close anywhere) are exit 2 before this report
(:func:`sielaff.tools.kinds.other_kind`).
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from sielaff.tools.check.sections import CheckReport
from sielaff.tools.common import EXIT_NOT_CRANK_ROCKER, work_text

__all__ = ["check_kind", "kind_facts", "peak_list"]

GRID = 0.1
FINE = 0.001


def _analyze(m: Any, th: Any, names: list[str], scene: Any) -> Any:
    from sielaff.engine import AssemblyWarning, analyze
    from sielaff.engine.friction import FrictionWarning

    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", AssemblyWarning)
        warnings.simplefilter("ignore", FrictionWarning)
        return analyze(m, th, names, scene=scene)


def _score(v: np.ndarray, how: str) -> np.ndarray:
    v = np.where(np.isfinite(v), v, -np.inf if how != "min" else np.inf)
    return np.abs(v) if how == "maxabs" else -v if how == "min" else v


def peak_list(m: Any) -> list[tuple[str, str, str]]:
    """(label, output, how) of each peak the report gives for ``m``'s model: every pin's
    force, each slide's normal force both ways, TORQ both ways, SHAK."""
    from sielaff.engine import model_for
    from sielaff.engine.joints import joints
    from sielaff.engine.linkage_model import _renamer

    model = model_for(m)
    topology = model.topology
    rename = _renamer(topology)
    pins, slides = joints(topology)
    out = []
    for j in pins:
        on = "the frame" if j.on == 1 else f"link {j.on}"
        out.append((f"pin {j.point}, link {j.by} on {on} ({rename(j.name)})", rename(j.name),
                    "max"))
    for s in slides:
        name = rename(f"FN{s.label}")
        out += [(f"guide force {name}, largest", name, "max"),
                (f"guide force {name}, most negative", name, "min")]
    return out + [("driving torque, largest", "TORQ", "max"),
                  ("driving torque, most negative", "TORQ", "min"),
                  ("shaking force SHAK", "SHAK", "max")]


def peaks(m: Any, scene: Any) -> list[tuple[str, str, float, float]]:
    """(label, name, value, THETA 2 [deg]) for each of :func:`peak_list`: the grid's best,
    refined on a 0.001 deg grid 0.1 deg either side of it."""
    th = np.arange(0.0, 360.0, GRID)
    wanted = peak_list(m)
    names = sorted({p[1] for p in wanted})
    r = _analyze(m, th, names, scene)
    out = []
    for label, name, how in wanted:
        i = int(np.argmax(_score(np.asarray(r[name]), how)))
        fine = th[i] + np.arange(-GRID, GRID + FINE / 2, FINE)
        v = np.asarray(_analyze(m, np.mod(fine, 360.0), [name], scene)[name])
        j = int(np.argmax(_score(v, how)))
        out.append((label, name, float(v[j]), float(np.mod(fine[j], 360.0))))
    return out


def _fields(deck: Any, rep: CheckReport) -> None:
    from decimal import Decimal

    from sielaff.quantities import unit

    m = deck.mechanism
    names = type(m).SPEC_NAMES
    where = {field: f"[{t}] {k}" + (f".{sub}" if sub else "") for (t, k, sub), field in
             names.items()}
    rep.add(f'Linkage: the {m.TOPOLOGY.title} ([linkage] kind = "{m.KIND}"); units {m.units}')
    for name in m.as_dict():
        value = deck.exact.get(name, Decimal(repr(float(getattr(m, name)))))
        u = unit(name, m.units)
        what = where.get(name, "")
        if name.startswith("W") and m.units == "SI":
            what += " (a mass)"
        rep.add(f"  {name:<6} = {str(value):>10} {u:<12} {what}")
    from sielaff.tools.kinds import count, exact_range

    for i, r in enumerate(deck.ranges):
        n = count(*exact_range(deck, i))
        rep.add(f"  [[range]] {i + 1}: start = {r.THZERO:g} deg, step = {r.DELTA:g} deg, stop = "
                f"{r.THMAX:g} deg: {n} position{'s' if n != 1 else ''} in sielaff table")


def _dyads(m: Any, scene: Any, rep: CheckReport) -> list[dict[str, Any]]:
    """Each dyad's least margin over the revolution's grid (an RRR's least transmission
    angle, where it is)."""
    from sielaff.engine import model_for
    from sielaff.engine.assembly import dyad_name, margins
    from sielaff.linkage import RRR

    topology = model_for(m).topology
    th = np.arange(0.0, 360.0, GRID)
    values = {k: float(v) for k, v in m.as_dict().items()}
    mg = margins(topology, values, th, scene.branch)
    facts = []
    for i, d in enumerate(topology.dyads):
        v = np.where(np.isfinite(mg[i]), mg[i], np.inf)
        j = int(np.argmin(v))
        if not np.isfinite(v[j]):
            continue
        fact: dict[str, Any] = {"dyad": dyad_name(topology, i), "margin": float(v[j]),
                                "at": float(th[j])}
        if isinstance(d, RRR):
            gamma = _analyze(m, th, [f"GAMMA{d.joint}" if f"GAMMA{d.joint}" in
                                     model_for(m).outputs else "GAMMA"], scene)
            g = np.asarray(next(iter(gamma.values())))
            k = int(np.nanargmin(np.abs(g - 90.0) * -1.0))
            worst = float(g[k])
            fact["gamma"] = worst
            fact["at"] = float(th[k])
            rep.add(f"  {fact['dyad']}: transmission angle from {np.nanmin(g):.2f} to "
                    f"{np.nanmax(g):.2f} deg (furthest from 90 at THETA 2 = {th[k]:.1f})")
        else:
            rep.add(f"  {fact['dyad']}: least margin from its toggle {v[j]:.4g} at THETA 2 = "
                    f"{th[j]:.1f} deg")
        facts.append(fact)
    return facts


def _slider_geometry(m: Any, rep: CheckReport, facts: dict[str, Any]) -> None:
    from sielaff.quantities import unit
    from sielaff.slider_crank import stroke

    L = unit("R2", m.units)
    rep.add(f"  rod/crank ratio R3/R2 = {float(m.R3) / float(m.R2):.4g}")
    s = stroke(m)
    rep.add(f"  outer dead centre: XB = {s.xb_outer:.4f} {L} at THETA 2 = {s.at_outer:.3f} deg")
    rep.add(f"  inner dead centre: XB = {s.xb_inner:.4f} {L} at THETA 2 = {s.at_inner:.3f} deg")
    rep.add(f"  stroke {s.length:.4f} {L}; the crank turns {s.inward:.3f} deg on the inward "
            f"stroke, {s.outward:.3f} deg on the outward: time ratio {s.time_ratio:.4f}")
    facts["stroke"] = {"value": s.length, "unit": L}
    facts["dead_centres"] = {"outer": {"XB": s.xb_outer, "at": s.at_outer},
                             "inner": {"XB": s.xb_inner, "at": s.at_inner}, "unit": L}
    facts["time_ratio"] = s.time_ratio


def _inverted_geometry(m: Any, rep: CheckReport, facts: dict[str, Any]) -> None:
    from sielaff.inverted_slider_crank import quick_return

    if float(m.R2) > float(m.R1):
        rep.add("  R2 > R1: link 4 turns fully with the crank (a Whitworth quick return)")
        return
    q = quick_return(m)
    rep.add(f"  R2 < R1: link 4 rocks (a crank-shaper); it turns back at THETA 2 = "
            f"{q.at[0]:.3f} and {q.at[1]:.3f} deg: the crank turns {q.forward:.3f} deg one "
            f"way and {q.back:.3f} deg back, time ratio {q.time_ratio:.4f}")
    facts["quick_return"] = {"at": list(q.at), "forward": q.forward, "back": q.back,
                             "time_ratio": q.time_ratio}


def check_kind(deck: Any, scene: Any, crank_rocker: bool = False
               ) -> tuple[CheckReport, dict[str, Any]]:
    """The report for another kind's spec ``deck`` in ``scene`` (see the module doc), and
    its facts for ``--format json``.  A crank that cannot turn fully is usable (status 0:
    the commands work over the arcs where it assembles), as a four-bar that is not a
    crank-rocker is; ``crank_rocker`` (``check --crank-rocker``) requires one (exit 3)."""
    from sielaff.tools.common import describe_scene
    from sielaff.tools.kinds import full_turn_failure

    m = deck.mechanism
    system = m.units
    rep = CheckReport()
    facts: dict[str, Any] = {"kind": m.KIND, "units": system}
    rep.add(f"sielaff check: {deck.path}")
    rep.add()
    _fields(deck, rep)
    rep.add()
    rep.add("Geometry")
    failure = full_turn_failure(m, scene.branch)
    if failure:
        rep.add(f"  the crank cannot turn fully: {failure}")
        rep.add()
        if crank_rocker:
            rep.status = EXIT_NOT_CRANK_ROCKER
            rep.error = f"{deck.path}: [lengths]: {failure}"
            rep.add("Verdict: --crank-rocker: the crank rocks between its limits (exit 3)")
        else:
            rep.add("Verdict: usable where it assembles: the crank rocks between its limits "
                    "(sielaff table, plot and report work over those arcs; no revolution, so "
                    "no peaks over one, cycle work or flywheel)")
        facts.update(status=rep.status, error=rep.error, lines=rep.lines)
        return rep, facts
    rep.add("  the crank turns fully: every dyad closes over the whole revolution")
    facts["dyads"] = _dyads(m, scene, rep)
    if m.KIND == "slider-crank":
        _slider_geometry(m, rep, facts)
    elif m.KIND == "inverted-slider-crank":
        _inverted_geometry(m, rep, facts)
    rep.add()
    effects = describe_scene(scene, system)
    rep.add(f"One revolution (modern engine, {effects or 'no gravity, no loads'})")
    rep.add(f"  THETA 2 = 0 to 360 on a {GRID:g} deg grid, peaks refined to {FINE:g} deg")
    from sielaff.quantities import unit

    found = peaks(m, scene)
    width = max(len(p[0]) for p in found)
    for label, name, value, at in found:
        shown = f"{value:.4g} {unit(name, system)}"
        rep.add(f"  {label:<{width}} {shown:>16} at THETA 2 = {at:7.3f} deg")
    facts["peaks"] = [{"label": label, "name": name, "value": value,
                       "unit": unit(name, system), "at": at}
                      for label, name, value, at in found]
    work, abs_work = cycle_work(m, scene)
    rep.add(f"  cycle work, integral of TORQ d(THETA 2) over a revolution: "
            f"{work_text(work, abs_work, system)}")
    from sielaff.quantities import unit_of

    facts["cycle_work"] = {"value": work if math.isfinite(work) else None, "abs": abs_work,
                           "unit": unit_of("work", system)}
    _effects(m, scene, rep, facts)
    rep.add()
    from sielaff.tools.spec_fields import KIND_COMMANDS

    rep.add(f"Verdict: usable (sielaff {', '.join(KIND_COMMANDS)}); not a 1966 deck (sielaff "
            "run and punch take four-bars)")
    facts.update(status=rep.status, error=rep.error, lines=rep.lines)
    return rep, facts


def _effects(m: Any, scene: Any, rep: CheckReport, facts: dict[str, Any]) -> None:
    """Each effect the scene calls for: its parameters and its figures over a revolution."""
    from sielaff.design.effects import effect_facts, effects_json, effects_lines

    found = effect_facts(m, scene)
    if not found:
        return
    rep.add()
    rep.add("Scene (the effects the spec's [scene] calls for; docs/effects.md)")
    for line in effects_lines(found, m.units):
        rep.add(line)
    facts["effects"] = effects_json(found, m.units)


def cycle_work(m: Any, scene: Any) -> tuple[float, float]:
    """(integral of TORQ, of |TORQ|) d(THETA 2) [rad] over a revolution, trapezoid rule on
    the 0.1 deg grid, both ends."""
    th = np.linspace(0.0, 360.0, round(360.0 / GRID) + 1)
    torq = np.asarray(_analyze(m, th, ["TORQ"], scene)["TORQ"])
    x = np.radians(th)
    return float(np.trapezoid(torq, x)), float(np.trapezoid(np.abs(torq), x))


def kind_facts(facts: dict[str, Any]) -> str:
    """``--format json``: the facts as JSON."""
    import json

    return json.dumps(facts, indent=1) + "\n"
