"""simulate's inputs, each checked before any work and refused in one line; a run that
cannot finish in its budget stopped with why (issue 32, families 1, 4 and 5)."""

from __future__ import annotations

import importlib
import math

import pytest

from sielaff import EXAMPLE, PinFriction, Scene

pytest.importorskip("scipy")
from sielaff.dynamics.motor import Motor  # noqa: E402
from sielaff.dynamics.simulate import SimulationError, simulate  # noqa: E402

#: The module itself (the package exports the function under its name).
S = importlib.import_module("sielaff.dynamics.simulate")

MOTOR = Motor.linear(2000.0, 55.0)


@pytest.mark.parametrize("kwargs, words", [
    ({"steady": "no"}, "steady = 'no': True or False"),
    ({"atol": math.nan}, "atol = nan: a positive number"),
    ({"atol": -1.0}, "atol = -1.0: a positive number"),
    ({"t_max": -1.0}, "t_max = -1.0: a positive number"),
    ({"t_max": math.inf}, "t_max = inf: a positive number"),
])
def test_bad_arguments_are_one_line(kwargs, words):
    with pytest.raises(SimulationError, match=words.replace("(", r"\(")) as e:
        simulate(EXAMPLE, MOTOR, flywheel=7.41, revolutions=1, **kwargs)
    assert "\n" not in str(e.value)


def test_no_mechanism_is_one_line():
    with pytest.raises(SimulationError, match="mechanism = None: a sielaff.Mechanism"):
        simulate(None, MOTOR)


def test_a_motor_that_turns_nan_is_named():
    def motor(w):  # fine at the start, NaN once the crank passes 52 rad/sec
        return 2000.0 * (1.0 - w / 55.0) if w < 52.0 else math.nan

    with pytest.raises(SimulationError, match="the motor's torque at .* rad/sec is nan"):
        simulate(EXAMPLE, motor, flywheel=7.41, speed0=50.0, revolutions=5)


def test_the_cpu_budget_stops_a_run_that_goes_through_the_engine(monkeypatch):
    monkeypatch.setattr(S, "MAX_CPU_SECONDS", 0.2)
    with pytest.raises(SimulationError, match=r"more than 0.2 s of CPU after \d+ "
                                              "evaluations .* by the engine at every state"):
        simulate(EXAMPLE, MOTOR, flywheel=7.41, scene=Scene(friction=PinFriction(0.1, 0.25)),
                 speed0=50.0, revolutions=50, tables=False)


def test_the_advice_never_names_the_method_in_use(monkeypatch):
    monkeypatch.setattr(S, "MAX_EVALUATIONS", 50)
    monkeypatch.setattr(S, "EVALUATIONS_PER_REVOLUTION", 1)
    for method in ("LSODA", "RK45"):
        with pytest.raises(SimulationError, match="more than 50 evaluations") as e:
            simulate(EXAMPLE, MOTOR, flywheel=7.41, speed0=50.0, revolutions=5, method=method)
        advice = str(e.value).split("wants ", 1)[1]
        assert f"'{method}'" not in advice


def _no_tables(monkeypatch):
    """Fail if the run gets as far as building its tables (the first work)."""
    def boom(*a, **k):
        raise AssertionError("the run started")
    monkeypatch.setattr(S, "_Tables", boom)
    monkeypatch.setattr(S, "FrictionTables", boom)


def test_more_revolutions_than_the_samples_bound_are_refused_before_any_work(monkeypatch):
    _no_tables(monkeypatch)
    most = S.max_revolutions(360)
    assert most <= S.MAX_SAMPLES / 360 < most + 0.01
    with pytest.raises(SimulationError, match=r"revolutions = 100000: in \(0, 2912.71\] "
                                              r"\(360 samples a revolution, at most "
                                              "1,048,576 in a result"):
        simulate(EXAMPLE, MOTOR, flywheel=7.41, revolutions=100_000)
    with pytest.raises(SimulationError, match=r"revolutions = 3000: in \(0, 1048.57\]"):
        simulate(EXAMPLE, MOTOR, flywheel=7.41, revolutions=3000, per_revolution=1000)


@pytest.mark.parametrize("kwargs, words", [
    ({"speed0": 1e98}, "speed0 = 1e+98 rad/sec: past 1e+49"),
    ({"speed0": -1e50}, "speed0 = -1e+50 rad/sec: past 1e+49"),
])
def test_a_speed_past_the_engines_range_is_refused_before_any_work(monkeypatch, kwargs,
                                                                   words):
    _no_tables(monkeypatch)
    with pytest.raises(SimulationError, match=words.replace("+", r"\+")):
        simulate(EXAMPLE, MOTOR, flywheel=7.41, **kwargs)
    with pytest.raises(SimulationError, match=r"the motor's no_load_speed = 1e\+60 rad/sec"):
        simulate(EXAMPLE, Motor.linear(2000.0, 1e60), flywheel=7.41, speed0=50.0)


def test_the_si_messages_say_rad_per_second():
    si = EXAMPLE.replace(units="SI")
    with pytest.raises(SimulationError, match=r"speed0 = 1e\+98 rad/s: past") as e:
        simulate(si, MOTOR, flywheel=7.41, speed0=1e98)
    assert "rad/sec" not in str(e.value)


