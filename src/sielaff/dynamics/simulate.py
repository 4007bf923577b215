"""``simulate``: the crank driven by a motor, its speed a result (forward dynamics).

The linkage has one degree of freedom, the crank angle th2.  The engine's kinetostatic
drive torque TORQ at a state (th2, w = TH2D, a = TH2DD) is what the crank must be given
for that motion; with a motor torque M(w) and a flywheel of inertia F on the crank, the
motion is the one where the motor gives exactly that torque and the flywheel's share:

    M(w) = F a + TORQ(th2, w, a)

TORQ is affine in a (the inertia forces are), TORQ(th2, w, a) = TORQ(th2, w, 0) + J(th2) a,
with J the reduced inertia of the linkage about O2 (Eksergian's form: TORQ = J a +
J'(th2) w^2 / 2 + the loads' share).  So

    (J(th2) + F) a = M(w) - TORQ(th2, w, 0)

and TORQ(th2, w, 0) is, for every scene the engine has without friction, a quadratic in
w: B(th2) w^2 (inertia) + C(th2) w (dampers) + D(th2) (gravity, loads, TEX, springs).
``simulate`` reads J, B, C and D from the engine on a grid of crank angles (five analyze
calls of one array each, one of them a check that TORQ really is that quadratic), holds
them as Fourier series (periodic and smooth; the grid doubles until the series' tail is
below 1e-13 of its largest term) and integrates with those.  Pin friction (TORQ depends
on |pin force|, nonlinear in a) has tables of its own (:mod:`sielaff.dynamics.friction`:
the pin forces' parts, the couples' statics and the speed ratios, a and the couples
solved together per state).  Tables that fail their check against the engine, or a
series that does not converge (near a toggle), are replaced by the engine at each state:
J from two calls (a = 0 and a = 1), then, for friction, a short fixed-point iteration on a
(a += (M - F a - TORQ(a)) / (J + F), secant slope J) to 1e-12 of the torque scale.

Time integration: ``scipy.integrate.solve_ivp`` (the ``dynamics`` extra).  It gives what
this problem needs in one place: adaptive steps with error control (the speed varies on
the linkage's own time scale and, with a stiff motor, on the much shorter one
(J + F) / stiffness), dense output (samples at any time), events located by root finding
(the stall w = 0, the end after N revolutions), and both explicit (DOP853, RK45) and
implicit/switching (Radau, BDF, LSODA) methods behind one call.  The default is LSODA:
it switches to BDF by itself when a stiff motor makes the explicit steps too short, and
uses Adams steps otherwise (benchmarks/simulate.py measures the choice, docs/effects.md).

``steady=True`` finds the periodic steady state directly: the speed w0 at THETA 2 = start
whose speed one revolution later is w0 again, by Brent's method on
f(w0) = w(start + 360 deg) - w0 (scipy.optimize.brentq), integrating in the crank angle
(dt/dth2 = 1/w, dw/dth2 = a/w), which is exact for a turning crank.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np

from sielaff.dynamics.friction import FrictionError, FrictionTables
from sielaff.dynamics.runs import TWO_PI, SimulationError, _at_times, _steady, _transient
from sielaff.engine.analysis import analyze, model_for
from sielaff.engine.scene import Scene, SceneBase, scene_of
from sielaff.mechanism import Mechanism
from sielaff.quantities import unit, unit_of

__all__ = ["Simulation", "simulate"]

#: Evaluations of the equation of motion allowed per run: a bound on time, never a hang.
#: A run may take this many, or EVALUATIONS_PER_REVOLUTION for each revolution asked
#: for, whichever is more (the decks take 190 to 300 a revolution at rtol 1e-8).
MAX_EVALUATIONS = 400_000
EVALUATIONS_PER_REVOLUTION = 2000
#: Samples a result may hold (revolutions x per_revolution): the memory of the result's
#: arrays and of the CSV written from them (1,048,576 rows, some 130 MB of text).
MAX_SAMPLES = 2 ** 20
#: Results are computed from the samples this many at a time (a block's analysis takes
#: at most 1 KB a position, design.sweep.BYTES_PER_POSITION: 64 MB).
SAMPLE_BLOCK = 65536
#: The largest speed [rad/sec or rad/s] a run may start at or a motor may name: the
#: tables probe accelerations of the speed squared, and the engine takes numbers to 1e100.
MAX_SPEED = 1e49
#: After this much CPU [s], a run whose pace says it cannot finish within
#: MAX_CPU_SECONDS is stopped then, with the estimate, instead of at the budget's end.
PACE_SECONDS = 5.0
#: The CPU seconds a run may take: when the tables do not fit (friction near a change
#: point) every state goes through the engine, some 30 ms each, and the evaluations'
#: bound alone would allow hours.
MAX_CPU_SECONDS = 300.0
#: Largest Fourier grid tried for the tables (beyond: the engine at each state).
MAX_GRID = 16384


#: solve_ivp's methods, and the relative tolerances a run may ask for.
METHODS = ("LSODA", "RK45", "RK23", "DOP853", "Radau", "BDF")
RTOL = (1e-14, 0.1)


def max_revolutions(per_revolution: int = 360) -> float:
    """The most revolutions a run may ask for at ``per_revolution`` samples each [-]:
    MAX_SAMPLES in all."""
    return math.floor(MAX_SAMPLES / per_revolution * 100.0) / 100.0


class Simulation(dict):
    """``simulate``'s answer: ``{name: array}`` over the samples, and what happened.

    Keys: ``t`` [s]; ``ATH2`` [deg], unwrapped (it keeps growing past 360); ``TH2D``
    [rad/sec or rad/s]; ``TH2DD`` [rad/sec^2 or rad/s^2]; ``MOTOR``, the motor's torque
    [in-lb or N m]; and
    each asked-for engine output at those states.  Attributes: ``stalled`` (the crank
    stopped and would turn back), ``finished`` (it made the revolutions asked for, or
    for ``steady``, the steady state was found), ``message`` (one line saying which),
    ``steady``, ``flywheel`` [in-lb-sec^2 or kg m^2], ``motor``, ``mode`` (``"tables"``
    or ``"engine"``: how the equation of motion was evaluated; ``engine_states``: the
    states the friction tables could not solve, solved by the engine), ``evaluations`` (of the
    equation of motion), ``method``, ``rtol``, ``units`` (a unit for each key).
    """

    stalled: bool = False
    finished: bool = True
    message: str = ""
    steady: bool = False
    flywheel: float = 0.0
    motor: Any = None
    mode: str = "tables"
    evaluations: int = 0
    method: str = "LSODA"
    rtol: float = 1e-8
    units: dict[str, str] = {}
    #: States whose friction the tables' iteration could not solve, solved by the engine.
    engine_states: int = 0
    #: The unit system of the numbers (the mechanism's): "in-lb-sec" or "SI".
    mechanism_units: str = "in-lb-sec"

    def to_frame(self) -> Any:
        """The samples as a pandas DataFrame (the ``frames`` extra): time ``t`` [s] as
        the index, one column per key, each column's unit in ``frame.attrs["units"]``;
        the run's message and motor sizing (:meth:`sizing`) in ``frame.attrs``."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Simulation.to_frame needs pandas: pip install -e "
                              "\".[frames]\"") from None
        columns = {k: np.asarray(v) for k, v in self.items() if k != "t"}
        frame = pd.DataFrame(columns, index=pd.Index(np.asarray(self["t"]), name="t"))
        frame.attrs["units"] = dict(self.units)
        frame.attrs["message"] = self.message
        frame.attrs["sizing"] = self.sizing()
        return frame

    def sizing(self) -> dict[str, Any]:
        """What a motor must give for this run (:func:`sielaff.dynamics.sizing.sizing`)."""
        from sielaff.dynamics.sizing import sizing

        return sizing(self)


