"""``sielaff check DECK``: what a designer needs to know about a deck before using it.

The report (stdout) has four parts:

Deck
    Every value as punched, with its unit and meaning, and for each range
    card the sheets the 1966 listing will print.
Linkage
    The Grashof sum (s + l against p + q, with its margin), which link is
    the shortest and so what kind of four-bar it is, and the report's five
    crank-rocker conditions (statements 45-51) each with its margin.
One revolution (modern engine, TEX = 0)
    Transmission angle extremes (closed form: they lie at THETA 2 = 0 and
    180) and the closest approach to toggle; the peak bearing loads F 2 ON 1
    (FOA), F 4 ON 1 (FOB), F 3 ON 2 (FA32) and F 3 ON 4 (FB34), the peak
    driving torque either way, the peak shaking force and its largest X and
    Y components, all found on a 0.1-degree grid and refined to 0.001
    degree; and the cycle work, the integral of TORQ over one revolution
    (trapezoid rule on the 0.1-degree grid), which is zero for TEX = 0 since
    the crank turns at constant speed.
1966 quirks
    Every quirk of docs/quirks.md this deck triggers in ``sielaff run``.  The
    sheets a range card prints, and so the trailing sheet past THMAX, the
    two sheets of THZERO = THMAX, the angles past 360 (Case II) or below 0
    (Case I) and an endless range, are predicted from the range cards with
    the port's own float64 arithmetic (THETA 2 = (THZERO - DELTA) + I*DELTA),
    so a deck of a million sheets is checked at once.  The TAN3/TAN4
    stand-in, SQRT of a negative argument, and a 1966 arithmetic that fails
    can only be seen by running the port: it is run (without printing) on
    the first ``SHEET_LIMIT`` sheets.

Exit status: 0 usable, 2 unusable (a deck that does not read, an endless
range, 1966 arithmetic that fails), 3 not a crank-rocker; the reason is one
line on stderr.

The module reads better whole: the report's sections follow in the order they print.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass, field
from decimal import Decimal

import numpy as np

from sielaff.design.report import power_text
from sielaff.emulator.cards import PARAMETER_CARDS, Deck
from sielaff.engine.classify import linkage_class
from sielaff.engine.derived import GRID_STEP, cycle_work, revolution
from sielaff.engine.scene import Scene
from sielaff.mechanism import Mechanism, crank_rocker_failure
from sielaff.quantities import fmt, unit, unit_of
from sielaff.tools.common import describe_scene, work_text

__all__ = [
    "SHEET_LIMIT", "CheckReport", "RangeSheets", "check_deck",
    "range_sheets", "revolution",
]

from sielaff.tools.common import EXIT_DECK as EXIT_UNUSABLE  # noqa: E402
from sielaff.tools.common import EXIT_NOT_CRANK_ROCKER  # noqa: E402

EXIT_OK = 0
#: Range cards reported one by one; the rest are counted.
DETAIL_CARDS = 20

#: The port is run on at most this many sheets to find the quirks that need it.
SHEET_LIMIT = 10_000

#: One revolution, the grid the loads are found on (degrees).
REFINE_STEP = 0.001

#: Rule of thumb for the transmission angle (degrees).
GAMMA_GUIDE = 40.0

MEANINGS = {
    "W2": "weight of link 2 (crank)",
    "W3": "weight of link 3 (coupler)",
    "W4": "weight of link 4 (rocker)",
    "ZI2": "moment of inertia of link 2 (used only when TH2DD != 0)",
    "ZI3": "moment of inertia of link 3 (about G3)",
    "ZI4": "moment of inertia of link 4 (about G4)",
    "R1": "frame, O2 to O4",
    "R2": "crank, O2 to A",
    "R3": "coupler, A to B",
    "R4": "rocker, O4 to B",
    "ADEL2": "line O2-G2, from link 2",
    "ADEL3": "line A-G3, from link 3",
    "ADEL4": "line O4-G4, from link 4",
    "RG2": "O2 to G2",
    "RG3": "A to G3",
    "RG4": "O4 to G4",
    "TH2D": "crank speed (constant)",
}

LINK_NAMES = {"R1": "frame", "R2": "crank", "R3": "coupler", "R4": "rocker"}

#: The bearing loads reported: (listing name, printed heading, the bearing).
BEARINGS = (
    ("FOA", "F 2 ON 1", "O2"),
    ("FOB", "F 4 ON 1", "O4"),
    ("FA32", "F 3 ON 2", "A"),
    ("FB34", "F 3 ON 4", "B"),
)


def num(value: float | Decimal) -> str:
    """A deck value as the report prints it: shortest exact form."""
    if isinstance(value, Decimal):
        if value == 0:
            return "0.0"
        text = f"{value.normalize():f}"
        if len(text) > 16:
            return f"{float(value):.10g}"
        return text if "." in text else text + ".0"
    return f"{value:.10g}" if "e" in f"{value:.10g}" else _plain(value)


def _plain(value: float) -> str:
    text = f"{value:.10g}"
    return text if "." in text else text + ".0"


# --------------------------------------------------------------------------
# What the 1966 loop does with a range card
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class RangeSheets:
    """The sheets the 1966 loop prints for one range card (float64 arithmetic).

    ``count`` is None for an endless range.  ``past_360``/``below_0`` are
    (number of sheets, first THETA 2, last THETA 2) or None.
    """

    thzero: float
    delta: float
    thmax: float
    count: int | None
    first: float | None = None
    last: float | None = None
    past_360: tuple[int, float, float] | None = None
    below_0: tuple[int, float, float] | None = None


def _angle(th: float, delta: float, i: int) -> float:
    """THETA 2 of sheet ``i`` (1-based): ``ATH2 = TH + ZZZ*DELTA``, as the port does it."""
    return th + float(i) * delta


def _first(pred, lo: int, hi: int) -> int:
    """The smallest i in [lo, hi] with pred(i) true, pred monotone; hi + 1 if none."""
    while lo <= hi:
        mid = (lo + hi) // 2
        if pred(mid):
            hi = mid - 1
        else:
            lo = mid + 1
    return lo


def range_sheets(thzero: float, delta: float, thmax: float) -> RangeSheets:
    """Predict the sheets of one range card without running the loop."""
    from sielaff.emulator.ranges import sheet_count

    th = thzero - delta
    n = sheet_count(thzero, delta, thmax)  # the port's own float64 loop, counted
    if n is None:
        return RangeSheets(thzero, delta, thmax, None)
    first, last = _angle(th, delta, 1), _angle(th, delta, n)
    past = below = None
    if delta > 0.0:
        k = _first(lambda i: _angle(th, delta, i) > 360.0, 1, n)
        if k <= n:
            past = (n - k + 1, _angle(th, delta, k), last)
        k = _first(lambda i: not _angle(th, delta, i) < 0.0, 1, n)
        if k > 1:
            below = (k - 1, first, _angle(th, delta, k - 1))
    else:
        if first > 360.0:
            past = (1, first, first)
        if first < 0.0:
            below = (1, first, first)
    return RangeSheets(thzero, delta, thmax, n, first, last, past, below)


# --------------------------------------------------------------------------
# One revolution with the modern engine
# --------------------------------------------------------------------------


def _extreme(mechanism: Mechanism, name: str, sign: float = 1.0,
             scene: Scene | None = None) -> tuple[float, float]:
    """(THETA 2, value) where ``sign * name`` is largest over one revolution."""
    from sielaff.engine import analyze

    th = revolution()[:-1]
    scene = scene or Scene()
    v = sign * analyze(mechanism, th, [name], scene=scene)[name]
    t0 = th[int(np.argmax(v))]
    fine = t0 + np.arange(-GRID_STEP, GRID_STEP + REFINE_STEP / 2, REFINE_STEP)
    v = sign * analyze(mechanism, fine, [name], scene=scene)[name]
    i = int(np.argmax(v))
    return float(fine[i] % 360.0) + 0.0, float(sign * v[i])


# --------------------------------------------------------------------------
# The report
# --------------------------------------------------------------------------


@dataclass
class CheckReport:
    """The lines printed, the exit status and (if not 0) the one-line reason."""

    lines: list[str] = field(default_factory=list)
    status: int = EXIT_OK
    error: str | None = None
    #: The report has the revolution's peaks, cycle work and bearings (``--format json``
    #: gives the same facts).
    revolution: bool = False

    def add(self, text: str = "") -> None:
        self.lines.append(text)

    @property
    def text(self) -> str:
        return "\n".join(self.lines) + "\n"


def _deck_section(deck: Deck, rep: CheckReport, sheets: list[RangeSheets]) -> None:
    n_cards = len(PARAMETER_CARDS) + len(deck.ranges)
    rep.add(f"Deck: {len(PARAMETER_CARDS)} parameter cards and {len(deck.ranges)} range "
            f"card{'s' if len(deck.ranges) != 1 else ''} ({n_cards} cards); units "
            f"{getattr(deck.mechanism, 'units', 'in-lb-sec')}")
    for card, names in enumerate(PARAMETER_CARDS, 1):
        for k, name in enumerate(names):
            value = deck.exact.get(name, Decimal(repr(getattr(deck.mechanism, name))))
            head = f"card {card}" if k == 0 else ""
            u = unit(name, getattr(deck.mechanism, "units", "in-lb-sec"))
            rep.add(f"  {head:7} {name:5} = {num(value):>9} {u:11}  {MEANINGS[name]}")
    for card, rs, exact in zip(deck.range_cards, sheets, _exact_ranges(deck)):
        rep.add(f"  card {card:<2} THZERO = {num(exact[0])} deg, DELTA = {num(exact[1])} deg, "
                f"THMAX = {num(exact[2])} deg")
        if rs.count is None:
            rep.add("          1966 listing: endless (see the quirks below)")
        elif rs.count == 1:
            rep.add(f"          1966 listing: 1 sheet, THETA 2 = {_plain(rs.first)}")
        else:
            rep.add(f"          1966 listing: {rs.count:,} sheets, THETA 2 = {_plain(rs.first)} "
                    f"to {_plain(rs.last)}")
    more = len(deck.ranges) - len(sheets)
    if more > 0:
        rest = _more_sheets(deck, len(sheets))
        rep.add(f"  cards {deck.range_cards[len(sheets)]}-{deck.range_cards[-1]}: {more:,} more "
                f"range cards, {rest:,} sheets (shown in detail: the first {DETAIL_CARDS})")
    for warning in deck.warnings:
        rep.add(f"  warning: {warning}")


def _more_sheets(deck: Deck, start: int) -> int:
    """Sheets of the range cards from ``start`` on (0 for one that never ends: the quirks
    and the verdict say so)."""
    from sielaff.emulator.ranges import sheet_count

    return sum(sheet_count(*deck.ranges[i]) or 0 for i in range(start, len(deck.ranges)))


def _exact_ranges(deck: Deck) -> list[tuple]:
    """The first DETAIL_CARDS range cards' values as punched (as floats for a deck in code)."""
    if deck.exact_ranges and len(deck.exact_ranges) == len(deck.ranges):
        return list(deck.exact_ranges[:DETAIL_CARDS])
    return [tuple(r) for r in deck.ranges[:DETAIL_CARDS]]


