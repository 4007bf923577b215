"""Pin friction in ``simulate``: the equation of motion from tables, not the engine per state.

With Coulomb friction in the pins TORQ is not affine in the crank's acceleration a (the
friction couples grow with |pin force|), so ``simulate``'s J, B, C, D tables do not hold.
What does hold, at each crank angle th, is the structure the engine's friction effect
solves (engine/friction.py):

* the frictionless totals X (the eight pin-force components and TORQ) are
  ``X = P(th) a + B(th) w^2 + C(th) w + D(th)`` (inertia affine in a, quadratic in w;
  dampers linear in w; gravity, loads, TEX, springs constant);
* the friction couples T (O2, A, B, O4) act on links 2-4 as moments m(T, signs), and
  the totals they add are linear in m: ``K(th) m`` (statics, no motion);
* each couple is ``mu r |F|`` of its pin's total force, its sign that of the pin's
  relative rotation, ``sign(w) sign(k(th))`` with k = (1, k3 - 1, k4 - k3, k4) and
  k3 = TH3D / TH2D, k4 = TH4D / TH2D.

So :class:`FrictionTables` reads P, B, C, D, K and k3, k4 from the engine on a grid
(eight analyze calls of one array each), holds them as Fourier series like the
frictionless tables, checks the solve below against the engine's TORQ with friction at
every grid angle (else ``simulate`` falls back to the engine per state), and per state
iterates a and T together to 1e-12 of the torque scale: microseconds, not the engine's
milliseconds.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sielaff.engine.analysis import analyze
from sielaff.engine.friction import PINS, mu_r, rest_sign
from sielaff.engine.loads import Load
from sielaff.engine.scene import Scene
from sielaff.mechanism import Mechanism

#: The totals friction changes, in engine/friction.py's order (pins, then TORQ).
TOTALS = ("FA32X", "FA32Y", "FB34X", "FB34Y", "FOAX", "FOAY", "FOBX", "FOBY", "TORQ")
#: Which totals make each pin's force (O2: FOA, A: FA32, B: FB34, O4: FOB).
PIN_FORCE = {"O2": (4, 5), "A": (0, 1), "B": (2, 3), "O4": (6, 7)}
#: Iterations of the joint solve of a and the couples per state.
MAX_ITER = 200


class FrictionError(ValueError):
    """The joint solve of a and the friction couples did not converge (one line)."""


def _mur(scene: Scene) -> np.ndarray:
    """Each pin's mu r, in the order of PINS (the friction effect's own)."""
    per = mu_r(scene)
    return np.array([per[k] for k in PINS])


def _series(values: np.ndarray) -> np.ndarray | None:
    """Fourier coefficients of rows of ``values`` sampled on an even grid over a
    revolution, or None if the upper half of the spectrum is not below 1e-13 of the top."""
    n = values.shape[-1]
    f = np.fft.rfft(values, axis=-1) * (2.0 / n)
    f[..., 0] *= 0.5
    mag = np.abs(f)
    if not np.all(np.isfinite(mag)):
        return None
    if np.max(mag[..., n // 4:]) > 1e-13 * max(float(np.max(mag)), 1e-300):
        return None
    return f[..., : n // 4 + 1]


def _signs(w, k3, k4) -> list[np.ndarray]:
    """The signs of the pins' relative rotations (O2, A, B, O4), zero at rest as the
    engine's are (engine/friction.py's ``rest_sign``; the rates in units of the crank's,
    k3 = TH3D / TH2D and k4 = TH4D / TH2D)."""
    scale = 1.0 + np.abs(k3) + np.abs(k4)
    sw = np.sign(w)
    return [sw, sw * rest_sign(k3 - 1.0, scale), sw * rest_sign(k4 - k3, scale),
            sw * rest_sign(k4, scale)]


class FrictionTables:
    """P, B, C, D (9 totals), K (9 x 3) and k3, k4 as Fourier series; :meth:`accel`."""

    def __init__(self, mechanism: Mechanism, scene: Scene, scale: float, f_in: float,
                 max_grid: int = 16384) -> None:
        self.ok = False
        self.f_in = f_in
        self.mur = _mur(scene)
        plain = scene.replace(friction=None)
        n = 256
        while n <= max_grid:
            th = np.arange(n) * (360.0 / n)
            rows = self._sample(mechanism, plain, th, scale)
            if rows is None:
                return
            coef = _series(rows)
            if coef is not None:
                self.coef = coef
                self.k = np.arange(coef.shape[-1], dtype=float)
                self.ok = self._check(mechanism, scene, th, scale)
                return
            n *= 2

    @staticmethod
    def _sample(m: Mechanism, plain: Scene, th: np.ndarray, s: float) -> np.ndarray | None:
        """The 65 rows: P, B, C, D for each total (36), K's 27, k3, k4."""
        n = len(th)
        w = np.array([0.0, 0.0, s, -s])[:, None]
        a = np.array([0.0, s * s, 0.0, 0.0])[:, None]
        with np.errstate(all="ignore"):
            r = analyze(m.replace(TH2D=w), np.broadcast_to(th, (4, n)), list(TOTALS),
                        scene=plain.replace(th2dd=a))
            q = np.stack([r[t] for t in TOTALS])  # (9, 4, n)
            d = q[:, 0]
            p = (q[:, 1] - d) / (s * s)
            b = (q[:, 2] + q[:, 3] - 2.0 * d) / (2.0 * s * s)
            c = (q[:, 2] - q[:, 3]) / (2.0 * s)
            base = Scene(branch=plain.branch)
            k_cols = []
            for link in (2, 3, 4):
                unit = analyze(m.replace(TH2D=0.0), th, list(TOTALS),
                               scene=base.replace(loads=[Load(link, torque=1.0)]))
                k_cols.append(np.stack([unit[t] for t in TOTALS]))
            kin = analyze(m.replace(TH2D=1.0), th, ["TH3D", "TH4D"], scene=base)
        rows = np.concatenate([p, b, c, d, *k_cols, kin["TH3D"][None], kin["TH4D"][None]])
        return rows if np.all(np.isfinite(rows)) else None

    def _at(self, theta: np.ndarray) -> np.ndarray:
        """The 65 rows at ``theta`` [rad]: (65, len(theta))."""
        if len(theta) == 1:  # one state (each step): sums, not BLAS (no thread start-up)
            x = self.k * theta[0]
            return ((self.coef.real * np.cos(x)).sum(axis=1)
                    - (self.coef.imag * np.sin(x)).sum(axis=1))[:, None]
        e = np.exp(1j * self.k[:, None] * theta[None, :])
        return (self.coef @ e).real

    def accel(self, theta: Any, w: Any, mt: Any) -> np.ndarray:
        """TH2DD [rad/sec^2] at crank angles ``theta`` [rad], speeds ``w`` [rad/sec] and
        motor torques ``mt`` [in-lb or N m] (arrays), solving a and the couples jointly;
        FrictionError naming the first state that does not converge."""
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        w = np.atleast_1d(np.asarray(w, dtype=float))
        mt = np.atleast_1d(np.asarray(mt, dtype=float))
        return self._solve(self._at(theta), theta, w, mt)[0]

    def _solve(self, v: np.ndarray, theta: np.ndarray, w: np.ndarray, mt: np.ndarray):
        p, b, c, d = v[0:9], v[9:18], v[18:27], v[27:36]
        kmat = v[36:63].reshape(3, 9, -1)  # link 2, 3, 4 -> totals
        k3, k4 = v[63], v[64]
        sg = _signs(w, k3, k4)
        q = b * w * w + c * w + d  # (9, N): the totals but for inertia
        jj = p[8] + self.f_in
        a = (mt - q[8]) / jj
        t = np.zeros((4, len(w)))
        scale = np.maximum(np.abs(mt), np.abs(q[8])) + 1e-300
        for _ in range(MAX_ITER):
            m2 = sg[1] * t[1] - sg[0] * t[0]
            m3 = sg[2] * t[2] - sg[1] * t[1]
            m4 = -sg[2] * t[2] - sg[3] * t[3]
            tot = p * a + q + kmat[0] * m2 + kmat[1] * m3 + kmat[2] * m4
            new = np.stack([self.mur[i] * np.hypot(tot[j], tot[k])
                            for i, (j, k) in enumerate(PIN_FORCE.values())])
            r = mt - self.f_in * a - tot[8]
            change = np.max(np.abs(new - t), axis=0)
            tmax = np.max(new, axis=0)
            t = new
            a = a + r / jj
            if np.all((np.abs(r) <= 1e-12 * scale) & (change <= 1e-12 * tmax)):
                return a, tot
        bad = int(np.argmax(~((np.abs(r) <= 1e-12 * scale) & (change <= 1e-12 * tmax))))
        raise FrictionError(f"the friction solve does not converge at THETA 2 = "
                            f"{np.degrees(theta[bad]) % 360.0:.6g} deg, TH2D = {w[bad]:.6g} "
                            "rad/sec (near a toggle the pin forces grow without bound)")

    def _check(self, m: Mechanism, scene: Scene, th: np.ndarray, s: float) -> bool:
        """Whether the tables' TORQ with friction is the engine's to 1e-9 of its peak at
        every grid angle, at a speed and an acceleration of the run's scale."""
        w, a = 0.83 * s, 0.37 * s * s
        with np.errstate(all="ignore"), _quiet():
            ref = analyze(m.replace(TH2D=w), th, ["TORQ"], scene=scene.replace(th2dd=a))
        ref_t = ref["TORQ"]
        if not np.all(np.isfinite(ref_t)):
            return False
        theta = np.radians(th)
        v = self._at(theta)
        # the totals at the given a: solve the couples with a held (the torque follows)
        got = self._torq_at(v, theta, np.full_like(th, w), np.full_like(th, a))
        peak = max(float(np.max(np.abs(ref_t))), 1e-300)
        # where a relative rotation is zero the sign (and so the couple) is a matter of
        # rounding, in the engine as here (FRICTION_STATUS 1): those angles are skipped
        firm = np.all(np.array(_signs(np.full_like(th, w), v[63], v[64])) != 0.0, axis=0)
        return bool(np.max(np.abs(got - ref_t)[firm], initial=0.0) <= 1e-9 * peak)

    def _torq_at(self, v, theta, w, a) -> np.ndarray:
        """TORQ with friction at given accelerations (the couples iterated, a held)."""
        p, b, c, d = v[0:9], v[9:18], v[18:27], v[27:36]
        kmat = v[36:63].reshape(3, 9, -1)
        k3, k4 = v[63], v[64]
        sg = _signs(w, k3, k4)
        x0 = p * a + b * w * w + c * w + d
        t = np.zeros((4, len(w)))
        for _ in range(MAX_ITER):
            m2 = sg[1] * t[1] - sg[0] * t[0]
            m3 = sg[2] * t[2] - sg[1] * t[1]
            m4 = -sg[2] * t[2] - sg[3] * t[3]
            tot = x0 + kmat[0] * m2 + kmat[1] * m3 + kmat[2] * m4
            new = np.stack([self.mur[i] * np.hypot(tot[j], tot[k])
                            for i, (j, k) in enumerate(PIN_FORCE.values())])
            done = np.max(np.abs(new - t)) <= 1e-13 * max(float(np.max(new)), 1e-300)
            t = new
            if done:
                break
        m2 = sg[1] * t[1] - sg[0] * t[0]
        m3 = sg[2] * t[2] - sg[1] * t[1]
        m4 = -sg[2] * t[2] - sg[3] * t[3]
        return (x0 + kmat[0] * m2 + kmat[1] * m3 + kmat[2] * m4)[8]


class _quiet:
    """Friction's warnings silenced while the tables are checked (a NaN fails the check)."""

    def __enter__(self) -> None:
        import warnings

        self._cm = warnings.catch_warnings()
        self._cm.__enter__()
        warnings.simplefilter("ignore")

    def __exit__(self, *exc: Any) -> None:
        self._cm.__exit__(*exc)
