"""Every solution of the pin-friction law, the continuous one taken, self-locking only
where none exists (issue 32, item 7; engine/friction_solve.py).

The counts are checked against an independent solve that shares nothing with the engine
but the frictionless pin forces: the law written as three polynomials in the pins' force
magnitudes (|FA32|, |FB34|, |FOB|), solved exactly by a Groebner basis (sympy, an outside
tool), its real non-negative roots counted.  The chosen solution is checked against the
law written here again, and for continuity as mu r grows from 0.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from sielaff import EXAMPLE, PinFriction, Scene, analyze
from sielaff.engine.friction import FrictionWarning
from sielaff.engine.positions import reachable

#: The bench's double rocker (R = 12, 9, 16, 12): friction mu r = 0.3 near its toggles.
ROCKER = EXAMPLE.replace(R2=9.0)
MUR = 0.3
FRICTION = Scene(friction=PinFriction(0.3, 1.0))
NAMES = ["FA32X", "FA32Y", "FB34X", "FB34Y", "FOAX", "FOAY", "FOBX", "FOBY"]


def _frictionless(m, th):
    r = analyze(m, np.atleast_1d(th), NAMES + ["ATH3", "ATH4", "TH3D", "TH4D"])
    return {k: float(v[0]) for k, v in r.items()}


def _law(m, g, mur):
    """The law's pieces at a position (the frictionless forces g): u, v, d and the signs."""
    a3, a4 = np.radians(g["ATH3"]), np.radians(g["ATH4"])
    u = np.array([m.R3 * np.cos(a3), m.R3 * np.sin(a3)])
    v = np.array([m.R4 * np.cos(a4), m.R4 * np.sin(a4)])
    d = np.sin(a3 - a4) * m.R3 * m.R4
    sa, sb, s4 = (np.sign(g["TH3D"] - m.TH2D), np.sign(g["TH4D"] - g["TH3D"]),
                  np.sign(g["TH4D"]))
    return u, v, d, (sa, sb, s4)


def sympy_count(m, th, mur) -> int:
    """Real roots with |F| >= 0 of the law as polynomials in nA, nB, nD (Groebner, lex)."""
    sp = pytest.importorskip("sympy")
    g = _frictionless(m, th)
    u, v, d, (sa, sb, s4) = _law(m, g, mur)
    R = sp.Rational
    k = R(mur)
    nA, nB, nD = sp.symbols("nA nB nD")
    m3 = int(sb) * k * nB - int(sa) * k * nA
    m4 = -int(sb) * k * nB - int(s4) * k * nD
    x = [-(R(u[i]) * m4 + R(v[i]) * m3) / R(d) for i in range(2)]
    a0 = [R(g["FA32X"]), R(g["FA32Y"])]
    b0 = [R(g["FB34X"]), R(g["FB34Y"])]
    d0 = [R(g["FOBX"]), R(g["FOBY"])]
    eqs = [sp.expand(nA**2 - (a0[0] - x[0])**2 - (a0[1] - x[1])**2),
           sp.expand(nB**2 - (b0[0] + x[0])**2 - (b0[1] + x[1])**2),
           sp.expand(nD**2 - (d0[0] + x[0])**2 - (d0[1] + x[1])**2)]
    basis = sp.groebner(eqs, nA, nB, nD, order="lex")
    last = basis.exprs[-1]
    assert last.free_symbols <= {nD}
    found = 0
    for root in sp.Poly(last, nD).nroots(n=30, maxsteps=200):
        if abs(sp.im(root)) > 1e-12 * (1 + abs(root)) or sp.re(root) < 0:
            continue
        rest = [e.subs(nD, sp.re(root)) for e in basis.exprs[:-1]]
        for sol in sp.solve(rest, [nA, nB], dict=True):
            a, b = complex(sol[nA]), complex(sol[nB])
            if all(abs(z.imag) <= 1e-9 * (1 + abs(z)) and z.real >= -1e-9 for z in (a, b)):
                found += 1
    return found


@pytest.fixture(scope="module")
def rocker():
    th = reachable(ROCKER, 3600)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = analyze(ROCKER, th, ["FRICTION_STATUS", "FRICTION_SOLUTIONS", "TORQ", "FB34X",
                                 "FB34Y", "FA32X", "FA32Y", "FOBX", "FOBY"], scene=FRICTION)
    return th, r, [str(w.message) for w in caught if w.category is FrictionWarning]


