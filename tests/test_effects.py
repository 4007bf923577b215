"""The effects a scene calls for (crank acceleration, gravity, loads), checked by routes
that trust nothing of the engine.

* An independent kinematic solve: B from the intersection of two circles, the rates
  from the differentiated loop equation (2 x 2 linear systems).
* An independent Newton-Euler solve: the nine equations of force and moment balance of
  the three moving links, unknowns the four pin forces and the drive torque, by
  ``numpy.linalg.solve``.
* The power balance, every effect on: drive + TEX + loads + gravity = dT/dt.
* The energy identity over a cycle at constant speed: the drive's cycle work is what
  the non-conservative loads take (gravity and fixed forces take none).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from sielaff import engine
from sielaff.engine import Load, analyze
from sielaff.mechanism import EXAMPLE, crank_rocker_failure
from sielaff.quantities import G

FORCES = ("FA32X", "FA32Y", "FB34X", "FB34Y", "FOAX", "FOAY", "FOBX", "FOBY", "TORQ")


def cross(a, b):
    return a.real * b.imag - a.imag * b.real


def kinematics(m, th2_deg, w2, a2, engine_b):
    """Independent positions and rates; the branch is the one whose B the engine has."""
    t2 = math.radians(th2_deg)
    A = m.R2 * complex(math.cos(t2), math.sin(t2))
    O4 = complex(m.R1, 0.0)
    d = abs(O4 - A)
    a = (m.R3**2 - m.R4**2 + d * d) / (2 * d)
    h = math.sqrt(max(m.R3**2 - a * a, 0.0))
    P = A + a * (O4 - A) / d
    perp = 1j * (O4 - A) / d
    B = min((P + h * perp, P - h * perp), key=lambda b: abs(b - engine_b))
    e2, e3, e4 = (A / abs(A), (B - A) / m.R3, (B - O4) / m.R4)
    # velocity loop: i w2 R2 e2 + i w3 R3 e3 - i w4 R4 e4 = 0
    M = np.array([[(1j * m.R3 * e3).real, (-1j * m.R4 * e4).real],
                  [(1j * m.R3 * e3).imag, (-1j * m.R4 * e4).imag]])
    rhs = -(1j * w2 * m.R2 * e2)
    w3, w4 = np.linalg.solve(M, [rhs.real, rhs.imag])
    # acceleration loop: (i a - w^2) R e summed, unknown a3, a4
    known = (1j * a2 - w2**2) * m.R2 * e2 - w3**2 * m.R3 * e3 + w4**2 * m.R4 * e4
    a3, a4 = np.linalg.solve(M, [-known.real, -known.imag])
    return A, B, O4, e2, e3, e4, w3, w4, a3, a4


def rot(e, deg):
    return e * complex(math.cos(math.radians(deg)), math.sin(math.radians(deg)))


def newton_euler(m, th2_deg, a2, gravity, loads, tex, engine_b):
    """FA32, FB34, FOA, FOB (x, y) and TORQ from the nine balance equations."""
    w2 = m.TH2D
    A, B, O4, e2, e3, e4, w3, w4, a3, a4 = kinematics(m, th2_deg, w2, a2, engine_b)
    g = complex(*gravity) if gravity else 0j
    mass = {k: getattr(m, f"W{k}") / G for k in (2, 3, 4)}
    rg = {2: m.RG2 * rot(e2, m.ADEL2), 3: m.RG3 * rot(e3, m.ADEL3), 4: m.RG4 * rot(e4, m.ADEL4)}
    acc = {2: (1j * a2 - w2**2) * rg[2],
           3: (1j * a2 - w2**2) * m.R2 * e2 + (1j * a3 - w3**2) * rg[3],
           4: (1j * a4 - w4**2) * rg[4]}
    alpha = {2: a2, 3: a3, 4: a4}
    zi = {2: m.ZI2, 3: m.ZI3, 4: m.ZI4}
    line = {2: e2, 3: e3, 4: e4}
    # applied loads per link: force, and moment about the base pin (O2, A, O4)
    F = {k: mass[k] * g for k in (2, 3, 4)}
    Mo = {k: cross(rg[k], mass[k] * g) for k in (2, 3, 4)}
    for ld in loads:
        p = ld.r * rot(line[ld.link], ld.angle)
        f = complex(ld.fx, ld.fy)
        F[ld.link] += f
        Mo[ld.link] += cross(p, f) + ld.torque
    Mo[4] += tex
    # unknowns: F12 (frame on 2), F32 (3 on 2), F43 (4 on 3), F14 (frame on 4), T
    K = np.zeros((9, 9))
    r = np.zeros(9)

    def row(i, coeffs, value):
        for j, c in coeffs.items():
            K[i, j] = c
        r[i] = value

    # link 2: F12 + F32 + F2 = m2 aG2; about O2: A x F32 + M2 + T = ZI2 a2 + rG2 x m2 aG2
    d2 = mass[2] * acc[2] - F[2]
    row(0, {0: 1, 2: 1}, d2.real)
    row(1, {1: 1, 3: 1}, d2.imag)
    row(2, {2: -A.imag, 3: A.real, 8: 1}, zi[2] * a2 + cross(rg[2], mass[2] * acc[2]) - Mo[2])
    # link 3: -F32 + F43 + F3 = m3 aG3; about A: (B-A) x F43 + M3 = ZI3 a3 + rG3 x m3 aG3
    d3 = mass[3] * acc[3] - F[3]
    u = B - A
    row(3, {2: -1, 4: 1}, d3.real)
    row(4, {3: -1, 5: 1}, d3.imag)
    row(5, {4: -u.imag, 5: u.real}, zi[3] * a3 + cross(rg[3], mass[3] * acc[3]) - Mo[3])
    # link 4: -F43 + F14 + F4 = m4 aG4; about O4: (B-O4) x (-F43) + M4 = ZI4 a4 + rG4 x m4 aG4
    d4 = mass[4] * acc[4] - F[4]
    v = B - O4
    row(6, {4: -1, 6: 1}, d4.real)
    row(7, {5: -1, 7: 1}, d4.imag)
    row(8, {4: v.imag, 5: -v.real}, zi[4] * a4 + cross(rg[4], mass[4] * acc[4]) - Mo[4])
    x = np.linalg.solve(K, r)
    f12, f32, f43, f14 = (complex(x[i], x[i + 1]) for i in (0, 2, 4, 6))
    out = dict(zip(FORCES, (f32.real, f32.imag, -f43.real, -f43.imag, -f12.real, -f12.imag,
                            -f14.real, -f14.imag, x[8])))
    return out, dict(w3=w3, w4=w4, a3=a3, a4=a4, vel={
        2: 1j * w2 * rg[2], 3: 1j * w2 * m.R2 * e2 + 1j * w3 * rg[3], 4: 1j * w4 * rg[4]},
        acc=acc, alpha=alpha, mass=mass, zi=zi, line=line, A=A, e2=e2)


def engine_b(m, th2):
    r = analyze(m, [th2], ["ATH3"])
    t2, t3 = math.radians(th2), math.radians(float(r["ATH3"][0]))
    return m.R2 * complex(math.cos(t2), math.sin(t2)) + m.R3 * complex(math.cos(t3),
                                                                      math.sin(t3))


mechanisms = st.builds(
    lambda r1, r3, r4, rg3, w, zi, d3, th2d: EXAMPLE.replace(
        R1=r1, R2=1.0, R3=r3, R4=r4, RG2=0.4, RG3=rg3 * r3, RG4=0.6 * r4, W2=w[0], W3=w[1],
        W4=w[2], ZI2=zi[0], ZI3=zi[1], ZI4=zi[2], ADEL3=d3, TH2D=th2d),
    st.floats(1.5, 6.0), st.floats(1.5, 6.0), st.floats(1.5, 6.0), st.floats(0.0, 1.0),
    st.tuples(*[st.floats(0.0, 10.0)] * 3), st.tuples(*[st.floats(0.0, 2.0)] * 3),
    st.floats(-45.0, 45.0), st.floats(-60.0, 60.0))
scenes = st.fixed_dictionaries({
    "th2dd": st.floats(-400.0, 400.0),
    "gravity": st.one_of(st.none(), st.tuples(st.floats(-400, 400), st.floats(-400, 400))),
    "loads": st.lists(st.builds(Load, st.sampled_from([2, 3, 4]), st.floats(0.0, 3.0),
                                st.floats(-180, 180), st.floats(-100, 100),
                                st.floats(-100, 100), st.floats(-50, 50)), max_size=3),
    "tex": st.floats(-50.0, 50.0),
})


@settings(max_examples=150, derandomize=True)
@given(mechanisms, scenes, st.floats(0.0, 359.0))
def test_every_effect_agrees_with_newton_euler(m, scene, th2):
    assume(crank_rocker_failure(m) is None)
    gamma = float(analyze(m, [th2], ["GAMMA"])["GAMMA"][0])
    assume(15.0 < gamma < 165.0)  # away from toggle, where both solves lose digits
    r = analyze(m, [th2], list(FORCES), scene["tex"], th2dd=scene["th2dd"],
                gravity=scene["gravity"], loads=scene["loads"])
    want, _ = newton_euler(m, th2, scene["th2dd"], scene["gravity"], scene["loads"],
                           scene["tex"], engine_b(m, th2))
    scale = max(abs(v) for v in want.values()) + 1e-300
    for name in FORCES:
        assert float(r[name][0]) == pytest.approx(want[name], abs=1e-9 * scale), name


def test_example_with_every_effect_agrees_with_newton_euler():
    scene = dict(th2dd=-40.0, gravity=(0.0, -386.088),
                 loads=[Load(3, r=8.0, angle=10.0, fx=80.0), Load(4, r=6.0, fy=-20.0,
                                                                 torque=15.0)])
    for th2 in np.arange(0.0, 360.0, 15.0):
        r = analyze(EXAMPLE, [th2], list(FORCES), 12.0, **scene)
        want, _ = newton_euler(EXAMPLE, th2, -40.0, scene["gravity"], scene["loads"], 12.0,
                               engine_b(EXAMPLE, th2))
        scale = max(abs(v) for v in want.values())
        for name in FORCES:
            assert float(r[name][0]) == pytest.approx(want[name], abs=1e-9 * scale), name


@settings(max_examples=80, derandomize=True)
@given(mechanisms, scenes)
def test_power_balance_with_every_effect(m, scene):
    """TORQ w2 + TEX w4 + loads' power + gravity's power = dT/dt, at every position."""
    assume(crank_rocker_failure(m) is None)
    th = np.arange(0.0, 360.0, 7.5)
    gamma = analyze(m, th, ["GAMMA"])["GAMMA"]
    assume(np.all((gamma > 15.0) & (gamma < 165.0)))
    r = analyze(m, th, ["TORQ", "TH3D", "TH4D", "TH3DD", "TH4DD", "VG2X", "VG2Y", "VG3X",
                        "VG3Y", "VG4X", "VG4Y", "AG2X", "AG2Y", "AG3X", "AG3Y", "AG4X", "AG4Y",
                        "ATH3", "ATH4"], scene["tex"], th2dd=scene["th2dd"],
                gravity=scene["gravity"], loads=scene["loads"])
    w = {2: m.TH2D, 3: r["TH3D"], 4: r["TH4D"]}
    al = {2: scene["th2dd"], 3: r["TH3DD"], 4: r["TH4DD"]}
    gx, gy = scene["gravity"] or (0.0, 0.0)
    power_in = r["TORQ"] * m.TH2D + scene["tex"] * w[4]
    size = np.abs(r["TORQ"] * m.TH2D) + np.abs(scene["tex"] * w[4])  # each term, for scale
    kinetic = 0.0
    for k in (2, 3, 4):
        mass = getattr(m, f"W{k}") / G
        vx, vy = r[f"VG{k}X"], r[f"VG{k}Y"]
        power_in = power_in + mass * (gx * vx + gy * vy)
        inertia = mass * (r[f"AG{k}X"] * vx + r[f"AG{k}Y"] * vy)
        spin = getattr(m, f"ZI{k}") * al[k] * w[k]
        kinetic = kinetic + inertia + spin
        size = size + np.abs(mass * (gx * vx + gy * vy)) + np.abs(inertia) + np.abs(spin)
    t2 = np.radians(th)
    angle = {2: t2, 3: np.radians(r["ATH3"]), 4: np.radians(r["ATH4"])}
    base_v = {2: 0.0, 3: m.R2 * m.TH2D * (-np.sin(t2) + 1j * np.cos(t2)), 4: 0.0}
    for ld in scene["loads"]:
        p = ld.r * np.exp(1j * (angle[ld.link] + math.radians(ld.angle)))
        v = base_v[ld.link] + 1j * w[ld.link] * p
        p_load = ld.fx * v.real + ld.fy * v.imag + ld.torque * w[ld.link]
        power_in = power_in + p_load
        size = size + np.abs(p_load)
    np.testing.assert_allclose(power_in, kinetic, rtol=0, atol=1e-9 * max(np.max(size), 1.0))


def test_cycle_work_with_gravity_is_what_the_loads_take():
    """Constant speed: over one revolution the drive does the work the non-conservative
    loads take.  Gravity, fixed forces and a torque on the rocker take none; a constant
    torque T0 on the crank takes -2 pi T0."""
    th = np.linspace(0.0, 360.0, 3601)[:-1]
    x = np.radians(th)

    def work(**scene):
        torq = analyze(EXAMPLE, th, ["TORQ"], **scene)["TORQ"]
        return float(np.sum(torq) * (x[1] - x[0]))  # periodic: spectrally accurate

    base = work(tex=0.0)
    scale = float(np.sum(np.abs(analyze(EXAMPLE, th, ["TORQ"])["TORQ"])) * (x[1] - x[0]))
    assert abs(base) < 1e-10 * scale
    assert abs(work(gravity=(30.0, -386.088))) < 1e-10 * scale
    assert abs(work(loads=[Load(3, r=5.0, angle=20.0, fx=40.0, fy=-10.0)])) < 1e-10 * scale
    assert abs(work(loads=[Load(4, torque=25.0)], tex=7.0)) < 1e-10 * scale
    assert work(loads=[Load(2, torque=25.0)], gravity=(0.0, -386.088)) == pytest.approx(
        -2 * math.pi * 25.0, rel=1e-9)


def test_the_torque_breakdown_adds_up():
    scene = dict(th2dd=-40.0, gravity=(0.0, -386.088),
                 loads=[Load(3, r=8.0, angle=10.0, fx=80.0)])
    names = ["TORQ", "TORQ_INERTIA", "TORQ_GRAVITY", "TORQ_LOADS", "TORQ_TEX"]
    th = np.arange(0.0, 360.0, 10.0)
    r = analyze(EXAMPLE, th, names, 30.0, **scene)
    total = r["TORQ_INERTIA"] + r["TORQ_GRAVITY"] + r["TORQ_LOADS"] + r["TORQ_TEX"]
    np.testing.assert_allclose(total, r["TORQ"], rtol=1e-12, atol=1e-9)
    assert np.all(r["TORQ_GRAVITY"] != 0) and np.all(r["TORQ_TEX"] != 0)
    g_only = analyze(EXAMPLE, th, ["TORQ"], gravity=scene["gravity"])["TORQ"]
    np.testing.assert_allclose(g_only - analyze(EXAMPLE, th, ["TORQ"])["TORQ"],
                               r["TORQ_GRAVITY"], rtol=1e-9, atol=1e-9)


def test_callables_and_arrays_for_every_effect():
    th = np.arange(0.0, 360.0, 30.0)
    a = analyze(EXAMPLE, th, ["TORQ"], th2dd=lambda t: 0.1 * t,
                loads=[Load(3, r=8.0, fx=lambda t: np.cos(np.radians(t)))])
    b = analyze(EXAMPLE, th, ["TORQ"], th2dd=0.1 * th,
                loads=[Load(3, r=8.0, fx=np.cos(np.radians(th)))])
    np.testing.assert_array_equal(a["TORQ"], b["TORQ"])
    with pytest.raises(ValueError, match="a moving link, 2"):
        Load(1)  # the frame: no load to carry
    with pytest.raises(ValueError, match="this linkage's moving links are 2 to 4"):
        analyze(EXAMPLE, th, loads=[Load(5)])  # a six-bar's link, not the four-bar's
    with pytest.raises(ValueError, match="gravity"):
        analyze(EXAMPLE, th, gravity=3.0)
    with pytest.raises(ValueError, match="is not a sielaff.Load"):
        analyze(EXAMPLE, th, loads=[(3, 1.0)])


# ----- only what a scene calls for ------------------------------------------------------------
def ran(**kw) -> set[str]:
    engine.STEP_CALLS.clear()
    analyze(**kw)
    return set(engine.STEP_CALLS)


def test_effects_that_are_off_cost_nothing():
    steps = ran(mechanism=EXAMPLE, ath2=np.arange(0.0, 360.0, 10.0))
    for effect in ("_gravity", "_loads", "_angular_acc_crank", "_acc_A_crank", "_acc_G2_crank",
                   "_crank_inertia_torque", "_crank_acceleration", "_effects"):
        assert effect not in steps, effect
    on = ran(mechanism=EXAMPLE, ath2=[10.0], gravity=(0.0, -1.0), th2dd=1.0,
             loads=[Load(3, fx=1.0)])
    assert {"_gravity", "_loads", "_angular_acc_crank", "_crank_inertia_torque"} <= on


def test_kinematics_with_gravity_and_loads_run_no_force_step():
    steps = ran(mechanism=EXAMPLE, ath2=[10.0, 20.0], outputs=["ATH3", "TH4DD", "AG3X"],
                gravity=(0.0, -386.088), loads=[Load(3, fx=5.0)], th2dd=3.0)
    assert steps and not any(s.startswith(("_force", "_inertia", "_total", "_gravity",
                                           "_loads", "_effects")) for s in steps), steps


def test_quasi_static_torque_with_gravity_runs_no_inertia_step():
    still = EXAMPLE.replace(TH2D=0.0)
    steps = ran(mechanism=still, ath2=np.arange(0.0, 360.0, 10.0), outputs=["TORQ"],
                gravity=(0.0, -386.088))
    assert "_gravity" in steps
    assert not any(s.startswith(("_inertia", "_force_link", "_acc", "_angular_acc"))
                   for s in steps), steps
    r = analyze(still, [30.0], ["TORQ", "TORQ_GRAVITY"], gravity=(0.0, -386.088))
    assert float(r["TORQ"][0]) == float(r["TORQ_GRAVITY"][0]) != 0.0


# ----- units: the same physics in SI ----------------------------------------------------------
IN, LBF, LB = 0.0254, 4.4482216152605, 0.45359237  # m, N, kg (exact definitions)


def test_si_gives_the_same_physics_in_si_units():
    """The example converted to metres, kilograms (masses in the W fields) and kg m^2,
    with standard gravity in each system: every output is the same quantity in SI."""
    m = EXAMPLE
    si = m.replace(units="SI", W2=m.W2 * LB, W3=m.W3 * LB, W4=m.W4 * LB,
                   ZI2=m.ZI2 * LBF * IN, ZI3=m.ZI3 * LBF * IN, ZI4=m.ZI4 * LBF * IN,
                   **{k: getattr(m, k) * IN for k in ("R1", "R2", "R3", "R4", "RG2", "RG3",
                                                      "RG4")})
    th = np.arange(0.0, 360.0, 10.0)
    names = ["TORQ", "FA32X", "FOBY", "AG3X", "VB", "TH3DD", "ATH4", "TORQ_GRAVITY"]
    a = analyze(m, th, names, gravity="down", loads=[Load(3, r=8.0, fx=80.0)])
    b = analyze(si, th, names, gravity="down", loads=[Load(3, r=8.0 * IN, fx=80.0 * LBF)])
    # Gravity: a weight of 1 lb is 0.45359237 kg x 9.80665 m/s^2 = 4.4482216152605 N
    # exactly, so TORQ_GRAVITY agrees to roundoff.  Inertia: the report's g = 386.088
    # in/s^2 is 9.8066352 m/s^2, 2.2E-6 off standard gravity, so the masses W / g differ
    # by that much from W x 0.45359237 kg: hence rtol 2E-5 on the rest.
    factor = {"TORQ": LBF * IN, "FA32X": LBF, "FOBY": LBF, "AG3X": IN, "VB": IN,
              "TH3DD": 1.0, "ATH4": 1.0}
    for name, f in factor.items():
        np.testing.assert_allclose(b[name], a[name] * f, rtol=2e-5, atol=1e-9, err_msg=name)
    np.testing.assert_allclose(b["TORQ_GRAVITY"], a["TORQ_GRAVITY"] * LBF * IN, rtol=1e-12)
    ratio = 9.80665 / (386.088 * IN)
    assert 1e-6 < ratio - 1 < 3e-6  # and TORQ differs from the converted value by about it
    assert np.max(np.abs(b["TORQ"] / (a["TORQ"] * LBF * IN) - 1)) > 1e-7
    from sielaff.quantities import unit

    assert (unit("TORQ", "SI"), unit("W3", "SI"), unit("ZI3", "SI")) == ("N m", "kg", "kg m^2")
    with pytest.raises(ValueError, match="unit systems"):
        analyze(m.replace(units="cgs"), th)


# ----- the emulator: the report's edit of statement 74, TEX = constant -------------------------
@pytest.mark.parametrize("arith, rtol", [("float64", 1e-6), ("ibm1410", 2e-4)])
def test_run_tex_is_the_reports_edit_and_agrees_with_the_engine(arith, rtol):
    """``run --tex 150`` prints EX TORQ ON 4 = .1500E 03 on every sheet, and its TORQ is
    the engine's with tex=150 within the arithmetic's error (ARCCOS, 8 digits)."""
    from conftest import DECKS
    from sielaff.emulator.cards import read_deck
    from sielaff.emulator.run import sheet_values

    deck = read_deck(DECKS / "example.dat")
    sheets = list(sheet_values(deck, arith, tex=150.0))[:36]  # 10..360, not 370 (Case II)
    th = np.array([s["ATH2"] for s in sheets])
    assert all(s["TEX"] == 150.0 for s in sheets)
    torq = np.array([s["TORQ"] for s in sheets])
    want = analyze(EXAMPLE, th, ["TORQ"], tex=150.0)["TORQ"]
    scale = np.max(np.abs(want))
    np.testing.assert_allclose(torq, want, rtol=0, atol=rtol * scale)
    plain = np.array([s["TORQ"] for s in list(sheet_values(deck, arith))[:36]])
    assert np.max(np.abs(torq - plain)) > 10.0  # TEX did change the driving torque


def test_run_tex_on_the_command_line(tmp_path):
    import procs
    from conftest import DECKS

    run = ["run", DECKS / "example.dat"]
    plain = procs.run(run, text=True).stdout
    zero = procs.run([*run, "--tex", "0"], text=True).stdout
    assert zero == plain
    loaded = procs.run([*run, "--tex", "150", "--max-sheets", "2"], text=True)
    assert loaded.stdout.count("   .1500E 03") == 2
    bad = procs.run([*run, "--tex", "1E120"], text=True)
    assert bad.returncode == 2 and "is not a torque in in-lb" in bad.stderr


# ----- every tool reaches the effects: a TOML spec with a [scene] ----------------------------
SCENE = dict(gravity="down", th2dd=-40.0, loads=[Load(3, r=8.0, angle=0.0, fx=80.0)])


def _cli(*argv):
    import contextlib
    import io

    from sielaff.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(list(argv))
    return status, out.getvalue(), err.getvalue()


def test_table_of_a_spec_with_a_scene_is_the_engine_bit_for_bit():
    import csv
    import io

    from conftest import DECKS

    status, out, err = _cli("table", str(DECKS / "scene.toml"))
    assert status == 0 and err == ""
    rows = list(csv.reader(io.StringIO(out)))
    names = [h.split("[")[0] for h in rows[0]][1:]
    values = np.array([[float(v) for v in r[1:]] for r in rows[1:]])
    want = analyze(EXAMPLE, values[:, 0], names, **SCENE)
    for j, name in enumerate(names):
        np.testing.assert_array_equal(values[:, j], want[name], err_msg=name)
    plain = analyze(EXAMPLE, values[:, 0], ["TORQ"])["TORQ"]
    assert np.max(np.abs(want["TORQ"] - plain)) > 50.0  # the scene matters


def test_plot_and_check_of_a_spec_use_its_scene(tmp_path):
    pytest.importorskip("matplotlib")
    from conftest import DECKS
    from sielaff.tools.common import read_spec_deck
    from sielaff.tools.plot import plot_data

    deck, scene = read_spec_deck(str(DECKS / "scene.toml"))
    d = plot_data(deck, None, scene)["fig12-driving-torque"]
    torq = analyze(EXAMPLE, d.ath2, ["TORQ"], **SCENE)["TORQ"]
    np.testing.assert_array_equal(d.series["driving torque TORQ"], torq)
    assert "gravity, 1 load, TH2DD = -40 rad/sec^2" in d.title
    status, _, err = _cli("plot", str(DECKS / "scene.toml"), "-o", str(tmp_path / "p"))
    assert status == 0 and err == "" and len(list((tmp_path / "p").iterdir())) == 6
    status, text, _ = _cli("check", str(DECKS / "scene.toml"))
    assert status == 0 and "with the spec's scene: gravity, 1 load, TH2DD = -40" in text
    from sielaff.engine.derived import cycle_work

    work, _ = cycle_work(EXAMPLE, **SCENE)
    assert f"over a revolution: {work:.3g} in-lb" in text


def test_punch_leaves_the_scene_out_and_refuses_si(tmp_path):
    from conftest import DECKS

    status, out, _ = _cli("punch", str(DECKS / "scene.toml"))
    assert status == 0 and out == (DECKS / "example.dat").read_text()
    si = tmp_path / "si.toml"
    si.write_text((DECKS / "scene.toml").read_text().replace('units = "in-lb-sec"',
                                                              'units = "SI"'))
    status, _, err = _cli("punch", str(si))
    assert status == 2 and "a 1966 deck is in the report's in-lb-sec units" in err
    status, out, _ = _cli("table", str(si), "--only", "kinematics")
    assert status == 0 and "VG2[m/s]" in out.splitlines()[0]


@pytest.mark.parametrize("text, words", [
    ('[scene]\ngravitty = "down"\n', "unknown"),
    ('[scene]\n[[scene.load]]\nlink = "frame"\n', "crank, coupler or rocker"),
    ('[scene]\ngravity = [1.0]\n', '"down" or [gx, gy]'),
    ('[scene]\nunits = "cgs"\n', "in-lb-sec or SI"),
])
def test_bad_scenes_are_one_line(tmp_path, text, words):
    from conftest import DECKS

    spec = tmp_path / "bad.toml"
    base = (DECKS / "example.toml").read_text()
    spec.write_text(base + "\n" + text)
    for command in ("table", "check"):
        status, _, err = _cli(command, str(spec))
        assert status == 2 and err.count("\n") == 1 and words in err, (command, err)
