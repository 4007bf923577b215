"""Coulomb friction in the pins and slides of the linkage engine's kinds
(engine/joint_friction.py) against an independent fixed-point Newton-Euler solve in 40
digits (tests/linkage_reference.py), the power balance (the drive's power is the kinetic
energy's rate plus every joint's loss), and what friction that is off costs (nothing).
The compiled backend (``backend="numba"``, which runs the same three steps: engine/
kernel.py) is held to the same reference and balance, and to the numpy engine's status
and iterations where the solve needs the ramp from mu = 0 or finds no solution."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import linkage_reference as ref
from sielaff import (
    INVERTED_EXAMPLE,
    SLIDER_EXAMPLE,
    STEPHENSON_EXAMPLE,
    WATT_EXAMPLE,
    FrictionWarning,
    PinFriction,
    analyze,
    scene_for,
)
from sielaff.engine import model_for
from sielaff.engine.compiled import NOT_GIVEN, available
from sielaff.engine.joint_friction import NEWTON

BACKENDS = ["numpy", pytest.param("numba", marks=pytest.mark.skipif(
    not available(), reason="numba is not installed"))]

CASES = [("slider", SLIDER_EXAMPLE.replace(offset=0.6, ADEL3=8.0, TH2D=60.0)),
         ("inverted", INVERTED_EXAMPLE.replace(offset=0.8)),
         ("watt", WATT_EXAMPLE.replace(TH2D=20.0)),
         ("stephenson", STEPHENSON_EXAMPLE.replace(TH2D=20.0))]

#: Each pin's mu r [in], the slide's mu: different at each joint, so a joint mixed up fails.
MUR = {"O2": 0.02, "A": 0.03, "B": 0.025, "O4": 0.035, "C": 0.015, "D": 0.04, "O6": 0.01}
MU_SLIDE = 0.12


def _scene(m, gravity="down"):
    friction = {p: PinFriction(mur / 0.5, 0.5) for p, mur in MUR.items()
                if p in _pins(m)}
    if "slide" in _joints(m):
        friction["slide"] = PinFriction(MU_SLIDE, 0.0)
    return scene_for(m)(gravity=gravity, th2dd=-15.0, friction=friction)


def _outputs(m, backend):
    """Every output of the kind for numpy; for numba those the two tests below compare, so
    that they share one kernel per kind, and a smaller one (every output of a six-bar
    with friction makes a kernel several times slower to compile)."""
    outputs = model_for(m).outputs
    if backend == "numpy":
        return outputs
    return [n for n in outputs if n not in NOT_GIVEN
            and n.startswith(("F", "MN", "TORQ", "PLOSS_", "AG", "VG", "TH"))]


def _agrees_with_the_reference(kind, m, th, r, j):
    """Position j (crank angle th) of the results r against the 40-digit Newton-Euler
    solve with _scene's friction: TORQ, every pin force, FN and MN where there is a
    slide, to 1e-10 of the forces' and the torque's scales; the torque's scale."""
    out = ref.newton_euler(kind, m, th, m.TH2D, -15.0, branch=(1, 1),
                           gravity=(0.0, -386.088), mur={p: MUR[p] for p in _pins(m)},
                           mu_slide=MU_SLIDE if "slide" in _joints(m) else 0.0)
    scale = max(abs(complex(v)) for k, v in out.items() if isinstance(k, tuple))
    tscale = abs(float(out["TORQ"])) + 1.0
    assert float(r["TORQ"][j]) == pytest.approx(float(out["TORQ"]), abs=1e-10 * tscale)
    forces = [(key, F) for key, F in out.items() if isinstance(key, tuple)]
    assert len(forces) == len(ref.pins(kind))
    for key, F in forces:
        name = _force_name(m, *key)
        assert abs(complex(r[name + "X"][j], r[name + "Y"][j]) - complex(F)) \
            <= 1e-10 * scale, name
    if "FN" in out:
        assert float(r["FN"][j]) == pytest.approx(float(out["FN"]), abs=1e-10 * scale)
        assert float(r["MN"][j]) == pytest.approx(float(out["MN"]), abs=1e-10 * tscale)
    return tscale


def _joints(m):
    from sielaff.engine.joint_friction import _names

    return _names(model_for(m).topology)[2]


