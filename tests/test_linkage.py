"""The linkage engine (a crank and Assur dyads: sielaff.linkage, engine/dyads.py,
engine/joints.py) against what it must agree with:

* the 1966 four-bar written as a Linkage gives the four-bar engine's outputs to 1e-12 of
  scale, on drawn linkages, both branches, with gravity, loads, springs, dampers and a
  crank acceleration;
* the inverted slider-crank and the Watt II and Stephenson III six-bars against an
  independent solve in 40 digits (tests/linkage_reference.py: acos positions, rates by
  numerical differentiation, Newton-Euler about each centre of mass);
* the power balance and zero cycle work where nothing dissipates;
* pylinkage's positions of the six-bars;
* the inverted slider-crank's time ratio against its construction and the printed
  examples (Khurmi & Gupta, Sarkar).

No published six-bar example with printed numbers was found in the stored material
(docs/mechanisms.md, "Verification"); the six-bars are checked by the independent solve
and the identities alone.
"""

from __future__ import annotations

import math
import warnings

import mpmath as mp
import numpy as np
import pytest

import linkage_reference as ref
from sielaff import (
    EXAMPLE,
    INVERTED_EXAMPLE,
    RRR,
    STEPHENSON_EXAMPLE,
    WATT_EXAMPLE,
    Crank,
    Damper,
    InvertedSliderCrank,
    Linkage,
    Load,
    Pivot,
    Scene,
    Spring,
    StephensonIII,
    Topology,
    WattII,
    analyze,
    scene_for,
)
from sielaff.engine import model_for
from sielaff.inverted_slider_crank import quick_return

FOUR_BAR = Topology(pivots=(Pivot("O4", "R1", 0.0),), crank=Crank("R2", "A"),
                    dyads=(RRR("A", "O4", "B", "R3", "R4"),),
                    names=(("FO2", "FOA"), ("FO4", "FOB"), ("GAMMAB", "GAMMA")),
                    title="four-bar")


def as_linkage(m):
    values = {k: v for k, v in m.as_dict().items()}
    return Linkage(FOUR_BAR, values, m.units)


