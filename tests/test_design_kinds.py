"""The design answers on every kind of linkage (tests/test_design.py has the four-bar's),
each checked by a route that trusts nothing of the code under test: the engine's TORQ
integrated by a dense trapezoid; the slider-crank's shaking-force harmonics by an FFT of
the engine's SHAKX and SHAKY against the textbook's closed forms and against a 40-digit
DFT of the exact piston position; the counterweight's force superposed by hand on the
engine's unbalanced shaking force; sweeps, tolerances, peaks and bearings against the
engine's raw outputs on grids of their own; toggles against the geometry that makes them.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

from sielaff import (
    EXAMPLE,
    INVERTED_EXAMPLE,
    RRR,
    SLIDER_EXAMPLE,
    STEPHENSON_EXAMPLE,
    WATT_EXAMPLE,
    Crank,
    Linkage,
    Pivot,
    Scene,
    Topology,
    analyze,
    scene_for,
)
from sielaff.design import (
    balance,
    bearings,
    counterweights,
    flywheel,
    flywheel_from_torque,
    tolerance,
)
from sielaff.design.figures import FIGURES, figure_table, figures
from sielaff.design.peaks import peaks
from sielaff.design.report import balance_lines, compare, slider_balance_lines
from sielaff.design.slider_balance import slider_balance
from sielaff.design.sweep import Grid, column_units, columns, iter_blocks, pareto_pair
from sielaff.engine import linkage_class
from sielaff.tools.common import load_scene

#: in/sec^2: a weight W [lb] has the mass W / G (README, conventions).
G = 386.088
DECKS = __import__("pathlib").Path(__file__).resolve().parent.parent / "decks"

FOUR_BAR = Topology(pivots=(Pivot("O4", "R1", 0.0),), crank=Crank("R2", "A"),
                    dyads=(RRR("A", "O4", "B", "R3", "R4"),),
                    names=(("FO2", "FOA"), ("FO4", "FOB"), ("GAMMAB", "GAMMA")),
                    title="four-bar")


def as_linkage(m):
    """The four-bar ``m`` as a Linkage: the other kinds' path through every answer."""
    return Linkage(FOUR_BAR, m.as_dict(), m.units)


def _one_line(exc: pytest.ExceptionInfo) -> str:
    text = str(exc.value)
    assert "\n" not in text
    return text


def _trapezoid_fluctuation(m, fex=None):
    """max E - min E, E the cumulative trapezoid of the engine's TORQ less its mean on a
    0.01 deg grid (``fex(th)``: a slider force sampled on that grid)."""
    th = np.linspace(0.0, 360.0, 36001)
    scene = None if fex is None else scene_for(m)(fex=fex(th))
    torq = analyze(m, th, ["TORQ"], scene=scene)["TORQ"]
    h = np.radians(0.01)
    e = np.concatenate([[0.0], np.cumsum((torq[1:] + torq[:-1]) * h / 2)])
    e -= e[-1] * th / 360.0  # less the mean torque's work: what the flywheel gives or takes
    return e.max() - e.min(), torq


# -- flywheel --------------------------------------------------------------------------

@pytest.mark.parametrize("m", [SLIDER_EXAMPLE, SLIDER_EXAMPLE.replace(offset=1.5),
                               WATT_EXAMPLE, INVERTED_EXAMPLE],
                         ids=["slider", "offset-slider", "watt", "inverted"])
def test_flywheel_of_another_kind_against_a_dense_trapezoid(m):
    """The energy fluctuation against a trapezoid of the engine's TORQ (error O(h^2),
    about 1E-7 relative); the inertia is energy / (cf w^2); no net work without loads."""
    energy, torq = _trapezoid_fluctuation(m)
    fw = flywheel(m, cf=0.04)
    w = float(m.TH2D)
    assert float(fw.energy) == pytest.approx(energy, rel=1e-6)
    assert float(fw.inertia) == pytest.approx(energy / (0.04 * w * w), rel=1e-6)
    assert abs(float(fw.mean_torque)) < 1e-9 * float(np.max(np.abs(torq)))


