"""sielaff.simulate: the motor-driven crank, checked by what does not trust its code.

* the equation of motion at every sample, against an independent ``analyze`` call at the
  simulated state (motor torque - flywheel x TH2DD - TORQ);
* TH2D and TH2DD are the time derivatives of ATH2 and TH2D (finite differences);
* energy: the motor's work (and TEX's) equals the change of kinetic energy, the kinetic
  energy summed here from the engine's velocities and the masses, not from J;
* the steady state is periodic, and a time integration started on it stays on it;
* the flywheel round trip: design.flywheel's inertia for cf gives cf back, within the
  bound the constant-speed approximation explains;
* stall and a start from rest; the motor curves; the errors, one line each.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from sielaff import EXAMPLE, Scene, analyze, flywheel
from sielaff.dynamics import Motor, SimulationError, simulate

pytest.importorskip("scipy")
from scipy.integrate import simpson  # noqa: E402

G = 386.088  # in/sec^2: W / G is a mass in the report's units


def residual(r, mech, scene, fw):
    """motor - flywheel * TH2DD - TORQ of an independent analyze at the same states."""
    q = analyze(mech.replace(TH2D=r["TH2D"]), r["ATH2"], ["TORQ"],
                scene=scene.replace(th2dd=r["TH2DD"]))["TORQ"]
    return r["MOTOR"] - fw * r["TH2DD"] - q, np.max(np.abs(q))


def kinetic(mech, r, fw):
    """Kinetic energy [in-lb] of links 2-4 and the flywheel from the engine's velocities."""
    k = analyze(mech.replace(TH2D=r["TH2D"]), r["ATH2"], ["VG2", "VG3", "VG4", "TH3D", "TH4D"])
    w = r["TH2D"]
    return (0.5 * (mech.W2 * k["VG2"] ** 2 + mech.W3 * k["VG3"] ** 2
                   + mech.W4 * k["VG4"] ** 2) / G
            + 0.5 * (mech.ZI2 * w ** 2 + mech.ZI3 * k["TH3D"] ** 2 + mech.ZI4 * k["TH4D"] ** 2)
            + 0.5 * fw * w ** 2)


SCENES = {"1966": Scene(), "gravity+tex": Scene(gravity="down", tex=120.0)}


@pytest.mark.parametrize("tables", [True, False], ids=["tables", "engine"])
@pytest.mark.parametrize("name", sorted(SCENES))
def test_equation_of_motion_holds_at_every_sample(name, tables):
    sc = SCENES[name]
    fw = 1.5
    r = simulate(EXAMPLE, Motor.linear(600.0, 60.0), flywheel=fw, scene=sc,
                 revolutions=3 if tables else 1.25, tables=tables, outputs=["TORQ"])
    assert r.mode == ("tables" if tables else "engine")
    assert r.finished and not r.stalled
    res, peak = residual(r, EXAMPLE, sc, fw)
    assert np.max(np.abs(res)) < 1e-9 * peak
    # TORQ asked as an output is the same engine call's answer
    assert np.allclose(r["TORQ"], r["MOTOR"] - fw * r["TH2DD"], rtol=0, atol=1e-9 * peak)
    # TH2D = d ATH2/dt and TH2DD = d TH2D/dt, by differences on the samples
    t = r["t"]
    d_th = np.gradient(np.radians(r["ATH2"]), t, edge_order=2)
    d_w = np.gradient(r["TH2D"], t, edge_order=2)
    assert np.max(np.abs(d_th - r["TH2D"])[1:-1]) < 1e-3 * np.max(np.abs(r["TH2D"]))
    assert np.max(np.abs(d_w - r["TH2DD"])[2:-2]) < 2e-2 * np.max(np.abs(r["TH2DD"]))
    assert r["ATH2"][-1] > 360.0  # unwrapped