def _linkage_section(m: Mechanism, rep: CheckReport, exact: dict | None = None) -> str | None:
    rep.add("Linkage")
    links = sorted(("R1", "R2", "R3", "R4"), key=lambda n: getattr(m, n))
    s, p, q, lng = (getattr(m, n) for n in links)
    L = unit_of("length", m.units)  # noqa: N806
    rep.add("  lengths: " + ", ".join(f"{LINK_NAMES[n]} {n} = {_plain(getattr(m, n))} {L}"
                                      for n in ("R1", "R2", "R3", "R4")))
    sl, pq = s + lng, p + q
    if sl < pq:
        verdict, cmp = "a Grashof linkage: the shortest link turns fully", "<"
    elif sl > pq:
        verdict, cmp = "not Grashof: no link turns fully (a triple rocker)", ">"
    else:
        verdict, cmp = "a change-point linkage: all four links can line up", "="
    rep.add(f"  Grashof sum: s + l = {_plain(s)} + {_plain(lng)} = {_plain(sl)} {L} {cmp} "
            f"p + q = {_plain(p)} + {_plain(q)} = {_plain(pq)} {L} (margin {_plain(pq - sl)} {L})")
    rep.add(f"    {verdict}")
    shortest = [n for n in links if getattr(m, n) == s]
    names = " and ".join(f"{LINK_NAMES[n]} {n}" for n in shortest)
    c = linkage_class(m)
    phrase = {"crank-rocker": "a crank-rocker", "double-crank": "a double crank (drag link)",
              "double-rocker": "a double rocker", "rocker-crank":
              "a rocker-crank (link 4 turns fully)"}.get(c.kind)
    if phrase and len(shortest) == 1:
        rep.add(f"  shortest link: {names} = {_plain(s)} {L}, so {phrase}")
    else:
        rep.add(f"  shortest link{'s' if len(shortest) > 1 else ''}: {names} = {_plain(s)} {L}")
    if c.kind != "crank-rocker":
        rep.add(f"  kind: {c.kind} (link 2 the input, link 1 the frame; sielaff.linkage_class)")
        for a, b in ([] if c.turns_fully else c.arcs):
            through = " (through 0)" if b < a else ""
            rep.add(f"    link 2 swings from THETA 2 = {a:.2f} deg to {b:.2f} deg{through}, "
                    "between toggles")
    failure = crank_rocker_failure(m, exact)
    if not m.R2 > 0:
        rep.add(f"  crank-rocker conditions: {failure}")
        return failure
    A, B, C = m.R3 / m.R2, m.R4 / m.R2, m.R1 / m.R2
    rep.add("  crank-rocker conditions (report p. 4; statements 45-51), "
            "A = R3/R2, B = R4/R2, C = R1/R2:")
    rows = (
        (f"A = {A:.6g} > 1", A - 1.0),
        (f"B = {B:.6g} > 1", B - 1.0),
        (f"C = {C:.6g} > 1", C - 1.0),
        (f"C = {C:.6g} < A + B - 1 = {A + B - 1.0:.6g}", A + B - 1.0 - C),
        (f"C = {C:.6g} > |B - A| + 1 = {abs(B - A) + 1.0:.6g}", C - abs(B - A) - 1.0),
    )
    for text, margin in rows:
        rep.add(f"    {text:38} margin {margin:<8.4g} {'ok' if margin > 0 else 'FAILS'}")
    return failure


