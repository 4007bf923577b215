"""The three runs ``simulate`` makes of the equation of motion th'' = accel(th, th'):
N revolutions (stopping at a stall), the state at given times (through stops and
reversals: a free linkage swings), and the periodic steady state (by shooting on the
speed at the start).  ``accel`` is simulate's (the tables or the engine); each run
integrates with ``scipy.integrate.solve_ivp`` (passed in: scipy is an extra) and writes
its one-line message into the result."""

from __future__ import annotations

import math
import warnings

import numpy as np

__all__ = ["TWO_PI", "SimulationError"]

TWO_PI = 2.0 * math.pi


class SimulationError(ValueError):
    """A simulation that cannot be run or has no answer (one line)."""


def _transient(accel, solve_ivp, th0, w0, revs, per_rev, method, rtol, atol, t_max,
               scale, result, tu):
    """Integrate in time from (th0, w0) until ``revs`` revolutions, a stall or t_max."""
    a0 = accel(th0, w0)
    if w0 == 0.0 and a0 <= 0.0:
        result.stalled, result.finished = True, False
        result.message = (f"stalled: at rest at THETA 2 = {math.degrees(th0):.6g} deg the "
                          f"motor cannot start the crank (it would turn back, "
                          f"{a0:.6g} rad/sec^2)")
        return np.array([0.0]), np.array([th0]), np.array([w0])
    t_end = float(t_max) if t_max is not None else 100.0 * revs * TWO_PI / scale + 10.0

    def rhs(_t, y):
        return [y[1], accel(y[0], y[1])]

    def stall(_t, y):
        return y[1]
    stall.terminal, stall.direction = True, -1

    def done(_t, y):
        return y[0] - th0 - TWO_PI * revs
    done.terminal, done.direction = True, 1

    with warnings.catch_warnings():  # lsoda's own: a failure is sol.status, said below
        warnings.simplefilter("ignore")
        sol = solve_ivp(rhs, (0.0, t_end), [th0, w0], method=method, rtol=rtol,
                        atol=[atol, atol], events=[stall, done], dense_output=True)
    if sol.status == -1:
        raise SimulationError(f"simulate: solve_ivp failed ({sol.message})")
    t_stop = float(sol.t[-1])
    made = (float(sol.y[0, -1]) - th0) / TWO_PI
    n = max(2, int(math.ceil(per_rev * max(abs(made), 1.0 / per_rev)))) + 1
    t = np.linspace(0.0, t_stop, n)
    y = sol.sol(t)
    y[:, -1] = sol.y[:, -1]
    if len(sol.t_events[0]) and (not len(sol.t_events[1])
                                 or sol.t_events[0][0] <= sol.t_events[1][0]):
        result.stalled, result.finished = True, False
        result.message = (f"stalled: the crank stopped at THETA 2 = "
                          f"{math.degrees(float(sol.y[0, -1])):.6g} deg after "
                          f"{t_stop:.6g} s and {made:.4g} revolutions; the motor cannot "
                          "carry the linkage over it (it would turn back)")
    elif len(sol.t_events[1]):
        result.message = (f"{revs:g} revolution{'' if revs == 1 else 's'} in {t_stop:.6g} s; "
                          "the crank speed ended "
                          f"at {float(sol.y[1, -1]):.6g} rad/sec")
    else:
        result.finished = False
        result.message = (f"stopped at t_max = {t_end:.6g} s after {made:.4g} of "
                          f"{revs:g} revolutions (the crank barely turns)")
    return t, y[0], y[1]


def _at_times(accel, solve_ivp, th0, w0, ts, method, rtol, atol, result):
    """Integrate in time from (th0, w0) at t = 0 to the last of ``ts``, through stops and
    reversals (the crank at rest is a state like any other here), sampled at ``ts``."""
    def rhs(_t, y):
        return [y[1], accel(y[0], y[1])]

    def turn(_t, y):  # counted, not terminal: where the crank stops and turns back
        return y[1]

    with warnings.catch_warnings():  # lsoda's own: a failure is sol.status, said below
        warnings.simplefilter("ignore")
        sol = solve_ivp(rhs, (0.0, float(ts[-1])), [th0, w0], method=method, rtol=rtol,
                        atol=[atol, atol], events=[turn], dense_output=True)
    if sol.status == -1:
        raise SimulationError(f"simulate: solve_ivp failed ({sol.message})")
    y = sol.sol(ts)
    y[:, -1] = sol.y[:, -1]
    if ts[0] == 0.0:
        y[:, 0] = (th0, w0)
    stops = len(sol.t_events[0])
    lo, hi = (math.degrees(float(f(y[0]))) for f in (np.min, np.max))
    made = (float(y[0, -1]) - th0) / TWO_PI
    result.message = (f"{len(ts)} states from t = {ts[0]:.6g} to {ts[-1]:.6g} s: THETA 2 "
                      f"from {lo:.6g} to {hi:.6g} deg, "
                      + (f"the crank stopped and turned back {stops} time"
                         f"{'s' if stops != 1 else ''}" if stops else
                         f"{made:.4g} revolutions")
                      + f"; the crank speed ended at {float(y[1, -1]):.6g} rad/sec")
    return ts, y[0], y[1]