def _drawn_crank_rockers(n, seed):
    """Crank-rockers drawn at random: R2 the shortest, a Grashof sum with room."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        R1, R3, R4 = rng.uniform(6.0, 20.0, 3)
        R2 = rng.uniform(1.0, 0.8 * min(R1, R3, R4))
        lengths = sorted((R1, R2, R3, R4))
        if lengths[0] + lengths[3] < lengths[1] + lengths[2] - 1.0:
            out.append(EXAMPLE.replace(R1=R1, R2=R2, R3=R3, R4=R4,
                                       ADEL2=rng.uniform(-40, 40), ADEL3=rng.uniform(-40, 40),
                                       ADEL4=rng.uniform(-40, 40),
                                       RG3=rng.uniform(0, R3), RG4=rng.uniform(0, R4)))
    return out


def _close(a, b, name, rtol=1e-12, magnitude=None):
    a, b = np.asarray(a, float), np.asarray(b, float)
    if name.startswith(("ATH", "D")):  # angles: modulo a revolution
        d = np.abs((a - b + 180.0) % 360.0 - 180.0)
        if magnitude is not None:  # a direction: none where the vector is all but zero
            d = np.where(magnitude > 1e-9 * np.max(magnitude), d, 0.0)
        scale = 360.0
    else:
        d = np.abs(a - b)
        scale = max(float(np.nanmax(np.abs(a))), 1e-300)
    return float(np.nanmax(d)) <= rtol * scale, float(np.nanmax(d)) / scale


SCENES = {
    "1966": {},
    "everything": dict(th2dd=-33.0, gravity="down",
                       loads=[Load(3, r=5.0, angle=10.0, fx=30.0, fy=-4.0, torque=7.0)],
                       elements=[Spring((1, 3.0, 40.0), (4, 5.0, 10.0), 20.0, 3.0),
                                 Damper((2, 2.0, 0.0), (3, 6.0, 0.0), 0.4)]),
}


@pytest.mark.parametrize("branch", ["open", "crossed"])
@pytest.mark.parametrize("scene", sorted(SCENES))
def test_the_four_bar_as_a_linkage_is_the_four_bar_engine(scene, branch):
    th = np.arange(0.0, 360.0, 5.0)
    drawn = _drawn_crank_rockers(6, seed=34)
    compared = 0
    for m in [EXAMPLE, *drawn]:
        lk = as_linkage(m)
        kw = dict(SCENES[scene], branch=branch)
        ours = analyze(m, th, None, scene=Scene(**kw))
        theirs = analyze(lk, th, None, scene=scene_for(lk)(**kw))
        for name in ours:
            if name == "TEX":  # the four-bar's own effect (loads= puts a torque on link 4)
                continue
            mag = ours.get(name[1:]) if name[0] == "D" else None
            ok, err = _close(ours[name], theirs[name], name, magnitude=mag)
            assert ok, (m, name, err)
            compared += 1
    assert compared == 7 * (len(ours) - 1)  # every output of every drawn linkage


def _kinds():
    return [("inverted", INVERTED_EXAMPLE.replace(offset=0.8, ADEL2=12.0, RG3=0.5, ADEL4=5.0)),
            ("inverted", INVERTED_EXAMPLE.replace(R2=14.0, offset=-1.5)),  # a Whitworth
            ("watt", WATT_EXAMPLE.replace(ADEL5=10.0, ADEL6=-20.0)),
            ("stephenson", STEPHENSON_EXAMPLE.replace(ADEL3=15.0))]


def _force_name(m, p, by, on):
    names = dict(m.TOPOLOGY.names)
    generic = f"F{p}" if on == 1 else f"F{p}{by}{on}"
    return names.get(generic, generic)


@pytest.mark.parametrize("case", range(4))
@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_each_kind_is_the_independent_newton_euler_solve(case, branch):
    kind, m = _kinds()[case]
    # the six-bars' second dyad: its other assembly (both dyads crossed does not close)
    signs = (1, 1) if branch == "open" else (1, -1)
    if kind != "inverted" and branch == "crossed":
        branch = ("open", "crossed")
    if kind == "inverted":
        signs = (1,) if branch == "open" else (-1,)  # the slide position's sign
    checked = 0
    for th in (17.0, 133.0, 250.0):
        load_link = 4
        scene = scene_for(m)(branch=branch, th2dd=-35.0, gravity="down",
                             loads=[Load(load_link, r=3.0, angle=20.0, fx=40.0, fy=-10.0,
                                         torque=15.0)])
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            r = analyze(m, [th], model_for(m).outputs, scene=scene)
        out = ref.newton_euler(kind, m, th, m.TH2D, -35.0, branch=signs,
                               gravity=(0.0, -386.088),
                               loads=[(4, _load_point(kind, m, th, signs), complex(40, -10),
                                       15.0)])
        mo = out["motion"]
        scale = abs(float(out["TORQ"])) + 1.0
        assert float(r["TORQ"][0]) == pytest.approx(float(out["TORQ"]), abs=1e-10 * scale)
        for key, F in out.items():
            if isinstance(key, tuple):
                name = _force_name(m, *key)
                fscale = max(abs(complex(v)) for k, v in out.items() if isinstance(k, tuple))
                assert float(r[name + "X"][0]) == pytest.approx(float(F.real),
                                                                 abs=1e-10 * fscale), name
                assert float(r[name + "Y"][0]) == pytest.approx(float(F.imag),
                                                                 abs=1e-10 * fscale), name
                checked += 1
        points = ["A", "B", "C", "D"] if kind != "inverted" else ["A"]
        for p in points + [f"G{k}" for k in range(2, 5 if kind == "inverted" else 7)]:
            for d, prefix in ((0, ""), (1, "V"), (2, "A")):
                want = complex(mo[p][d])
                x = f"X{p}" if d == 0 else f"{prefix}{p}X"
                y = f"Y{p}" if d == 0 else f"{prefix}{p}Y"
                vs = max(abs(complex(mo[q][d])) for q in points) + 1.0
                assert float(r[x][0]) == pytest.approx(want.real, abs=1e-10 * vs), x
                assert float(r[y][0]) == pytest.approx(want.imag, abs=1e-10 * vs), y
                checked += 1
        for k in range(3, 5 if kind == "inverted" else 7):
            th_k = mo[f"th{k}"]
            got = math.radians(float(r[f"ATH{k}"][0]))
            assert abs(math.remainder(got - float(th_k[0]), 2 * math.pi)) < 1e-12
            assert float(r[f"TH{k}D"][0]) == pytest.approx(float(th_k[1]), rel=1e-10, abs=1e-10)
            assert float(r[f"TH{k}DD"][0]) == pytest.approx(float(th_k[2]), rel=1e-10,
                                                             abs=1e-8)
            checked += 3
        if kind == "inverted":
            assert float(r["FN"][0]) == pytest.approx(float(out["FN"]), abs=1e-10 * scale)
            assert float(r["MN"][0]) == pytest.approx(float(out["MN"]), abs=1e-10 * scale)
            s = abs(mo["A"][0] - mo["O4"][0]) ** 2 - mp.mpf(repr(float(m.offset))) ** 2
            assert float(r["S"][0]) == pytest.approx(signs[0] * float(mp.sqrt(s)), rel=1e-12)
    assert checked >= 3 * (12 if kind != "inverted" else 9)


def _load_point(kind, m, th, signs):
    mo = ref.motion(kind, m, th, m.TH2D, -35.0, branch=signs)
    return complex(mo["O4"][0] + 3.0 * mp.expj(mo["th4"][0] + mp.radians(20)))


def _energy_rate(m, r, gw):
    """d(kinetic energy)/dt from the engine's own rates: sum m aG . vG + ZI alpha w."""
    total = 0.0
    links = model_for(m).topology.links
    for k in range(2, links + 1):
        mass = float(getattr(m, f"W{k}", 0.0)) / gw
        total = total + mass * (r[f"AG{k}X"] * r[f"VG{k}X"] + r[f"AG{k}Y"] * r[f"VG{k}Y"])
        zi = float(getattr(m, f"ZI{k}", 0.0))
        if k > 2:
            total = total + zi * r[f"TH{k}DD"] * r[f"TH{k}D"]
        else:
            total = total + zi * r["TH2DD"] * m.TH2D
    return total


