"""Slider-cranks synthesised for a stroke and a time ratio, and the crank-shaper, against
what does not trust the construction: the engine's slider position and link angles over
a turn (their extremes found from a fine grid and refined to the zero of the engine's own
rate), the kind modules' dead centres and quick return, and Khurmi and Gupta's printed
worked example."""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest

import sielaff.synthesis.slider_crank as synth
from sielaff import analyze
from sielaff.inverted_slider_crank import quick_return
from sielaff.slider_crank import stroke as dead_centres
from sielaff.synthesis.slider_crank import crank_shaper, offset_slider_crank

#: (stroke, time ratio, working, th2d, units): in-line, mild and strong quick returns,
#: either working direction, either turning, both unit systems
CASES = [(4.0, 1.0, "outward", 1.0, "in-lb-sec"),
         (4.0, 1.25, "outward", 10.0, "in-lb-sec"),
         (0.15, 1.6, "inward", 5.0, "SI"),
         (2.5, 2.2, "outward", -3.0, "in-lb-sec"),
         (7.0, 2.8, "inward", -1.0, "in-lb-sec")]
GRID = np.arange(7200) * 0.05  # crank angles [deg]


def _bisect(m, rate, lo, hi, branch):
    """The crank angle in [lo, hi] where the engine's ``rate`` changes sign."""
    f_lo = float(analyze(m, np.array([lo]), [rate], branch=branch)[rate][0])
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        f = float(analyze(m, np.array([mid]), [rate], branch=branch)[rate][0])
        if f == 0.0:
            return mid
        if (f > 0.0) == (f_lo > 0.0):
            lo, f_lo = mid, f
        else:
            hi = mid
    return 0.5 * (lo + hi)


def engine_extremes(m, name, rate, branch="open"):
    """The crank angles [deg] and values of the engine's largest and smallest ``name``
    over a turn: the grid's extreme, refined where ``rate`` (its derivative) is zero."""
    v = analyze(m, GRID, [name], branch=branch)[name]
    out = []
    for i in (int(np.argmax(v)), int(np.argmin(v))):
        th = _bisect(m, rate, GRID[i] - 0.05, GRID[i] + 0.05, branch)
        out.append((th % 360.0, float(analyze(m, np.array([th]), [name],
                                              branch=branch)[name][0])))
    return out


def _turn(a, b, sign):
    """The crank's turn [deg] from a to b, turning CCW (sign > 0) or CW."""
    return (math.copysign(1.0, sign) * (b - a)) % 360.0


def _rel(a, b):
    return abs(a - b) / abs(b)


@pytest.mark.parametrize("case", CASES)
def test_every_member_has_the_stroke_and_time_ratio_the_engine_finds(case):
    S, Q, working, th2d, units = case
    fam = offset_slider_crank(S, Q, working=working, th2d=th2d, units=units)
    designs = fam.members(6) + [fam.best]
    assert len(designs) == 7
    for d in designs:
        m = d.mechanism
        assert m.units == units and m.TH2D == th2d and d.branch == "open"
        (th_out, xb_out), (th_in, xb_in) = engine_extremes(m, "XB", "VXB", d.branch)
        assert _rel(xb_out - xb_in, S) < 1e-9, (d.ratio, xb_out - xb_in)
        # the slow stroke moves the slider the way ``working`` says, turning as TH2D does
        outward = _turn(th_in, th_out, th2d)
        slow = outward if working == "outward" else 360.0 - outward
        assert _rel(slow / (360.0 - slow), Q) < 1e-9, (d.ratio, slow)
        start, end = (th_in, th_out) if working == "outward" else (th_out, th_in)
        assert abs((d.dead_centres[0] - start + 180.0) % 360.0 - 180.0) < 1e-9
        assert abs((d.dead_centres[1] - end + 180.0) % 360.0 - 180.0) < 1e-9
        # the kind module's construction of the dead centres agrees
        st = dead_centres(m)
        assert _rel(st.length, S) < 1e-9 and _rel(st.time_ratio, Q) < 1e-9
        assert _rel(m.R3 / m.R2, d.ratio) < 1e-12
        assert m.R3 > m.R2 + abs(m.offset)  # the crank turns fully


