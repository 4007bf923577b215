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
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["contraction", "solve"]

#: Continuation steps from mu = 0 to mu, Newton steps per continuation step.
STEPS, STEP_NEWTON = 16, 5
#: Newton steps from each start of the search for every solution.
NEWTON = 60
#: Directions and magnitudes of the starts (magnitudes 1e-4 .. 1e8 times the scale).
DIRECTIONS, MAGNITUDES = 64, 25


def contraction(k: tuple[Any, Any, Any, Any], R3: Any, R4: Any, s34: Any) -> Any:
    """s of the module doc: below 1 the law has exactly one solution [-]."""
    _, ka, kb, kd = k
    with np.errstate(divide="ignore", invalid="ignore"):
        return (R3 * (kb + kd) + R4 * (ka + kb)) / np.abs(s34 * R3 * R4)


def _parts(x, f0, k, sg, u, v, d, lam):
    """H(x) and its Jacobian, for positions along the first axis; x has shape (..., 2)."""
    fa, fb, fd = f0[0] - x, f0[1] + x, f0[3] + x  # FA32, FB34, FOB with the couples
    ka, kb, kd = lam * k[1], lam * k[2], lam * k[3]
    na, nb, nd = (np.hypot(f[..., 0], f[..., 1]) for f in (fa, fb, fd))
    ta, tb, td = ka * na, kb * nb, kd * nd
    s1, s2, s3 = sg[1], sg[2], sg[3]
    m3 = s2 * tb - s1 * ta
    m4 = -s2 * tb - s3 * td
    h = x + (u * m4[..., None] + v * m3[..., None]) / d[..., None]

    def unit(f, n):
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(n[..., None] > 0.0, f / n[..., None], 0.0)

    dta = -ka[..., None] * unit(fa, na) if np.ndim(ka) else -ka * unit(fa, na)
    dtb = (kb[..., None] if np.ndim(kb) else kb) * unit(fb, nb)
    dtd = (kd[..., None] if np.ndim(kd) else kd) * unit(fd, nd)
    dm3 = s2[..., None] * dtb - s1[..., None] * dta
    dm4 = -s2[..., None] * dtb - s3[..., None] * dtd
    jac = np.zeros(x.shape[:-1] + (2, 2))
    jac[..., 0, 0] = jac[..., 1, 1] = 1.0
    jac += (u[..., :, None] * dm4[..., None, :] + v[..., :, None] * dm3[..., None, :]) \
        / d[..., None, None]
    return h, jac


def _newton_step(x, h, jac):
    det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
    with np.errstate(invalid="ignore", divide="ignore"):
        dx0 = (jac[..., 1, 1] * h[..., 0] - jac[..., 0, 1] * h[..., 1]) / det
        dx1 = (-jac[..., 1, 0] * h[..., 0] + jac[..., 0, 0] * h[..., 1]) / det
    return x - np.stack([dx0, dx1], axis=-1), det