def test_tables_and_engine_modes_agree():
    sc = SCENES["gravity+tex"]
    a = simulate(EXAMPLE, Motor.linear(600.0, 60.0), flywheel=1.0, scene=sc, revolutions=1,
                 rtol=1e-10)
    b = simulate(EXAMPLE, Motor.linear(600.0, 60.0), flywheel=1.0, scene=sc, revolutions=1,
                 rtol=1e-10, tables=False)
    assert a["t"][-1] == pytest.approx(b["t"][-1], rel=1e-7)
    assert a["TH2D"][-1] == pytest.approx(b["TH2D"][-1], rel=1e-7)


@pytest.mark.parametrize("speed0", [50.0, 0.0], ids=["running", "from-rest"])
def test_energy_motor_and_tex_work_is_the_change_of_kinetic_energy(speed0):
    tex, fw = 100.0, 0.8
    sc = Scene(tex=tex)
    motor = Motor.linear(800.0, 70.0)
    r = simulate(EXAMPLE, motor, flywheel=fw, scene=sc, speed0=speed0, revolutions=2,
                 per_revolution=4000, rtol=1e-11, outputs=["ATH4"])
    assert r.finished and r["TH2D"][0] == speed0
    th2 = np.radians(r["ATH2"])
    motor_work = simpson(r["MOTOR"], x=th2)
    ath4 = np.radians(np.unwrap(r["ATH4"], period=360.0))
    tex_work = tex * (ath4[-1] - ath4[0])
    ke = kinetic(EXAMPLE, r, fw)
    gained = ke[-1] - ke[0]
    assert gained > 100.0  # the motor did speed it up
    assert motor_work + tex_work == pytest.approx(gained, rel=1e-7)


def test_steady_state_is_periodic_and_a_time_integration_stays_on_it():
    sc = Scene(gravity="down", tex=80.0)
    motor = Motor.linear(900.0, 60.0)
    s = simulate(EXAMPLE, motor, flywheel=2.0, scene=sc, steady=True, rtol=1e-11,
                 outputs=["TORQ"])
    assert s.steady and s.finished
    w = s["TH2D"]
    assert s["ATH2"][-1] - s["ATH2"][0] == pytest.approx(360.0)
    assert abs(w[-1] - w[0]) < 1e-8 * w[0]
    assert np.ptp(w) > 1e-3 * w[0]  # it does fluctuate: periodicity is not trivial
    # over the period the motor's work balances TEX and gravity (zero net energy change)
    res, peak = residual(s, EXAMPLE, sc, 2.0)
    assert np.max(np.abs(res)) < 1e-9 * peak
    # a time integration from the steady speed comes back to it, revolution after revolution
    r = simulate(EXAMPLE, motor, flywheel=2.0, scene=sc, speed0=float(w[0]), revolutions=3,
                 rtol=1e-11)
    assert r["TH2D"][-1] == pytest.approx(w[0], rel=1e-7)
    assert r["t"][-1] == pytest.approx(3 * s["t"][-1], rel=1e-7)


def test_a_steady_state_from_a_poor_guess():
    sc = Scene(tex=80.0)
    s = simulate(EXAMPLE, Motor.linear(900.0, 60.0), flywheel=2.0, scene=sc, steady=True,
                 speed0=5.0, rtol=1e-11)
    t = simulate(EXAMPLE, Motor.linear(900.0, 60.0), flywheel=2.0, scene=sc, steady=True,
                 speed0=200.0, rtol=1e-11)
    # the root's accuracy is the integration's divided by |d w(360)/d w(0) - 1|
    assert s["TH2D"][0] == pytest.approx(t["TH2D"][0], rel=1e-8)


def reduced_inertia(mech, n=720):
    th = np.arange(n) * (360.0 / n)
    q0 = analyze(mech.replace(TH2D=0.0), th, ["TORQ"])["TORQ"]
    q1 = analyze(mech.replace(TH2D=0.0), th, ["TORQ"], th2dd=1.0)["TORQ"]
    return q1 - q0


