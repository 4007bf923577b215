"""Pin friction (engine/friction.py) against an independent Newton-Euler solve with the
friction couples iterated (tests/newton_euler.py), the power balance with every effect
on (friction losses from the reported pin forces), the hard cases (a toggle, zero
relative rotation), and friction off or mu = 0 bit for bit with no friction step."""

from __future__ import annotations

import warnings
from collections import Counter

import numpy as np
import pytest

import newton_euler as ne
from sielaff import (
    EXAMPLE,
    Damper,
    FrictionWarning,
    Load,
    PinFriction,
    Scene,
    Spring,
    analyze,
)
from sielaff.engine import FOURBAR, OUTPUTS, STEP_CALLS, plan
from sielaff.engine.compiled import available
from test_elements import angles, draw

FORCES = ("FA32", "FB34", "FOA", "FOB")
PLOSS = ("PLOSS_O2", "PLOSS_A", "PLOSS_B", "PLOSS_O4")
CASES = [(m, kind, branch, i) for i, (m, kind) in enumerate(draw(12, 7))
         for branch in ("open", "crossed")]
DRAWN: Counter[str] = Counter()


def scene_for(rng, branch, friction):
    els = [Spring((1, 2.0, 60.0), (3, 1.0, 20.0), float(rng.uniform(0, 100)), 1.0),
           Damper((2, 1.0, 0.0), (4, 1.0, 30.0), float(rng.uniform(0, 3)))]
    return Scene(friction=friction, elements=els, tex=float(rng.uniform(-50, 50)),
                 th2dd=float(rng.uniform(-300, 300)),
                 gravity=(float(rng.uniform(-400, 400)), float(rng.uniform(-400, 400))),
                 loads=[Load(3, 1.0, 10.0, 30.0, -5.0, 2.0)], branch=branch)


def pin_force(r, pin, j):
    n = {"O2": "FOA", "A": "FA32", "B": "FB34", "O4": "FOB"}[pin]
    return float(np.hypot(r[n + "X"][j], r[n + "Y"][j]))


def case_draw(m, branch, i):
    """CASES' i-th draw: each pin's friction, the scene (every effect on) and the crank
    angles away from toggles; skipped where there are none."""
    rng = np.random.default_rng(100 + i)
    mus = {p: PinFriction(float(rng.uniform(0, 0.3)), float(rng.uniform(0, 0.1)))
           for p in ne.PINS}
    sc = scene_for(rng, branch, mus)
    th = angles(m, branch)
    if not len(th):
        pytest.skip("no position away from a toggle")
    return mus, sc, th


@pytest.mark.parametrize("m, kind, branch, i", CASES,
                         ids=[f"{c[1]}-{c[2]}-{c[3]}" for c in CASES])