@pytest.mark.parametrize("n", [1, 5, 12])
@pytest.mark.parametrize("Q", [1.0, 1.4, 2.5])
def test_the_family_covers_its_range(Q, n):
    fam = offset_slider_crank(3.0, Q)
    alpha = 180.0 * (Q - 1.0) / (Q + 1.0)
    assert fam.alpha == pytest.approx(alpha, abs=1e-12)
    # the family ends where the rod is square to the line at the inner dead centre:
    # R3 = R2 + offset, i.e. R3/R2 = cot^2(alpha/2) (infinite for Q = 1)
    h = math.radians(alpha) / 2.0
    limit = math.inf if Q == 1.0 else 1.0 / math.tan(h) ** 2
    assert fam.ratio_limit == pytest.approx(limit, rel=1e-12)
    lo, hi = fam.ratio_range
    assert lo == 1.0 and hi == pytest.approx(min(limit, 10.0), rel=1e-12)
    drawn = fam.members(n)
    ratios = np.array([d.ratio for d in drawn])
    assert len(drawn) == n
    assert np.all(np.diff(ratios) > 0) and lo < ratios[0] and ratios[-1] < hi
    step = (hi - lo) / n
    np.testing.assert_allclose(ratios, lo + step * (np.arange(n) + 0.5), rtol=1e-12)
    # both ends of the family are reachable, and nothing beyond them (a little inside:
    # at the limit the inner dead centre's XB = sqrt(L2^2 - offset^2) loses its digits)
    near = [fam.member(1.0 + 1e-6), fam.member(min(limit * (1.0 - 1e-4), 1e6))]
    for d in near:
        assert _rel(dead_centres(d.mechanism).length, 3.0) < 1e-9
    for bad in (1.0, limit * (1.0 + 1e-9)) if Q > 1.0 else (1.0,):
        with pytest.raises(ValueError, match=r"^ratio = "):
            fam.member(bad)


def test_no_quick_return_is_the_in_line_slider_crank():
    fam = offset_slider_crank(5.0, 1.0, ratio_max=6.0)
    for d in fam.members(4) + [fam.best]:
        m = d.mechanism
        assert m.offset == 0.0 and not math.copysign(1.0, m.offset) < 0
        assert m.R2 == pytest.approx(2.5, rel=1e-15)
        assert m.R3 == pytest.approx(2.5 * d.ratio, rel=1e-15)
        assert d.working_arc == 180.0 and d.time_ratio == 1.0
    # R2/R3 = 1/ratio keeps falling, so the best is the search's bound
    assert fam.best.ratio == 6.0


def engine_max_pressure(d):
    """The engine's largest |ATH3| [deg] over a turn, refined where TH3D is zero."""
    m = d.mechanism
    a = np.abs(analyze(m, GRID, ["ATH3"], branch=d.branch)["ATH3"])
    i = int(np.argmax(a))
    th = _bisect(m, "TH3D", GRID[i] - 0.05, GRID[i] + 0.05, d.branch)
    return abs(float(analyze(m, np.array([th]), ["ATH3"], branch=d.branch)["ATH3"][0]))


@pytest.mark.parametrize("Q", [1.15, 1.5, 2.0, 2.6])
def test_the_best_has_the_largest_least_transmission_angle(Q):
    fam = offset_slider_crank(2.0, Q, working="inward")
    best = fam.best
    worst_best = engine_max_pressure(best)
    assert best.min_transmission == pytest.approx(90.0 - worst_best, abs=1e-9)
    lo, hi = fam.ratio_range
    assert lo < best.ratio < hi  # an interior optimum for these time ratios
    width = hi - lo
    for r in (best.ratio - 0.01 * width, best.ratio + 0.01 * width):
        assert engine_max_pressure(fam.member(r)) > worst_best + 1e-9, r
    for d in fam.members(25):
        assert engine_max_pressure(d) >= worst_best - 1e-9, d.ratio


