"""Springs and dampers (engine/elements.py) against an independent Newton-Euler solve
(tests/newton_euler.py: B by circle intersection, rates by 2 x 2 solves, the nine balance
equations) and the power balance with every effect on, on drawn mechanisms of every
kind the draw reaches and both branches (counted)."""

from __future__ import annotations

import warnings
from collections import Counter

import numpy as np
import pytest

import newton_euler as ne
from sielaff import EXAMPLE, Damper, Load, PinFriction, Scene, Spring, analyze
from sielaff.engine import plan
from sielaff.engine.classify import linkage_class
from sielaff.engine.positions import reachable

FORCES = ("FA32", "FB34", "FOA", "FOB")


def draw(n, seed):
    """``n`` mechanisms (lengths, masses, speeds) from a fixed seed, with their kinds."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        r = rng.uniform(1.0, 6.0, 4)
        m = EXAMPLE.replace(R1=r[0], R2=r[1], R3=r[2], R4=r[3], RG2=0.4 * r[1],
                            RG3=rng.uniform(0, 1) * r[2], RG4=0.6 * r[3],
                            W2=rng.uniform(0, 10), W3=rng.uniform(0, 10), W4=rng.uniform(0, 10),
                            ZI2=rng.uniform(0, 2), ZI3=rng.uniform(0, 2), ZI4=rng.uniform(0, 2),
                            ADEL3=rng.uniform(-45, 45), TH2D=rng.uniform(-60, 60))
        kind = linkage_class(m).kind
        if kind == "change-point":
            continue
        out.append((m, kind))
    return out


def random_elements(rng):
    els = []
    for _ in range(rng.integers(1, 4)):
        a = (int(rng.integers(1, 5)), float(rng.uniform(0, 3)), float(rng.uniform(-180, 180)))
        b = (int(rng.integers(1, 5)), float(rng.uniform(0, 3)), float(rng.uniform(-180, 180)))
        if a[0] == b[0]:
            b = (a[0] % 4 + 1,) + b[1:]
        if rng.uniform() < 0.5:
            els.append(Spring(a, b, float(rng.uniform(0, 200)), float(rng.uniform(0, 5))))
        else:
            els.append(Damper(a, b, float(rng.uniform(0, 5))))
    return els


def angles(m, branch, k=6):
    """``k`` crank angles the linkage reaches, away from its toggles (|sin GAMMA| > 0.2)."""
    th = reachable(m, 73)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        g = analyze(m, th, ["GAMMA"], scene=Scene(branch=branch))["GAMMA"]
    th = th[np.abs(np.sin(np.radians(g))) > 0.2]
    return th[:: max(1, len(th) // k)][:k]


SEEN: Counter[str] = Counter()
CASES = [(m, kind, branch, i) for i, (m, kind) in enumerate(draw(14, 23))
         for branch in ("open", "crossed")]


@pytest.mark.parametrize("m, kind, branch, i", CASES,
                         ids=[f"{c[1]}-{c[2]}-{c[3]}" for c in CASES])
def test_elements_agree_with_newton_euler_and_the_power_balance(m, kind, branch, i):
    rng = np.random.default_rng(i)
    els = random_elements(rng)
    gravity = (float(rng.uniform(-400, 400)), float(rng.uniform(-400, 400)))
    loads = [Load(int(rng.integers(2, 5)), 1.0, 30.0, 20.0, -10.0, 5.0)]
    tex = float(rng.uniform(-50, 50))
    a2 = float(rng.uniform(-300, 300))
    sc = Scene(elements=els, gravity=gravity, loads=loads, tex=tex, th2dd=a2, branch=branch)
    th = angles(m, branch)
    if not len(th):
        pytest.skip("no position away from a toggle")
    SEEN[kind + " " + branch] += 1
    names = [n + c for n in FORCES for c in "XY"] + ["TORQ", "TORQ_ELEMENTS", "TH4D"]
    names += [f"{kind_}{k}_{q}" for kind_ in ("SPRING", "DAMPER") for k in (1, 2, 3)
              for q in ("L", "LD", "F")]
    r = analyze(m, th, names, scene=sc)
    without = analyze(m, th, ["TORQ"], scene=sc.replace(elements=()))
    for j, t in enumerate(th):
        ref = ne.solve(m, float(t), ne.engine_b(m, float(t), sc), a2=a2, tex=tex, elements=els,
                       gravity=gravity, loads=loads)
        scale = max(abs(ref[n]) for n in FORCES) + abs(ref["TORQ"]) / m.R2
        for n in FORCES:
            assert abs(complex(r[n + "X"][j], r[n + "Y"][j]) - ref[n]) <= 1e-9 * scale, n
        assert abs(r["TORQ"][j] - ref["TORQ"]) <= 1e-9 * scale * m.R2
        assert abs(r["TORQ"][j] - without["TORQ"][j] - r["TORQ_ELEMENTS"][j]) <= 1e-9 * scale * m.R2
        count = Counter()
        for e in els:
            kind_ = "SPRING" if isinstance(e, Spring) else "DAMPER"
            count[kind_] += 1
            L, rate, ten, *_ = ne.element(ref["state"], e)
            k = count[kind_]
            assert r[f"{kind_}{k}_L"][j] == pytest.approx(L, rel=1e-9)
            assert r[f"{kind_}{k}_LD"][j] == pytest.approx(rate, rel=1e-9,
                                                           abs=1e-9 * abs(L * m.TH2D))
            assert r[f"{kind_}{k}_F"][j] == pytest.approx(ten, rel=1e-9, abs=1e-9 * scale)
        for kind_ in ("SPRING", "DAMPER"):
            for k in range(count[kind_] + 1, 4):
                assert r[f"{kind_}{k}_L"][j] == 0.0  # an element the scene does not have
        # power: drive + TEX + gravity + loads + springs/dampers = d(KE)/dt
        power = r["TORQ"][j] * m.TH2D + ref["p_external"] + ref["p_elements"]
        big = max(abs(r["TORQ"][j] * m.TH2D), abs(ref["p_external"]), abs(ref["p_elements"]),
                  abs(ref["ke_rate"]), 1e-300)
        assert abs(power - ref["ke_rate"]) <= 1e-9 * big


def test_the_draw_reaches_several_kinds_and_both_branches():
    kinds = Counter((kind, branch) for _, kind, branch, _ in CASES)
    assert len({k for k, _ in kinds}) >= 3, kinds
    assert {b for _, b in kinds} == {"open", "crossed"}


def test_a_spring_in_the_1966_example_by_virtual_work():
    """A spring between the frame and the coupler, the drive torque it takes by virtual
    work with L from finite differences of independently found points (no engine)."""
    sp = Spring((1, 6.0, 90.0), (3, 8.0, 0.0), 30.0, 5.0)
    th = np.arange(5.0, 360.0, 20.0)
    r = analyze(EXAMPLE, th, ["TORQ_ELEMENTS", "SPRING1_L", "SPRING1_F"], scene=Scene(
        elements=[sp]))

    def length(t):
        s = ne.state(EXAMPLE, t, 1.0, 0.0, ne.engine_b(EXAMPLE, t))
        return ne.element(s, sp)[0]

    h = 1e-4
    for j, t in enumerate(th):
        dl = (length(t + h) - length(t - h)) / np.radians(2 * h)  # dL/dth2
        ten = 30.0 * (length(t) - 5.0)
        # virtual work: TORQ dth2 = T dL (the drive stretches the spring against T)
        assert r["TORQ_ELEMENTS"][j] == pytest.approx(ten * dl, rel=1e-6, abs=1e-6)
        assert r["SPRING1_F"][j] == pytest.approx(ten, rel=1e-12)


def test_no_elements_is_the_1966_engine_bit_for_bit_and_runs_no_element_step():
    th = np.arange(0.0, 360.0, 7.0)
    a = analyze(EXAMPLE, th, scene=Scene(tex=3.0))
    b = analyze(EXAMPLE, th, scene=Scene(tex=3.0, elements=()))
    for n in a:
        np.testing.assert_array_equal(a[n], b[n])
    steps = plan(None, scene=Scene(elements=()))
    assert not any(s.startswith("_element") and not s.endswith("=0") for s in steps)
    assert "_elements" in plan(None, scene=Scene(elements=[Damper((1, 1, 0), (2, 1, 0), 1.0)]))


@pytest.mark.parametrize("bad, words", [
    (lambda: Spring((0, 1, 0), (2, 1, 0), 1.0, 1.0), "Spring.a link"),
    (lambda: analyze(EXAMPLE, [10.0],
                     scene=Scene(elements=[Spring((5, 1, 0), (2, 1, 0), 1.0, 1.0)])),
     "point on link 5: this linkage's links are 1 (the frame) to 4"),
    (lambda: Spring((1, 1, 0), (2, float("nan"), 0), 1.0, 1.0), "Spring.b r"),
    (lambda: Spring((1, 1, 0), (2, 1, 0), 1.0, -1.0), "Spring.length"),
    (lambda: Damper((1, 1), (2, 1, 0), 1.0), "Damper.a"),
    (lambda: Damper((1, 1, 0), (2, 1, 0), float("inf")), "Damper.c"),
    (lambda: Scene(elements=[Load(2)]), "Scene.elements[0]"),
    (lambda: Scene(elements=Spring((1, 1, 0), (2, 1, 0), 1, 1)), "Scene.elements"),
    (lambda: Scene(elements=[Damper((1, 1, 0), (2, 1, 0), 1.0)] * 9), "more than 8"),
])
def test_bad_elements_are_one_line_errors_naming_the_field(bad, words):
    with pytest.raises(ValueError) as e:
        bad()
    assert words in str(e.value) and "\n" not in str(e.value)


def test_the_compiled_backend_takes_pin_friction():
    """Springs, dampers and pin friction are compiled (tests/test_compiled.py and
    tests/test_compiled_friction.py compare them, with friction's count of solutions)."""
    pytest.importorskip("numba")
    sc = Scene(friction=PinFriction(0.1, 0.2))
    got = analyze(EXAMPLE, [10.0], ["TORQ"], scene=sc, backend="numba")["TORQ"]
    ref = analyze(EXAMPLE, [10.0], ["TORQ"], scene=sc)["TORQ"]
    assert abs(got[0] - ref[0]) <= 1e-12 * abs(ref[0])