def _pins(m):
    return [j for j in _joints(m) if not j.startswith("slide")]


def _force_name(m, p, by, on):
    names = dict(model_for(m).topology.names)
    generic = f"F{p}" if on == 1 else f"F{p}{by}{on}"
    return names.get(generic, generic)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("case", range(len(CASES)))
def test_friction_is_the_independent_fixed_point(case, backend):
    kind, m = CASES[case]
    compared = 0
    for th in (23.0, 141.0, 262.0):
        r = analyze(m, [th], _outputs(m, backend), scene=_scene(m), backend=backend)
        assert r["FRICTION_STATUS"][0] == 0.0
        tscale = _agrees_with_the_reference(kind, m, th, r, 0)
        compared += 1
    assert compared == 3
    # and friction did something: TORQ moved by more than the tolerance
    assert np.max(np.abs(analyze(m, [23.0, 141.0], _outputs(m, backend), scene=_scene(m),
                                 backend=backend)["TORQ_FRICTION"])) > 1e-3 * tscale


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("case", range(len(CASES)))
def test_the_drive_power_is_the_energy_rate_plus_the_losses(case, backend):
    """TORQ TH2D = d(kinetic + potential energy)/dt + sum of the joints' losses (gravity
    the only other force that works on the linkage: each weight W VGY), on the engine's
    own rates: an identity the friction solve must satisfy, whatever the law's signs."""
    kind, m = CASES[case]
    th = np.arange(1.0, 360.0, 7.0)
    model = model_for(m)
    r = analyze(m, th, _outputs(m, backend), scene=_scene(m), backend=backend)
    losses = sum(r[n] for n in model.outputs if n.startswith("PLOSS_"))
    assert np.all(losses >= 0.0)
    energy_rate = 0.0
    for k in range(2, model.topology.links + 1):
        mass = float(getattr(m, f"W{k}", 0.0)) / 386.088
        energy_rate = energy_rate + mass * (r[f"AG{k}X"] * r[f"VG{k}X"]
                                            + r[f"AG{k}Y"] * r[f"VG{k}Y"])
        energy_rate = energy_rate + mass * 386.088 * r[f"VG{k}Y"]  # gravity's: W VGY
        zi = float(getattr(m, f"ZI{k}", 0.0))
        energy_rate = energy_rate + zi * (r[f"TH{k}DD"] * r[f"TH{k}D"] if k > 2
                                          else -15.0 * m.TH2D)
    power = r["TORQ"] * m.TH2D
    ok = r["FRICTION_STATUS"] == 0.0
    assert ok.sum() >= th.size - 2
    np.testing.assert_allclose(power[ok], (energy_rate + losses)[ok], rtol=0,
                               atol=1e-10 * np.max(np.abs(power)))


#: Each kind's example and the crank angles where one of its joints is at rest by the
#: geometry (found by scanning the rates over a revolution: exactly, or to some 1e-16 of
#: them, of either sign): the slider-crank's slide at 0 and 180, its pin B at 90 and 270;
#: the inverted slider-crank's slide at 0 and 180; the six-bars' B at 0 and 180, and at
#: 240 the Watt's pins O6 (its rocker at a dead point) and the Stephenson's O4.
AT_REST = [("slider", SLIDER_EXAMPLE, (0.0, 90.0, 180.0, 270.0)),
           ("inverted", INVERTED_EXAMPLE, (0.0, 180.0)),
           ("watt", WATT_EXAMPLE, (0.0, 180.0, 240.0)),
           ("stephenson", STEPHENSON_EXAMPLE, (0.0, 180.0, 240.0))]


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("case", range(len(AT_REST)))
def test_a_joint_at_rest_to_within_roundoff_is_at_rest(case, backend):
    """Where a joint is at rest by the geometry its computed relative rate is zero or a
    few ulps of either sign, which may differ between machines: the joint is at rest
    (engine/friction.py's rest_sign: FRICTION_STATUS 1, its friction and its loss zero)
    and the answer is the 40-digit reference's (where the rate is zero to 40 digits);
    a degree away every joint moves (status 0)."""
    kind, m, rest = AT_REST[case]
    model = model_for(m)
    th = np.sort(np.concatenate([rest, np.array(rest) + 1.0]))
    r = analyze(m, th, _outputs(m, backend), scene=_scene(m), backend=backend)
    at_rest = np.isin(th, rest)
    np.testing.assert_array_equal(r["FRICTION_STATUS"], np.where(at_rest, 1.0, 0.0))
    losses = np.array([r[n] for n in model.outputs if n.startswith("PLOSS_")])
    assert np.all(np.any(losses[:, at_rest] == 0.0, axis=0))
    assert np.all(losses[:, ~at_rest] > 0.0)
    compared = 0
    for j in np.flatnonzero(at_rest):
        _agrees_with_the_reference(kind, m, th[j], r, j)
        compared += 1
    assert compared == len(rest)