def test_flywheel_of_a_slider_pressed_against_its_motion_takes_net_work():
    """FEX = F0 sin th (an array over the crank angles) opposes the slider: with no offset
    XB holds cos th and even harmonics only, so dXB/dth holds sin th (-R2 sin th) and
    sines of even multiples, and the work FEX does over a revolution is -F0 R2 pi; the
    motor's mean torque is F0 R2 / 2, the fluctuation the trapezoid's."""
    f0, n = 300.0, 3600

    def fex(th):
        return f0 * np.sin(np.radians(th))

    sc = scene_for(SLIDER_EXAMPLE)(fex=fex(np.arange(n) * (360.0 / n)))
    fw = flywheel(SLIDER_EXAMPLE, cf=0.05, n=n, scene=sc)
    energy, _ = _trapezoid_fluctuation(SLIDER_EXAMPLE, fex)
    assert float(fw.energy) == pytest.approx(energy, rel=1e-6)
    assert float(fw.mean_torque) == pytest.approx(f0 * SLIDER_EXAMPLE.R2 / 2, rel=1e-9)


def test_flywheel_of_designs_as_arrays_one_by_one():
    r3 = np.array([6.0, 8.0, 11.0])
    both = flywheel(SLIDER_EXAMPLE.replace(R3=r3), n=720)
    for i, v in enumerate(r3):
        one = flywheel(SLIDER_EXAMPLE.replace(R3=float(v)), n=720)
        assert both.energy[i] == pytest.approx(float(one.energy), rel=1e-12)


def test_a_four_bars_flywheel_is_unchanged():
    """The four-bar's answer is still the spectral integral of its own TORQ, bit for bit,
    and the same four-bar as a Linkage (the other kinds' path) agrees with it."""
    th = np.arange(3600) * 0.1
    ref = flywheel_from_torque(analyze(EXAMPLE, th, ["TORQ"])["TORQ"], 50.0, 0.05)
    fw = flywheel(EXAMPLE)
    assert float(fw.energy) == float(ref.energy)
    assert float(fw.inertia) == float(ref.inertia)
    assert float(flywheel(as_linkage(EXAMPLE)).energy) == pytest.approx(float(fw.energy), rel=1e-9)


def test_flywheel_refusals_name_the_kind():
    with pytest.raises(ValueError) as exc:
        flywheel(SLIDER_EXAMPLE.replace(R3=np.array([8.0, 1.5])))
    assert "SliderCrank" in _one_line(exc) and "whole revolution" in str(exc.value)
    with pytest.raises(ValueError) as exc:
        flywheel(SLIDER_EXAMPLE, scene=Scene())  # the four-bar's scene
    assert "SliderCrank" in _one_line(exc)
    with pytest.raises(ValueError, match="th2dd"):
        flywheel(WATT_EXAMPLE, th2dd=5.0)


# -- the slider-crank's balance ----------------------------------------------------------

def _coefficients(samples, upto):
    """c_k with samples = Re sum c_k e^{i k th}, th = 2 pi j / n (the test's own FFT)."""
    n = len(samples)
    s = np.fft.fft(samples) / n
    return np.array([s[0]] + [2.0 * s[k] for k in range(1, upto + 1)])


def _exact_xb_series(r, l, e, upto, n=128):
    """X_k of XB(th) = r cos th + sqrt(l^2 - (e - r sin th)^2) = Re sum X_k e^{i k th}, by a
    40-digit DFT of n samples (the coefficients decay geometrically: no aliasing left)."""
    with mpmath.workdps(40):
        r, l, e = mpmath.mpf(r), mpmath.mpf(l), mpmath.mpf(e)
        t = [2 * mpmath.pi * j / n for j in range(n)]
        x = [r * mpmath.cos(a) + mpmath.sqrt(l * l - (e - r * mpmath.sin(a)) ** 2) for a in t]
        out = []
        for k in range(upto + 1):
            s = mpmath.fsum(xj * mpmath.exp(-1j * k * a) for xj, a in zip(x, t)) / n
            out.append(complex(s if k == 0 else 2 * s))
    return np.array(out)


def _parts(m):
    """(u, c, W_rec): the rotating first moment in the crank's frame, the rod's centre of
    mass as a fraction of A->B, the reciprocating weight (the module doc's algebra, done
    again here)."""
    c = m.RG3 / m.R3 * np.exp(1j * np.radians(m.ADEL3))
    u = m.W2 * m.RG2 * np.exp(1j * np.radians(m.ADEL2)) + m.W3 * (1 - c) * m.R2
    return u, c, m.W4 + m.W3 * c.real