@pytest.mark.parametrize("case", range(4))
def test_the_drive_power_is_the_rate_of_kinetic_energy(case):
    """TORQ TH2D = d(kinetic energy)/dt with the crank speeding up: the engine's forces
    against its own kinematics, an identity the statics must satisfy."""
    _, m = _kinds()[case]
    th = np.arange(0.0, 360.0, 3.0)
    names = ["TORQ", "TH2DD"] + [f"{p}G{k}{a}" for k in range(2, 7) for p in "AV"
                                 for a in "XY"] + [f"TH{k}{d}" for k in range(3, 7)
                                                   for d in ("D", "DD")]
    model = model_for(m)
    names = [n for n in names if n in model.outputs]
    r = analyze(m, th, names, th2dd=25.0)
    power = r["TORQ"] * m.TH2D
    rate = _energy_rate(m, r, 386.088)
    assert np.max(np.abs(power - rate)) < 1e-11 * np.max(np.abs(power))


@pytest.mark.parametrize("case", [0, 2, 3])
def test_no_cycle_work_where_nothing_dissipates(case):
    """Gravity and a spring are conservative, the crank turns at constant speed: the
    drive's work over a revolution is zero (spectral: the periodic trapezoid rule)."""
    _, m = _kinds()[case]
    th = np.arange(0.0, 360.0, 0.25)
    scene = scene_for(m)(gravity="down",
                         elements=[Spring((1, 20.0, 60.0), (3, 2.0, 0.0), 15.0, 8.0)])
    torq = analyze(m, th, ["TORQ"], scene=scene)["TORQ"]
    work = np.sum(torq) * math.radians(0.25)
    assert abs(work) < 1e-9 * np.sum(np.abs(torq)) * math.radians(0.25)