def _clamp(x: float) -> float:
    return min(1.0, max(-1.0, x))


def _revolution_section(m: Mechanism, rep: CheckReport, scene: Scene | None = None) -> None:
    scene = scene or Scene()
    system = getattr(m, "units", "in-lb-sec")
    U = {"lb": unit("FA32", system), "in-lb": unit("TORQ", system)}  # noqa: N806
    effects = describe_scene(scene, system)
    if effects:
        rep.add(f"One revolution (modern engine, with the spec's scene: {effects})")
    else:
        rep.add("One revolution (modern engine, TEX = 0)")
    rep.add(f"  THETA 2 = 0 to 360 on a {GRID_STEP:g} deg grid, peaks refined to "
            f"{REFINE_STEP:g} deg")
    # Transmission angle: ZL is smallest at THETA 2 = 0 and largest at 180.
    k = 2.0 * m.R3 * m.R4
    g_min = math.degrees(math.acos(_clamp((m.R3**2 + m.R4**2 - (m.R1 - m.R2) ** 2) / k)))
    g_max = math.degrees(math.acos(_clamp((m.R3**2 + m.R4**2 - (m.R1 + m.R2) ** 2) / k)))
    rep.add("  transmission angle GAMMA (between coupler and rocker, at B):")
    rep.add(f"    minimum {g_min:6.2f} deg at THETA 2 = 0.0 deg")
    rep.add(f"    maximum {g_max:6.2f} deg at THETA 2 = 180.0 deg")
    if g_min <= 180.0 - g_max:
        toggle, at, which = g_min, 0.0, "0"
    else:
        toggle, at, which = 180.0 - g_max, 180.0, "180"
    rep.add(f"    closest approach to toggle (GAMMA = {which} deg): {toggle:.2f} deg, "
            f"at THETA 2 = {at:.1f} deg")
    lo, hi = GAMMA_GUIDE, 180.0 - GAMMA_GUIDE
    if g_min < lo or g_max > hi:
        near = " and ".join(a for bad, a in ((g_min < lo, "0"), (g_max > hi, "180")) if bad)
        rep.add(f"    outside the usual {lo:.0f}-{hi:.0f} deg guideline: the rocker is "
                f"driven poorly near THETA 2 = {near} deg")
    else:
        rep.add(f"    within the usual {lo:.0f}-{hi:.0f} deg guideline")
    from sielaff.engine import analyze

    rep.add("  peak bearing loads:")
    peak_loads = []
    for name, heading, where in BEARINGS:
        at, value = _extreme(m, name, scene=scene)
        peak_loads.append(value)
        direction = float(analyze(m, at, ["D" + name], scene=scene)["D" + name])
        rep.add(f"    {heading} ({name + ')':5} at {where:2} {value:9.1f} {U['lb']} at THETA 2 = "
                f"{at:5.1f} deg, direction {direction:5.1f} deg")
    at_max, t_max = _extreme(m, "TORQ", scene=scene)
    at_min, t_min = _extreme(m, "TORQ", -1.0, scene=scene)
    peak = max(abs(t_max), abs(t_min))
    rep.add("  driving torque TORQ:")
    rep.add(f"    largest       {t_max:9.1f} {U['in-lb']} at THETA 2 = {at_max:5.1f} deg")
    rep.add(f"    most negative {t_min:9.1f} {U['in-lb']} at THETA 2 = {at_min:5.1f} deg")
    rep.add(f"    peak power |TORQ| TH2D = {power_text(peak * abs(m.TH2D), system)}")
    work, abs_work = cycle_work(m, scene=scene)
    ok = abs(work) <= 1e-6 * max(abs_work, 1.0)
    rep.add("  cycle work, integral of TORQ d(THETA 2) over a revolution: "
            + work_text(work, abs_work, system))
    if effects:
        rep.add(f"    (integral of |TORQ|: {fmt(abs_work, 'work', system, '.1f')}): the work "
                "the scene's "
                "loads, crank acceleration, friction and dampers take (gravity's and a "
                "spring's are zero)")
    else:
        rep.add(f"    (integral of |TORQ|: {fmt(abs_work, 'work', system, '.1f')}): "
                + ("zero, as it must be with TEX = 0" if ok else "NOT zero although TEX = 0"))
    at, shak = _extreme(m, "SHAK", scene=scene)
    _, sx = _extreme(m, "SHAKX", scene=scene)
    _, sx_neg = _extreme(m, "SHAKX", -1.0, scene=scene)
    _, sy = _extreme(m, "SHAKY", scene=scene)
    _, sy_neg = _extreme(m, "SHAKY", -1.0, scene=scene)
    if shak <= 1e-9 * max(peak_loads):  # balanced: zero to roundoff, an angle would be noise
        rep.add(f"  shaking force SHAKE: 0 {U['lb']} to roundoff (below 1E-9 of the largest "
                "pin load): the linkage is force-balanced")
    else:
        text = f"{shak:.1f}" if shak >= 1.0 else f"{shak:.2g}"  # a balanced deck's residual
        rep.add(f"  shaking force SHAKE: peak {text} {U['lb']} at THETA 2 = {at:.1f} deg")
    rep.add(f"    X component from {sx_neg:.1f} to {sx:.1f} {U['lb']}, "
            f"Y component from {sy_neg:.1f} to {sy:.1f} {U['lb']}")


