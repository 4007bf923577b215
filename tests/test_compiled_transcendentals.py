"""The compiled backend's sin, cos and atan2 (engine/kernel_math.py) against mpmath.

compiled.py states: sin and cos within 1 ulp of the correctly rounded value for
|x| <= 4 pi (the kernel takes them of angles in [0, 2 pi)), within 2 ulp for |x| < 2^20;
atan2 within 2 ulp (the division and the octant's shift round before the polynomial);
every input class handled as libm does (infinities, the axes, NaN in NaN out).  Checked
here on drawn arguments, both as the plain Python the kernel inlines (its fma exact, by
fractions) and compiled by numba with the kernel's intrinsics (bit for bit the same);
the polynomials' coefficients are checked to be the fits that
benchmarks/fit_transcendentals.py makes.
"""

from __future__ import annotations

import importlib.util
import inspect
import math
from pathlib import Path

import numpy as np
import pytest

mp = pytest.importorskip("mpmath")

from sielaff.engine import kernel_math as C  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
mp.mp.prec = 130


def _rounded(v) -> float:
    return float(v)  # mpmath rounds to nearest


def _ulps(got: float, exact) -> float:
    """How many ulps ``got`` is from the correctly rounded value of ``exact``."""
    b = _rounded(exact)
    if b == 0.0:
        return 0.0 if got == 0.0 else math.inf
    return abs(got - b) / math.ulp(b)


def _angles(n: int, seed: int) -> np.ndarray:
    """Crank-like arguments: uniform on [0, 2 pi) (the kernel's use: ATH2 in radians),
    near each multiple of pi/4 (the quadrant and octant changes, sin's zeros), large
    ones up to 2^20, and the signed zeros."""
    rng = np.random.default_rng(seed)
    k = rng.integers(-16, 17, n)
    near = k * (math.pi / 4) + rng.normal(size=n) * np.exp(rng.uniform(-40, 0, n))
    return np.concatenate([rng.uniform(0.0, 2 * math.pi, n), near,
                           rng.uniform(-2.0**20, 2.0**20, n // 4),
                           np.radians(np.arange(0.0, 360.0, 0.25)), [0.0, -0.0]])


def _points(n: int, seed: int) -> np.ndarray:
    """(y, x) over 60 decades, near each octant's edge and each breakpoint of the
    reduction (tan(pi/16), tan(3 pi/16)), the axes, infinities and NaN."""
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(n, 2)) * np.exp(rng.uniform(-30, 30, (n, 1)))
    t = np.array([math.tan(math.pi / 16), math.tan(3 * math.pi / 16), 1.0])
    x = np.exp(rng.uniform(-5, 5, n))
    ratio = t[rng.integers(0, 3, n)] * (1.0 + rng.normal(size=n) * 1e-12)
    sx, sy = rng.choice([-1.0, 1.0], n), rng.choice([-1.0, 1.0], n)
    edges = np.stack([sy * x * ratio, sx * x], axis=1)
    swap = rng.random(n) < 0.5
    edges[swap] = edges[swap][:, ::-1]
    special = [[0.0, 1.0], [1.0, 0.0], [0.0, -1.0], [-0.0, -1.0], [-1.0, 0.0], [1.0, 1.0],
               [np.inf, np.inf], [-np.inf, 2.0], [3.0, np.inf], [2.0, -np.inf],
               [np.inf, -np.inf], [1e-300, 1e300], [1e300, 1e-300]]
    return np.concatenate([pts, edges, special])


def _numba_helpers():
    """_sincos and _atan2 compiled by numba with the kernel's intrinsics."""
    numba = pytest.importorskip("numba")
    ns = {k: v for k, v in vars(C).items()
          if k.startswith("_") and isinstance(v, float)}
    ns["math"] = math
    ns["np"] = np
    (ns["_select"], ns["_floor"], ns["_fma"]) = C._intrinsics()
    for f in (C._sincos, C._half_turn, C._atan2):
        exec(inspect.getsource(f), ns)  # noqa: S102
        ns[f.__name__] = numba.njit(ns[f.__name__])

    sincos, atan2 = ns["_sincos"], ns["_atan2"]

    @numba.njit
    def many_sincos(xs, s, c):
        for i in range(xs.size):
            s[i], c[i] = sincos(xs[i])

    @numba.njit
    def many_atan2(ys, xs, a):
        for i in range(xs.size):
            a[i] = atan2(ys[i], xs[i])

    return many_sincos, many_atan2