@pytest.mark.parametrize("kind", [WattII, StephensonIII])
def test_six_bar_positions_where_pylinkage_puts_them(kind):
    """pylinkage's Revolute joints (circle intersections) stepped round from the engine's
    first position: every later B and D is pylinkage's own."""
    pl = pytest.importorskip("pylinkage")
    m = WATT_EXAMPLE if kind is WattII else STEPHENSON_EXAMPLE
    n = 90
    th = np.arange(n) * (360.0 / n)
    r = analyze(m, th, ["XB", "YB", "XC", "YC", "XD", "YD"])
    o2, o4, o6 = pl.Ground(0.0, 0.0), pl.Ground(m.R1, 0.0), pl.Ground(m.X6, m.Y6)
    crank = pl.Crank(anchor=o2, radius=m.R2, angular_velocity=math.radians(360.0 / n))
    b = pl.RRRDyad(crank.output, o4, distance1=m.R3, distance2=m.R4,
                   x=float(r["XB"][0]), y=float(r["YB"][0]))
    # C: RC from O4 (Watt II) or A (Stephenson III), ADELC from that link's line to B
    c = pl.FixedDyad(o4 if kind is WattII else crank.output, b, distance=m.RC,
                     angle=math.radians(m.ADELC))
    d = pl.RRRDyad(c, o6, distance1=m.R5, distance2=m.R6,
                   x=float(r["XD"][0]), y=float(r["YD"][0]))
    linkage = pl.Linkage([o2, o4, o6, crank, b, c, d])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        steps = np.array(list(linkage.step(iterations=n - 1)), dtype=float)
    scale = m.R1 + m.R3 + m.R5
    # each step: every component's (x, y) in the order given; B, C, D are 4, 5, 6
    for j, p in ((4, "B"), (5, "C"), (6, "D")):
        np.testing.assert_allclose(steps[:, j, 0], r[f"X{p}"][1:], atol=1e-9 * scale)
        np.testing.assert_allclose(steps[:, j, 1], r[f"Y{p}"][1:], atol=1e-9 * scale)


def _extremes_by_the_engine(m):
    """Where link 4 turns back: TH4D's sign changes, each found by bisection on the
    engine's TH4D."""
    th = np.arange(0.0, 360.0, 1.0)
    w = analyze(m, th, ["TH4D"])["TH4D"]
    found = []
    for i in np.nonzero(np.sign(w) != np.sign(np.roll(w, -1)))[0]:
        a, b = th[i], th[i] + 1.0
        for _ in range(60):
            mid = 0.5 * (a + b)
            wm = analyze(m, [mid % 360.0], ["TH4D"])["TH4D"][0]
            if np.sign(wm) == np.sign(w[i]):
                a = mid
            else:
                b = mid
        found.append((0.5 * (a + b)) % 360.0)
    return sorted(found)


@pytest.mark.parametrize("offset", [0.0, 1.5, -2.0])
def test_the_quick_return_extremes_are_the_construction(offset):
    m = INVERTED_EXAMPLE.replace(offset=offset)
    q = quick_return(m)
    engine = _extremes_by_the_engine(m)
    assert len(engine) == 2
    np.testing.assert_allclose(sorted(q.at), engine, atol=1e-9)


@pytest.mark.parametrize("R1, R2, printed, source", [
    (300.0, 120.0, 1.7, "Khurmi & Gupta, Theory of Machines, 14th ed., Ex. 5.1, p. 110"),
    (240.0, 120.0, 2.0, "Khurmi & Gupta, Theory of Machines, 14th ed., Ex. 5.2, p. 110"),
    (300.0, 150.0, 2.0, "Sarkar, Theory of Machines, Ch. 1, Ex. 2, p. 16"),
])
def test_the_time_ratio_of_printed_shapers(R1, R2, printed, source):
    """Crank-and-slotted-lever shapers as printed (by their FOSSEE Python Textbook
    Companion notebooks: FOSSEE/Python-Textbook-Companions at d34b2ae); the books give
    the ratio to the digits shown."""
    m = INVERTED_EXAMPLE.replace(R1=R1, R2=R2, offset=0.0)
    q = quick_return(m)
    digits = len(repr(printed).split(".")[1])
    assert round(q.time_ratio, digits) == printed, source
    # and the engine's own extremes give the same ratio
    a, b = _extremes_by_the_engine(m)
    forward = (b - a) % 360.0
    assert max(forward, 360 - forward) / min(forward, 360 - forward) == pytest.approx(
        q.time_ratio, rel=1e-10)