def test_zero_offset_harmonics_are_the_textbooks():
    """No offset, centres of mass on the links' lines: the FFT of the engine's SHAKX has
    the primary (u + W_rec r) w^2 / g and the secondary W_rec r w^2 (r / l) / g to the
    order of the series left out, (r / l)^2 / 4, which is there: sqrt(1 - l^2 sin^2)'s
    cos 2 th term is l^2 / 4 + l^4 / 16 + ..., so the secondary is W_rec r w^2 / g
    (lam + lam^3 / 4 + O(lam^5))."""
    m = SLIDER_EXAMPLE
    w, r, lam = m.TH2D, m.R2, m.R2 / m.R3
    u, _, w_rec = _parts(m)
    th = np.arange(720) * 0.5
    shake = analyze(m, th, ["SHAKX", "SHAKY"])
    cx, cy = _coefficients(shake["SHAKX"], 3), _coefficients(shake["SHAKY"], 3)
    primary = w_rec * r * w * w / G
    textbook = primary * lam
    assert cx[1] == pytest.approx((u.real + w_rec * r) * w * w / G, rel=1e-9, abs=1e-9)
    assert cy[1] == pytest.approx(-1j * u * w * w / G, rel=1e-9, abs=1e-9)  # sin th
    assert abs(cx[2] / textbook - 1.0 - lam**2 / 4) < 0.2 * lam**4
    assert abs(cx[3]) < 1e-9 * primary  # odd harmonics: none without offset
    b = slider_balance(m)
    assert b.primary == pytest.approx(primary, rel=1e-12)
    assert b.secondary == pytest.approx(abs(cx[2]), rel=1e-9)
    assert b.reciprocating == pytest.approx(w_rec, rel=1e-15)


OFFSET = SLIDER_EXAMPLE.replace(offset=1.25, ADEL2=25.0, ADEL3=12.0, RG3=3.0)


def test_any_offset_harmonics_are_the_exact_series():
    """With an offset the piston's series has every harmonic, sines too: the 40-digit DFT
    of the exact XB gives H_k = W_rec k^2 w^2 X_k / g along the stroke; the engine's SHAKX
    has exactly those beyond the first (the rotating part is all in the first), and its
    SHAKY the rod's share across the stroke, W3 Im(c) k^2 w^2 X_k / g."""
    m = OFFSET
    w = m.TH2D
    u, c, w_rec = _parts(m)
    x = _exact_xb_series(m.R2, m.R3, m.offset, 8)
    k = np.arange(9)
    h = w_rec * k * k * w * w * x / G
    b = slider_balance(m)
    scale = abs(h[1])
    np.testing.assert_allclose(b.harmonics, h, rtol=0, atol=1e-10 * scale)
    th = np.arange(720) * 0.5
    shake = analyze(m, th, ["SHAKX", "SHAKY"])
    cx, cy = _coefficients(shake["SHAKX"], 8), _coefficients(shake["SHAKY"], 8)
    np.testing.assert_allclose(cx[2:], h[2:], rtol=0, atol=1e-10 * scale)
    np.testing.assert_allclose(cy[2:], (m.W3 * c.imag) * k[2:] ** 2 * w * w * x[2:] / G,
                               rtol=0, atol=1e-10 * scale)
    assert cx[1] == pytest.approx(u * w * w / G + h[1], rel=1e-10)
    assert cy[1] == pytest.approx(-1j * u * w * w / G + m.W3 * c.imag * w * w * x[1] / G,
                                  rel=1e-10)
    assert abs(x[1].imag) > 1e-3 * m.R2  # an offset gives the primary a sine part


