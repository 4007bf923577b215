"""``sielaff check --format json``: the report's facts, from the same computations."""


from __future__ import annotations

import math

import numpy as np

from sielaff.emulator.cards import Deck
from sielaff.engine.classify import linkage_class
from sielaff.engine.derived import cycle_work
from sielaff.engine.scene import Scene
from sielaff.mechanism import Mechanism, crank_rocker_failure
from sielaff.quantities import unit, unit_of
from sielaff.tools.check.sections import BEARINGS, CheckReport, _clamp, _extreme
from sielaff.tools.common import EXIT_DECK as EXIT_UNUSABLE
from sielaff.tools.common import work_text

__all__ = ["report_json"]


def report_json(deck: Deck, rep: CheckReport, scene: Scene | None = None) -> str:
    """The report as JSON, the same facts as the text: the linkage's kind and what decides
    it, the toggles, arcs and limit positions, the transmission angle, the peak loads and
    torques with their angles, the cycle work, the flywheel and bearings, the verdict, the
    status and error, and the report's lines.  A number is ``{"value": x, "unit": "lb"}``
    (angles in degrees, ``"deg"``), the unit the mechanism's unit system gives it."""
    import json

    m = deck.mechanism
    scene = scene or Scene()
    try:
        with np.errstate(all="ignore"):
            c = linkage_class(m)
    except (ValueError, ArithmeticError):  # fields no linkage has: the report says why
        c = None

    def finite(values) -> list[float]:
        return [float(v) for v in np.ravel(values) if np.isfinite(v)]

    system = getattr(m, "units", "in-lb-sec")
    length = unit_of("length", system)
    data: dict = {"path": str(deck.path), "units": system, "length_unit": length,
                  "lengths": {n: _q(getattr(m, n), length) for n in ("R1", "R2", "R3", "R4")}}
    if c is not None and rep.status != EXIT_UNUSABLE:
        data.update({
            "kind": c.kind, "grashof_sum": float(c.grashof_sum),
            "grashof_margin": float(c.grashof_margin), "turns_fully": bool(c.turns_fully),
            "toggles_deg": finite(c.toggles),
            "arcs_deg": [[float(a), float(b)] for a, b in (c.arcs or [])],
            "grashof": {"sum": _q(c.grashof_sum, length),
                        "margin": _q(c.grashof_margin, length)},
            "crank_rocker_failure": crank_rocker_failure(m, deck.exact)})
        if not c.turns_fully and c.arcs:
            data["limit_positions"] = _limit_positions(m, finite(c.toggles), scene)
    if rep.effects:  # each effect the scene calls for, as the text gives it
        from sielaff.design.effects import effects_json

        data["effects"] = effects_json(rep.effects, system)
    if rep.revolution:
        data.update(_revolution_facts(m, scene, rep.pins))
    verdict = next((line for line in reversed(rep.lines) if line.startswith("Verdict: ")), "")
    data.update({"verdict": verdict.removeprefix("Verdict: "), "status": rep.status,
                 "error": rep.error, "report": rep.lines})
    return json.dumps(data, indent=1) + "\n"


def _q(value: float, unit_text: str) -> dict:
    """A number with its unit for the JSON report (None for a value that is not finite)."""
    value = float(value)
    return {"value": value if math.isfinite(value) else None, "unit": unit_text}


def _limit_positions(m: Mechanism, toggles: list[float], scene: Scene) -> list[dict]:
    """THETA 3 and THETA 4 at each toggle, as the kind section prints them."""
    import warnings

    from sielaff.engine import analyze
    from sielaff.engine.analysis import AssemblyWarning

    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", AssemblyWarning)
        r = analyze(m, np.array(toggles), ["ATH3", "ATH4"], scene=scene)
    return [{"THETA 2": _q(t, "deg"), "THETA 3": _q(a, "deg"), "THETA 4": _q(b, "deg")}
            for t, a, b in zip(toggles, r["ATH3"], r["ATH4"])]


def _revolution_facts(m: Mechanism, scene: Scene, pins: dict | None = None) -> dict:
    """The revolution section's facts (the same computations: :func:`_extreme`,
    :func:`cycle_work`, the flywheel, and the text's :func:`sielaff.design.bearings`
    ``pins``, whose peaks are the peak loads)."""
    from sielaff.design import bearings, flywheel
    from sielaff.engine import analyze

    pins = pins if pins is not None else bearings(m, scene=scene)
    by_force = {pin.force: pin for pin in pins.values()}

    system = m.units
    deg = "deg"
    k = 2.0 * m.R3 * m.R4
    g_min = math.degrees(math.acos(_clamp((m.R3**2 + m.R4**2 - (m.R1 - m.R2) ** 2) / k)))
    g_max = math.degrees(math.acos(_clamp((m.R3**2 + m.R4**2 - (m.R1 + m.R2) ** 2) / k)))
    peaks = {}
    for name, heading, where in BEARINGS:
        at, value = by_force[name].at, by_force[name].peak
        direction = float(analyze(m, at, ["D" + name], scene=scene)["D" + name])
        peaks[name] = {"heading": heading, "pin": where, "peak": _q(value, unit(name, system)),
                       "theta2": _q(at, deg), "direction": _q(direction, deg)}
    torque = unit("TORQ", system)
    at_max, t_max = _extreme(m, "TORQ", scene=scene)
    at_min, t_min = _extreme(m, "TORQ", -1.0, scene=scene)
    force = unit("SHAK", system)
    at_shak, shak = _extreme(m, "SHAK", scene=scene)
    components = {f"{name}_{end}": _q(_extreme(m, name, sign, scene=scene)[1], force)
                  for name in ("SHAKX", "SHAKY") for end, sign in (("max", 1.0), ("min", -1.0))}
    work, abs_work = cycle_work(m, scene=scene)
    facts: dict = {
        "transmission_angle": {"min": _q(g_min, deg), "min_at_theta2": _q(0.0, deg),
                               "max": _q(g_max, deg), "max_at_theta2": _q(180.0, deg)},
        "peak_loads": peaks,
        "torque": {"max": _q(t_max, torque), "max_at_theta2": _q(at_max, deg),
                   "min": _q(t_min, torque), "min_at_theta2": _q(at_min, deg),
                   "peak_power": _q(max(abs(t_max), abs(t_min)) * abs(m.TH2D),
                                    unit_of("power", system))},
        "cycle_work": {"work": _q(work, unit_of("work", system)),
                       "abs_integral": _q(abs_work, unit_of("work", system)),
                       "text": work_text(work, abs_work, system)},
        "shaking_force": {"peak": _q(shak, force), "peak_at_theta2": _q(at_shak, deg),
                          **components},
    }
    if m.TH2D != 0.0 and not callable(scene.th2dd) and not np.any(scene.th2dd):
        fw = flywheel(m, scene=scene)
        facts["flywheel"] = {"cf": fw.cf, "energy": _q(fw.energy, unit_of("work", system)),
                             "inertia": _q(fw.inertia, unit("ZI2", system))}
    facts["bearings"] = [
        {"pin": pin.name, "force": pin.force, "peak": _q(pin.peak, force),
         "at_theta2": _q(pin.at, deg),
         "members": [{"member": mb.name, "never_loaded_deg": [[float(a), float(b)]
                                                              for a, b in mb.unloaded],
                      "reversals": int(mb.reversals)} for mb in pin.members]}
        for pin in pins.values()]
    return facts