def test_friction_that_is_off_costs_nothing():
    m = WATT_EXAMPLE
    model = model_for(m)
    th = np.arange(0.0, 360.0, 10.0)
    plain = analyze(m, th, model.results, gravity="down")
    model.calls.clear()
    off = analyze(m, th, model.results,
                  scene=scene_for(m)(gravity="down", friction=PinFriction(0.0, 1.0)))
    assert not [c for c in model.calls if c.startswith("_joint_friction")]
    for name in plain:
        np.testing.assert_array_equal(plain[name], off[name])
    # the scene says so as the four-bar's does (check and report ask it)
    analyze(m, th, ["TORQ"], scene=scene_for(m)(friction=PinFriction(0.1, 1.0)))
    assert {"_joint_friction_system", "_joint_friction_newton",
            "_joint_friction_losses"} <= set(model.calls)  # the check above can fail
    assert not scene_for(m)(friction=PinFriction(0.0, 1.0)).has_friction
    assert scene_for(m)(friction=PinFriction(0.1, 1.0)).has_friction


def _slide_solutions(m, th, mu, fex):
    """How many solutions the slide's friction law has (no pin friction), counted exactly:
    the guide's friction force phi along +x on the slider is affine in FN (superposition,
    the independent solve at phi = 0 and 1), and phi = -mu |FN| sgn(VXB) has, for each sign
    s of FN, the one candidate FN = FN0 / (1 + k mu sgn(VXB) s), a solution if its sign is
    s."""
    import mpmath as mp

    mo = ref.motion("slider", m, th, m.TH2D)
    bs = ref.bodies("slider", m)
    pts = mo["B"][0]

    def fn(phi):
        loads = [(4, pts, mp.mpc(phi, 0), 0), (4, pts, mp.mpc(fex, 0), 0)]
        return ref._solve("slider", m, mo, bs, (0.0, 0.0), loads, "in-lb-sec")["FN"]

    fn0 = fn(0)
    k = fn(1) - fn0
    v = mp.sign(mo["ths"][1])
    count = 0
    for s in (1, -1):
        cand = fn0 / (1 + k * mu * v * s)
        count += int(mp.sign(cand) == s)
    return count


def test_a_slide_that_locks_is_nan_and_said_so():
    """A slider-crank with mu = 5 at its guide and a gas force: where the rod's thrust lies
    inside the friction cone the law has no solution (self-locking).  The engine's status
    2 is exactly where an exact count of the law's solutions is 0; elsewhere it solves."""
    m = SLIDER_EXAMPLE.replace(TH2D=40.0)
    th = np.arange(1.0, 360.0, 4.0)
    sc = scene_for(m)(friction={"slide": PinFriction(5.0, 0.0)}, fex=-500.0)
    with pytest.warns(FrictionWarning, match="reach no solution"):
        r = analyze(m, th, ["TORQ", "FRICTION_STATUS"], scene=sc)
    locked = r["FRICTION_STATUS"] == 2.0
    counts = np.array([_slide_solutions(m, t, 5.0, -500.0) for t in th])
    assert 0 < locked.sum() < th.size
    np.testing.assert_array_equal(locked, counts == 0)
    assert np.all(np.isnan(r["TORQ"][locked])) and np.all(np.isfinite(r["TORQ"][~locked]))