@pytest.mark.parametrize("cf", [0.02, 0.05, 0.1])
def test_flywheel_round_trip(cf):
    """design.flywheel sizes I for cf at constant speed; simulate with I gives cf back.

    The flywheel is sized as if the motor's torque were constant and the linkage moved
    at constant speed.  Simulated, (1) the linkage's own reduced inertia J(th2) also
    stores energy, and (2) the inertia torques scale with w^2 = w_avg^2 (1 +- cf/2)^2; a
    nearly constant motor torque (a linear motor of small slope k, so that the mean
    speed is set) (3) gives or takes k (w - w_avg) over the half cycle.  Together:
    |cf_sim / cf - 1| <= max J / I + cf + 2 pi k cf w_avg^2 / E.
    """
    w_avg = float(EXAMPLE.TH2D)
    fw = flywheel(EXAMPLE, cf)
    inertia, energy = float(fw.inertia), float(fw.energy)
    k = 0.005 * energy / (math.pi * cf * w_avg ** 2)
    motor = Motor.linear(k * w_avg, w_avg)  # no torque at w_avg: mean TORQ is 0 here
    s = simulate(EXAMPLE, motor, flywheel=inertia, steady=True, per_revolution=7200,
                 rtol=1e-11)
    w = s["TH2D"]
    cf_sim = (w.max() - w.min()) / ((w.max() + w.min()) / 2.0)
    jmax = float(np.max(reduced_inertia(EXAMPLE)))
    bound = jmax / inertia + cf + 2.0 * math.pi * k * cf * w_avg ** 2 / energy
    assert abs(cf_sim / cf - 1.0) <= bound
    assert abs(cf_sim / cf - 1.0) < 0.5 * cf + jmax / inertia  # and well inside it
    # the speed curve the design predicts, against the simulated one at the same angles
    # (their fluctuations about their means: the design's w_avg is the mid-range speed,
    # the simulation's mean is set by the motor)
    pred = np.interp(s["ATH2"] % 360.0, fw.theta2, fw.speed, period=360.0)
    assert np.max(np.abs((pred - pred.mean()) - (w - w.mean()))) <= bound * cf * w_avg


def test_a_weak_motor_stalls_and_says_so():
    heavy = EXAMPLE.replace(W3=40.0, TH2D=2.0)
    sc = Scene(gravity="down")
    r = simulate(heavy, Motor.constant(5.0), scene=sc, speed0=2.0, revolutions=5)
    assert r.stalled and not r.finished
    assert r.message.startswith("stalled: the crank stopped at THETA 2 =")
    assert abs(r["TH2D"][-1]) < 1e-6 and r["ATH2"][-1] < 360.0
    # the same linkage with a motor strong enough gets over
    ok = simulate(heavy, Motor.constant(400.0), scene=sc, speed0=2.0, revolutions=2)
    assert ok.finished and not ok.stalled
    # and from rest, a motor that cannot even start it
    r0 = simulate(heavy, Motor.constant(0.0), scene=sc, speed0=0.0, start=30.0)
    assert r0.stalled and "at rest" in r0.message


def test_start_from_rest_reaches_the_motors_speed():
    r = simulate(EXAMPLE, Motor.linear(300.0, 40.0), flywheel=1.0, speed0=0.0,
                 revolutions=30)
    assert r.finished and r["TH2D"][0] == 0.0 and r["t"][0] == 0.0
    last = r["TH2D"][-360:]
    assert 35.0 < last.mean() < 40.0  # near no-load: the linkage alone takes no mean power


def test_motor_curves():
    lin = Motor.linear(200.0, 50.0)
    assert lin(0.0) == 200.0 and lin(50.0) == 0.0 and lin(25.0) == 100.0
    ind = Motor.induction(rated_torque=100.0, rated_speed=180.0, breakdown_torque=250.0,
                          synchronous_speed=188.5)
    assert ind(180.0) == pytest.approx(100.0, rel=1e-12)
    assert ind(188.5) == 0.0
    w = np.linspace(0.0, 188.5, 400001)
    t = ind(w)
    assert t.max() == pytest.approx(250.0, rel=1e-8)
    sb = dict(ind.parameters)["breakdown_slip"]
    assert (188.5 - w[np.argmax(t)]) / 188.5 == pytest.approx(sb, abs=1e-5)
    assert sb > (188.5 - 180.0) / 188.5  # rated on the stable side of the peak
    assert Motor.constant(7.0)(np.array([1.0, 2.0])).tolist() == [7.0, 7.0]


