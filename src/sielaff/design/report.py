"""The design answers as the text ``sielaff check`` and ``sielaff balance`` print.

Every number carries its unit (:func:`sielaff.quantities.unit`).  Values are printed to
a precision the engine's last bits cannot change, except where a value sits within a
few ulps of a printed-digit boundary, which the tests allow for.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sielaff.design.balance import counterweights
from sielaff.design.bearings import Pin
from sielaff.design.flywheel import Flywheel
from sielaff.design.kinds import four_bar_only
from sielaff.design.slider_balance import SliderBalance
from sielaff.engine.analysis import analyze
from sielaff.engine.scene import Scene
from sielaff.mechanism import Mechanism
from sielaff.quantities import fmt, unit, unit_of

__all__ = ["balance_lines", "bearing_lines", "compare", "flywheel_lines",
           "slider_balance_lines"]


#: A value below this fraction of its scale is roundoff and printed as 0, so the text
#: does not depend on the last bits of a CPU's libm.
ROUNDOFF = 1e-9


def _num(value: float, scale: float, width: int = 11) -> str:
    if abs(value) <= ROUNDOFF * abs(scale):
        return f"{'0':>{width}}"
    return f"{value:{width}.4g}"


def _energy_unit(system: str) -> str:
    return unit_of("work", system)


def power_text(value: float, system: str) -> str:
    """A power [in-lb/sec or W] as printed (with horsepower beside in-lb/sec)."""
    if value == 0.0:
        return fmt(0, "power", system, ".0f")
    if system == "in-lb-sec":
        return f"{fmt(value, 'power', system, '.0f')} = {value / 6600.0:.3g} hp"
    return fmt(value, "power", system, ".0f")


def flywheel_lines(fw: Flywheel, system: str) -> list[str]:
    """The flywheel section."""
    t, e, i = unit("TORQ", system), _energy_unit(system), unit("ZI2", system)
    mean = float(fw.mean_torque)
    if abs(mean) <= ROUNDOFF * float(fw.peak_torque):
        mean = 0.0  # roundoff: the cycle's net work is zero (TEX = 0, no loads)
    return [
        f"  flywheel on the crank shaft (coefficient of speed fluctuation cf = {fw.cf:g}):",
        f"    energy fluctuation        {float(fw.energy):11.4g} {e}",
        f"    flywheel inertia          {float(fw.inertia):11.4g} {i} "
        f"(at the mean speed TH2D = {float(fw.th2d):g} {unit('TH2D', system)})",
        f"    motor's mean torque       {_num(mean, 1.0)} {t}, mean power "
        + power_text(mean * float(fw.th2d), system),
        f"    peak |TORQ| without it    {float(fw.peak_torque):11.4g} {t} (with it the motor "
        "gives the mean)",
    ]


def _arcs(arcs: list[tuple[float, float]]) -> str:
    if not arcs:
        return "none (loaded all round)"
    return ", ".join(f"{a:.0f} to {b:.0f} deg" for a, b in arcs)


def bearing_lines(pins: dict[str, Pin], system: str) -> list[str]:
    """The bearings section (directions relative to each member, the report's Fig. 14)."""
    f = unit("FA32", system)
    share = next(iter(pins.values())).threshold if pins else 0.0
    out = ["  bearings (load direction on each member, deg CCW from its line; an arc never",
           "  loaded is an oil-groove candidate; reversals: of the load along the line;",
           f"  loads below {100 * share:g}% of the pin's peak do not count: --bearing-threshold):"]
    for pin in pins.values():
        out.append(f"    pin {pin.name:2} ({pin.force:4}) peak {pin.peak:9.1f} {f} at "
                   f"THETA 2 = {pin.at:5.1f} deg")
        for m in pin.members:
            out.append(f"      on the {m.name:7}: never loaded {_arcs(m.unloaded)}; "
                       f"{m.reversals} reversal{'s' if m.reversals != 1 else ''}")
    return out


#: The comparison rows: (label, output, reduction).
ROWS = (
    ("peak shaking force", "SHAK", "max"),
    ("peak |shaking moment|", "SHAKM", "maxabs"),
    ("peak |driving torque|", "TORQ", "maxabs"),
    ("RMS driving torque", "TORQ", "rms"),
    ("peak load, pin O2", "FOA", "max"),
    ("peak load, pin A", "FA32", "max"),
    ("peak load, pin B", "FB34", "max"),
    ("peak load, pin O4", "FOB", "max"),
)


def compare(before: Mechanism, after: Mechanism, n: int = 3600, *,
            scene: Scene | None = None) -> list[tuple[str, str, float, float]]:
    """(label, unit, before, after) for :data:`ROWS` over one revolution, or over the arcs
    where the linkage assembles when its crank cannot turn fully (the toggles, where the
    rates are infinite, left out).  A four-bar's (its pins); another kind is refused in
    one line."""
    four_bar_only(before, "compare (the four-bar's pins O2, A, B, O4)")
    import warnings

    from sielaff.engine.analysis import AssemblyWarning
    from sielaff.engine.classify import linkage_class
    from sielaff.engine.positions import reachable

    whole = bool(linkage_class(before).turns_fully)
    th = np.arange(n) * (360.0 / n) if whole else reachable(before, n)
    names = sorted({r[1] for r in ROWS})
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", AssemblyWarning)
        a, b = analyze(before, th, names, scene=scene), analyze(after, th, names, scene=scene)
    ok = np.ones(th.shape, bool)
    for r in (a, b):
        for name in names:
            ok &= np.isfinite(r[name])
    out = []
    for label, name, how in ROWS:
        vals = []
        for r in (a, b):
            v = r[name][ok]
            vals.append(float(np.max(v)) if how == "max" else float(np.max(np.abs(v)))
                        if how == "maxabs" else float(np.sqrt(np.mean(v * v))))
        out.append((label, unit(name, before.units), vals[0], vals[1]))
    return out


def balance_lines(before: Mechanism, after: Mechanism, radius2: Any = None,
                  radius4: Any = None, *, scene: Scene | None = None) -> list[str]:
    """The counterweights and the comparison, side by side (a four-bar's: another kind is
    refused in one line; a slider-crank's is :func:`slider_balance_lines`)."""
    four_bar_only(before, "balance_lines (Berkof-Lowen counterweights)")
    system = before.units
    w, r = unit("W2", system), unit("R1", system)
    cw2, cw4 = counterweights(before, radius2, radius4)
    out = ["Counterweights (Berkof-Lowen: the shaking force cancelled at every position)"]
    for c, name in ((cw2, "crank (link 2)"), (cw4, "rocker (link 4)")):
        out.append(f"  on the {name:15}: {float(c.weight):.4g} {w} at {float(c.radius):g} {r} "
                   f"from its pivot, {float(c.angle):.1f} deg from the link's line")
    out.append("  merged into the links:")
    for k in ("W2", "ZI2", "RG2", "ADEL2", "W4", "ZI4", "RG4", "ADEL4"):
        out.append(f"    {k:5} {float(getattr(before, k)):11.5g} -> "
                   f"{float(getattr(after, k)):11.5g} {unit(k, system)}")
    out.append("")
    from sielaff.engine.classify import linkage_class

    if linkage_class(before).turns_fully:
        out.append("Before and after, over one revolution (modern engine)")
    else:
        out.append("Before and after, over the crank angles where the linkage assembles "
                   "(modern engine)")
        out.append("  (toggles included: a crank kept at constant speed drives link 4 into a "
                   "toggle, where the rates and loads grow without bound)")
    out.append(f"  {'':24} {'before':>11} {'after':>11}")
    for label, u, b, a in compare(before, after, scene=scene):
        out.append(f"  {label:24} {_num(b, b)} {_num(a, b)} {u}")
    return out


def slider_balance_lines(b: SliderBalance) -> list[str]:
    """A slider-crank's crank counterweight (:func:`sielaff.design.slider_balance`) and
    what it leaves, before and after, over one revolution.

    Parameters
    ----------
    b : SliderBalance
        The answer [the slider-crank's unit system].
    """
    system = b.mechanism.units
    w, r, f = unit("W2", system), unit("R2", system), unit("SHAK", system)
    cw = b.counterweight
    out = ["Crank counterweight of a slider-crank (its shaking force cannot be cancelled by",
           "  counterweights: this is what one on the crank leaves)",
           f"  reciprocating {'mass' if system == 'SI' else 'weight'} (the slider and the rod's "
           f"share at B) {b.reciprocating:.4g} {w}",
           f"  rotating first moment (the crank and the rod's share at A) {b.rotating:.4g} "
           f"{w} {r}",
           f"  unbalanced along the stroke: primary {b.primary:.4g} {f}, secondary "
           f"{b.secondary:.4g} {f}",
           f"  on the crank: {float(cw.weight):.4g} {w} at {float(cw.radius):g} {r} from O2, "
           f"{float(cw.angle):.1f} deg from the crank's line ({float(b.product):.4g} {w} {r});",
           f"  it balances the rotating mass and {100 * b.fraction:g}% of the primary",
           "  merged into the crank:"]
    for k in ("W2", "ZI2", "RG2", "ADEL2"):
        out.append(f"    {k:5} {float(getattr(b.unbalanced, k)):11.5g} -> "
                   f"{float(getattr(b.mechanism, k)):11.5g} {unit(k, system)}")
    out += ["", "Shaking force over one revolution (modern engine)",
            f"  {'':30} {'before':>11} {'after':>11}"]
    rows = (("peak |SHAKX| (along the stroke)", "peak_x"), ("peak |SHAKY| (across it)", "peak_y"),
            ("peak SHAK", "peak"), ("primary along the stroke", "primary_along"),
            ("primary across the stroke", "primary_across"),
            ("secondary along the stroke", "secondary_along"))
    for label, key in rows:
        x, y = getattr(b.before, key), getattr(b.after, key)
        scale = max(b.before.peak, b.after.peak)
        out.append(f"  {label:30} {_num(x, scale)} {_num(y, scale)} {f}")
    return out