class _TooSlow(Exception):
    """The run passed MAX_CPU_SECONDS."""


class _TooLong(Exception):
    pass


class _WontFinish(Exception):
    """The pace so far says the run would pass MAX_CPU_SECONDS: (cpu s, fraction done)."""


def _torq(mechanism: Mechanism, scene: Scene, ath2: Any, w: Any, a: Any) -> np.ndarray:
    """The engine's TORQ at crank angles ``ath2`` [deg], speeds ``w``, accelerations ``a``."""
    m = mechanism.replace(TH2D=w)
    return analyze(m, ath2, ["TORQ"], scene=scene.replace(th2dd=a))["TORQ"]


def _nonlinear(scene: Scene) -> bool:
    """Whether the scene has an effect that is not affine in the crank's acceleration:
    one that corrects the totals (pin friction), when it is on (its own rule)."""
    return any(e.corrects for e in scene.effects)


class _Tables:
    """J, B, C, D of TORQ(th2, w, a) = J a + B w^2 + C w + D as Fourier series."""

    def __init__(self, mechanism: Mechanism, scene: Scene, scale: float) -> None:
        self.ok = False
        n = 256
        while n <= MAX_GRID:
            th = np.arange(n) * (360.0 / n)
            s = scale
            w = np.array([0.0, 0.0, s, -s, 2.0 * s])[:, None]
            a = np.array([0.0, s * s, 0.0, 0.0, 0.7 * s * s])[:, None]
            with np.errstate(all="ignore"):
                q = _torq(mechanism, scene, np.broadcast_to(th, (5, n)), w, a)
            if not np.all(np.isfinite(q)):
                return
            d = q[0]
            jj = (q[1] - d) / (s * s)
            b = (q[2] + q[3] - 2.0 * d) / (2.0 * s * s)
            c = (q[2] - q[3]) / (2.0 * s)
            check = jj * a[4, 0] + b * w[4, 0] ** 2 + c * w[4, 0] + d
            peak = max(float(np.max(np.abs(q))), 1e-300)
            if np.max(np.abs(check - q[4])) > 1e-9 * peak:
                return  # not affine in a, or not quadratic in w: the engine per state
            f = np.fft.rfft(np.stack([jj, b, c, d]), axis=-1) * (2.0 / n)
            f[:, 0] *= 0.5
            mag = np.abs(f)
            tail = np.max(mag[:, n // 4:])
            if tail <= 1e-13 * max(float(np.max(mag)), 1e-300):
                self.coef = f[:, : n // 4 + 1]
                self.k = np.arange(self.coef.shape[1], dtype=float)
                self.n = n
                self.ok = True
                self.jmin = float(np.min(jj))
                return
            n *= 2

    def __call__(self, theta: float) -> np.ndarray:
        """(J, B, C, D) at ``theta`` [rad] (sums, not BLAS: no thread start-up per step)."""
        x = self.k * theta
        return (self.coef.real * np.cos(x)).sum(axis=1) - (self.coef.imag * np.sin(x)).sum(
            axis=1)


def _check_speed(name: str, v: Any) -> float:
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise SimulationError(f"{name} = {v!r}: not a number") from None
    if not math.isfinite(x):
        raise SimulationError(f"{name} = {v!r}: not finite")
    return x


def simulate(mechanism: Mechanism, motor: Callable[[Any], Any], *, flywheel: float = 0.0,
             scene: Scene | None = None, speed0: float | None = None,
             revolutions: float = 20, steady: bool = False,
             outputs: Iterable[str] | str | None = None, start: float = 0.0,
             per_revolution: int = 360, method: str = "LSODA", rtol: float = 1e-8,
             atol: float | None = None, t_max: float | None = None,
             tables: bool = True, times: Iterable[float] | None = None) -> Simulation:
    """The crank of ``mechanism`` driven by ``motor``: the motion that follows.

    Parameters
    ----------
    mechanism : Mechanism
        One design (scalar fields); its TH2D [rad/sec] is the starting speed unless
        ``speed0`` is given.  The crank must turn fully.
    motor : callable
        The drive torque [in-lb or N m] as a function of the crank speed TH2D [rad/sec]
        (:class:`sielaff.Motor` has the common curves).
    flywheel : float
        Inertia added to the crank [in-lb-sec^2 or kg m^2].
    scene : Scene, optional
        What else acts (gravity, loads, TEX, ...); its ``th2dd`` must be 0 (the crank's
        acceleration is the result here).
    speed0 : float, optional
        The crank speed at the start [rad/sec]; 0 starts from rest.
    revolutions : float
        How many crank revolutions to integrate (not with ``steady``).
    steady : bool
        Return one revolution of the periodic steady state, found by shooting.
    outputs : names, optional
        Engine outputs wanted at the samples (any of ``analyze``'s), besides the state.
    start : float
        The crank angle at the start [deg].
    per_revolution : int
        Samples per revolution of the result.
    method, rtol, atol
        ``solve_ivp``'s method and tolerances (atol default: rtol x the speed scale).
    t_max : float, optional
        A bound on the simulated time [s] (default: 100 x the time of ``revolutions``
        at the starting or the motor's speed).
    tables : bool
        Use the Fourier tables when the scene allows (False: the engine at every state).
    times : list of float, optional
        The times of the samples [s], increasing from 0 or later: the run integrates to
        the last one, whatever the crank does (it may stop and turn back: a free linkage
        driven only by springs and forces swings; ``revolutions`` and ``per_revolution``
        are not used, and ``t_max``, if given, must not be before the last time).

    Returns
    -------
    Simulation
    """
    units = getattr(mechanism, "units", "in-lb-sec")
    try:
        result = _simulate(mechanism, motor, flywheel=flywheel, scene=scene, speed0=speed0,
                           revolutions=revolutions, steady=steady, outputs=outputs,
                           start=start, per_revolution=per_revolution, method=method,
                           rtol=rtol, atol=atol, t_max=t_max, tables=tables,
                           times=times)
    except SimulationError as exc:
        raise SimulationError(_in_units(str(exc), units)) from None
    result.message = _in_units(result.message, units)
    return result


def _in_units(text: str, units: str) -> str:
    """A message's speeds and accelerations in the unit system in force."""
    if units not in ("in-lb-sec", "SI"):
        return text
    return text.replace("rad/sec^2", unit_of("angular acceleration", units)).replace(
        "rad/sec", unit_of("rate", units))


def _times(times: Any, steady: Any, t_max: float | None) -> np.ndarray | None:
    """``times`` checked [s]: None, or an increasing 1-d array of at least 2 finite times
    >= 0, at most MAX_SAMPLES of them, none past ``t_max``."""
    if times is None:
        return None
    what = f"times: an increasing list of 2 to {MAX_SAMPLES:,} times >= 0 [s]"
    if steady:
        raise SimulationError("times: not with steady = True (the steady state is one "
                              "revolution, sampled by per_revolution)")
    try:
        ts = np.array(times, dtype=float)
    except (TypeError, ValueError):
        raise SimulationError(f"{what}, not {times!r}") from None
    if ts.ndim != 1 or not 2 <= len(ts) <= MAX_SAMPLES or not np.all(np.isfinite(ts)) \
            or ts[0] < 0.0 or np.any(np.diff(ts) <= 0.0):
        raise SimulationError(f"{what}; these are not")
    if t_max is not None and ts[-1] > t_max:
        raise SimulationError(f"times: the last, {ts[-1]:g} s, is past t_max = {t_max:g} s")
    return ts


def _simulate(mechanism, motor, *, flywheel, scene, speed0, revolutions, steady, outputs,
              start, per_revolution, method, rtol, atol, t_max, tables, times
              ) -> Simulation:
    try:
        from scipy.integrate import solve_ivp
        from scipy.optimize import brentq
    except ImportError:
        raise SimulationError('simulate needs scipy: pip install -e ".[dynamics]"') from None
    try:
        model = model_for(mechanism)
    except ValueError:
        raise SimulationError(f"mechanism = {mechanism!r}: a sielaff.Mechanism or "
                              "SliderCrank") from None
    sc = scene_of(model)() if scene is None else scene
    if not isinstance(sc, SceneBase) or sc._model is not model:
        raise SimulationError(f"scene = {scene!r} is not a {model.name}'s Scene")
    if callable(sc.th2dd) or np.any(np.asarray(sc.th2dd) != 0.0):
        raise SimulationError("simulate: the scene's th2dd must be 0 (the crank's "
                              "acceleration is what simulate finds)")
    if sc.per_position():
        raise SimulationError("simulate: the scene's values must be constants or "
                              "functions, not arrays over crank angles")
    try:
        (model.validate or (lambda m: None))(mechanism)
    except ValueError as exc:
        raise SimulationError(str(exc)) from None
    for name, v in mechanism.as_dict().items():
        if np.ndim(v):
            raise SimulationError(f"simulate runs one design: {name} is an array")
    if not isinstance(steady, bool | np.bool_):
        raise SimulationError(f"steady = {steady!r}: True or False")
    for name, v, what in (("atol", atol, "rtol times the speed scale"),
                          ("t_max", t_max, "100 times the time of the revolutions")):
        if v is not None and (isinstance(v, bool) or not isinstance(v, int | float)
                              or not math.isfinite(v) or not v > 0.0):
            raise SimulationError(f"{name} = {v!r}: a positive number, or None ({what})")
    if not callable(motor):
        raise SimulationError(f"motor = {motor!r}: a function of TH2D (sielaff.Motor)")
    f_in = _check_speed("flywheel", flywheel)
    if f_in < 0.0:
        raise SimulationError(f"flywheel = {flywheel!r}: an inertia cannot be negative")
    why = model.full_turn(mechanism) if model.full_turn is not None else None
    if why is not None:
        raise SimulationError(f"simulate: {why}")
    start_name = "speed0" if speed0 is not None else "the mechanism's TH2D"
    w0 = _check_speed(start_name, mechanism.TH2D if speed0 is None else speed0)
    ts = _times(times, steady, t_max)
    revs = _check_speed("revolutions", revolutions)
    if isinstance(per_revolution, bool) or not isinstance(per_revolution, int) \
            or not 2 <= per_revolution <= 100_000:
        raise SimulationError(f"per_revolution = {per_revolution!r}: an integer 2..100000")
    if not steady and ts is None:
        most = max_revolutions(per_revolution)
        if not 0.0 < revs <= most:
            raise SimulationError(
                f"revolutions = {revolutions!r}: in (0, {most:g}] ({per_revolution} "
                f"samples a revolution, at most {MAX_SAMPLES:,} in a result: its memory); "
                "steady = True gives the periodic state in one revolution")
    speeds = [(start_name, w0)]
    if speed0 is not None:
        speeds.append(("the mechanism's TH2D", float(mechanism.TH2D)))
    speeds += [(f"the motor's {k}", float(v)) for k, v in getattr(motor, "parameters", ())
               if k.endswith("speed")]
    for name, v in speeds:
        if abs(v) > MAX_SPEED:
            raise SimulationError(
                f"{name} = {v:g} rad/sec: past {MAX_SPEED:g} (a crank's accelerations go "
                "as its speed squared, and the engine takes numbers to 1e100)")
    if method not in METHODS:
        raise SimulationError(f"method = {method!r}: one of solve_ivp's ("
                              f"{', '.join(METHODS)})")
    if not (isinstance(rtol, float | int) and not isinstance(rtol, bool)
            and RTOL[0] <= rtol <= RTOL[1]):
        raise SimulationError(f"rtol = {rtol!r}: in [{RTOL[0]:g}, {RTOL[1]:g}]")
    wanted = tuple(dict.fromkeys([outputs] if isinstance(outputs, str) else (outputs or ())))
    analyze(mechanism, 0.0, wanted or ["TORQ"], scene=sc)  # unknown names fail here, first
    th_start = math.radians(_check_speed("start", start))
    m0 = float(np.asarray(motor(w0)))
    if not math.isfinite(m0):
        raise SimulationError(f"the motor's torque at {w0:g} rad/sec is {m0!r}")

    motor_speed = float(getattr(motor, "speed_scale", 0.0) or 0.0)
    scale = max(abs(w0), abs(float(mechanism.TH2D)), motor_speed, 1.0)
    nonlinear = _nonlinear(sc)
    tab = _Tables(mechanism, sc, scale) if tables and not nonlinear else None
    if tab is not None and not tab.ok:
        tab = None
    # the friction tables are the four-bar's pins; another kind's friction: the engine
    ftab = FrictionTables(mechanism, sc, scale, f_in) \
        if tables and nonlinear and isinstance(mechanism, Mechanism) else None
    if ftab is not None and not ftab.ok:
        ftab = None
    count = [0]
    fallbacks = [0]

    def accel_many(theta: Any, w: Any) -> np.ndarray:
        """TH2DD at crank angles ``theta`` [rad] and speeds ``w`` [rad/sec] (arrays), by
        the friction tables when they fit and converge, else by the engine (whose pin
        friction is a Newton solve that finds every solution the law has): one call for
        TORQ at a = 0 and a = 1, then, with friction, one call per iteration for every
        state still short of 1e-12 of its torque scale."""
        theta, w = np.atleast_1d(theta).astype(float), np.atleast_1d(w).astype(float)
        mt = np.asarray(motor(w), dtype=float) * np.ones_like(w)
        if not np.all(np.isfinite(mt)):
            k = int(np.argmax(~np.isfinite(mt)))
            raise SimulationError(f"the motor's torque at {w[k]:.6g} rad/sec is {mt[k]!r}: "
                                  "not a number")
        if ftab is not None:
            try:
                return ftab.accel(theta, w, mt)
            except FrictionError:
                fallbacks[0] += len(w)  # the tables' fixed point diverged: the engine's
                # Newton solve decides these states
        deg = np.degrees(theta)
        with warnings.catch_warnings():  # a NaN is one line below, never a warning
            warnings.simplefilter("ignore")
            q = _torq(mechanism, sc, np.concatenate([deg, deg]), np.concatenate([w, w]),
                      np.concatenate([np.zeros_like(w), np.ones_like(w)]))
        bad = ~np.isfinite(q[: len(w)] + q[len(w):])
        if np.any(bad):
            k = int(np.argmax(bad))
            raise SimulationError(f"pin friction has no solution at THETA 2 = "
                                  f"{deg[k] % 360.0:.6g} deg, TH2D = {w[k]:.6g} rad/sec "
                                  "(the linkage self-locks there with this friction)")
        q0, jj = q[: len(w)], q[len(w):] - q[: len(w)]
        a = (mt - q0) / (jj + f_in)
        if nonlinear:
            tol = 1e-12 * np.maximum(np.maximum(np.abs(mt), np.abs(q0)), 1e-300)
            todo = np.arange(len(w))
            for _ in range(50):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    r = mt[todo] - f_in * a[todo] - _torq(mechanism, sc, deg[todo],
                                                           w[todo], a[todo])
                if not np.all(np.isfinite(r)):  # the engine's friction has no solution
                    todo = todo[~np.isfinite(r)]
                    break
                done = np.abs(r) <= tol[todo]
                a[todo] += np.where(done, 0.0, r / (jj[todo] + f_in))
                todo = todo[~done]
                if not len(todo):
                    break
            if len(todo):
                k = todo[0]
                raise SimulationError(f"the friction iteration does not converge at "
                                      f"THETA 2 = {deg[k] % 360.0:.6g} deg, TH2D = "
                                      f"{w[k]:.6g} rad/sec")
        return a

    cpu0 = time.process_time()
    budget = MAX_EVALUATIONS if steady else max(MAX_EVALUATIONS,
                                                 int(EVALUATIONS_PER_REVOLUTION * revs))
    angle_end = TWO_PI * revs if ts is None else math.inf  # no pace by angle for times

    def accel(theta: float, w: float) -> float:
        count[0] += 1
        if count[0] > budget:
            raise _TooLong
        if count[0] % 256 == 0:
            # the pace first: on a slow machine the first check may already be past the
            # budget, and the estimate then says more than the budget alone
            cpu = time.process_time() - cpu0
            done = (theta - th_start) / angle_end
            if not steady and cpu > PACE_SECONDS and 0.0 < done < 1.0 \
                    and cpu / done > 1.2 * MAX_CPU_SECONDS:
                raise _WontFinish(cpu, done)
            if cpu > MAX_CPU_SECONDS:
                raise _TooSlow
        if tab is not None:
            mt = float(np.asarray(motor(w)))
            if not math.isfinite(mt):
                raise SimulationError(f"the motor's torque at {w:.6g} rad/sec is {mt!r}: "
                                      "not a number")
            jj, b, c, d = tab(theta)
            return (mt - (b * w * w + c * w + d)) / (jj + f_in)
        return float(accel_many(theta, w)[0])  # the friction tables, or the engine

    tu = unit("TORQ", mechanism.units)
    atol_ = rtol * scale if atol is None else float(atol)
    result = Simulation()
    result.flywheel, result.motor, result.method, result.rtol = f_in, motor, method, rtol
    result.mode = "tables" if tab is not None or ftab is not None else "engine"
    result.steady = bool(steady)

    try:
        if steady:
            t, th, w = _steady(accel, solve_ivp, brentq, th_start, w0, per_revolution,
                               method, rtol, atol_)
            period = float(t[-1])
            result.message = (f"periodic steady state: a revolution in {period:.6g} s, mean "
                              f"speed {TWO_PI / period:.6g} rad/sec (2 pi / period, the time "
                              f"average), from {float(np.min(w)):.6g} to "
                              f"{float(np.max(w)):.6g}")
        elif ts is not None:
            t, th, w = _at_times(accel, solve_ivp, th_start, w0, ts, method, rtol, atol_,
                                 result)
        else:
            t, th, w = _transient(accel, solve_ivp, th_start, w0, revs, per_revolution,
                                  method, rtol, atol_, t_max, scale, result, tu)
    except _TooLong:
        other = "'Radau' or 'BDF'" if method == "LSODA" else "'LSODA', 'Radau' or 'BDF'"
        raise SimulationError(f"simulate: more than {budget} evaluations of the "
                              f"equation of motion (method {method}, rtol {rtol:g}): a "
                              f"stiff motor wants method={other}, or a looser rtol") from None
    except _WontFinish as exc:
        cpu, done = exc.args
        est = cpu / done
        fits = math.floor(revs * MAX_CPU_SECONDS / est * 10.0) / 10.0
        raise SimulationError(
            f"simulate: {revs:g} revolutions would take about {est:.3g} s of CPU at the "
            f"pace of the first {done * revs:.3g} ({cpu:.3g} s), past the budget of "
            f"{MAX_CPU_SECONDS:g} s: ask for at most about {fits:g}, a looser rtol, or "
            "steady = True") from None
    except _TooSlow:
        how = ("the engine at every state (the friction tables do not fit this linkage)"
               if result.mode == "engine" else "the tables")
        raise SimulationError(f"simulate: more than {MAX_CPU_SECONDS:g} s of CPU after "
                              f"{count[0]} evaluations of the equation of motion by {how}: "
                              "fewer revolutions, a looser rtol or less friction") from None
    result.evaluations = count[0]
    result.engine_states = fallbacks[0]
    # The samples' results a block at a time: memory flat in the revolutions.
    parts: dict[str, list[np.ndarray]] = {}
    for i in range(0, len(t), SAMPLE_BLOCK):
        th_b, w_b = th[i:i + SAMPLE_BLOCK], w[i:i + SAMPLE_BLOCK]
        a_b = accel_many(th_b, w_b) if tab is None else _accel_table(tab, motor, f_in,
                                                                      th_b, w_b)
        block = {"TH2DD": a_b, "MOTOR": np.asarray(motor(w_b), dtype=float)
                 * np.ones_like(w_b)}
        if wanted:
            r = analyze(mechanism.replace(TH2D=w_b), np.degrees(th_b), wanted,
                        scene=sc.replace(th2dd=a_b))
            block.update({n: np.asarray(r[n]) for n in wanted if n not in block})
        for name, v in block.items():
            parts.setdefault(name, []).append(v)
    result["t"] = t
    result["ATH2"] = np.degrees(th)
    result["TH2D"] = w
    for name, v in parts.items():
        if name not in result:
            result[name] = np.concatenate(v)
    u = mechanism.units
    result.units = {"t": "s", "ATH2": "deg", "TH2D": unit_of("rate", u),
                    "TH2DD": unit_of("angular acceleration", u), "MOTOR": tu}
    result.units.update({n: unit(n, u) for n in wanted if n not in result.units})
    result.mechanism_units = u
    return result


def _accel_table(tab: _Tables, motor, f_in, th, w) -> np.ndarray:
    e = np.exp(1j * tab.k[:, None] * np.asarray(th)[None, :])
    jj, b, c, d = (tab.coef @ e).real
    return (np.asarray(motor(w), dtype=float) - (b * w * w + c * w + d)) / (jj + f_in)