@pytest.mark.skipif(not available(), reason="numba is not installed")
def test_compiled_where_the_ramp_is_needed_and_where_the_slide_locks():
    """A slider-crank with mu = 3.5 at its guide and mu r = 0.6 in its pins (searched for:
    the ramp is rare), where Newton at full mu fails and the ramp from mu = 0 solves
    (more than NEWTON iterations: counted), and where it locks (status 2): the compiled
    kernel, which runs Newton's passes over a chunk with no branch, gives the numpy
    engine's status at every position, its iterations at nearly all, its answers to a
    bound (Gaussian elimination there, LAPACK here), and the same warning."""
    m = SLIDER_EXAMPLE.replace(TH2D=40.0)
    th = np.arange(1.0, 360.0, 0.5)
    pin = PinFriction(2.0, 0.3)
    sc = scene_for(m)(friction={"slide": PinFriction(3.5, 0.0), "O2": pin, "A": pin, "B": pin})
    names = ["TORQ", "FN", "TORQ_FRICTION", "PLOSS_S", "PLOSS_B", "FRICTION_STATUS",
             "FRICTION_ITERATIONS"]
    got = {}
    for backend in ("numpy", "numba"):
        with pytest.warns(FrictionWarning, match="reach no solution"):
            got[backend] = analyze(m, th, names, scene=sc, backend=backend)
    a, b = got["numpy"], got["numba"]
    np.testing.assert_array_equal(a["FRICTION_STATUS"], b["FRICTION_STATUS"])
    locked = a["FRICTION_STATUS"] == 2.0
    ramp = (a["FRICTION_ITERATIONS"] > NEWTON) & ~locked
    assert locked.sum() >= 5 and ramp.sum() >= 5, (locked.sum(), ramp.sum())
    assert np.count_nonzero((b["FRICTION_ITERATIONS"] > NEWTON) & ~locked) >= 5  # the kernel's
    assert np.count_nonzero(a["FRICTION_ITERATIONS"] != b["FRICTION_ITERATIONS"]) <= th.size // 50
    for name in names[:5]:
        assert np.array_equal(np.isnan(a[name]), np.isnan(b[name])), name
        ok = ~np.isnan(a[name])
        np.testing.assert_allclose(b[name][ok], a[name][ok], rtol=0,
                                   atol=1e-9 * np.max(np.abs(a[name][ok])), err_msg=name)


def test_a_newton_step_that_is_not_finite_is_no_answer(monkeypatch):
    """A step that overflows (here the first one, made infinite by hand) sends the position
    to the ramp from mu = 0, which reaches the answer Newton reaches undisturbed; it is
    not taken as converged (an infinite step once passed the test largest <= tol big)."""
    from sielaff.engine import joints

    m = SLIDER_EXAMPLE
    sc = scene_for(m)(friction=PinFriction(0.1, 0.5))
    names = ["TORQ", "FOAX", "PLOSS_O2", "FRICTION_STATUS", "FRICTION_ITERATIONS"]
    plain = analyze(m, [30.0], names, scene=sc)
    newton = next(s for e in model_for(m).effects for s in e.steps
                  if s.name == "_joint_friction_newton")
    scope = newton.iterates[0].__globals__
    where = [k for k, v in scope.items() if v is joints.linear]
    assert len(where) == 1
    calls = []

    def overflowing(*args):
        x = list(joints.linear(*args))
        if not calls:
            x[0] = x[0] + np.inf
        calls.append(1)
        return tuple(x)

    monkeypatch.setitem(scope, where[0], overflowing)
    hit = analyze(m, [30.0], names, scene=sc)
    assert len(calls) > plain["FRICTION_ITERATIONS"][0]  # the patched solve ran
    assert hit["FRICTION_ITERATIONS"][0] > NEWTON  # through the ramp
    assert hit["FRICTION_STATUS"][0] == 0.0
    for name in names[:3]:
        assert hit[name][0] == pytest.approx(plain[name][0], rel=1e-12), name


def test_a_friction_mapping_names_the_joints():
    with pytest.raises(ValueError, match="unknown joint 'Q'.*joints: O2, A, B, slide"):
        scene_for(SLIDER_EXAMPLE)(friction={"Q": PinFriction(0.1, 0.1)})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = analyze(SLIDER_EXAMPLE, [30.0], ["PLOSS_A", "PLOSS_S", "PLOSS_O2"],
                    scene=scene_for(SLIDER_EXAMPLE)(friction={"A": PinFriction(0.1, 0.2)}))
    assert r["PLOSS_A"][0] > 0.0 and r["PLOSS_S"][0] == 0.0 and r["PLOSS_O2"][0] == 0.0