def _design_section(m: Mechanism, rep: CheckReport, scene: Scene | None = None) -> None:
    """The flywheel and the bearings (docs/design.md); a crank acceleration has no steady
    speed to size a flywheel for."""
    from sielaff.design import bearings, flywheel
    from sielaff.design.report import bearing_lines, flywheel_lines

    scene = scene or Scene()
    if m.TH2D == 0.0:
        rep.add("  flywheel: not sized (TH2D = 0: the crank does not turn)")
    elif not callable(scene.th2dd) and not np.any(scene.th2dd):
        for line in flywheel_lines(flywheel(m, scene=scene), m.units):
            rep.add(line)
    else:
        rep.add("  flywheel: not sized (the scene accelerates the crank; a flywheel is sized "
                "at a steady speed)")
    for line in bearing_lines(bearings(m, scene=scene), m.units):
        rep.add(line)


class _Collector:
    """A ``notice`` callback that keeps the port's notices by kind."""

    def __init__(self) -> None:
        self.by_kind: dict[str, list[str]] = {}

    def __call__(self, kind: str, text: str) -> None:
        self.by_kind.setdefault(kind, []).append(text)


class _NullSink:
    def write(self, text: str) -> int:
        return len(text)

    def flush(self) -> None:
        pass


def _quirk_section(deck: Deck, sheets: list[RangeSheets], rep: CheckReport,
                   sheet_limit: int) -> str | None:
    """The quirks; returns the one-line reason if the deck is unusable."""
    from sielaff.tools.common import range_problem

    rep.add("1966 quirks this deck triggers in sielaff run")
    rep.add("  (docs/quirks.md; the modern engine has none of them)")
    quirks: list[str] = []
    for card, rs in zip(deck.range_cards, sheets):
        where = f"card {card}"
        if rs.count is None:
            quirks.append(f"{where}, columns 9-16: DELTA = {_plain(rs.delta)} with THZERO = "
                          f"{_plain(rs.thzero)} <= THMAX = {_plain(rs.thmax)}: the 1966 loop "
                          "never ends (THETA 2 never passes THMAX); sielaff run refuses the deck")
            continue
        if rs.count == 1 and rs.thzero > rs.thmax:
            quirks.append(f"{where}: THZERO = {_plain(rs.thzero)} > THMAX = {_plain(rs.thmax)}, "
                          f"yet the 1966 loop prints one sheet, at THETA 2 = {_plain(rs.first)}")
        elif rs.thzero == rs.thmax:
            quirks.append(f"{where}: THZERO = THMAX = {_plain(rs.thmax)} prints "
                          f"{rs.count} sheets (THETA 2 = {_plain(rs.first)} to "
                          f"{_plain(rs.last)}), not the one the report promises")
        else:
            quirks.append(f"{where}: trailing sheet past THMAX: the last sheet is THETA 2 = "
                          f"{_plain(rs.last)} > THMAX = {_plain(rs.thmax)} (the 1966 loop "
                          "prints a sheet before testing ATH2.GT.THMAX)")
        for span, text in ((rs.past_360, "past one revolution, where the 1966 program takes "
                            "the Case II branch (TH2 >= PI)"),
                           (rs.below_0, "below zero, where the 1966 program takes the Case I "
                            "branch (TH2 < PI)")):
            if span:
                n, a, b = span
                at = (f"THETA 2 = {_plain(a)}" if n == 1
                      else f"THETA 2 = {_plain(a)} to {_plain(b)}")
                quirks.append(f"{where}: {n:,} sheet{'s' if n > 1 else ''} {text}: {at}; "
                              f"{'their' if n > 1 else 'its'} THETA 3, THETA 4 and all that "
                              "follows are not the mechanism's")
    problem = range_problem(deck)
    reason = None if problem is None else str(problem)
    if reason is None and crank_rocker_failure(deck.mechanism, deck.exact) is None:
        reason = _run_port(deck, sheets, quirks, sheet_limit)
    if len(deck.ranges) > len(sheets):
        quirks.append(f"(range-card quirks of the first {DETAIL_CARDS} range cards only; "
                      "sielaff run reports every one)")
    for q in quirks:
        rep.lines.extend(textwrap.wrap(q, 96, initial_indent="  ", subsequent_indent="    ",
                                       break_on_hyphens=False))
    if not quirks:
        rep.add("  none")
    return reason