#: The steady-state search steps its speed by this factor, at most STEADY_STEPS times each
#: way (1.3^80: nine decades above or below the guess).
STEADY_FACTOR, STEADY_STEPS = 1.3, 80


def _bracket(f, w0, brentq, rtol):
    """The start speed of the periodic motion: a zero of f (the speed a revolution gains,
    None where the crank stalls within it), bracketed from the guess ``w0`` either way.

    A revolution gains, loses, stalls, or changes the speed by no more than the
    integration resolves (``100 rtol w``: flat).  A gain or a stall (too slow to pass the
    hump) says "faster", a loss "slower"; the search steps by :data:`STEADY_FACTOR` that
    way until the sign turns, then solves between a gain and a loss.  A zero is never
    taken from a flat revolution alone: a motor that gains a little every revolution at
    a high speed has no steady state, whatever the last digits of an integration say.
    """
    k = STEADY_FACTOR

    def kind(v, w):
        if v is None:
            return "stall"
        noise = 100.0 * rtol * w
        return "gain" if v > noise else "loss" if v < -noise else "flat"

    def solve(lo, hi):
        return brentq(lambda x: f(x) or 0.0, lo, hi, xtol=1e-13 * hi,
                      rtol=4.0 * np.finfo(float).eps)

    c0 = kind(f(w0), w0)
    up = c0 in ("gain", "stall")
    if c0 == "flat":  # at the steady state already, or where f cannot tell: look around
        below, above = kind(f(w0 / k), w0 / k), kind(f(w0 * k), w0 * k)
        if below == "gain" and above == "loss":
            return solve(w0 / k, w0 * k)
        up = above in ("gain", "flat", "stall")
    gained = w0 if c0 == "gain" else None
    w = w0
    for _ in range(STEADY_STEPS):
        nxt = w * k if up else w / k
        c = kind(f(nxt), nxt)
        if up and c == "gain":
            gained = nxt
        elif up and c == "loss":
            if gained is None:
                raise SimulationError(
                    f"steady: no periodic steady state: below {w:.6g} rad/sec the crank "
                    f"stalls within a revolution and from {nxt:.6g} rad/sec it slows down")
            return solve(gained, nxt)
        elif not up and c == "stall":
            raise SimulationError(
                f"steady: no periodic steady state: the crank slows down from every speed "
                f"down to {w:.6g} rad/sec, and below it stalls within a revolution; the "
                "motor cannot carry the linkage")
        elif not up and c == "gain":
            return solve(nxt, w)
        w = nxt
    if up:
        raise SimulationError(
            f"steady: no periodic steady state: the crank gains speed every revolution from "
            f"{w0:.6g} up to {w:.6g} rad/sec, or changes it by less than the integration "
            "resolves (the motor's torque never falls to what the linkage takes)")
    raise SimulationError(f"steady: no periodic steady state: the crank slows down every "
                          f"revolution from {w0:.6g} down to {w:.6g} rad/sec")


def _steady(accel, solve_ivp, brentq, th0, w0, per_rev, method, rtol, atol):
    """One revolution of the periodic motion through th0: shooting on its speed."""
    def rev(w_start, dense=False):
        floor = 1e-6 * abs(w_start)

        def rhs(th, y):
            return [1.0 / y[1], accel(th, y[1]) / y[1]]

        def slow(_th, y):
            return y[1] - floor
        slow.terminal, slow.direction = True, -1
        with warnings.catch_warnings():  # a failed revolution is status != 0: None
            warnings.simplefilter("ignore")
            sol = solve_ivp(rhs, (th0, th0 + TWO_PI), [0.0, w_start], method=method,
                            rtol=rtol, atol=[atol, atol], events=[slow], dense_output=dense)
        if sol.status != 0:
            return None
        return sol

    def f(w_start):
        sol = rev(w_start)
        return None if sol is None else float(sol.y[1, -1]) - w_start

    if not w0 > 0.0:
        raise SimulationError(f"steady: speed0 = {w0:g} rad/sec: give a positive guess of "
                              "the mean speed")
    ws = _bracket(f, w0, brentq, rtol)
    sol = rev(ws, dense=True)
    if sol is None:
        raise SimulationError(f"steady: the crank stalls from {ws:.6g} rad/sec")
    th = th0 + np.linspace(0.0, TWO_PI, per_rev + 1)
    y = sol.sol(th)
    y[:, -1] = sol.y[:, -1]
    return y[0], th, y[1]