def solve(f0: list[np.ndarray], k: tuple[Any, Any, Any, Any], sg: list[np.ndarray],
          R3: np.ndarray, R4: np.ndarray, c3: np.ndarray, s3: np.ndarray, c4: np.ndarray,
          s4: np.ndarray, s34: np.ndarray, count_all: bool = False
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """At each of m positions: (x, count, status) with x (m, 2) the chosen solution (NaN
    where none), count the solutions found and status 0 (continuous from mu = 0), 3 (not
    reached from mu = 0: the least-friction one) or 2 (none: self-locking).  The search
    for every solution runs where the continuation fails, and everywhere with
    ``count_all`` (else count is NaN where the continuous one was found).

    Parameters
    ----------
    f0 : list of 4 arrays (m, 2)
        The frictionless FA32, FB34, FOA, FOB [lb or N].
    k : 4 numbers
        mu r at O2, A, B, O4 [in or m].
    sg : list of 4 arrays (m,)
        The signs of the relative rotations at O2, A, B, O4 [-].
    R3, R4, c3, s3, c4, s4, s34 : arrays (m,)
        The coupler's and rocker's lengths [in or m] and the cosines and sines of their
        angles and of th3 - th4 [-].
    """
    m = s34.shape[0]
    u = np.stack([R3 * c3, R3 * s3], axis=-1)
    v = np.stack([R4 * c4, R4 * s4], axis=-1)
    d = s34 * R3 * R4
    scale = np.max([np.hypot(f[:, 0], f[:, 1]) for f in f0], axis=0) + 1e-300
    tol = 1e-9  # |H| relative to the forces: what Newton reaches near a toggle, too
    # the continuous solution: from x = 0 at mu = 0
    x = np.zeros((m, 2))
    alive = np.ones(m, dtype=bool)
    for j in range(1, STEPS + 1):
        lam = j / STEPS
        for _ in range(STEP_NEWTON):
            h, jac = _parts(x, f0, k, sg, u, v, d, lam)
            x, det = _newton_step(x, h, jac)
            alive &= np.isfinite(x).all(axis=-1) & (det > 0.0)
        h, _ = _parts(x, f0, k, sg, u, v, d, lam)
        alive &= np.hypot(h[:, 0], h[:, 1]) <= tol * (scale + np.hypot(x[:, 0], x[:, 1]))
        x = np.where(alive[:, None], x, 0.0)
    continuous = np.where(alive[:, None], x, np.nan)
    out = np.full((m, 2), np.nan)
    count = np.full(m, np.nan)
    status = np.full(m, 2.0)
    out[alive], status[alive] = continuous[alive], 0.0
    look = np.flatnonzero(np.ones(m, dtype=bool) if count_all else ~alive)
    if look.size:
        c_, x_, st_ = _search([f[look] for f in f0], k, [g[look] for g in sg], u[look],
                              v[look], d[look], scale[look], continuous[look], alive[look],
                              tol)
        count[look] = c_
        gone = ~alive[look]
        out[look[gone]], status[look[gone]] = x_[gone], st_[gone]
    return out, count, status


def _search(f0, k, sg, u, v, d, scale, continuous, alive, tol):
    """Every solution at each of m positions (see ``solve``): (count, x, status)."""
    m = scale.shape[0]
    # every solution: Newton from many starts (each position's starts along axis 1)
    phi = np.linspace(0.0, 2.0 * np.pi, DIRECTIONS, endpoint=False)
    rho = np.logspace(-4.0, 8.0, MAGNITUDES)
    e = np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    starts = (rho[:, None, None] * e[None, :, :]).reshape(-1, 2)
    xs = scale[:, None, None] * starts[None, :, :]
    xs = np.concatenate([xs, np.nan_to_num(continuous)[:, None, :]], axis=1)
    n_starts = xs.shape[1]

    def tile(a):
        return np.repeat(a, n_starts, axis=0)

    f0_t = [tile(f) for f in f0]
    sg_t = [tile(s) for s in sg]
    u_t, v_t, d_t = tile(u), tile(v), tile(d)
    y = xs.reshape(-1, 2)
    for _ in range(NEWTON):
        h, jac = _parts(y, f0_t, k, sg_t, u_t, v_t, d_t, 1.0)
        y_new, _ = _newton_step(y, h, jac)
        y = np.where(np.isfinite(y_new), y_new, y)
    h, _ = _parts(y, f0_t, k, sg_t, u_t, v_t, d_t, 1.0)
    ok = np.hypot(h[:, 0], h[:, 1]) <= tol * (tile(scale) + np.hypot(y[:, 0], y[:, 1]))
    roots_all = y.reshape(m, n_starts, 2)
    ok = ok.reshape(m, n_starts) & np.isfinite(roots_all).all(axis=-1)
    out = np.full((m, 2), np.nan)
    count = np.zeros(m)
    status = np.full(m, 2.0)
    total = np.full((m, n_starts), np.inf)  # the friction of each converged root
    for j, fk in ((0, k[0]), (1, k[1]), (2, k[2]), (3, k[3])):
        f = f0[j][:, None, :] + (roots_all if j in (1, 3) else -roots_all)
        total = np.where(ok, np.where(np.isinf(total), 0.0, total)
                         + fk * np.hypot(f[..., 0], f[..., 1]), np.inf)
    for i in range(m):
        roots = roots_all[i][ok[i]]
        near = 1e-8 * (scale[i] + np.hypot(roots[:, 0], roots[:, 1]))
        distinct = 0
        while roots.shape[0]:  # merge the roots that agree: as many rounds as solutions
            same = np.hypot(*(roots - roots[0]).T) <= near
            roots, near = roots[~same], near[~same]
            distinct += 1
        count[i] = max(distinct, 1) if alive[i] else distinct
        if alive[i]:
            out[i], status[i] = continuous[i], 0.0
        elif distinct:  # not reached from mu = 0: the one with the least friction
            out[i], status[i] = roots_all[i][int(np.argmin(total[i]))], 3.0
    return count, out, status