def test_the_search_without_scipy_is_a_golden_section(monkeypatch):
    pytest.importorskip("scipy")
    calls = []
    golden = synth.golden  # engine.assembly's golden section, as the module uses it

    def spy(*args):
        calls.append(args)
        return golden(*args)

    monkeypatch.setattr(synth, "golden", spy)
    with_scipy = offset_slider_crank(3.0, 1.7).best
    assert not calls
    monkeypatch.setitem(sys.modules, "scipy.optimize", None)  # import fails
    without = offset_slider_crank(3.0, 1.7).best
    assert len(calls) == 1
    assert without.ratio == pytest.approx(with_scipy.ratio, rel=1e-6)
    assert without.min_transmission == pytest.approx(with_scipy.min_transmission, abs=1e-9)
    assert engine_max_pressure(without) == pytest.approx(90.0 - with_scipy.min_transmission,
                                                         abs=1e-9)


def test_default_masses_are_steel_bars():
    d = offset_slider_crank(0.2, 1.3, units="SI").best
    m, w = d.mechanism, 7850.0 * 3.125e-4  # kg per m of bar
    assert m.W2 == pytest.approx(w * m.R2, rel=1e-14)
    assert m.W3 == pytest.approx(w * m.R3, rel=1e-14)
    assert m.ZI3 == pytest.approx(w * m.R3 ** 3 / 12.0, rel=1e-14)
    assert (m.RG2, m.RG3, m.ADEL2, m.ADEL3) == (m.R2 / 2, m.R3 / 2, 0.0, 0.0)
    s = crank_shaper(0.12, 1.7, crank=0.03, units="SI")
    assert s.mechanism.W4 == pytest.approx(w * s.lever, rel=1e-14)
    assert s.mechanism.RG4 == s.lever / 2


def test_khurmi_crank_and_slotted_lever():
    """Khurmi and Gupta, Theory of Machines, 14th ed., Example 5.3, p. 112 (a crank and
    slotted lever quick return; crank BC = 30 mm, stroke R1R2 = 120 mm, time ratio 1.7),
    as the FOSSEE Python Textbook Companion prints it (GitHub
    FOSSEE/Python-Textbook-Companions @ d34b2ae7,
    Theory_Of_Machines_by_R._S._Khurmi_And_J._K._Gupta/ch5.ipynb):
    "The length of AC  =  75.7 mm." and "The length of AP  =  151.48 mm." (AC the fixed
    centres O2-O4, AP the slotted lever)."""
    s = crank_shaper(0.120, 1.7, crank=0.030, units="SI")
    assert f"{s.centres * 1000.0:.1f}" == "75.7"
    assert f"{s.lever * 1000.0:.2f}" == "151.48"
    assert s.mechanism.R1 == s.centres and s.mechanism.R2 == 0.030


@pytest.mark.parametrize("S,Q,crank,th2d", [(0.120, 1.7, 0.030, 1.0), (12.0, 1.4, 2.5, -4.0),
                                            (6.0, 2.5, 1.5, 2.0)])
def test_shaper_against_quick_return_and_the_engine(S, Q, crank, th2d):
    s = crank_shaper(S, Q, crank=crank, th2d=th2d, units="SI" if S < 1 else "in-lb-sec")
    m = s.mechanism
    qr = quick_return(m)
    assert _rel(qr.time_ratio, Q) < 1e-9
    assert sorted(s.extremes) == pytest.approx(list(qr.at), abs=1e-9)
    (th_hi, ath_hi), (th_lo, ath_lo) = engine_extremes(m, "ATH4", "TH4D", s.branch)
    swing = ath_hi - ath_lo
    assert swing == pytest.approx(s.swing, abs=1e-9)
    # the lever's end P sweeps a chord of 2 |O4 P| sin(swing/2): the ram's stroke
    assert _rel(2.0 * s.lever * math.sin(math.radians(swing) / 2.0), S) < 1e-9
    arc = _turn(th_hi, th_lo, 1.0)
    assert _rel(max(arc, 360.0 - arc) / min(arc, 360.0 - arc), Q) < 1e-9
    # the cutting stroke runs from extremes[0] to extremes[1] the way the crank turns, the
    # longer way; the lever is at lever_angles there
    assert _turn(*s.extremes, th2d) == pytest.approx(max(arc, 360.0 - arc), abs=1e-9)
    assert s.cutting_arc == pytest.approx(max(arc, 360.0 - arc), abs=1e-9)
    at = analyze(m, np.array(s.extremes), ["ATH4"], branch=s.branch)["ATH4"]
    np.testing.assert_allclose(at, s.lever_angles, rtol=0, atol=1e-9)
    # the block stays in the slot: A is never further from O4 than the lever is long
    assert float(np.max(analyze(m, GRID, ["S"], branch=s.branch)["S"])) <= s.lever
    # the lever follows from the stroke and time ratio alone; centres= gives the same
    other = crank_shaper(S, Q, centres=s.centres, th2d=th2d, units=m.units)
    assert other.crank == pytest.approx(crank, rel=1e-15)
    assert crank_shaper(S, Q, crank=0.5 * crank, units=m.units).lever == s.lever