def _run_port(deck: Deck, sheets: list[RangeSheets], quirks: list[str],
              sheet_limit: int) -> str | None:
    """Run the port without printing; add the quirks only a run shows."""
    from sielaff.emulator.program import ProgramError, SheetLimit
    from sielaff.emulator.run import run

    total = sum(rs.count or 0 for rs in sheets) + _more_sheets(deck, len(sheets))
    notes = _Collector()
    reason = None
    try:
        run(deck, _NullSink(), notice=notes, max_sheets=sheet_limit)
    except SheetLimit:
        pass
    except ProgramError as exc:
        reason = f"{deck.path}: the 1966 arithmetic fails: {exc}"
        quirks.append(f"the 1966 arithmetic fails: {exc}; sielaff run stops there")
    for kind in ("tan-standin", "library"):
        texts = notes.by_kind.get(kind, [])
        quirks.extend(texts[:5])
        if len(texts) > 5:
            quirks.append(f"... and {len(texts) - 5:,} more like it")
    if total > sheet_limit:
        quirks.append(f"(TAN3/TAN4 stand-ins and SQRT errors: only the first {sheet_limit:,} of "
                      f"the {total:,} sheets were run; sielaff run reports the rest)")
    return reason


def _kind_section(m: Mechanism, rep: CheckReport, scene: Scene | None = None) -> None:
    """A linkage whose crank cannot turn fully: its toggles, the arcs it swings over, the
    limit positions there, and the transmission angle over those arcs."""
    import warnings

    from sielaff.engine import analyze
    from sielaff.engine.analysis import AssemblyWarning
    from sielaff.engine.positions import reachable

    scene = scene or Scene()
    c = linkage_class(m)
    rep.add(f"Over the arcs where it assembles (modern engine, the {scene.branch} branch)")
    toggles = [float(t) for t in np.ravel(c.toggles) if np.isfinite(t)]
    rep.add("  toggles (coupler and rocker in line) at THETA 2 = "
            + ", ".join(f"{t:.2f}" for t in toggles) + " deg")
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", AssemblyWarning)
        r = analyze(m, np.array(toggles), ["ATH3", "ATH4"], scene=scene)
        for t, th3, th4 in zip(toggles, r["ATH3"], r["ATH4"]):
            rep.add(f"    limit position at THETA 2 = {t:7.2f} deg: THETA 3 = {th3:7.2f} deg, "
                    f"THETA 4 = {th4:7.2f} deg")
        th = reachable(m, 3601)
        g = analyze(m, th, ["GAMMA"], scene=scene)["GAMMA"]
    g = g[np.isfinite(g)]
    if g.size:
        rep.add(f"  transmission angle GAMMA over the arcs: {g.min():.2f} to {g.max():.2f} deg "
                "(0 or 180 at a toggle)")
    rep.add("  loads: a crank kept at constant speed drives link 4 into each toggle, where the "
            "rates and loads grow without bound; sielaff table and plot show them over the arcs")