def test_a_run_whose_pace_cannot_finish_is_stopped_early_with_the_estimate(monkeypatch):
    monkeypatch.setattr(S, "MAX_CPU_SECONDS", 2.0)
    monkeypatch.setattr(S, "PACE_SECONDS", 0.2)
    with pytest.raises(SimulationError, match=r"50 revolutions would take about .* s of "
                                              r"CPU at the pace of the first .*, past the "
                                              r"budget of 2 s: ask for at most about") as e:
        simulate(EXAMPLE, MOTOR, flywheel=7.41, scene=Scene(friction=PinFriction(0.1, 0.25)),
                 speed0=50.0, revolutions=50, tables=False)
    assert "\n" not in str(e.value)


@pytest.mark.parametrize("key, value, words", [
    ("revolutions", "100000", "revolutions = 100000: in (0, 2912.71]"),
    ("speed", "1e98", "speed = 1e+98: past 1e+49 rad/sec"),
    ("no_load_speed", "1e60", "no_load_speed = 1e+60: past 1e+49 rad/sec"),
    ("method", '"Euler"', "method"),
    ("method", '["LSODA"]', "method"),
    ("rtol", "0.5", "rtol = 0.5: in [1e-14, 0.1]"),
])
def test_the_motor_table_is_bounded_before_any_work(tmp_path, key, value, words):
    import re
    import subprocess
    import sys
    from pathlib import Path

    spec = (Path(__file__).resolve().parents[1] / "decks" / "motor.toml").read_text()
    head, motor = spec.split("\n[motor]\n")
    lines = [ln for ln in motor.splitlines() if not ln.startswith(f"{key} =")]
    spec = head + "\n[motor]\n" + "\n".join(lines) + f"\n{key} = {value}\n"
    (tmp_path / "m.toml").write_text(spec)
    p = subprocess.run([sys.executable, "-m", "sielaff", "simulate", "m.toml", "-o", "m.csv"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert p.returncode == 2 and len(p.stderr.splitlines()) == 1, p.stderr
    assert f"[motor] {words}" in p.stderr
    assert re.match(r"m\.toml: \[motor\] ", p.stderr)
    assert not (tmp_path / "m.csv").exists()


def test_the_motor_table_chooses_the_method_and_tolerance():
    from pathlib import Path

    from sielaff import load_spec

    spec = (Path(__file__).resolve().parents[1] / "decks" / "motor.toml").read_text()
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "m.toml"
        p.write_text(spec + 'method = "Radau"\nrtol = 1e-6\n')
        run = load_spec(str(p)).motor
    assert run["method"] == "Radau" and run["rtol"] == 1e-6
    r = simulate(EXAMPLE, run["motor"], flywheel=run["flywheel"], speed0=50.0,
                 revolutions=0.2, method=run["method"], rtol=run["rtol"])
    assert r.method == "Radau" and r.rtol == 1e-6 and r.finished


def _spec_with(tmp_path, name, edit):
    from pathlib import Path

    spec = (Path(__file__).resolve().parents[1] / "decks" / name).read_text()
    for old, new in edit:
        assert old in spec
        spec = spec.replace(old, new)
    (tmp_path / "s.toml").write_text(spec)
    return "s.toml"


def _capped(gib):
    import resource

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (gib << 30, gib << 30))
    return limit


@pytest.mark.slow
def test_the_most_revolutions_run_within_two_gib_of_address_space(tmp_path):
    import subprocess
    import sys

    spec = _spec_with(tmp_path, "motor.toml", [("revolutions = 20", "revolutions = 2912.71")])
    p = subprocess.run([sys.executable, "-m", "sielaff", "simulate", spec, "-o", "m.csv"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=600,
                       preexec_fn=_capped(2))
    assert p.returncode == 0, p.stderr
    assert "2912.71 revolutions in " in p.stderr
    rows = (tmp_path / "m.csv").read_text().count("\n")
    assert rows == S.MAX_SAMPLES + 2  # the header, and MAX_SAMPLES + 1 samples (both ends)


@pytest.mark.slow
def test_friction_near_the_change_point_finishes_or_says_why_within_the_budget(tmp_path):
    """Issue 32, family 1: R3 = 19.999 with the friction deck's pins ran for 10 minutes."""
    import subprocess
    import sys
    import time

    spec = _spec_with(tmp_path, "friction.toml", [("coupler = 16.0", "coupler = 19.999")])
    t0 = time.monotonic()
    p = subprocess.run([sys.executable, "-m", "sielaff", "simulate", spec, "-o", "f.csv"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert time.monotonic() - t0 < 1.2 * S.MAX_CPU_SECONDS + 60
    assert "Traceback" not in p.stderr and "Warning" not in p.stderr
    if p.returncode == 0:
        assert "20 revolutions in " in p.stderr and (tmp_path / "f.csv").exists()
    else:
        assert p.returncode == 2 and len(p.stderr.splitlines()) == 1
        assert not (tmp_path / "f.csv").exists()


@pytest.mark.parametrize("steady", [False, True])
def test_the_integrators_warnings_never_reach_the_user(monkeypatch, steady):
    """scipy's LSODA warns ("lsoda-- ...", "Excess work done") where it also returns a
    status; the status is said in one line, the warning never."""
    import warnings

    import scipy.integrate

    real = scipy.integrate.solve_ivp

    def noisy(*a, **k):
        warnings.warn("lsoda--  warning..t (=r1) and h (=r2) are such that t + h = t",
                      UserWarning, stacklevel=2)
        return real(*a, **k)

    monkeypatch.setattr(scipy.integrate, "solve_ivp", noisy)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = simulate(EXAMPLE, MOTOR, flywheel=7.41, speed0=50.0, revolutions=0.2,
                     steady=steady)
    assert r.finished
