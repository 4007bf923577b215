"""Pin friction compiled (``backend="numba"``) from the numpy engine's own step.

engine/friction.py's steps are one definition for both engines (its fixed point an
iterated step, engine/iterate.py: compacted over arrays, passes over a chunk in the
kernel; the law's solve where it need not contract, engine/friction_solve.py, array
code).  Checked here, on the compiled backend:

* against the numpy engine on drawn four-bars of several kinds, both branches, every
  reachable position (contracting and not, near toggles, self-locking ones): the same
  FRICTION_STATUS, the same FRICTION_ITERATIONS (but by one where the fixed point's stop
  test sits at its tolerance, the engines' inputs an ulp or two apart: counted, rare),
  the same NaN, the same FrictionWarning text, every force, torque and loss within
  1e-10 of the position's scale (a thousand times the worst seen, 1e-13);
  ``test_the_draw_holds_every_case`` counts what the draw holds (non-contracting
  positions, positions solved by Newton, self-locking ones) so that a claim of
  coverage is shown, not assumed; positions at a toggle to within roundoff (|sin GAMMA|
  < 1e-6) are left out, as in test_compiled.py (either engine's rates are infinite or
  finite there by the luck of rounding);
* at positions whose solution is not reached from mu = 0 (FRICTION_STATUS 3: found by a
  search of drawn four-bars, kept here as data);
* against the independent references test_friction.py and test_friction_solutions.py
  use: the Newton-Euler solve with friction iterated (tests/newton_euler.py) with every
  effect on, and, where the law has several solutions, the law written again.

Three kernels serve the file (friction and TEX; test_friction.py's scene of every effect;
the count of solutions, FRICTION_SOLUTIONS), each compiled once (some 70 s) and then kept
in the kernel cache.
"""

from __future__ import annotations

import functools
import warnings
from collections import Counter

import numpy as np
import pytest

pytest.importorskip("numba")

import newton_euler as ne  # noqa: E402
from sielaff import EXAMPLE, FrictionWarning, PinFriction, Scene, analyze  # noqa: E402
from sielaff.engine.friction import per_joint  # noqa: E402
from sielaff.engine.friction_solve import contraction  # noqa: E402
from sielaff.engine.positions import reachable  # noqa: E402
from test_elements import draw  # noqa: E402
from test_friction import CASES, FORCES, PLOSS, case_draw, pin_force  # noqa: E402
from test_friction_solutions import NAMES as PIN_FORCES  # noqa: E402
from test_friction_solutions import ROCKER, _law, _moderate  # noqa: E402

NAMES = [n + c for n in FORCES for c in "XY"] + [
    "TORQ", "TORQ_FRICTION", *PLOSS, "FRICTION_STATUS", "FRICTION_ITERATIONS", "ATH3",
    "ATH4", "GAMMA"]
VALUES = NAMES[:14]  # the pin forces, TORQ, TORQ_FRICTION and the losses
AT_TOGGLE = 1e-6
DRAWN = [(m, kind, branch, i) for i, (m, kind) in enumerate(draw(8, 31))
         for branch in ("open", "crossed")]

#: Positions whose law has solutions but none continuous from mu = 0 (FRICTION_STATUS 3),
#: found by drawing four-bars and frictions: (R1..R4, each pin's (mu, radius), TEX,
#: branch, the crank angle [deg]).
NOT_FROM_ZERO = [
    ((15.75139469170161, 13.58958834389786, 7.039055336281544, 2.394997013021122),
     {"O2": (0.21380014604369732, 1.652895888026166),
      "A": (0.7739774012395142, 0.07082088397889774),
      "B": (0.574741578549169, 2.875736540124363),
      "O4": (0.7715795810468431, 1.786265199022401)}, 114.2691634238987, "open", 24.5),
    ((2.1843737184342205, 8.231487525428523, 3.3751908186723654, 11.28362270523548),
     {"O2": (0.06847669556999413, 0.17186676246446952),
      "A": (0.41360214840380705, 2.824813432199174),
      "B": (0.6482757847649001, 2.8510045227341285),
      "O4": (0.23957074893179478, 2.7673573333667543)}, -169.38003400891319, "open",
     116.25)]