def test_the_counts_are_the_polynomial_system_s(rocker):
    """One position with no solution, one with one and one with two."""
    th, r, _ = rocker
    for want in (0, 1, 2):
        hit = np.flatnonzero(r["FRICTION_SOLUTIONS"] == want)
        assert hit.size, want
        assert sympy_count(ROCKER, th[hit[0]], MUR) == want, (th[hit[0]], want)


@pytest.mark.slow  # a Groebner basis a position, some 2 s each
def test_every_self_locking_position_has_no_solution(rocker):
    th, r, _ = rocker
    locked = np.flatnonzero(r["FRICTION_STATUS"] == 2.0)
    assert locked.size >= 2
    for i in locked:
        assert sympy_count(ROCKER, th[i], MUR) == 0, th[i]


def test_self_locking_only_where_none_exists(rocker):
    _, r, messages = rocker
    locked = r["FRICTION_STATUS"] == 2.0
    assert locked.any() and np.all(r["FRICTION_SOLUTIONS"][locked] == 0)
    assert np.all(np.isnan(r["TORQ"][locked])) and np.all(np.isfinite(r["TORQ"][~locked]))
    assert np.all(r["FRICTION_SOLUTIONS"][~locked] >= 1)
    assert len(messages) == 1 and f"{int(locked.sum())} have no solution" in messages[0]


def _moderate(r):
    """Positions whose pin forces are physical (below 1e9 lb): not the ones so close to a
    toggle that double precision has no digit of them left."""
    return np.hypot(r["FB34X"], r["FB34Y"]) < 1e9


def test_the_chosen_solution_satisfies_the_law(rocker):
    """x = FB34 - FB34_0 (the couples' share) makes H(x) = 0, H written here again."""
    th, r, _ = rocker
    several = np.flatnonzero((r["FRICTION_SOLUTIONS"] >= 2) & _moderate(r))[:5]
    assert several.size
    for i in several:
        g = _frictionless(ROCKER, th[i])
        u, v, d, (sa, sb, s4) = _law(ROCKER, g, MUR)
        fa = np.array([r["FA32X"][i], r["FA32Y"][i]])
        fb = np.array([r["FB34X"][i], r["FB34Y"][i]])
        fd = np.array([r["FOBX"][i], r["FOBY"][i]])
        x = fb - np.array([g["FB34X"], g["FB34Y"]])
        ta, tb, td = (MUR * np.hypot(*f) for f in (fa, fb, fd))
        m3, m4 = sb * tb - sa * ta, -sb * tb - s4 * td
        h = x + (u * m4 + v * m3) / d
        assert np.hypot(*h) <= 1e-8 * np.hypot(*fb), th[i]


def test_the_chosen_solution_is_the_one_continuous_from_mu_zero(rocker):
    """Where the law has two solutions, the one taken moves smoothly as mu r grows from
    0 to its value: each step's TORQ differs from the last by a small share."""
    th, r, _ = rocker
    i = int(np.flatnonzero((r["FRICTION_SOLUTIONS"] >= 2) & (r["FRICTION_STATUS"] == 0)
                           & _moderate(r))[0])
    torqs = []
    for lam in np.linspace(0.05, 1.0, 20):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", FrictionWarning)
            torqs.append(float(analyze(ROCKER, th[i], ["TORQ"], scene=Scene(
                friction=PinFriction(0.3 * lam, 1.0)))["TORQ"]))
    base = float(analyze(ROCKER, th[i], ["TORQ"])["TORQ"])
    steps = np.abs(np.diff([base] + torqs))
    assert np.all(np.isfinite(torqs)) and steps.max() <= 0.2 * np.abs(torqs).max()


def test_where_the_law_is_a_contraction_it_has_one_solution():
    """The friction deck's example (mu r = 0.025): one solution everywhere, taken by the
    fixed point as before (its iterations counted)."""
    r = analyze(EXAMPLE, np.arange(0.0, 360.0, 5.0), ["FRICTION_SOLUTIONS",
                                                       "FRICTION_ITERATIONS"],
                scene=Scene(friction=PinFriction(0.1, 0.25)))
    assert np.all(r["FRICTION_SOLUTIONS"] == 1.0) and np.all(r["FRICTION_ITERATIONS"] > 0)
