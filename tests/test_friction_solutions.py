"""Every solution of the pin-friction law, the continuous one taken, self-locking only
where none exists (issue 32, item 7; engine/friction_solve.py).

The counts are checked against an independent solve that shares nothing with the engine
but the frictionless pin forces: the law written as three polynomials in the pins' force
magnitudes (|FA32|, |FB34|, |FOB|), solved exactly by a Groebner basis (sympy, an outside
tool), its real non-negative roots counted.  The chosen solution is checked against the
law written here again, for continuity as mu r grows from 0, and, where the continuous
one is lost, for the least friction among the polynomial solve's roots (each pin's own
mu r with its own force).
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


def _frictionless(m, th, scene=None):
    r = analyze(m, np.atleast_1d(th), NAMES + ["ATH3", "ATH4", "TH3D", "TH4D"], scene=scene)
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


def law_roots(u, v, d, signs, murs, f0) -> list[np.ndarray]:
    """Every solution x (the force the couples add to FB34) of the law with the pieces
    ``u``, ``v``, ``d``, the signs (A, B, O4) and each pin's mu r (``murs``: O2, A, B, O4;
    the crank's couple reaches no pin force), ``f0`` the frictionless FA32, FB34, FOB (x,
    y each): the real roots with |F| >= 0 of three polynomials in nA, nB, nD (Groebner,
    lex)."""
    sp = pytest.importorskip("sympy")
    sa, sb, s4 = signs
    R = sp.Rational
    _, ka, kb, kd = (R(k) for k in murs)
    nA, nB, nD = sp.symbols("nA nB nD")
    m3 = int(sb) * kb * nB - int(sa) * ka * nA
    m4 = -int(sb) * kb * nB - int(s4) * kd * nD
    x = [-(R(u[i]) * m4 + R(v[i]) * m3) / R(d) for i in range(2)]
    a0, b0, d0 = ([R(f0[2 * j]), R(f0[2 * j + 1])] for j in range(3))
    eqs = [sp.expand(nA**2 - (a0[0] - x[0])**2 - (a0[1] - x[1])**2),
           sp.expand(nB**2 - (b0[0] + x[0])**2 - (b0[1] + x[1])**2),
           sp.expand(nD**2 - (d0[0] + x[0])**2 - (d0[1] + x[1])**2)]
    basis = sp.groebner(eqs, nA, nB, nD, order="lex")
    last = basis.exprs[-1]
    assert last.free_symbols <= {nD}
    found = []
    for root in sp.Poly(last, nD).nroots(n=30, maxsteps=200):
        if abs(sp.im(root)) > 1e-12 * (1 + abs(root)) or sp.re(root) < 0:
            continue
        rest = [e.subs(nD, sp.re(root)) for e in basis.exprs[:-1]]
        for sol in sp.solve(rest, [nA, nB], dict=True):
            a, b = complex(sol[nA]), complex(sol[nB])
            if all(abs(z.imag) <= 1e-9 * (1 + abs(z)) and z.real >= -1e-9 for z in (a, b)):
                at = {nA: a.real, nB: b.real, nD: float(sp.re(root))}
                found.append(np.array([float(xi.subs(at)) for xi in x]))
    return found


def sympy_solutions(m, th, murs, scene=None) -> list[np.ndarray]:
    """:func:`law_roots` at the crank angle ``th`` of ``m`` (``scene``: the frictionless
    forces', its friction left out)."""
    g = _frictionless(m, th, None if scene is None else scene.replace(friction=None))
    u, v, d, signs = _law(m, g, 0.0)
    f0 = [g[n] for n in ("FA32X", "FA32Y", "FB34X", "FB34Y", "FOBX", "FOBY")]
    return law_roots(u, v, d, signs, murs, f0)


def sympy_count(m, th, mur) -> int:
    """How many solutions the law has with mu r ``mur`` at every pin."""
    return len(sympy_solutions(m, th, (mur,) * 4))


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


#: Laws where the continuous solution is lost and the least friction decides between
#: solutions whose order changes if a pin's mu r is paired with another pin's force:
#: found among 20,000 laws drawn with numpy's default_rng(7) (f0 normal, sd 100; th3
#: uniform; th3 - th4 within 0.6 rad; R3 = 4, R4 = 3; mu r as KS), kept as data.
KS = (0.3, 2.5, 0.2, 1.7)
CHOICES = [
    ((57.66895836701853, 28.480775264621577, -80.16596836034115, -124.62410894132057,
      71.00223692588015, 97.2829324019791, 47.87313605278302, -90.8385489255954),
     (-1.0, 1.0, -1.0, -1.0), 3.6981925872668358, 3.377520895534341),
    ((114.89027416429072, 113.04614365058887, 128.20159354123427, 81.74118295419855,
      -89.24565255157155, -43.73548479909915, -184.51102907333694, -112.27985270741965),
     (1.0, -1.0, -1.0, 1.0), 3.7960319956987942, 3.875902569929621),
    ((-103.68485607757371, 87.13349613191373, 130.97543938962113, 178.10016458761143,
      -82.29279121256694, 5.9649639162590615, 131.22317623171392, -89.54972904830825),
     (-1.0, -1.0, -1.0, 1.0), 2.020817469417825, 1.9422737558858185)]


@pytest.mark.parametrize("case", range(len(CHOICES)))
def test_not_reached_from_mu_zero_the_least_friction_is_taken(case):
    """FRICTION_STATUS 3: of every solution the polynomial solve finds, the one
    friction_solve.solve takes has the least friction, the sum over the four pins of
    each pin's own mu r times its own force (FOA = FOA_0 - x, FA32 = FA32_0 - x, FB34 =
    FB34_0 + x, FOB = FOB_0 + x); the draw's laws are ones where pairing a pin's mu r
    with another pin's force would choose another solution (counted)."""
    from sielaff.engine.friction_solve import solve

    f0, sg, a3, a4 = CHOICES[case]
    R3, R4 = 4.0, 3.0
    arr = [np.array([x]) for x in (R3, R4, np.cos(a3), np.sin(a3), np.cos(a4), np.sin(a4),
                                   np.sin(a3 - a4))]
    x0, x1, count, status = solve(tuple(np.array([f]) for f in f0), KS,
                                  tuple(np.array([s]) for s in sg), *arr)
    assert status[0] == 3.0
    u = R3 * np.array([np.cos(a3), np.sin(a3)])
    v = R4 * np.array([np.cos(a4), np.sin(a4)])
    roots = law_roots(u, v, np.sin(a3 - a4) * R3 * R4, sg[1:], KS, f0[:4] + f0[6:])
    assert len(roots) == count[0] >= 2

    def friction(x, pins):
        at = {"FA32": (0, -1.0), "FB34": (2, 1.0), "FOA": (4, -1.0), "FOB": (6, 1.0)}
        return sum(k * np.hypot(f0[at[p][0]] + at[p][1] * x[0], f0[at[p][0] + 1]
                                + at[p][1] * x[1]) for k, p in zip(KS, pins, strict=True))

    best = min(roots, key=lambda x: friction(x, ("FOA", "FA32", "FB34", "FOB")))
    other = min(roots, key=lambda x: friction(x, ("FA32", "FB34", "FOA", "FOB")))
    assert np.hypot(*(best - other)) > 1e-3 * np.hypot(*best)  # the draw discriminates
    assert np.hypot(x0[0] - best[0], x1[0] - best[1]) <= 1e-8 * (1.0 + np.hypot(*best))