def test_a_simulation_with_an_induction_motor_runs_near_synchronous_speed():
    ind = Motor.induction(rated_torque=300.0, rated_speed=57.0, breakdown_torque=800.0,
                          synchronous_speed=60.0)
    s = simulate(EXAMPLE, ind, flywheel=2.0, scene=Scene(tex=60.0), steady=True)
    assert 57.0 < s["TH2D"].mean() < 60.0


@pytest.mark.parametrize("kwargs, match", [
    ({"flywheel": -1.0}, "flywheel = -1.0: an inertia cannot be negative"),
    ({"flywheel": float("nan")}, "flywheel = nan: not finite"),
    ({"scene": Scene(th2dd=3.0)}, "th2dd must be 0"),
    ({"revolutions": 0}, "revolutions = 0"),
    ({"outputs": ["NOPE"]}, "unknown output"),
    ({"method": "Euler"}, "method = 'Euler'"),
    ({"steady": True, "speed0": 0.0}, "steady: speed0 = 0"),
])
def test_errors_are_one_line(kwargs, match):
    with pytest.raises(ValueError, match=match) as e:
        simulate(EXAMPLE, Motor.constant(10.0), **kwargs)
    assert "\n" not in str(e.value)


def test_not_a_crank_rocker_is_refused():
    with pytest.raises(SimulationError, match="cannot make a whole revolution"):
        simulate(EXAMPLE.replace(R2=11.0), Motor.constant(10.0))


def test_bad_motor_parameters():
    with pytest.raises(ValueError, match="no_load_speed = 0"):
        Motor.linear(10.0, 0.0)
    with pytest.raises(ValueError, match="breakdown_torque"):
        Motor.induction(100.0, 180.0, 90.0, 188.5)
    with pytest.raises(ValueError, match="rated_speed"):
        Motor.induction(100.0, 190.0, 200.0, 188.5)


def test_without_scipy_one_line_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "scipy.integrate", None)
    with pytest.raises(SimulationError, match=r'pip install -e "\.\[dynamics\]"'):
        simulate(EXAMPLE, Motor.constant(10.0))


# --- the command line -------------------------------------------------------------------

MOTOR_DECK = Path(__file__).resolve().parent.parent / "decks" / "motor.toml"


def run_cli(argv, capsys):
    from sielaff.cli import main

    status = main(argv)
    out, err = capsys.readouterr()
    return status, out, err