def _scene(i, branch):
    """Each pin's friction drawn (mu r up to 0.5: the law need not contract near the
    toggles of these 1-6 inch links) and a TEX."""
    rng = np.random.default_rng(500 + i)
    fr = {p: PinFriction(float(rng.uniform(0, 0.5)), float(rng.uniform(0, 1.0)))
          for p in ne.PINS}
    return Scene(friction=fr, tex=float(rng.uniform(-50, 50)), branch=branch)


def _run(m, th, sc, backend):
    """(results, the FrictionWarnings' texts)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = analyze(m, th, NAMES, scene=sc, backend=backend)
    return dict(r), [str(w.message) for w in caught if w.category is FrictionWarning]


@functools.cache
def _numpy(i, branch):
    m = DRAWN[2 * i][0]
    th = reachable(m, 181)
    return th, _run(m, th, _scene(i, branch), "numpy")


def _mur(sc):
    """Each pin's mu r in the scene (O2, A, B, O4)."""
    return tuple(f.mu * f.radius for f in per_joint(sc.friction).values())


def _solves_the_law(m, sc, th, got, j):
    """Whether the pin forces ``got`` reports at position ``j`` solve the friction law
    (test_friction_solutions.py's, written with each pin's mu r): H(x) = 0 for x =
    FB34 - FB34_0, the frictionless forces from the scene without friction."""
    r = analyze(m, th[j:j + 1], PIN_FORCES + ["ATH3", "ATH4", "TH3D", "TH4D"],
                scene=sc.replace(friction=None))
    g = {k: float(v[0]) for k, v in r.items()}
    u, v, d, (sa, sb, s4) = _law(m, g, 0.0)
    _, ka, kb, kd = _mur(sc)
    fa, fb, fd = (np.array([got[n + "X"][j], got[n + "Y"][j]]) for n in ("FA32", "FB34", "FOB"))
    x = fb - np.array([g["FB34X"], g["FB34Y"]])
    ta, tb, td = ka * np.hypot(*fa), kb * np.hypot(*fb), kd * np.hypot(*fd)
    h = x + (u * (-sb * tb - s4 * td) + v * (sb * tb - sa * ta)) / d
    return bool(np.hypot(*h) <= 1e-8 * np.hypot(*fb))


def _compare(m, got, ref):
    """The engines agree (see the module doc) away from toggles; the number of positions
    whose iterations differ by one."""
    away = (np.abs(np.sin(np.radians(ref["GAMMA"]))) >= AT_TOGGLE) & (
        np.abs(np.sin(np.radians(got["GAMMA"]))) >= AT_TOGGLE)
    g = {k: v[away] for k, v in got.items()}
    r = {k: v[away] for k, v in ref.items()}
    np.testing.assert_array_equal(g["FRICTION_STATUS"], r["FRICTION_STATUS"])
    it_g, it_r = g["FRICTION_ITERATIONS"], r["FRICTION_ITERATIONS"]
    assert np.array_equal(np.isnan(it_g), np.isnan(it_r))
    off = np.abs(it_g - it_r)[np.isfinite(it_r)]
    assert np.all((off == 0.0) | ((off == 1.0) & (it_r[np.isfinite(it_r)] > 0.0)))
    scale = np.max([np.hypot(r[n + "X"], r[n + "Y"]) for n in FORCES], axis=0) + np.abs(
        r["TORQ"]) / m.R2
    for n in VALUES:
        assert np.array_equal(np.isnan(g[n]), np.isnan(r[n])), n
        per = scale * (abs(m.TH2D) if n.startswith("PLOSS") else 1.0)
        ok = np.isfinite(r[n])
        assert np.all(np.abs(g[n][ok] - r[n][ok]) <= 1e-10 * per[ok]), n
    return int(np.count_nonzero(off))