@pytest.mark.parametrize("fraction", [0.0, 0.3, 0.5, 1.0])
def test_the_counterweight_leaves_what_the_closed_forms_say(fraction):
    """P = -u - fraction W_rec X_1 (test's algebra); the engine's shaking force on the
    merged crank is the unbalanced one plus the counterweight's w^2 P e^{i th} / g at every
    angle; it leaves (1 - fraction) |H_1| along the stroke, fraction |H_1| across, and the
    secondary as it was."""
    m = OFFSET.replace(ADEL3=0.0)  # G3 on A-B: nothing of the slider's across the stroke
    w = m.TH2D
    u, _, w_rec = _parts(m)
    x = _exact_xb_series(m.R2, m.R3, m.offset, 2)
    p = -u - fraction * w_rec * x[1]
    b = slider_balance(m, fraction, radius=1.5)
    cw = b.counterweight
    got = cw.weight * cw.radius * np.exp(1j * np.radians(cw.angle))
    assert abs(got - p) < 1e-9 * abs(p)
    assert cw.radius == 1.5 and b.product == pytest.approx(abs(p), rel=1e-12)
    th = np.arange(720) * 0.5
    before = analyze(m, th, ["SHAKX", "SHAKY"])
    turn = p * np.exp(1j * np.radians(th)) * w * w / G
    scale = float(np.max(np.abs(before["SHAKX"])))
    np.testing.assert_allclose(b.shakx, before["SHAKX"] + turn.real, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(b.shaky, before["SHAKY"] + turn.imag, rtol=0, atol=1e-9 * scale)
    h1 = w_rec * w * w * abs(x[1]) / G
    assert b.after.primary_along == pytest.approx((1 - fraction) * h1, rel=1e-9, abs=1e-9 * h1)
    assert b.after.primary_across == pytest.approx(fraction * h1, rel=1e-9, abs=1e-9 * h1)
    assert b.after.secondary_along == pytest.approx(b.before.secondary_along, rel=1e-9)
    assert b.after.secondary_along == pytest.approx(4 * w_rec * w * w * abs(x[2]) / G, rel=1e-9)
    assert b.after.peak_x == pytest.approx(float(np.max(np.abs(b.shakx))), rel=1e-15)
    assert b.before.peak_x == pytest.approx(scale, rel=1e-15)


def test_fraction_zero_cancels_the_rotating_unbalance_only():
    """No offset, G3 on A-B: with the rotating unbalance gone nothing is left across the
    stroke, and along it exactly the reciprocating mass's -W_rec AXB / g (the engine's
    AXB), its primary the whole W_rec r w^2 / g."""
    m = SLIDER_EXAMPLE.replace(ADEL2=40.0, RG2=0.8)
    _, _, w_rec = _parts(m)
    b = slider_balance(m, fraction=0.0)
    th = b.theta2
    axb = analyze(m, th, ["AXB"])["AXB"]
    scale = float(np.max(np.abs(axb))) * w_rec / G
    np.testing.assert_allclose(b.shaky, 0.0, atol=1e-9 * scale)
    np.testing.assert_allclose(b.shakx, -w_rec * axb / G, rtol=0, atol=1e-9 * scale)
    assert b.after.primary_along == pytest.approx(w_rec * m.R2 * m.TH2D**2 / G, rel=1e-9)
    assert b.after.primary_across < 1e-9 * scale


def test_no_offset_and_centres_on_their_lines_put_the_counterweight_opposite_the_pin():
    b = slider_balance(SLIDER_EXAMPLE, 0.6)
    assert b.counterweight.angle == pytest.approx(180.0, abs=1e-9)
    u, _, w_rec = _parts(SLIDER_EXAMPLE)
    assert b.product == pytest.approx(u.real + 0.6 * w_rec * SLIDER_EXAMPLE.R2, rel=1e-12)
    assert b.counterweight.radius == SLIDER_EXAMPLE.R2  # the default radius


@pytest.mark.parametrize("m", [INVERTED_EXAMPLE, WATT_EXAMPLE, STEPHENSON_EXAMPLE,
                               as_linkage(EXAMPLE)],
                         ids=["inverted", "watt", "stephenson", "four-bar-as-linkage"])
def test_berkof_lowen_refuses_every_other_kind_in_one_line(m):
    for fn in (balance, counterweights):
        with pytest.raises(ValueError) as exc:
            fn(m)
        text = _one_line(exc)
        assert "Berkof-Lowen counterweights are for the four-bar" in text
        assert type(m).__name__ in text


def test_balance_of_a_slider_crank_points_to_its_own_answer():
    with pytest.raises(ValueError) as exc:
        balance(SLIDER_EXAMPLE)
    text = _one_line(exc)
    assert "Berkof-Lowen" in text and "SliderCrank" in text and "slider_balance" in text


def test_the_slider_balance_text_says_each_row_before_and_after_in_its_units():
    b = slider_balance(SLIDER_EXAMPLE.replace(units="SI"), 0.5)
    lines = slider_balance_lines(b)
    assert not any(" lb" in line for line in lines)
    assert any(line.startswith("    W2 ") and line.endswith(" kg") for line in lines)
    rows = {label: line for line in lines for label in
            ("peak |SHAKX|", "primary along", "primary across", "secondary along")
            if line.strip().startswith(label)}
    assert len(rows) == 4 and all(line.endswith(" N") for line in rows.values())
    before, after = (float(x) for x in rows["secondary along"].split()[-3:-1])
    assert before == after == float(f"{b.before.secondary_along:.4g}")  # untouched
    assert float(rows["primary across"].split()[-2]) == float(f"{b.after.primary_across:.4g}")


@pytest.mark.parametrize("fn", [compare, balance_lines])
def test_the_four_bars_balance_text_refuses_a_slider_crank(fn):
    with pytest.raises(ValueError) as exc:
        fn(SLIDER_EXAMPLE, SLIDER_EXAMPLE)
    assert "four-bar" in _one_line(exc) and "SliderCrank" in str(exc.value)


@pytest.mark.parametrize("call, text", [
    (lambda: slider_balance(EXAMPLE), "Mechanism"),
    (lambda: slider_balance(WATT_EXAMPLE), "WattII"),
    (lambda: slider_balance(SLIDER_EXAMPLE.replace(R3=np.array([8.0, 9.0]))), "one design"),
    (lambda: slider_balance(SLIDER_EXAMPLE, fraction=1.5), "fraction"),
    (lambda: slider_balance(SLIDER_EXAMPLE, radius=0.0), "radius"),
    (lambda: slider_balance(SLIDER_EXAMPLE.replace(R3=1.5)), "full revolution"),
    (lambda: slider_balance(SLIDER_EXAMPLE, n=7), "n = 7"),
])
def test_slider_balance_refusals(call, text):
    with pytest.raises(ValueError) as exc:
        call()
    assert text in _one_line(exc)


# -- sweeps and tolerances over a slider-crank's fields --------------------------------

def test_a_sweep_of_a_slider_cranks_offset_and_rod():
    """Each row against the engine's raw outputs of that design alone; a rod too short
    for the crank and the offset (R3 < R2 + |offset|, the full-turn test in closed form)
    gets NaN figures."""
    g = Grid(SLIDER_EXAMPLE, {"R3": [1.5, 2.5, 8.0], "offset": [0.0, 0.75]})
    rows = np.concatenate(list(iter_blocks(g, n=180, size_of_block=4)))
    cols = columns(g)
    assert cols[:3] == ["DESIGN", "R3", "offset"]
    assert {"FOA_PEAK", "FA32_PEAK", "FB34_PEAK", "FN_PEAK", "FOB_PEAK"} & set(cols) == \
        {"FOA_PEAK", "FA32_PEAK", "FB34_PEAK", "FN_PEAK"}  # the slider has no pin O4
    th = np.arange(180) * 2.0
    for row in rows:
        got = dict(zip(cols, row))
        m = SLIDER_EXAMPLE.replace(R3=got["R3"], offset=got["offset"])
        if got["R3"] < SLIDER_EXAMPLE.R2 + abs(got["offset"]):
            assert np.isnan(got["TORQ_PEAK"]) and np.isnan(got["FN_PEAK"])
            continue
        r = analyze(m, th, ["TORQ", "FOA", "FB34", "FN", "SHAKM"])
        assert got["TORQ_PEAK"] == pytest.approx(np.max(np.abs(r["TORQ"])), rel=1e-12)
        assert got["TORQ_RMS"] == pytest.approx(np.sqrt(np.mean(r["TORQ"] ** 2)), rel=1e-12)
        assert got["FOA_PEAK"] == pytest.approx(np.max(r["FOA"]), rel=1e-12)
        assert got["FB34_PEAK"] == pytest.approx(np.max(r["FB34"]), rel=1e-12)
        assert got["FN_PEAK"] == pytest.approx(np.max(np.abs(r["FN"])), rel=1e-12)
        assert got["SHAKM_PEAK"] == pytest.approx(np.max(np.abs(r["SHAKM"])), rel=1e-12)
    units = column_units(cols, "in-lb-sec")
    assert (units["offset"], units["FN_PEAK"], units["TORQ_PEAK"]) == ("in", "lb", "in-lb")
    assert column_units(cols, "SI")["FLYWHEEL_I"] == "kg m^2"


def test_a_six_bars_figures_are_its_own_pins_and_angles():
    f = figures(WATT_EXAMPLE, n=360)
    th = np.arange(360) * 1.0
    r = analyze(WATT_EXAMPLE, th, ["FO6", "FC54", "GAMMAD"])
    assert float(f["FO6_PEAK"][0]) == pytest.approx(np.max(r["FO6"]), rel=1e-12)
    assert float(f["FC54_PEAK"][0]) == pytest.approx(np.max(r["FC54"]), rel=1e-12)
    g = r["GAMMAD"]
    assert float(f["GAMMAD_MIN"][0]) == pytest.approx(np.min(np.minimum(g, 180 - g)))
    assert "KIND" not in f  # the four-bar's class


def test_the_four_bar_as_a_linkage_gets_the_four_bars_figures():
    """The kinds' figures of the four-bar as a Linkage (its pins from its topology, its
    full turn from its dyad's margins) are the four-bar's own, KIND aside."""
    m = EXAMPLE.replace(R1=np.array([10.0, 12.0, 30.0]))  # 4 + 30 > 16 + 12: no crank
    four_bar, linkage = figures(m, n=360), figures(as_linkage(m), n=360)
    assert set(linkage) == set(FIGURES) - {"KIND"}
    assert np.isnan(four_bar["TORQ_PEAK"][2]) and np.isnan(linkage["TORQ_PEAK"][2])
    for name, v in linkage.items():
        np.testing.assert_allclose(v, four_bar[name], rtol=1e-9, equal_nan=True)


def test_pareto_figures_of_another_kind():
    table = figure_table(WATT_EXAMPLE)
    assert pareto_pair("FD56_PEAK,GAMMAD_MIN", table) == (("FD56_PEAK", "min"),
                                                          ("GAMMAD_MIN", "max"))
    with pytest.raises(ValueError, match="FN_PEAK"):
        pareto_pair("FN_PEAK,TORQ_PEAK", table)  # a six-bar has no slide
    assert pareto_pair("FN_PEAK,TORQ_PEAK", figure_table(SLIDER_EXAMPLE))[0] == \
        ("FN_PEAK", "min")


@pytest.mark.parametrize("name", ["TEX", "BALANCE", "R1"])
def test_a_sweep_of_a_slider_crank_refuses_the_four_bars_names(name):
    with pytest.raises(ValueError) as exc:
        Grid(SLIDER_EXAMPLE, {name: [0.0, 1.0]})
    assert "SliderCrank" in _one_line(exc) and name in str(exc.value)


def test_a_tolerance_of_a_slider_crank():
    """Zero deviations give the nominal exactly (the engine's peak on the same grid); the
    first-order sensitivity of TORQ_RMS to R3 is a central difference of the engine's."""
    th = np.arange(90) * 4.0
    t0 = tolerance(SLIDER_EXAMPLE, {"R3": 0.0, "offset": 0.0}, n=4, angles=90)
    torq = analyze(SLIDER_EXAMPLE, th, ["TORQ"])["TORQ"]
    assert t0.nominal["TORQ_PEAK"] == pytest.approx(np.max(np.abs(torq)), rel=1e-12)
    assert t0.std["TORQ_PEAK"] == 0.0 and t0.mean["FN_PEAK"] == t0.nominal["FN_PEAK"]
    t = tolerance(SLIDER_EXAMPLE, {"R3": 0.05}, n=50, angles=90)
    h = 1e-4

    def rms(r3):
        q = analyze(SLIDER_EXAMPLE.replace(R3=r3), th, ["TORQ"])["TORQ"]
        return np.sqrt(np.mean(q * q))

    slope = (rms(8.0 + h) - rms(8.0 - h)) / (2 * h)
    assert t.sensitivity["TORQ_RMS"]["R3"] == pytest.approx(slope, rel=1e-4)
    assert t.to_frame().attrs["units"]["FN_PEAK"] == "lb"


def test_a_slider_cranks_broken_samples_are_counted_as_drawn():
    """The samples are R3 = 8 + 5 z, z from block 0's generator (the module doc's seeding):
    R3 <= 0 is no linkage, 0 < R3 < R2 = 2 a crank that cannot turn (no offset)."""
    t = tolerance(SLIDER_EXAMPLE, {"R3": 5.0}, n=100, seed=3, angles=16)
    z = np.random.default_rng(np.random.SeedSequence(3, spawn_key=(0,))).standard_normal((100, 1))
    r3 = 8.0 + 5.0 * z[:, 0]
    assert t.invalid == int(np.sum(r3 <= 0.0)) > 0
    assert t.not_turning == int(np.sum((r3 > 0.0) & (r3 < 2.0))) > 0
    assert t.valid["TORQ_PEAK"] == 100 - t.invalid - t.not_turning


def test_a_tolerance_refuses_a_field_the_kind_has_not():
    with pytest.raises(ValueError) as exc:
        tolerance(SLIDER_EXAMPLE, {"R1": 0.1})
    assert "R1 is not a field" in _one_line(exc) and "offset" in str(exc.value)


# -- peaks over where it assembles -----------------------------------------------------

@pytest.mark.filterwarnings("ignore::sielaff.AssemblyWarning")
def test_a_rocking_slider_cranks_peaks_are_its_toggles():
    """R3 < R2 + |offset|: the rod stands square to the guide where offset - R2 sin th =
    +-R3; every force and torque grows toward those angles (checked here on the engine)."""
    m = SLIDER_EXAMPLE.replace(R3=2.5, offset=1.0)
    s = (m.offset - m.R3) / m.R2  # the other sign, (1 + 2.5) / 2, is past 1
    toggles = sorted([math.degrees(math.pi - math.asin(s)) % 360.0,
                      math.degrees(math.asin(s)) % 360.0])
    rows = peaks(m, scene_for(m)(), n=720)
    assert {p.name for p in rows} == {"TORQ", "SHAK", "SHAKM", "FOA", "FA32", "FB34", "FN"}
    for p in rows:
        assert p.unbounded and math.isnan(p.value)
        assert sorted(p.toggles) == pytest.approx(toggles, abs=1e-9)
        assert all(math.isnan(g) for g in p.gamma)  # a slider-crank has no GAMMA
    for t in toggles:
        d = 1.0 if np.isfinite(analyze(m, (t + 1e-3) % 360, ["TORQ"])["TORQ"]) else -1.0
        q = [abs(float(analyze(m, (t + d * e) % 360.0, ["TORQ"])["TORQ"]))
             for e in (1e-2, 1e-4, 1e-6)]
        assert q[1] > 5.0 * q[0] and q[2] > 5.0 * q[1], q


@pytest.mark.filterwarnings("ignore::sielaff.AssemblyWarning")
@pytest.mark.parametrize("deck", ["double-rocker.toml", "triple-rocker.toml"])
def test_the_four_bar_as_a_linkage_finds_the_four_bars_toggles(deck):
    """Where the dyad closes, found by bisection on its margin, ends at the toggles the
    four-bar's class gives in closed form; the rows and GAMMA there are the same."""
    m = load_scene(str(DECKS / deck), any_linkage=True)[0].mechanism
    toggles = sorted(float(t) for t in np.ravel(linkage_class(m).toggles) if np.isfinite(t))
    four_bar = {(p.label.split(" (")[0], p.name): p for p in peaks(m, Scene(), n=720)}
    linkage = {(p.label.split(" (")[0], p.name): p
               for p in peaks(as_linkage(m), scene_for(as_linkage(m))(), n=720)}
    assert set(linkage) == set(four_bar)
    for key, p in linkage.items():
        q = four_bar[key]
        assert p.unbounded == q.unbounded
        if p.unbounded:
            assert sorted(p.toggles) == pytest.approx(toggles, abs=1e-9)
            assert sorted(p.gamma) == pytest.approx(sorted(q.gamma), abs=1e-6)
        else:
            assert p.value == pytest.approx(q.value, rel=1e-9)


@pytest.mark.filterwarnings("ignore::sielaff.AssemblyWarning")
def test_a_six_bar_that_toggles_is_stretched_there():
    """The second dyad reaches |C O6| = R5 + R6 (the engine's C at the toggles says so)
    and GAMMAD is 180 deg there; the first dyad's GAMMAB stays a number."""
    m = WATT_EXAMPLE.replace(Y6=20.0, R5=7.0, R6=8.0)
    rows = peaks(m, scene_for(m)(), n=720)
    torq = next(p for p in rows if p.name == "TORQ")
    assert torq.unbounded and len(torq.toggles) == 2
    r = analyze(m, np.array(torq.toggles), ["XC", "YC"])
    np.testing.assert_allclose(np.hypot(r["XC"] - m.X6, r["YC"] - m.Y6), m.R5 + m.R6,
                               rtol=1e-9)
    assert torq.gamma == pytest.approx((180.0, 180.0), abs=1e-4)
    assert all(np.isfinite(p.value) for p in rows if p.name == "GAMMAB")


def test_a_six_bar_that_turns_fully_gets_every_peak():
    rows = peaks(WATT_EXAMPLE, scene_for(WATT_EXAMPLE)(), n=3600)
    th = np.arange(0.0, 360.0, 0.05)
    r = analyze(WATT_EXAMPLE, th, [p.name for p in rows])
    for p in rows:
        assert not p.unbounded
        v = r[p.name]
        if "magnitude" in p.label:
            best = v[np.argmax(np.abs(v))]
        elif p.label.endswith(("smallest", "least")):
            best = v.min()
        else:  # largest, greatest, a pin's load, the shaking force
            best = v.max()
        assert p.value == pytest.approx(best, rel=1e-4, abs=1e-6)
    assert [p.name for p in rows if p.label.startswith("load")] == \
        ["FOA", "FA32", "FOB", "FB34", "FC54", "FO6", "FD56"]


# -- bearings --------------------------------------------------------------------------

def test_a_slider_cranks_bearings_against_a_raster():
    """Pins O2, A and B; each peak at least the raster's largest load and hardly above
    it; each member's load direction the engine's force (or its reaction) from the
    member's line."""
    m = SLIDER_EXAMPLE.replace(offset=0.5)
    pins = bearings(m, n=360)
    assert list(pins) == ["O2", "A", "B"]
    raster = analyze(m, np.arange(0.0, 360.0, 0.01), ["FOA", "FA32", "FB34"])
    for pin in pins.values():
        top = float(np.max(raster[pin.force]))
        assert top * (1 - 1e-12) <= pin.peak <= top * (1 + 1e-6)
    b = pins["B"]  # FB34: the rod (link 3) on the slider (link 4)
    r = analyze(m, b.theta2, ["FB34X", "FB34Y", "ATH3", "ATH4"])
    on_rod = (np.degrees(np.arctan2(-r["FB34Y"], -r["FB34X"])) - r["ATH3"]) % 360.0
    on_slider = (np.degrees(np.arctan2(r["FB34Y"], r["FB34X"])) - r["ATH4"]) % 360.0
    for member, want in zip(b.members, (on_rod, on_slider)):
        ok = np.isfinite(member.direction)
        assert ok.sum() > 100
        diff = (member.direction[ok] - want[ok] + 180.0) % 360.0 - 180.0
        assert np.max(np.abs(diff)) < 1e-9


def test_a_six_bars_bearings_are_its_seven_pins():
    pins = bearings(WATT_EXAMPLE, n=180)
    assert set(pins) == {"O2", "A", "O4", "B", "C", "O6", "D"}
    assert [m.name for m in pins["O6"].members] == ["frame", "link 6"]
    r = analyze(WATT_EXAMPLE, np.arange(0.0, 360.0, 0.05), ["FO6"])
    assert pins["O6"].peak == pytest.approx(float(np.max(r["FO6"])), rel=1e-5)


def test_bearings_refuse_a_crank_that_cannot_turn():
    with pytest.raises(ValueError) as exc:
        bearings(SLIDER_EXAMPLE.replace(R3=1.5))
    assert "SliderCrank" in _one_line(exc) and "no bearing cycle" in str(exc.value)
