"""``simulate`` with pin friction and a spring on, checked by what trusts none of its code.

* the equation of motion at every sample: motor - flywheel x TH2DD - TORQ, with TORQ
  from an independent ``analyze`` call at the simulated state AND from the independent
  Newton-Euler solve of tests/newton_euler.py (friction iterated there on its own);
* energy over the run: the motor's work = the change of kinetic energy + the friction
  losses + the change of the spring's energy, every term summed here from the
  Newton-Euler state (point velocities, pin forces, element lengths), none from J;
* the friction tables and the engine per state give the same motion; the steady state
  with friction is periodic.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import newton_euler as ne
from sielaff import EXAMPLE, PinFriction, Scene, Spring, analyze
from sielaff.dynamics import Motor, simulate

pytest.importorskip("scipy")
from scipy.integrate import simpson  # noqa: E402

G = 386.088  # in/sec^2
MU_R = 0.1 * 0.25
SPRING = Spring((1, 18.0, 0.0), (4, 6.0, 0.0), 20.0, 8.0)
SCENE = Scene(friction=PinFriction(0.1, 0.25), elements=[SPRING])
MOTOR = Motor.linear(2000.0, 55.0)
FW = 7.41


@pytest.fixture(scope="module")
def run():
    """Two revolutions from rest (decks/friction.toml's scene and motor)."""
    return simulate(EXAMPLE, MOTOR, flywheel=FW, scene=SCENE, speed0=0.0, revolutions=2,
                    outputs=["TORQ", "PLOSS_O2", "PLOSS_A", "PLOSS_B", "PLOSS_O4"],
                    per_revolution=180)


@pytest.fixture(scope="module")
def independent(run):
    """The Newton-Euler solve at every sample: TORQ, losses, kinetic and spring energy."""
    out = {"TORQ": [], "loss": [], "ke": [], "pe": [], "firm": []}
    for th, w, a in zip(run["ATH2"], run["TH2D"], run["TH2DD"]):
        m = EXAMPLE.replace(TH2D=float(w))
        sol = ne.solve(m, float(th) % 360.0, ne.engine_b(m, float(th) % 360.0), a2=float(a),
                       elements=[SPRING], mur=(MU_R,) * 4)
        assert sol is not None
        s = sol["state"]
        line = {2: s["e2"], 3: s["e3"], 4: s["e4"]}
        rg = {k: getattr(m, f"RG{k}") * ne.rot(line[k], getattr(m, f"ADEL{k}"))
              for k in (2, 3, 4)}
        vel = {2: 1j * w * rg[2], 3: 1j * w * s["A"] + 1j * s["w3"] * rg[3],
               4: 1j * s["w4"] * rg[4]}
        rate = {2: w, 3: s["w3"], 4: s["w4"]}
        ke = sum(0.5 * getattr(m, f"W{k}") / G * abs(vel[k]) ** 2
                 + 0.5 * getattr(m, f"ZI{k}") * rate[k] ** 2 for k in (2, 3, 4))
        length = ne.element(s, SPRING)[0]
        out["TORQ"].append(sol["TORQ"])
        out["loss"].append(sum(sol["loss"]))
        out["ke"].append(ke + 0.5 * FW * w * w)
        out["pe"].append(0.5 * SPRING.k * (length - SPRING.length) ** 2)
        # a pin whose relative rotation is zero (within roundoff) has friction of no
        # determined sign: the engine decides by the rounded rate, the tables and this
        # solve call it zero, so the torques there may differ by that pin's mu r |F|
        out["firm"].append(all(g != 0.0 for g in sol["sg"]) or not any(sol["sg"]))
    return {k: np.array(v) for k, v in out.items()}


def test_the_friction_run_uses_the_tables_and_finishes(run):
    assert run.mode == "tables" and run.finished and not run.stalled
    assert run["TH2D"][0] == 0.0 and run["ATH2"][-1] == pytest.approx(720.0)


def test_equation_of_motion_against_analyze_and_newton_euler(run, independent):
    q = analyze(EXAMPLE.replace(TH2D=run["TH2D"]), run["ATH2"], ["TORQ"],
                scene=SCENE.replace(th2dd=run["TH2DD"]))["TORQ"]
    peak = np.max(np.abs(q))
    firm = independent["firm"]
    assert 0 < np.count_nonzero(~firm) <= 3  # THETA 2 = 360, 720 (and 0 moving)
    assert np.max(np.abs(run["MOTOR"] - FW * run["TH2DD"] - q)[firm]) < 1e-9 * peak
    assert np.max(np.abs(run["MOTOR"] - FW * run["TH2DD"] - independent["TORQ"])) \
        < 1e-8 * peak
    # friction is really on: without it the torque at the same states differs
    plain = analyze(EXAMPLE.replace(TH2D=run["TH2D"]), run["ATH2"], ["TORQ"],
                    scene=Scene(elements=[SPRING]).replace(th2dd=run["TH2DD"]))["TORQ"]
    assert np.median(np.abs(q - plain)[1:]) > 1e-3 * peak


def test_motor_work_is_kinetic_energy_plus_friction_losses_plus_spring_energy(
        run, independent):
    t = run["t"]
    work = simpson(run["MOTOR"] * run["TH2D"], x=t)
    losses = simpson(independent["loss"], x=t)
    d_ke = independent["ke"][-1] - independent["ke"][0]
    d_pe = independent["pe"][-1] - independent["pe"][0]
    assert losses > 1e-3 * work  # friction takes a share worth checking
    assert work == pytest.approx(d_ke + losses + d_pe, rel=2e-5)
    # and the engine's own loss outputs agree with the independent ones
    ploss = sum(run[f"PLOSS_{p}"] for p in ("O2", "A", "B", "O4"))
    firm = independent["firm"]
    assert np.allclose(ploss[firm], independent["loss"][firm], rtol=1e-8,
                       atol=1e-9 * np.max(ploss))


def test_the_friction_tables_and_the_engine_per_state_agree():
    kw = dict(flywheel=FW, scene=SCENE, speed0=20.0, revolutions=0.1, rtol=1e-10)
    a = simulate(EXAMPLE, MOTOR, **kw)
    b = simulate(EXAMPLE, MOTOR, tables=False, **kw)
    assert (a.mode, b.mode) == ("tables", "engine")
    assert a["t"][-1] == pytest.approx(b["t"][-1], rel=1e-8)
    assert a["TH2D"][-1] == pytest.approx(b["TH2D"][-1], rel=1e-8)


def test_the_steady_state_with_friction_is_periodic_and_slower():
    kw = dict(flywheel=FW, speed0=50.0, steady=True, per_revolution=90, rtol=1e-6)
    r = simulate(EXAMPLE, MOTOR, scene=SCENE, **kw)
    assert r.finished and r["TH2D"][-1] == pytest.approx(r["TH2D"][0], rel=1e-5)
    free = simulate(EXAMPLE, MOTOR, scene=Scene(elements=[SPRING]), **kw)
    # friction takes power: the motor runs further down its line, slower
    assert np.mean(r["TH2D"]) < np.mean(free["TH2D"]) - 0.01


def test_friction_that_cannot_converge_is_one_line():
    from sielaff.dynamics import SimulationError

    # mu r of the order of the links: the couples outgrow the forces that make them
    sc = Scene(friction=PinFriction(1.0, 6.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no warning escapes: the error is the one line
        with pytest.raises(SimulationError) as e:
            simulate(EXAMPLE, MOTOR, flywheel=FW, scene=sc, speed0=50.0, revolutions=0.5)
    # the engine now solves the static law where it has a solution (issue 32): the run
    # goes on until the law has none, or the joint solve with the acceleration fails
    assert "\n" not in str(e.value) and ("does not converge at THETA 2 = " in str(e.value)
                                         or "has no solution at THETA 2 = " in str(e.value))


def test_where_the_tables_fixed_point_diverges_the_engines_solve_decides(monkeypatch):
    """Issue 32, family 7: a state whose friction the tables' iteration cannot solve goes
    to the engine's Newton solve instead of ending the run (the iteration is made to fail
    everywhere here, so every state takes the engine's path: the same motion)."""
    import importlib

    fr = importlib.import_module("sielaff.dynamics.friction")
    kw = dict(flywheel=FW, scene=SCENE, speed0=50.0, revolutions=0.05, rtol=1e-10)
    tables = simulate(EXAMPLE, MOTOR, **kw)
    calls = []
    real = fr.FrictionTables._solve

    def diverges(self, *a):
        calls.append(1)
        raise fr.FrictionError("the friction solve does not converge (made to fail)")

    monkeypatch.setattr(fr.FrictionTables, "_solve", diverges)
    engine = simulate(EXAMPLE, MOTOR, **kw)
    assert calls and real is not diverges  # the tables were tried, and failed, every time
    assert engine.mode == "tables" and engine.finished and tables.engine_states == 0
    assert engine.engine_states >= engine.evaluations
    assert engine["TH2D"][-1] == pytest.approx(tables["TH2D"][-1], rel=1e-7)