def test_shaper_crank_limit_is_where_the_block_reaches_the_lever_end():
    beta = math.radians(180.0 / 2.7)
    most = 0.120 / (2.0 * (1.0 + math.cos(beta)))  # R1 + R2 = lever
    s = crank_shaper(0.120, 1.7, crank=most * (1.0 - 1e-9), units="SI")
    assert s.centres + s.crank <= s.lever
    with pytest.raises(ValueError, match=r"^crank = .*past the lever's end"):
        crank_shaper(0.120, 1.7, crank=most * (1.0 + 1e-9), units="SI")


REFUSALS = [
    (lambda: offset_slider_crank(0.0, 1.2), r"^stroke = 0"),
    (lambda: offset_slider_crank(-2.0, 1.2), r"^stroke = -2"),
    (lambda: offset_slider_crank(float("nan"), 1.2), r"^stroke = nan"),
    (lambda: offset_slider_crank("long", 1.2), r"^stroke = 'long'"),
    (lambda: offset_slider_crank(4.0, 0.9), r"^time_ratio = 0.9"),
    (lambda: offset_slider_crank(4.0, 3.0), r"^time_ratio = 3"),
    (lambda: offset_slider_crank(4.0, math.inf), r"^time_ratio = inf"),
    (lambda: offset_slider_crank(4.0, 1.2, working="up"), r"^working = 'up'"),
    (lambda: offset_slider_crank(4.0, 1.2, th2d=0.0), r"^th2d = 0"),
    (lambda: offset_slider_crank(4.0, 1.2, ratio_max=1.0), r"^ratio_max = 1"),
    (lambda: offset_slider_crank(4.0, 1.2, units="cgs"), r"^units = 'cgs'"),
    (lambda: offset_slider_crank(4.0, 1.2, area=0.0), r"^area = 0"),
    (lambda: offset_slider_crank(4.0, 1.5).member(0.5), r"^ratio = 0.5"),
    (lambda: offset_slider_crank(4.0, 1.5).member(9.5), r"^ratio = 9.5"),
    (lambda: offset_slider_crank(4.0, 1.5).members(0), r"^n = 0"),
    (lambda: crank_shaper(0.0, 1.7, crank=30.0), r"^stroke = 0"),
    (lambda: crank_shaper(120.0, 1.0, crank=30.0), r"^time_ratio = 1"),
    (lambda: crank_shaper(120.0, 0.5, crank=30.0), r"^time_ratio = 0.5"),
    (lambda: crank_shaper(120.0, 1.7), r"^crank = None, centres = None"),
    (lambda: crank_shaper(120.0, 1.7, crank=30.0, centres=75.0), r"^crank = 30"),
    (lambda: crank_shaper(120.0, 1.7, crank=-3.0), r"^crank = -3"),
    (lambda: crank_shaper(120.0, 1.7, crank=50.0), r"^crank = 50"),
    (lambda: crank_shaper(120.0, 1.7, centres=200.0), r"^centres = 200"),
    (lambda: crank_shaper(120.0, 1.7, centres=0.0), r"^centres = 0"),
    (lambda: crank_shaper(120.0, 1.7, crank=30.0, density=-1.0), r"^density = -1"),
    (lambda: crank_shaper(120.0, 1.7, crank=30.0, th2d=0), r"^th2d = 0"),
]


@pytest.mark.parametrize("call,match", REFUSALS)
def test_refusals_are_one_line_naming_the_argument(call, match):
    with pytest.raises(ValueError, match=match) as info:
        call()
    assert "\n" not in str(info.value)