def test_sin_cos_within_one_ulp():
    xs = _angles(3000, 11)
    edges = np.abs(xs - np.round(xs / (math.pi / 4)) * (math.pi / 4)) < 1e-10
    assert np.sum(edges) >= 1000  # the quadrant and octant edges are drawn
    worst = {"small": 0.0, "large": 0.0}
    for x in xs:
        s, c = C._sincos(float(x))
        X = mp.mpf(float(x))
        k = "small" if abs(x) <= 4 * math.pi else "large"
        worst[k] = max(worst[k], _ulps(s, mp.sin(X)), _ulps(c, mp.cos(X)))
        if x == 0.0:  # (of -0.0, sin is +0.0: the kernel takes it of angles in [0, 360))
            assert s == 0.0 and c == 1.0
    assert worst["small"] <= 1.0 and worst["large"] <= 2.0, worst


def test_atan2_within_two_ulp_and_its_special_cases():
    pts = _points(4000, 12)
    worst = 0.0
    for y, x in pts:
        a, b = C._atan2(float(y), float(x)), math.atan2(y, x)
        if not (math.isfinite(x) and math.isfinite(y)) or x == 0.0 or y == 0.0:
            # infinities and the axes (signed zeros, which mpmath has not): libm's value;
            # the zero vector is not atan2's to decide (its callers give 0)
            assert a == b or (math.isnan(a) and math.isnan(b)) or x == y == 0.0, (y, x, a, b)
            continue
        worst = max(worst, _ulps(a, mp.atan2(mp.mpf(float(y)), mp.mpf(float(x)))))
    assert worst <= 2.0, worst
    nan = C._atan2(math.nan, 1.0), C._atan2(1.0, math.nan)
    assert all(math.isnan(v) for v in nan)


def test_compiled_is_the_python_bit_for_bit():
    many_sincos, many_atan2 = _numba_helpers()
    xs = _angles(2000, 13)
    s, c = np.empty_like(xs), np.empty_like(xs)
    many_sincos(xs, s, c)
    for k in range(xs.size):
        ps, pc = C._sincos(float(xs[k]))
        assert (s[k], c[k]) == (ps, pc), xs[k]
    pts = _points(2000, 14)
    pts = np.concatenate([pts, [[np.nan, 1.0], [1.0, np.nan]]])
    a = np.empty(len(pts))
    many_atan2(np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1]), a)
    for k, (y, x) in enumerate(pts):
        b = C._atan2(float(y), float(x))
        assert a[k] == b or (math.isnan(a[k]) and math.isnan(b)), (y, x, a[k], b)


def test_fma_is_exact():
    """The Python stand-in for the kernel's llvm.fma rounds once (the compiled one is
    the hardware's: test_compiled_is_the_python_bit_for_bit)."""
    rng = np.random.default_rng(15)
    for x, y, z in rng.normal(size=(2000, 3)) * np.exp(rng.uniform(-20, 20, (2000, 3))):
        exact = mp.mpf(float(x)) * mp.mpf(float(y)) + mp.mpf(float(z))
        assert C._fma(float(x), float(y), float(z)) == _rounded(exact)


@pytest.mark.slow  # about ten seconds of mpmath
def test_coefficients_are_the_fits():
    spec = importlib.util.spec_from_file_location(
        "fit_transcendentals", ROOT / "benchmarks" / "fit_transcendentals.py")
    fit = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(fit)
    cases = [("atan", fit._atan_rest, mp.tan(mp.pi / 16), [C._A0, C._A1, C._A2, C._A3, C._A4,
                                                          C._A5, C._A6, C._A7]),
             ("sin", fit._sin_rest, mp.pi / 4, [C._S0, C._S1, C._S2, C._S3, C._S4, C._S5,
                                                C._S6]),
             ("cos", fit._cos_rest, mp.pi / 4, [C._C0, C._C1, C._C2, C._C3, C._C4, C._C5])]
    for name, rest, xmax, used in cases:
        coeffs, _ = fit.fit(rest, 0, xmax * xmax, len(used))
        assert coeffs == used, name
        assert fit.measured_error(name, used, xmax, points=800) < fit.TARGET, name
