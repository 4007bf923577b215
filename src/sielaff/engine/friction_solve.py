"""Every solution of the pin-friction law at a position, by Newton on one 2-vector.

The law (engine/friction.py): each pin's couple is T = mu r |F|, F the pin's force with
the couples' own share in it.  The couples are pure moments on links 2-4, and a pure
moment on link 3 or 4 changes every pin force by the same vector, the force x of link 3
on link 4 it takes (``statics.pins`` with no forces: FB34 and FOB gain x, FA32 and FOA
lose it; the crank's moment m2 reaches only TORQ).  So the law is one equation in x:

    H(x) = x + (u m4(x) + v m3(x)) / d = 0,   u = B - A,  v = B - O4,  d = R3 R4 sin(th3 - th4)

with m3 = sB T_B - sA T_A and m4 = -sB T_B - s4 T_O4 (the couples' moments on links 3 and
4, s the signs of the pins' relative rotations), T_A = kA |FA32_0 - x|, T_B = kB |FB34_0 +
x|, T_O4 = kO4 |FOB_0 + x|, k = mu r.  H is smooth but where a pin force is zero, and its
Jacobian is exact: d|F|/dx = +-F/|F|.

Uniqueness.  |dG/dx| <= s = (R3 (kB + kO4) + R4 (kA + kB)) / |d| for G = x - H: with
s < 1 the law is a contraction, with one solution, which the fixed point finds (the
effect's own iteration, kept bit for bit there).  Where s >= 1 (near a toggle, or mu r
large beside the links) this module looks for all of them:

* **the continuous one**: x followed from the frictionless x = 0 as mu grows from 0 to its
  value (16 steps of Newton on H scaled by lambda), given up where the branch folds (the
  Jacobian's determinant, 1 at mu = 0, reaches 0) or Newton fails;
* **every one**: Newton from 64 directions x 25 magnitudes (1e-4 to 1e8 times the
  frictionless pin forces, and the continuous one), the converged roots merged where
  they agree to 1e-8.  Newton from a dense set of starts is not a proof that none was
  missed; ``tests/test_friction_solutions.py`` checks the counts against an independent
  polynomial solve (sympy) at positions with none, one and several.

The position's answer is the continuous solution where it exists (FRICTION_STATUS 0);
else, if the law has solutions, the one with the least friction (status 3, "not reached
from mu = 0"); else none (status 2: the linkage self-locks there, the results NaN).
``FRICTION_SOLUTIONS`` counts them (1 where s < 1, proved).

One definition for both engines: this is array code (:func:`sielaff.engine.arith.array_code`),
x as its two components, each an array over positions (numpy: the positions where the law
need not contract; the compiled kernel: the one position, an array of one), the search's
starts along the same flat axis.  numba compiles it with its own numpy, so it uses only
what numba has (no ``errstate``: the engine runs its steps with floating-point warnings
off).  :func:`contraction` is a step's own arithmetic (it runs at every position).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sielaff.engine.arith import array_code

__all__ = ["contraction", "solve"]

#: Continuation steps from mu = 0 to mu, Newton steps per continuation step.
STEPS, STEP_NEWTON = 16, 5
#: Newton steps from each start of the search for every solution.
NEWTON = 60
#: Directions and magnitudes of the starts (magnitudes 1e-4 .. 1e8 times the scale).
DIRECTIONS, MAGNITUDES = 64, 25

# the search's starts before scaling: magnitude rho times direction (cos phi, sin phi),
# magnitudes outer, directions inner
_PHI = np.linspace(0.0, 2.0 * np.pi, DIRECTIONS, endpoint=False)
_RHO = np.logspace(-4.0, 8.0, MAGNITUDES)
_START0 = (_RHO[:, None] * np.cos(_PHI)[None, :]).reshape(-1)
_START1 = (_RHO[:, None] * np.sin(_PHI)[None, :]).reshape(-1)


def contraction(k: tuple[Any, Any, Any, Any], R3: Any, R4: Any, s34: Any) -> Any:
    """s of the module doc: below 1 the law has exactly one solution [-]."""
    _, ka, kb, kd = k
    return (R3 * (kb + kd) + R4 * (ka + kb)) / np.abs(s34 * R3 * R4)


@array_code
def _unit(f, n):
    return np.where(n > 0.0, f / n, 0.0)


@array_code
def _parts(x0, x1, f0, k, sg, u0, u1, v0, v1, d, lam):
    """H(x) and its Jacobian (h0, h1, j00, j01, j10, j11) at x = (x0, x1), each an array
    over positions; f0 the eight frictionless pin-force components (FA32, FB34, FOA, FOB),
    sg the four signs, u = (u0, u1), v = (v0, v1)."""
    fa0, fa1 = f0[0] - x0, f0[1] - x1  # FA32, FB34, FOB with the couples
    fb0, fb1 = f0[2] + x0, f0[3] + x1
    fd0, fd1 = f0[6] + x0, f0[7] + x1
    ka, kb, kd = lam * k[1], lam * k[2], lam * k[3]
    na, nb, nd = np.hypot(fa0, fa1), np.hypot(fb0, fb1), np.hypot(fd0, fd1)
    ta, tb, td = ka * na, kb * nb, kd * nd
    s1, s2, s3 = sg[1], sg[2], sg[3]
    m3 = s2 * tb - s1 * ta
    m4 = -s2 * tb - s3 * td
    h0 = x0 + (u0 * m4 + v0 * m3) / d
    h1 = x1 + (u1 * m4 + v1 * m3) / d
    dta0, dta1 = -ka * _unit(fa0, na), -ka * _unit(fa1, na)
    dtb0, dtb1 = kb * _unit(fb0, nb), kb * _unit(fb1, nb)
    dtd0, dtd1 = kd * _unit(fd0, nd), kd * _unit(fd1, nd)
    dm30, dm31 = s2 * dtb0 - s1 * dta0, s2 * dtb1 - s1 * dta1
    dm40, dm41 = -s2 * dtb0 - s3 * dtd0, -s2 * dtb1 - s3 * dtd1
    j00 = 1.0 + (u0 * dm40 + v0 * dm30) / d
    j01 = 0.0 + (u0 * dm41 + v0 * dm31) / d
    j10 = 0.0 + (u1 * dm40 + v1 * dm30) / d
    j11 = 1.0 + (u1 * dm41 + v1 * dm31) / d
    return h0, h1, j00, j01, j10, j11


@array_code
def _newton_step(x0, x1, h0, h1, j00, j01, j10, j11):
    det = j00 * j11 - j01 * j10
    dx0 = (j11 * h0 - j01 * h1) / det
    dx1 = (-j10 * h0 + j00 * h1) / det
    return x0 - dx0, x1 - dx1, det


@array_code
def _at(f, idx):
    """Each array of the tuple ``f`` at ``idx``."""
    if len(f) == 4:
        return (f[0][idx], f[1][idx], f[2][idx], f[3][idx])
    return (f[0][idx], f[1][idx], f[2][idx], f[3][idx], f[4][idx], f[5][idx], f[6][idx],
            f[7][idx])


@array_code
def _tiled(f, n):
    """Each array of the tuple ``f`` with each position repeated ``n`` times."""
    if len(f) == 4:
        return (np.repeat(f[0], n), np.repeat(f[1], n), np.repeat(f[2], n),
                np.repeat(f[3], n))
    return (np.repeat(f[0], n), np.repeat(f[1], n), np.repeat(f[2], n), np.repeat(f[3], n),
            np.repeat(f[4], n), np.repeat(f[5], n), np.repeat(f[6], n), np.repeat(f[7], n))


@array_code
def solve(f0, k, sg, R3, R4, c3, s3, c4, s4, s34, count_all=False):
    """At each of m positions: (x0, x1, count, status) with x = (x0, x1) the chosen
    solution (NaN where none), count the solutions found and status 0 (continuous from
    mu = 0), 3 (not reached from mu = 0: the least-friction one) or 2 (none:
    self-locking).  The search for every solution runs where the continuation fails, and
    everywhere with ``count_all`` (else count is NaN where the continuous one was found).

    Parameters
    ----------
    f0 : tuple of 8 arrays (m,)
        The frictionless FA32X, FA32Y, FB34X, FB34Y, FOAX, FOAY, FOBX, FOBY [lb or N].
    k : 4 numbers
        mu r at O2, A, B, O4 [in or m].
    sg : tuple of 4 arrays (m,)
        The signs of the relative rotations at O2, A, B, O4 [-].
    R3, R4, c3, s3, c4, s4, s34 : arrays (m,)
        The coupler's and rocker's lengths [in or m] and the cosines and sines of their
        angles and of th3 - th4 [-].
    """
    m = s34.shape[0]
    u0, u1 = R3 * c3, R3 * s3
    v0, v1 = R4 * c4, R4 * s4
    d = s34 * R3 * R4
    scale = np.maximum(np.maximum(np.maximum(np.hypot(f0[0], f0[1]), np.hypot(f0[2], f0[3])),
                                  np.hypot(f0[4], f0[5])), np.hypot(f0[6], f0[7])) + 1e-300
    tol = 1e-9  # |H| relative to the forces: what Newton reaches near a toggle, too
    # the continuous solution: from x = 0 at mu = 0
    x0, x1 = np.zeros(m), np.zeros(m)
    alive = np.ones(m, dtype=np.bool_)
    for j in range(1, STEPS + 1):
        lam = j / STEPS
        for _ in range(STEP_NEWTON):
            h0, h1, j00, j01, j10, j11 = _parts(x0, x1, f0, k, sg, u0, u1, v0, v1, d, lam)
            x0, x1, det = _newton_step(x0, x1, h0, h1, j00, j01, j10, j11)
            alive = alive & np.isfinite(x0) & np.isfinite(x1) & (det > 0.0)
        h0, h1, j00, j01, j10, j11 = _parts(x0, x1, f0, k, sg, u0, u1, v0, v1, d, lam)
        alive = alive & (np.hypot(h0, h1) <= tol * (scale + np.hypot(x0, x1)))
        x0, x1 = np.where(alive, x0, 0.0), np.where(alive, x1, 0.0)
    out0, out1 = np.where(alive, x0, np.nan), np.where(alive, x1, np.nan)
    count = np.full(m, np.nan)
    status = np.where(alive, 0.0, 2.0)
    look = np.flatnonzero(~alive | count_all)
    if look.size:
        c_, y0, y1, st_ = _search(_at(f0, look), k, _at(sg, look), u0[look], u1[look],
                                  v0[look], v1[look], d[look], scale[look], out0[look],
                                  out1[look], alive[look], tol)
        count[look] = c_
        gone = ~alive[look]
        out0[look[gone]], out1[look[gone]], status[look[gone]] = y0[gone], y1[gone], st_[gone]
    return out0, out1, count, status


@array_code
def _search(f0, k, sg, u0, u1, v0, v1, d, scale, cont0, cont1, alive, tol):
    """Every solution at each of m positions (see ``solve``): (count, x0, x1, status)."""
    m = scale.shape[0]
    # every solution: Newton from many starts (each position's starts one after another)
    y0 = np.concatenate((scale[:, None] * _START0[None, :],
                         np.where(np.isnan(cont0), 0.0, cont0)[:, None]), axis=1).reshape(-1)
    y1 = np.concatenate((scale[:, None] * _START1[None, :],
                         np.where(np.isnan(cont1), 0.0, cont1)[:, None]), axis=1).reshape(-1)
    n_starts = _START0.size + 1
    f0_t, sg_t = _tiled(f0, n_starts), _tiled(sg, n_starts)
    u0_t, u1_t, v0_t, v1_t, d_t = _tiled((u0, u1, v0, v1), n_starts) + (np.repeat(d, n_starts),)
    for _ in range(NEWTON):
        h0, h1, j00, j01, j10, j11 = _parts(y0, y1, f0_t, k, sg_t, u0_t, u1_t, v0_t, v1_t,
                                            d_t, 1.0)
        n0, n1, _det = _newton_step(y0, y1, h0, h1, j00, j01, j10, j11)
        y0, y1 = np.where(np.isfinite(n0), n0, y0), np.where(np.isfinite(n1), n1, y1)
    h0, h1, j00, j01, j10, j11 = _parts(y0, y1, f0_t, k, sg_t, u0_t, u1_t, v0_t, v1_t, d_t,
                                        1.0)
    ok = (np.hypot(h0, h1) <= tol * (np.repeat(scale, n_starts) + np.hypot(y0, y1))) \
        & np.isfinite(y0) & np.isfinite(y1)
    ok = ok.reshape(m, n_starts)
    r0_all, r1_all = y0.reshape(m, n_starts), y1.reshape(m, n_starts)
    out0, out1 = np.full(m, np.nan), np.full(m, np.nan)
    count = np.zeros(m)
    status = np.full(m, 2.0)
    total = np.full((m, n_starts), np.inf)  # the friction of each converged root
    # FA32 = FA32_0 - x (pin A), FB34 = FB34_0 + x (B), FOA = FOA_0 - x (O2), FOB + x (O4),
    # each with its own pin's mu r (k: O2, A, B, O4)
    for j, pin in enumerate((1, 2, 0, 3)):
        g0, g1 = (r0_all, r1_all) if j % 2 else (-r0_all, -r1_all)
        f = np.hypot(f0[2 * j][:, None] + g0, f0[2 * j + 1][:, None] + g1)
        total = np.where(ok, np.where(np.isinf(total), 0.0, total) + k[pin] * f, np.inf)
    for i in range(m):
        r0, r1 = r0_all[i][ok[i]], r1_all[i][ok[i]]
        near = 1e-8 * (scale[i] + np.hypot(r0, r1))
        distinct = 0
        while r0.shape[0]:  # merge the roots that agree: as many rounds as solutions
            other = ~(np.hypot(r0 - r0[0], r1 - r1[0]) <= near)
            r0, r1, near = r0[other], r1[other], near[other]
            distinct += 1
        count[i] = max(distinct, 1) if alive[i] else distinct
        if alive[i]:
            out0[i], out1[i], status[i] = cont0[i], cont1[i], 0.0
        elif distinct:  # not reached from mu = 0: the one with the least friction
            best = np.argmin(total[i])
            out0[i], out1[i], status[i] = r0_all[i, best], r1_all[i, best], 3.0
    return count, out0, out1, status