def check_deck(deck: Deck, sheet_limit: int = SHEET_LIMIT,
               scene: Scene | None = None, crank_rocker: bool = False) -> CheckReport:
    """The report for ``deck`` (see the module doc).  A usable linkage of another kind
    gets its kind's report and status 0, unless ``crank_rocker`` requires one (3)."""
    from sielaff.tools.common import mechanism_problem, results_problem

    rep = CheckReport()
    rep.add(f"sielaff check: {deck.path}")
    rep.add()
    # Range cards in detail up to DETAIL_CARDS; past that only counted (flat memory, and a
    # million-card deck is checked in seconds).
    sheets = [range_sheets(*r) for r in deck.ranges[:DETAIL_CARDS]]
    _deck_section(deck, rep, sheets)
    rep.add()
    problem = mechanism_problem(deck)
    if problem is not None and problem.status == EXIT_UNUSABLE:
        rep.status, rep.error = problem.status, str(problem)
        rep.add(f"Verdict: unusable: {str(problem).split(': ', 1)[1]} (exit 2)")
        return rep
    failure = _linkage_section(deck.mechanism, rep, deck.exact)
    rep.add()
    overflow = None
    other = failure is not None and not crank_rocker and linkage_class(deck.mechanism).arcs
    if other and not linkage_class(deck.mechanism).turns_fully:
        _kind_section(deck.mechanism, rep, scene)
        rep.add()
    if failure is None or (other and linkage_class(deck.mechanism).turns_fully):
        overflow = results_problem(deck, None, scene)
        if overflow is None:
            _revolution_section(deck.mechanism, rep, scene)
            _design_section(deck.mechanism, rep, scene)
            rep.revolution = True
            rep.add()
    reason = _quirk_section(deck, sheets, rep, sheet_limit)
    rep.add()
    if other and overflow is None:
        kind = linkage_class(deck.mechanism).kind
        rep.add(f"Verdict: usable as a {kind} in the modern tools (check, table, plot, balance, "
                "sweep); not a crank-rocker, so sielaff run stops at statement 52 as the 1966 "
                "program does (exit 3 there, and here with --crank-rocker)")
    elif failure is not None and not other and not crank_rocker:
        rep.status = EXIT_UNUSABLE
        rep.error = f"{deck.path}: card 3: the loop never closes: no crank angle assembles it"
        rep.add("Verdict: unusable: no crank angle assembles this linkage (exit 2)")
    elif failure is not None:
        rep.status = EXIT_NOT_CRANK_ROCKER
        rep.error = str(problem)
        if _program_test_passes(deck.mechanism):
            rep.add("Verdict: not a crank-rocker (exit 3), although the 1966 program's own "
                    "test passes by roundoff: sielaff run prints sheets whose forces near the "
                    "toggle are meaningless")
        else:
            rep.add("Verdict: not a crank-rocker; the 1966 program stops at statement 52 "
                    "(exit 3)")
    elif reason is not None or overflow is not None:
        rep.status = EXIT_UNUSABLE
        rep.error = reason or str(overflow)
        rep.add("Verdict: unusable: sielaff run cannot complete this deck (exit 2)")
    else:
        traps = sum("no decimal point: read as" in w for w in deck.warnings)
        if traps:
            rep.add(f"Verdict: usable as read, but {traps} field{'s' if traps > 1 else ''} "
                    "without a decimal point read with 4 implied decimals (warnings above): "
                    "make sure that was meant")
        else:
            rep.add("Verdict: usable")
    return rep


