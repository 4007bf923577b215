"""The sections of ``sielaff check``'s report, in the order they print: the deck, the
linkage, the scene's effects, one revolution, the design answers, the 1966 quirks, and
the kind of a linkage that is not a crank-rocker."""


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
from sielaff.tools.check.sheets import RangeSheets, _plain, num
from sielaff.tools.common import describe_scene, work_text

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
    #: design.bearings' pins the report printed (the JSON gives the same numbers).
    pins: dict | None = None
    #: The scene's effects the report printed (design.effects: the JSON's "effects").
    effects: list = field(default_factory=list)

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
            system = getattr(deck.mechanism, "units", "in-lb-sec")
            u = unit(name, system)
            meaning = MEANINGS[name]
            if system == "SI" and meaning.startswith("weight "):  # SI's W fields are masses
                meaning = "mass " + meaning.removeprefix("weight ")
            rep.add(f"  {head:7} {name:5} = {num(value):>9} {u:11}  {meaning}")
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


def _scene_section(m: Mechanism, rep: CheckReport, scene: Scene, figures: bool) -> None:
    """Each effect the scene calls for: its parameters with their units and (``figures``:
    the crank turns fully) its headline figures over a revolution, as the effect itself
    declares them (design.effects)."""
    from sielaff.design.effects import effect_facts, effects_lines

    facts = effect_facts(m, scene, figures=figures)
    if not facts:
        return
    rep.effects = facts
    rep.add("Scene (the effects the spec's [scene] calls for; docs/effects.md)")
    if figures:
        rep.add(f"  figures over one revolution at TH2D = {fmt(abs(m.TH2D), 'rate', m.units)}: "
                "mean powers, and the work of one revolution")
    for line in effects_lines(facts, m.units):
        rep.add(line)
    rep.add()


def _revolution_section(m: Mechanism, rep: CheckReport, scene: Scene | None = None,
                        pins: dict | None = None) -> None:
    """One revolution; the peak bearing loads are ``pins``' (design.bearings), the same
    numbers the bearings section prints."""
    from sielaff.design import bearings

    scene = scene or Scene()
    pins = pins if pins is not None else bearings(m, scene=scene)
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
    by_force = {pin.force: pin for pin in pins.values()}
    for name, heading, where in BEARINGS:
        at, value = by_force[name].at, by_force[name].peak
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


def _design_section(m: Mechanism, rep: CheckReport, scene: Scene | None = None,
                    pins: dict | None = None) -> None:
    """The flywheel and the bearings ``pins`` (docs/design.md); a crank acceleration has
    no steady speed to size a flywheel for."""
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
    pins = pins if pins is not None else bearings(m, scene=scene)
    for line in bearing_lines(pins, m.units):
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
            last, top, why = _plain(rs.last), _plain(rs.thmax), ""
            if last == top:  # past by roundoff of TH + I*DELTA: the digits that differ
                last, top = repr(float(rs.last)), repr(float(rs.thmax))
                why = ", by roundoff: THZERO - DELTA + I*DELTA in binary floating point"
            quirks.append(f"{where}: trailing sheet past THMAX: the last sheet is THETA 2 = "
                          f"{last} > THMAX = {top} (the 1966 loop prints a sheet before "
                          f"testing ATH2.GT.THMAX{why})")
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
    limit positions there, and the transmission angle over those arcs; a change point:
    where it folds, and the transmission angle."""
    import warnings

    from sielaff.engine import analyze
    from sielaff.engine.analysis import AssemblyWarning
    from sielaff.engine.positions import reachable
    from sielaff.tools.common import change_points

    scene = scene or Scene()
    c = linkage_class(m)
    if c.kind == "change-point":
        folds = change_points(m)
        at = " and ".join(f"{a:g}" for a in folds) or "one position"
        rep.add(f"Around the revolution (modern engine, the {scene.branch} branch)")
        rep.add(f"  change point: the four links lie in line at THETA 2 = {at} deg, where")
        rep.add("    the linkage can fold from one branch to the other: its rates are not "
                "defined there")
        rep.add("    (0/0), and near it the branch the engine follows jumps, so rates and loads "
                "grow")
        rep.add("    without bound: no peaks are reported; sielaff table and plot leave the "
                "position out")
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore", AssemblyWarning)
            g = analyze(m, reachable(m, 3601), ["GAMMA"], scene=scene)["GAMMA"]
        g = g[np.isfinite(g)]
        if g.size:
            rep.add(f"  transmission angle GAMMA: {g.min():.2f} to {g.max():.2f} deg (0 or 180 "
                    "where it folds)")
        return
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