def test_friction_agrees_with_newton_euler_and_the_power_balance(m, kind, branch, i):
    mus, sc, th = case_draw(m, branch, i)
    names = [n + c for n in FORCES for c in "XY"] + ["TORQ", "TORQ_FRICTION",
                                                     "FRICTION_STATUS", *PLOSS]
    r = analyze(m, th, names, scene=sc)
    without = analyze(m, th, ["TORQ"], scene=sc.replace(friction=None))
    mur = tuple(mus[p].mu * mus[p].radius for p in ne.PINS)
    for j, t in enumerate(th):
        ref = ne.solve(m, float(t), ne.engine_b(m, float(t), sc), a2=sc.th2dd, tex=sc.tex,
                       elements=sc.elements, gravity=sc.gravity, loads=sc.loads, mur=mur)
        if r["FRICTION_STATUS"][j] == 2.0:
            assert ref is None or max(ref["T"]) > 0  # counted below as not converged
            DRAWN["not converged"] += 1
            continue
        DRAWN[f"{kind} {branch}"] += 1
        DRAWN[f"status {r['FRICTION_STATUS'][j]:g}"] += 1
        assert ref is not None
        assert (r["FRICTION_STATUS"][j] == 1.0) == (0.0 in ref["sg"])
        scale = max(abs(ref[n]) for n in FORCES) + abs(ref["TORQ"]) / m.R2
        for n in FORCES:
            assert abs(complex(r[n + "X"][j], r[n + "Y"][j]) - ref[n]) <= 1e-9 * scale, n
        assert abs(r["TORQ"][j] - ref["TORQ"]) <= 1e-9 * scale * m.R2
        assert abs(r["TORQ"][j] - without["TORQ"][j] - r["TORQ_FRICTION"][j]) \
            <= 1e-9 * scale * m.R2
        # the losses from the reported pin forces, by the Coulomb law (not the engine's)
        s = ref["state"]
        rel = (m.TH2D, s["w3"] - m.TH2D, s["w4"] - s["w3"], s["w4"])
        loss = [mur[k] * pin_force(r, p, j) * abs(rel[k]) * abs(ref["sg"][k])
                for k, p in enumerate(ne.PINS)]
        for k, p in enumerate(ne.PINS):
            assert r[p.join(("PLOSS_", ""))][j] == pytest.approx(loss[k], rel=1e-9,
                                                                 abs=1e-9 * scale)
        # drive + TEX + gravity + loads + springs/dampers = d(KE)/dt + friction losses
        lhs = r["TORQ"][j] * m.TH2D + ref["p_external"] + ref["p_elements"]
        rhs = ref["ke_rate"] + sum(loss)
        big = max(abs(r["TORQ"][j] * m.TH2D), abs(ref["p_external"]),
                  abs(ref["p_elements"]), abs(ref["ke_rate"]), sum(loss), 1e-300)
        assert abs(lhs - rhs) <= 1e-9 * big


def test_the_friction_draw_covers_kinds_and_branches():
    """The draw (CASES) holds several kinds and both branches; the positions checked
    above are counted in DRAWN (printed with -s) when run in the same session."""
    if DRAWN:
        print(dict(DRAWN))
    kinds = Counter((kind, branch) for _, kind, branch, _ in CASES)
    assert len({k for k, _ in kinds}) >= 3, kinds
    assert {b for _, b in kinds} == {"open", "crossed"}


def test_friction_off_or_mu_zero_is_bit_for_bit_with_no_friction_step():
    th = np.arange(0.0, 360.0, 5.0)
    base = Scene(tex=4.0, gravity="down", elements=[Damper((1, 1, 0), (3, 2, 0), 0.5)])
    a = analyze(EXAMPLE, th, OUTPUTS, scene=base)
    for friction in (PinFriction(0.0, 0.3), PinFriction(0.2, 0.0), {"A": PinFriction(0, 1)},
                     {}):
        sc = base.replace(friction=friction)
        STEP_CALLS.clear()
        b = analyze(EXAMPLE, th, OUTPUTS, scene=sc)
        assert not any(k.startswith(("_friction", "_corrections")) for k in STEP_CALLS)
        for n in OUTPUTS:
            np.testing.assert_array_equal(a[n], b[n], err_msg=n)
        steps = plan(["TORQ", "FA32", "SHAKM", "TORQ_INERTIA"], scene=sc)
        assert not any("friction" in s or "correction" in s for s in steps)
    on = plan(["TORQ"], scene=base.replace(friction=PinFriction(0.1, 0.2)))
    assert "_friction_fixed_point" in on and "_corrections" in on


def test_one_pin_only_and_the_breakdown_adds_up():
    th = np.arange(3.0, 360.0, 10.0)
    sc = Scene(friction={"B": PinFriction(0.2, 0.5)}, tex=10.0)
    r = analyze(EXAMPLE, th, ["TORQ", "TORQ_FRICTION", "TORQ_TEX", "TORQ_INERTIA", *PLOSS],
                scene=sc)
    for p in ("PLOSS_O2", "PLOSS_A", "PLOSS_O4"):
        assert not np.any(r[p])
    assert np.all(r["PLOSS_B"] >= 0) and np.any(r["PLOSS_B"] > 0)
    np.testing.assert_allclose(r["TORQ_FRICTION"] + r["TORQ_TEX"] + r["TORQ_INERTIA"],
                               r["TORQ"], rtol=1e-12, atol=1e-9)