@pytest.mark.parametrize("make, words", [
    (lambda: INVERTED_EXAMPLE.replace(R2=-1.0), "InvertedSliderCrank.R2 = -1: a link's"),
    (lambda: INVERTED_EXAMPLE.replace(R1=0.0), "InvertedSliderCrank.R1 = 0 in: must be > 0"),
    (lambda: INVERTED_EXAMPLE.replace(offset=20.0), "cannot close at any crank angle"),
    (lambda: WATT_EXAMPLE.replace(R5=1.0, R6=1.0), "the RRR dyad at D (links 5 and 6) "
                                                   "cannot close at any crank angle"),
    (lambda: WATT_EXAMPLE.replace(W5=-2.0), "WattII.W5 = -2: weights"),
    (lambda: STEPHENSON_EXAMPLE.replace(X6=float("nan")), "StephensonIII.X6 = nan is not"),
])
def test_bad_geometry_is_one_line_saying_why(make, words):
    with pytest.raises(ValueError) as info:
        analyze(make(), [0.0, 90.0])
    assert words in str(info.value) and "\n" not in str(info.value), str(info.value)


def test_a_crank_that_cannot_turn_fully_is_said_so():
    m = WATT_EXAMPLE.replace(R6=4.0, R5=6.0, X6=14.0, Y6=10.0)
    why = model_for(m).full_turn(m)
    assert why is not None and "the RRR dyad at D (links 5 and 6)" in why, why
    assert model_for(WATT_EXAMPLE).full_turn(WATT_EXAMPLE) is None
    whit = INVERTED_EXAMPLE.replace(R2=10.5, offset=1.0)
    assert "cannot turn a full revolution" in model_for(whit).full_turn(whit)


def test_a_sweep_broadcasts_over_six_bar_designs():
    m = WATT_EXAMPLE.replace(R5=np.array([[9.0], [10.0], [11.0]]))
    th = np.arange(0.0, 360.0, 30.0)
    r = analyze(m, th, ["ATH6", "TORQ"])
    assert r["TORQ"].shape == (3, th.size)
    for i, r5 in enumerate((9.0, 10.0, 11.0)):
        one = analyze(WATT_EXAMPLE.replace(R5=r5), th, ["ATH6", "TORQ"])
        np.testing.assert_allclose(r["TORQ"][i], one["TORQ"], rtol=1e-14, atol=1e-9)


def test_only_the_steps_an_answer_needs_run():
    model = model_for(WATT_EXAMPLE)
    model.calls.clear()
    analyze(WATT_EXAMPLE, [10.0, 20.0], ["ATH6", "TH6D"])
    ran = set(model.calls)
    assert {"_positions", "_velocities"} <= ran
    assert not ran & {"_accelerations", "_inertia_loads", "_inertia_forces", "_totals"}
    model.calls.clear()
    analyze(WATT_EXAMPLE, [10.0], ["TORQ"])
    assert "_inertia_forces" in model.calls
    assert not set(model.calls) & {"_gravity", "_loads", "_elements"}


def test_a_linkage_of_any_dyads_is_analysed():
    """A user's own topology: the slider-crank written as a Linkage (an RRP on the frame's
    line) is the SliderCrank's model, output for output."""
    from sielaff import RRP, SLIDER_EXAMPLE, Guide

    topo = Topology(crank=Crank("R2", "A"),
                    dyads=(RRP("A", "B", "R3", Guide(1, "offset", 90.0, 0.0)),))
    m = SLIDER_EXAMPLE.replace(offset=0.5)
    lk = Linkage(topo, m.as_dict(), m.units)
    th = np.arange(0.0, 360.0, 10.0)
    ours = analyze(m, th, ["XB", "TH3DD", "FB34X", "FN", "TORQ"], gravity="down")
    theirs = analyze(lk, th, ["XB", "TH3DD", "FB34X", "FN", "TORQ"], gravity="down")
    for name in ours:
        np.testing.assert_array_equal(ours[name], theirs[name])
    with pytest.raises(TypeError, match="Linkage has no field R9"):
        lk.replace(R9=1.0)


def test_the_kinds_are_their_own_types():
    assert isinstance(INVERTED_EXAMPLE, InvertedSliderCrank)
    with pytest.raises(TypeError, match="InvertedSliderCrank has no field R3"):
        INVERTED_EXAMPLE.replace(R3=3.0)
