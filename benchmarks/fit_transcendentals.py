"""The polynomial coefficients of the compiled backend's sin, cos and atan (engine/compiled.py).

Run from the repository root::

    python benchmarks/fit_transcendentals.py

Each polynomial is a Chebyshev fit (``mpmath.chebyfit``, 200-bit arithmetic: near the
minimax polynomial of its degree) of the part of the function past its leading terms, on
the interval the kernel reduces its argument to:

* atan(u) = u + u w A(w), w = u^2, |u| <= tan(pi/16) (the kernel shifts by atan 0,
  atan tan(pi/8) or atan 1 first);
* sin(r) = r + r z S(z), cos(r) = 1 - z/2 + z^2 C(z), z = r^2, |r| <= pi/4 (after the
  Cody-Waite reduction by multiples of pi/2).

The coefficients are rounded to doubles, and the error of the polynomial with the rounded
coefficients (evaluated exactly) is measured on a dense grid, relative to the function's
size (|u| for atan, |r| for sin, cos for cos); each printed error is what the kernel's
polynomial adds before its own rounding, a small part of an ulp (2.2e-16 relative).  The
degrees are the smallest whose error is below TARGET (1e-17, a twentieth of an ulp).
compiled.py quotes these coefficients; ``tests/test_compiled_transcendentals.py`` checks
the kernel's functions against mpmath on drawn arguments.
"""

from __future__ import annotations

import mpmath as mp

mp.mp.prec = 200

TARGET = mp.mpf("1e-17")


def _atan_rest(w):
    if w == 0:
        return mp.mpf(-1) / 3
    u = mp.sqrt(w)
    return (mp.atan(u) - u) / (u * w)


def _sin_rest(z):
    if z == 0:
        return mp.mpf(-1) / 6
    r = mp.sqrt(z)
    return (mp.sin(r) - r) / (r * z)


def _cos_rest(z):
    if z == 0:
        return mp.mpf(1) / 24
    r = mp.sqrt(z)
    return (mp.cos(r) - 1 + z / 2) / (z * z)


def _horner(coeffs, x):
    """coeffs lowest first, evaluated exactly (200 bits)."""
    acc = mp.mpf(0)
    for c in reversed(coeffs):
        acc = acc * x + c
    return acc


def fit(rest, lo, hi, terms):
    """(double coefficients lowest first, their Chebyshev fit's error estimate)."""
    poly, err = mp.chebyfit(rest, [lo, hi], terms, error=True)
    return [float(c) for c in reversed(poly)], err


def measured_error(name, coeffs, xmax, points=4001):
    """The largest error, relative to the function's size, over a grid of |x| <= xmax."""
    worst = mp.mpf(0)
    for k in range(points + 1):
        x = xmax * mp.mpf(k) / points
        if x == 0:
            continue
        z = x * x
        p = _horner([mp.mpf(c) for c in coeffs], z)
        if name == "atan":
            err = abs(x + x * z * p - mp.atan(x)) / x
        elif name == "sin":
            err = abs(x + x * z * p - mp.sin(x)) / x
        else:
            err = abs(1 - z / 2 + z * z * p - mp.cos(x)) / mp.cos(x)
        worst = max(worst, err)
    return worst


def main() -> None:
    cases = [("atan", _atan_rest, mp.tan(mp.pi / 16)), ("sin", _sin_rest, mp.pi / 4),
             ("cos", _cos_rest, mp.pi / 4)]
    for name, rest, xmax in cases:
        for terms in range(4, 13):
            coeffs, _ = fit(rest, 0, xmax * xmax, terms)
            err = measured_error(name, coeffs, xmax)
            if err < TARGET:
                break
        print(f"{name}: {terms} coefficients on |x| <= {mp.nstr(xmax, 17)}, largest error "
              f"relative to the function {mp.nstr(err, 3)} (below {mp.nstr(TARGET, 2)})")
        print("    (" + ",\n     ".join(repr(c) for c in coeffs) + ")")


if __name__ == "__main__":
    main()