def test_cli_writes_the_time_history_with_units_and_a_plot(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    csv, png = tmp_path / "m.csv", tmp_path / "m.png"
    status, out, err = run_cli(["simulate", str(MOTOR_DECK), "-o", str(csv), "--plot",
                                str(png)], capsys)
    assert status == 0 and out == ""
    assert err.startswith("sielaff: simulate: 20 revolutions in ")
    assert err.splitlines()[1].startswith("motor sizing over the last revolution")
    lines = csv.read_text().splitlines()
    assert lines[0] == "t[s],ATH2[deg],TH2D[rad/sec],TH2DD[rad/sec^2],MOTOR[in-lb],TORQ[in-lb]"
    rows = np.array([[float(x) for x in line.split(",")] for line in lines[1:]])
    assert rows[0, 2] == 0.0 and rows[-1, 1] == pytest.approx(20 * 360.0)  # from rest, 20 revs
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("motor, match", [
    ('kind = "diesel"', "[motor] kind = 'diesel'"),
    ('kind = "linear"\nstall_torque = 10.0', "[motor] has no no_load_speed"),
    ('kind = "constant"\ntorque = 1.0\nvolts = 3', "unknown key 'volts'"),
    ('kind = "constant"\ntorque = 1.0\nflywheel = -2.0', "flywheel = -2"),
    ('kind = "linear"\nstall_torque = 10.0\nno_load_speed = -5.0', "no_load_speed = -5"),
    ('kind = "constant"\ntorque = 1.0\nsteady = "yes"', "steady = 'yes'"),
])
def test_cli_bad_motor_is_one_line(tmp_path, capsys, motor, match):
    text = MOTOR_DECK.read_text().split("\n[motor]\n")[0] + "\n[motor]\n" + motor + "\n"
    spec = tmp_path / "bad.toml"
    spec.write_text(text)
    out_csv = tmp_path / "never.csv"
    status, out, err = run_cli(["simulate", str(spec), "-o", str(out_csv)], capsys)
    assert status == 2 and out == "" and err.count("\n") == 1 and match in err
    assert "Traceback" not in err and not out_csv.exists()


def test_cli_without_scipy_names_the_extra(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "scipy.integrate", None)
    status, out, err = run_cli(["simulate", str(MOTOR_DECK), "-o", str(tmp_path / "x.csv")],
                               capsys)
    assert status == 2 and out == ""
    assert err == 'sielaff: simulate needs scipy: pip install -e ".[dynamics]"\n'
    assert not (tmp_path / "x.csv").exists()


def test_cli_stall_is_reported(tmp_path, capsys):
    text = MOTOR_DECK.read_text().split("\n[motor]\n")[0]
    text += '\n[motor]\nkind = "constant"\ntorque = 5.0\nspeed = 1.0\n'
    text = text.replace("coupler = 8.0", "coupler = 40.0", 1)
    text += '\n[scene]\ngravity = "down"\n'
    spec = tmp_path / "weak.toml"
    spec.write_text(text)
    status, out, err = run_cli(["simulate", str(spec), "-o", str(tmp_path / "w.csv")], capsys)
    assert status == 0 and err.startswith("sielaff: simulate: stalled: the crank stopped")


def test_punch_leaves_the_motor_out(capsys):
    status, out, _ = run_cli(["punch", str(MOTOR_DECK)], capsys)
    assert status == 0
    assert out == (MOTOR_DECK.parent / "example.dat").read_text()


# --- design.flywheel over cycles other than one revolution -----------------------------

@pytest.mark.parametrize("cycle", [360.0, 720.0, 1080.0])
def test_flywheel_cycle_energy_is_the_integral_over_the_cycle(cycle):
    from sielaff.design.flywheel import flywheel_from_torque

    # T = 100 + A sin(2 pi phi / cycle), phi in degrees; with th = phi in radians,
    # E(th) = integral of A sin(360 th / cycle) d th = -A (cycle / 360) cos(360 th / cycle),
    # whose max - min is 2 A cycle / 360
    a, n = 50.0, 4096
    th = np.arange(n) * (cycle / n)
    f = flywheel_from_torque(100.0 + a * np.sin(2 * np.pi * th / cycle), 50.0, 0.05, cycle)
    expected = 2.0 * a * cycle / 360.0
    assert float(f.energy) == pytest.approx(expected, rel=1e-12)
    assert f.theta2[-1] == pytest.approx(cycle * (n - 1) / n)
    assert float(f.inertia) == pytest.approx(expected / (0.05 * 2500.0), rel=1e-12)


def test_flywheel_default_cycle_is_bit_for_bit_the_revolution():
    a = flywheel(EXAMPLE, 0.05)
    b = flywheel(EXAMPLE, 0.05, cycle=360.0)
    c = flywheel(EXAMPLE, 0.05, n=7200, cycle=720.0)  # the linkage repeats: same energy
    assert float(a.energy) == float(b.energy)
    assert float(c.energy) == pytest.approx(float(a.energy), rel=1e-12)
    with pytest.raises(ValueError, match="cycle = -1"):
        flywheel(EXAMPLE, 0.05, cycle=-1)


def test_cli_needs_a_spec_with_a_motor(tmp_path, capsys):
    status, _, err = run_cli(["simulate", str(MOTOR_DECK.parent / "example.dat")], capsys)
    assert status == 2 and err.endswith("simulate reads a TOML spec with a [motor] table\n")
    status, _, err = run_cli(["simulate", str(MOTOR_DECK.parent / "example.toml")], capsys)
    assert status == 2 and "no [motor] table" in err and err.count("\n") == 1