def test_friction_always_costs_the_drive_over_a_revolution():
    """Over a revolution at constant speed friction only takes work: the cycle work of
    TORQ_FRICTION equals the summed losses (positive)."""
    th = np.linspace(0.0, 360.0, 3601)[:-1]
    r = analyze(EXAMPLE, th, ["TORQ_FRICTION", *PLOSS], scene=Scene(
        friction=PinFriction(0.15, 0.4)))
    work = np.mean(r["TORQ_FRICTION"]) * 2 * np.pi
    losses = np.mean(sum(r[p] for p in PLOSS)) / EXAMPLE.TH2D * 2 * np.pi
    assert work > 0
    assert work == pytest.approx(losses, rel=1e-3)


def test_near_a_toggle_the_law_is_solved_where_the_fixed_point_diverges():
    """A double-rocker near its toggle: the pin forces grow without bound and the fixed
    point diverges (FRICTION_ITERATIONS 0), but the law has solutions there (two): the
    one continuous from mu = 0 is taken (status 0), with no warning; 30 degrees away
    the fixed point converges to the only one."""
    from sielaff.engine.classify import linkage_class

    m = EXAMPLE.replace(R1=10.0, R2=6.0, R3=3.0, R4=8.0, TH2D=10.0)
    toggles = linkage_class(m).toggles
    t0 = float(toggles[np.isfinite(toggles)][0])
    side = 1.0 if np.isfinite(analyze(m, t0 + 0.01, ["GAMMA"])["GAMMA"]) else -1.0
    th = t0 + side * np.array([1e-9, 1e-7, 1e-5, 1e-3, 1e-1, 30.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error", FrictionWarning)
        r = analyze(m, th, ["TORQ", "FRICTION_STATUS", "FRICTION_ITERATIONS",
                            "FRICTION_SOLUTIONS", "FA32X"],
                    scene=Scene(friction=PinFriction(0.3, 1.0)))
    assert np.all(r["FRICTION_STATUS"] == 0.0) and np.all(np.isfinite(r["TORQ"]))
    assert np.all(r["FRICTION_ITERATIONS"][:5] == 0) and r["FRICTION_ITERATIONS"][5] > 0
    assert list(r["FRICTION_SOLUTIONS"]) == [2.0] * 5 + [1.0]
    # the drive torque grows as the toggle nears (as 1 / distance)
    assert np.all(np.diff(np.abs(r["TORQ"][:5])) < 0)


def test_zero_relative_rotation_is_a_documented_case():
    """At rest (TH2D = 0) no pin turns: static friction is taken as zero, status 1.  In
    the 1966 example at THETA 2 = 0 the coupler and the rocker turn alike (TH3D = TH4D),
    so B does not slide: PLOSS_B is 0 and the status 1."""
    still = analyze(EXAMPLE.replace(TH2D=0.0), [10.0, 50.0], ["FRICTION_STATUS", "TORQ",
                                                               "TORQ_FRICTION"],
                    scene=Scene(friction=PinFriction(0.2, 0.5), tex=5.0))
    assert list(still["FRICTION_STATUS"]) == [1.0, 1.0]
    assert not np.any(still["TORQ_FRICTION"])
    r = analyze(EXAMPLE, [0.0, 10.0], ["TH3D", "TH4D", "FRICTION_STATUS", "PLOSS_B"],
                scene=Scene(friction=PinFriction(0.2, 0.5)))
    assert r["TH3D"][0] == r["TH4D"][0]
    assert list(r["FRICTION_STATUS"]) == [1.0, 0.0]
    assert r["PLOSS_B"][0] == 0.0 and r["PLOSS_B"][1] > 0.0


@pytest.mark.parametrize("backend", ["numpy", pytest.param("numba", marks=pytest.mark.skipif(
    not available(), reason="numba is not installed"))])
def test_a_pin_at_rest_to_within_roundoff_is_at_rest(backend):
    """In the 1966 example B is at rest at THETA 2 = 180 (TH3D = TH4D) and O4 at 240 (the
    rocker's dead point, TH4D = 0) by the geometry, but their computed relative rates are
    a few ulps of either sign, which may differ between machines: each is at rest
    (engine/friction.py's rest_sign), status 1, no loss there, and the answer the
    Newton-Euler solve's (which takes a rate within 1e-12 of the fastest link as zero),
    on both backends; a degree away each pin turns."""
    sc = Scene(friction=PinFriction(0.2, 0.5))
    th = np.array([180.0, 181.0, 240.0, 241.0])
    names = [n + c for n in FORCES for c in "XY"] + ["TORQ", "FRICTION_STATUS", *PLOSS]
    r = analyze(EXAMPLE, th, names, scene=sc, backend=backend)
    assert list(r["FRICTION_STATUS"]) == [1.0, 0.0, 1.0, 0.0]
    assert r["PLOSS_B"][0] == 0.0 and r["PLOSS_O4"][2] == 0.0
    assert r["PLOSS_B"][1] > 0.0 and r["PLOSS_O4"][3] > 0.0
    mur = (0.1,) * 4
    for j, t in enumerate(th):
        ref = ne.solve(EXAMPLE, float(t), ne.engine_b(EXAMPLE, float(t), sc), mur=mur)
        assert (0.0 in ref["sg"]) == (j % 2 == 0)
        scale = max(abs(ref[n]) for n in FORCES)
        for n in FORCES:
            assert abs(complex(r[n + "X"][j], r[n + "Y"][j]) - ref[n]) <= 1e-10 * scale, n
        assert abs(r["TORQ"][j] - ref["TORQ"]) <= 1e-10 * scale * EXAMPLE.R2


def test_speed_and_acceleration_arrays_as_simulate_uses_them():
    th = np.array([10.0, 100.0, 200.0])
    w = np.array([20.0, -30.0, 45.0])
    a2 = np.array([5.0, -50.0, 100.0])
    sc = Scene(friction=PinFriction(0.1, 0.3), elements=[Spring((1, 3, 0), (4, 2, 0), 5, 1)],
               th2dd=a2)
    r = analyze(EXAMPLE.replace(TH2D=w), th, ["TORQ"], scene=sc)
    for j in range(3):
        one = analyze(EXAMPLE.replace(TH2D=float(w[j])), th[j], ["TORQ"],
                      scene=sc.replace(th2dd=float(a2[j])))
        assert r["TORQ"][j] == pytest.approx(float(one["TORQ"]), rel=1e-12)


def test_out_blocks_give_the_same_friction():
    th = np.arange(0.0, 360.0, 1.0)
    sc = Scene(friction=PinFriction(0.1, 0.3))
    full = analyze(EXAMPLE, th, ["TORQ", "PLOSS_A"], scene=sc)
    out = {n: np.empty_like(th) for n in ("TORQ", "PLOSS_A")}
    analyze(EXAMPLE, th, scene=sc, out=out, block=50)
    for n in out:
        np.testing.assert_array_equal(out[n], full[n])


@pytest.mark.parametrize("bad, words", [
    (lambda: PinFriction(-0.1, 1.0), "PinFriction.mu"),
    (lambda: PinFriction(0.1, float("nan")), "PinFriction.radius"),
    (lambda: PinFriction(0.1, 1.0, tol=0.0), "PinFriction.tol"),
    (lambda: PinFriction(0.1, 1.0, max_iter=0), "PinFriction.max_iter"),
    (lambda: Scene(friction=0.2), "Scene.friction"),
    (lambda: Scene(friction={"C": PinFriction(0.1, 1)}), "unknown pin 'C'"),
    (lambda: Scene(friction={"A": 0.1}), "Scene.friction['A']"),
])
def test_bad_friction_is_one_line_naming_the_field(bad, words):
    with pytest.raises(ValueError) as e:
        bad()
    assert words in str(e.value) and "\n" not in str(e.value)


def test_the_model_knows_friction_outputs_even_when_off():
    for n in ("TORQ_FRICTION", *PLOSS, "FRICTION_STATUS", "FRICTION_ITERATIONS"):
        assert n in FOURBAR.outputs
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = analyze(EXAMPLE, [30.0], ["TORQ_FRICTION", "PLOSS_A"])
    assert r["TORQ_FRICTION"][0] == 0.0 and r["PLOSS_A"][0] == 0.0