def _program_test_passes(m: Mechanism) -> bool:
    """The 1966 test of statements 45-51 as the float64 port evaluates it."""
    from sielaff.emulator.program import first_failed_test

    return first_failed_test(m.R3 / m.R2, m.R4 / m.R2, m.R1 / m.R2, abs) is None


def cmd_check(args) -> int:
    """``sielaff check DECK``: the report on stdout, the reason for a non-zero exit on stderr."""
    import sys

    from sielaff.tools.common import (
        CommandError,
        input_exists,
        is_spec,
        read_input_deck,
        read_spec_deck,
        refuse_bad_output,
        write_stdout,
    )

    output = getattr(args, "output", None)
    refuse_bad_output(output, [args.deck])  # before any work
    if not input_exists(args.deck):
        raise CommandError(f"{args.deck}: no such deck")
    if is_spec(args.deck):  # a spec: its deck, and its scene for the engine
        deck, scene = read_spec_deck(args.deck)
    else:
        deck, scene = read_input_deck(args.deck), Scene()
    if getattr(args, "branch", None):
        import dataclasses

        scene = dataclasses.replace(scene, branch=args.branch)
    rep = check_deck(deck, scene=scene, crank_rocker=getattr(args, "crank_rocker", False))
    text = (rep.text if getattr(args, "format", "text") == "text"
            else report_json(deck, rep, scene))
    if output not in (None, "-"):
        from sielaff.tools.output import atomic_output

        with atomic_output(output) as out:
            out.write(text)
    else:
        write_stdout(text)  # a closed pipe keeps the status and the error line
    if rep.error:
        print(rep.error, file=sys.stderr)
    return rep.status


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
    if rep.revolution:
        data.update(_revolution_facts(m, scene))
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


def _revolution_facts(m: Mechanism, scene: Scene) -> dict:
    """The revolution section's facts (the same computations: :func:`_extreme`,
    :func:`cycle_work`, the flywheel and :func:`sielaff.design.bearings`)."""
    from sielaff.design import bearings, flywheel
    from sielaff.engine import analyze

    system = m.units
    deg = "deg"
    k = 2.0 * m.R3 * m.R4
    g_min = math.degrees(math.acos(_clamp((m.R3**2 + m.R4**2 - (m.R1 - m.R2) ** 2) / k)))
    g_max = math.degrees(math.acos(_clamp((m.R3**2 + m.R4**2 - (m.R1 + m.R2) ** 2) / k)))
    peaks = {}
    for name, heading, where in BEARINGS:
        at, value = _extreme(m, name, scene=scene)
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
        for pin in bearings(m, scene=scene).values()]
    return facts