@pytest.mark.parametrize("m, kind, branch, i", DRAWN, ids=[f"{c[1]}-{c[2]}-{c[3]}"
                                                           for c in DRAWN])
def test_compiled_friction_agrees_with_numpy_on_drawn_fourbars(m, kind, branch, i):
    th, (ref, ref_warned) = _numpy(i, branch)
    got, warned = _run(m, th, _scene(i, branch), "numba")
    assert warned == ref_warned  # the same FrictionWarning, or none on both
    assert _compare(m, got, ref) <= max(1, th.size // 100)


def test_the_draw_holds_every_case():
    """What the drawn four-bars above hold (numpy engine, the same positions): several
    kinds, both branches, positions where the law contracts and many where it need not,
    positions the fixed point does not solve (Newton's, FRICTION_ITERATIONS 0 and
    status 0), self-locking ones (2), ones with a pin at relative rest (1)."""
    seen: Counter[str] = Counter()
    for m, kind, branch, i in DRAWN:
        _, (r, warned) = _numpy(i, branch)
        s34 = np.sin(np.radians(r["ATH3"] - r["ATH4"]))
        finite = np.isfinite(s34)
        with np.errstate(divide="ignore"):
            hard = finite & ~(contraction(_mur(_scene(i, branch)), m.R3, m.R4, s34) < 1.0)
        st, it = r["FRICTION_STATUS"], r["FRICTION_ITERATIONS"]
        seen[kind] += 1
        seen[branch] += 1
        seen["contracting"] += int(np.count_nonzero(finite & ~hard))
        seen["not contracting"] += int(np.count_nonzero(hard))
        seen["by Newton"] += int(np.count_nonzero(hard & (st == 0.0) & (it == 0.0)))
        seen["fixed point where it need not contract"] += int(np.count_nonzero(hard & (it > 0)))
        for s in (1.0, 2.0):
            seen[f"status {s:g}"] += int(np.count_nonzero(st == s))
        seen["warned"] += len(warned)
    print(dict(seen))
    assert len({kind for _, kind, _, _ in DRAWN}) >= 3 and seen["open"] == seen["crossed"]
    assert seen["contracting"] >= 1000 and seen["not contracting"] >= 100
    assert seen["by Newton"] >= 10 and seen["fixed point where it need not contract"] >= 10
    assert seen["status 1"] >= 1 and seen["status 2"] >= 1 and seen["warned"] >= 1


@pytest.mark.parametrize("case", range(len(NOT_FROM_ZERO)))
def test_solutions_not_reached_from_mu_zero(case):
    """FRICTION_STATUS 3 (the search's least-friction solution) at the same positions on
    both backends, with the same warning; the solution taken solves the law (written
    again here, test_friction_solutions.py's)."""
    r, fr, tex, branch, t = NOT_FROM_ZERO[case]
    m = EXAMPLE.replace(R1=r[0], R2=r[1], R3=r[2], R4=r[3])
    sc = Scene(friction={k: PinFriction(*v) for k, v in fr.items()}, tex=tex, branch=branch)
    th = t + np.linspace(-2.0, 2.0, 41)
    ref, ref_warned = _run(m, th, sc, "numpy")
    got, warned = _run(m, th, sc, "numba")
    three = np.flatnonzero(ref["FRICTION_STATUS"] == 3.0)
    assert three.size and warned == ref_warned and f"{three.size} only solutions" in warned[0]
    _compare(m, got, ref)
    for j in three:
        assert _solves_the_law(m, sc, th, got, j), th[j]


def test_near_toggles_every_solution_and_self_locking_as_numpy():
    """The bench's double rocker near its toggles (test_friction_solutions.py's, with a
    TEX): positions solved by Newton with several solutions, self-locking ones; the
    compiled backend as the numpy engine (FRICTION_SOLUTIONS, the count of solutions,
    too: none, one and several counted), its chosen solutions solve the law, and with
    ``out=`` the same arrays and warning."""
    th = reachable(ROCKER, 3600)
    sc = Scene(friction=PinFriction(0.3, 1.0), tex=0.5)
    ref, ref_warned = _run(ROCKER, th, sc, "numpy")
    got, warned = _run(ROCKER, th, sc, "numba")
    assert warned == ref_warned and len(warned) == 1
    _compare(ROCKER, got, ref)
    counts = {}
    for backend in ("numpy", "numba"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            counts[backend] = analyze(ROCKER, th, ["FRICTION_SOLUTIONS"], scene=sc,
                                      backend=backend)["FRICTION_SOLUTIONS"]
    count = counts["numba"]
    np.testing.assert_array_equal(count, counts["numpy"])
    seen = Counter(np.minimum(count, 2.0).tolist())
    assert seen[0.0] >= 2 and seen[1.0] >= 100 and seen[2.0] >= 5, seen
    newton = (got["FRICTION_ITERATIONS"] == 0) & (got["FRICTION_STATUS"] == 0)
    assert np.count_nonzero(got["FRICTION_STATUS"] == 2.0) >= 2
    several = np.flatnonzero(newton & (count >= 2) & _moderate(got))
    assert several.size >= 5
    for j in several[:: max(1, several.size // 8)]:
        assert _solves_the_law(ROCKER, sc, th, got, j), th[j]
    out = {n: np.full(th.shape, -1.0) for n in NAMES}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        analyze(ROCKER, th, scene=sc, out=out, backend="numba")
    assert [str(w.message) for w in caught if w.category is FrictionWarning] == warned
    for n in NAMES:
        np.testing.assert_array_equal(out[n], got[n], err_msg=n)


@pytest.mark.parametrize("m, kind, branch, i", CASES, ids=[f"{c[1]}-{c[2]}-{c[3]}"
                                                           for c in CASES])
def test_compiled_friction_agrees_with_newton_euler(m, kind, branch, i):
    """test_friction.py's draw (every effect on: springs, dampers, a load, gravity, TEX,
    crank acceleration) on the compiled backend, against the independent Newton-Euler
    solve with friction iterated: pin forces, TORQ, the status of a pin at relative rest,
    and the losses by the Coulomb law from the reported forces."""
    _, sc, th = case_draw(m, branch, i)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FrictionWarning)
        r = analyze(m, th, NAMES, scene=sc, backend="numba")
    mur = _mur(sc)
    checked = 0
    for j, t in enumerate(th):
        ref = ne.solve(m, float(t), ne.engine_b(m, float(t), sc), a2=sc.th2dd, tex=sc.tex,
                       elements=sc.elements, gravity=sc.gravity, loads=sc.loads, mur=mur)
        if r["FRICTION_STATUS"][j] == 2.0:
            assert ref is None or max(ref["T"]) > 0
            continue
        assert ref is not None
        checked += 1
        assert (r["FRICTION_STATUS"][j] == 1.0) == (0.0 in ref["sg"])
        scale = max(abs(ref[n]) for n in FORCES) + abs(ref["TORQ"]) / m.R2
        for n in FORCES:
            assert abs(complex(r[n + "X"][j], r[n + "Y"][j]) - ref[n]) <= 1e-9 * scale, n
        assert abs(r["TORQ"][j] - ref["TORQ"]) <= 1e-9 * scale * m.R2
        s = ref["state"]
        rel = (m.TH2D, s["w3"] - m.TH2D, s["w4"] - s["w3"], s["w4"])
        for k, p in enumerate(ne.PINS):
            loss = mur[k] * pin_force(r, p, j) * abs(rel[k]) * abs(ref["sg"][k])
            assert r["PLOSS_" + p][j] == pytest.approx(loss, rel=1e-9, abs=1e-9 * scale)
    assert checked
