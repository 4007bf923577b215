"""The slider-crank, the inverted slider-crank and the Watt II and Stephenson III six-bars
by the compiled backend (``backend="numba"``), against the numpy engine and against an
independent solve in 40 digits (tests/linkage_reference.py: positions from the angle
forms, rates by differentiating them in time, Newton-Euler about each centre of mass).

The compiled backend runs the functions the numpy engine runs (each linkage step
unrolled into plain code, engine/unroll.py), compiled for one position; it differs from
the numpy engine only in sin, cos and atan2 (an ulp or two) and in the joints' linear
solve (LAPACK's there, Gaussian elimination with partial pivoting for one position
here): both backward stable, so both engines are held to one error bound, derived as
the four-bar's is, dyad by dyad (engine/accuracy.py's chain_bound and chain_scales):

    |error| <= C eps (L / l)^d S / s^p,    s = s_1 s_2 ... s_d

with d the number of dyads, L the sum of the lengths, l the shortest of a dyad's links,
s_i the i-th dyad's own conditioning (the engine's assembly margin: |sin| of an RRR's
angle at its inner pin, |cos| of a slider rod's angle to its guide, |s| / |PQ| for the
inverted slider's block), S and p the output's kind's scale and power.  Each dyad's inputs carry the
errors of the dyads before it, which it multiplies by (L / l) / s_i, as the four-bar's
one dyad multiplies A's and O4's.  Against the 40-digit reference each engine is held to
the bound; against each other, to twice it.

Designs are drawn (seeded) around each kind's example, both branches, and checked to
assemble at the drawn crank angles; what was drawn and compared is counted.  The scene
carries every effect these kinds take but friction (its compiled form is held to the
40-digit reference and to the numpy engine in tests/test_joint_friction.py):
a crank acceleration, gravity, an applied load (its force an array), a spring and a
damper, and the slider-crank's FEX; the reference takes them as loads (the damper's
coefficient is 0 there, its tension is then none).  Without numba the numpy engine is
still held to the bound and the compiled cases skip.
"""

from __future__ import annotations

import math
import warnings

import mpmath as mp
import numpy as np
import pytest

import linkage_reference as ref
from sielaff import (
    INVERTED_EXAMPLE,
    SLIDER_EXAMPLE,
    STEPHENSON_EXAMPLE,
    WATT_EXAMPLE,
    Damper,
    Load,
    Spring,
    analyze,
)
from sielaff.engine import AssemblyWarning, model_for
from sielaff.engine.accuracy import chain_bound, chain_scales
from sielaff.engine.compiled import available
from sielaff.engine.scene import scene_type
from sielaff.quantities import unit

HAVE_NUMBA = available()
BACKENDS = ["numpy", pytest.param("numba", marks=pytest.mark.skipif(
    not HAVE_NUMBA, reason="numba is not installed"))]

EXAMPLES = {"slider": SLIDER_EXAMPLE, "inverted": INVERTED_EXAMPLE, "watt": WATT_EXAMPLE,
            "stephenson": STEPHENSON_EXAMPLE}
#: Each kind's branches: the engine's Scene.branch and the reference's signs (the
#: six-bars' second dyad crossed: both crossed does not close on these designs).
BRANCHES = {"open": ("open", (1, 1)), "crossed": ("crossed", (-1, -1))}
SIX_BRANCHES = {"open": (("open", "open"), (1, 1)), "crossed": (("open", "crossed"), (1, -1))}
#: The unit of each output (in-lb-sec) to the bound's kind.
KIND_OF_UNIT = {"deg": "angle", "in": "length", "rad/sec": "rate", "in/sec": "velocity",
                "rad/sec^2": "angular acceleration", "in/sec^2": "acceleration",
                "lb": "force", "in-lb": "torque", "in-lb/sec": "power"}
GRAVITY = -386.088
LOAD = dict(r=2.0, angle=15.0, fx=40.0, fy=-10.0, torque=15.0)  # on link 3, every kind
SPRING = ((1, 6.0, 90.0), (3, 1.5, 20.0), 30.0, 5.0)  # frame to link 3, k, free length
FEX = -50.0


def _branch(kind, name):
    return (SIX_BRANCHES if kind in ("watt", "stephenson") else BRANCHES)[name]


def _scene(kind, m, branch, n, damping=0.0):
    """The scene with every effect the kind takes but pin friction (see the module doc);
    the load's force an array of the crank angles' length ``n``."""
    kw = dict(branch=branch, th2dd=-35.0, gravity="down",
              loads=[Load(3, r=LOAD["r"], angle=LOAD["angle"], fx=np.full(n, LOAD["fx"]),
                          fy=LOAD["fy"], torque=LOAD["torque"])],
              elements=[Spring(*SPRING), Damper((2, 1.0, 0.0), (3, 2.0, 0.0), damping)])
    if kind == "slider":
        kw["fex"] = FEX
    return scene_type(model_for(m))(**kw)


def _draw(kind, rng):
    """A design around the kind's example: lengths scaled by 0.8 to 1.25, the centres of
    mass, masses, inertias and the crank's speed varied (never one that cannot close)."""
    m = EXAMPLES[kind]
    lengths = set(m.TOPOLOGY.lengths()) | {"R1", "RC", "X6", "Y6"}
    values = {}
    for name, v in m.as_dict().items():
        if name in lengths:
            values[name] = v * rng.uniform(0.8, 1.25)
        elif name.startswith("ADEL"):
            values[name] = v + rng.uniform(-30.0, 30.0)
        elif name.startswith("RG"):
            values[name] = rng.uniform(0.0, 1.0) * max(v, 2.0)
        elif name.startswith(("W", "ZI")):
            values[name] = v * rng.uniform(0.5, 2.0)
        elif name == "TH2D":
            values[name] = v * rng.uniform(0.5, 2.0) * rng.choice([-1.0, 1.0])
        elif name == "offset":
            values[name] = rng.uniform(-0.5, 0.5) * (values.get("R2", 2.0))
    return m.replace(**values)


def _margins(kind, m, mo):
    """Each dyad's conditioning s_i at the reference's position (see the module doc)."""
    P = {k: v[0] for k, v in mo.items()}

    def sin_at(c, p, q, lp, lq):
        return abs(ref.cross(P[p] - P[c], P[q] - P[c])) / (ref.f(lp) * ref.f(lq))
    if kind == "slider":
        return [abs((P["B"] - P["A"]).real) / ref.f(m.R3)]
    if kind == "inverted":
        return [abs(mo["ths"][0]) / abs(P["A"] - P["O4"])]
    return [sin_at("B", "A", "O4", m.R3, m.R4), sin_at("D", "C", "O6", m.R5, m.R6)]


def _scales(m, kind, applied):
    """accuracy.chain_scales in this file's scene: its crank acceleration, gravity, the
    applied loads and the farthest point the load and the spring place on a link."""
    return chain_scales(m, th2dd=35.0, gravity=abs(GRAVITY), applied=applied,
                        reach=max(LOAD["r"], SPRING[0][1], SPRING[1][1]))


def _point(mo, base, line, r, angle):
    return mo[base][0] + ref.f(r) * mp.expj(mo["th" + line][0] + mp.radians(ref.f(angle)))


def _reference(kind, m, th, signs):
    """The 40-digit answers with the scene's effects as the reference's loads: gravity,
    the load on link 3, the spring's tension (a frame point to a point of link 3), FEX
    on the slider; and the dyads' conditioning there."""
    key = (kind, repr(m), th, signs)
    if key in _REFERENCES:
        return _REFERENCES[key]
    mo = ref.motion(kind, m, th, m.TH2D, -35.0, branch=signs)
    at = _point(mo, "A", "3", LOAD["r"], LOAD["angle"])  # link 3's base: A in every kind
    loads = [(3, at, complex(LOAD["fx"], LOAD["fy"]), LOAD["torque"])]
    (_, r1, a1), (_, r3, a3), k, free = SPRING
    pa = ref.f(r1) * mp.expj(mp.radians(ref.f(a1)))
    pb = _point(mo, "A", "3", r3, a3)
    length = abs(pb - pa)
    tension = ref.f(k) * (length - ref.f(free))
    loads.append((3, pb, -tension * (pb - pa) / length, 0))
    if kind == "slider":
        loads.append((4, mo["B"][0], complex(FEX, 0.0), 0))
    out = ref._solve(kind, m, mo, ref.bodies(kind, m), (0.0, GRAVITY), loads, m.units)
    out["motion"] = mo
    applied = abs(complex(LOAD["fx"], LOAD["fy"])) + abs(float(tension)) + abs(FEX) + abs(
        LOAD["torque"]) / 2.0
    _REFERENCES[key] = out, _margins(kind, m, mo), applied
    return _REFERENCES[key]


_REFERENCES: dict = {}  # the numpy and the compiled cases draw the same designs


def _expected(kind, m, out):
    """{output name: exact value} of the reference (the engine's names)."""
    names = dict(m.TOPOLOGY.names)
    mo = out["motion"]
    want = {"TORQ": out["TORQ"]}
    for key, F in out.items():
        if isinstance(key, tuple):
            p, by, on = key
            generic = f"F{p}" if on == 1 else f"F{p}{by}{on}"
            name = names.get(generic, generic)
            want[name + "X"], want[name + "Y"] = F.real, F.imag
    if "FN" in out:
        want["FN"], want["MN"] = out["FN"], out["MN"]
    links = range(3, 5) if kind in ("slider", "inverted") else range(3, 7)
    points = {"slider": ["A", "B"], "inverted": ["A"]}.get(kind, ["A", "B", "C", "D"])
    for p in points + [f"G{k}" for k in range(2, links.stop)]:
        want[f"X{p}"], want[f"Y{p}"] = mo[p][0].real, mo[p][0].imag
        for d, prefix in ((1, "V"), (2, "A")):
            want[f"{prefix}{p}X"], want[f"{prefix}{p}Y"] = mo[p][d].real, mo[p][d].imag
    for k in links:
        th_k = mo[f"th{k}"]
        want[f"ATH{k}"] = th_k[0]
        want[f"TH{k}D"], want[f"TH{k}DD"] = th_k[1], th_k[2]
    outputs = set(model_for(m).outputs)
    assert {n for n in want if n[0] == "F" or n in ("TORQ", "MN")} <= outputs
    return {n: v for n, v in want.items() if n in outputs}


def _error(name, got, exact):
    if name.startswith("ATH"):  # radians, modulo a revolution
        return abs(math.remainder(math.radians(got) - float(exact), 2 * math.pi))
    return abs(got - float(exact))


def _analyze(m, th, scene, backend):
    model = model_for(m)
    wanted = [n for n in model.outputs if n != "ASSEMBLED"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AssemblyWarning)
        return analyze(m, th, wanted, scene=scene, backend=backend)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("branch", ["open", "crossed"])
@pytest.mark.parametrize("kind", sorted(EXAMPLES))
def test_each_kind_within_the_bound_of_the_40_digit_solve(kind, branch, backend):
    """Drawn designs of each kind, each branch, every effect: the engine's pin forces,
    FN and MN, TORQ, points, link angles, rates and accelerations within the bound of
    the independent 40-digit solve."""
    rng = np.random.default_rng([35, len(kind), branch == "open"])
    scene_branch, signs = _branch(kind, branch)
    designs = compared = drawn = 0
    worst = 0.0
    names: set[str] = set()
    while designs < 3:
        drawn += 1
        assert drawn < 60, "too few drawn designs assemble"
        m = _draw(kind, rng)
        th = rng.uniform(0.0, 360.0, 3)
        numpy = _analyze(m, th, _scene(kind, m, scene_branch, th.size), "numpy")
        if numpy.not_assembled:
            continue
        designs += 1
        got = numpy if backend == "numpy" else _analyze(
            m, th, _scene(kind, m, scene_branch, th.size), "numba")
        assert got.not_assembled == 0
        for i, t in enumerate(th):
            out, margins, applied = _reference(kind, m, float(t), signs)
            scales, ratio = _scales(m, kind, applied)
            s = float(np.prod([float(x) for x in margins]))
            expected = _expected(kind, m, out)
            names |= set(expected)
            for name, exact in expected.items():
                limit = chain_bound(KIND_OF_UNIT[unit(name)], ratio, len(margins), s, scales)
                err = _error(name, float(got[name][i]), exact)
                assert err <= limit, (kind, branch, m, float(t), name, err, limit)
                worst = max(worst, err / limit)
                compared += 1
    assert compared == 3 * 3 * len(names)  # every quantity at every drawn position
    assert worst < 1.0


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba is not installed")
@pytest.mark.parametrize("branch", ["open", "crossed"])
@pytest.mark.parametrize("kind", sorted(EXAMPLES))
def test_compiled_agrees_with_numpy_on_every_output(kind, branch):
    """Every output the kind gives (but the ASSEMBLED mask), with a damper that damps,
    over a revolution with the positions that cannot assemble: NaN exactly where the
    numpy engine's, the same count, and each value within twice the bound of it."""
    rng = np.random.default_rng([36, len(kind), branch == "open"])
    scene_branch, signs = _branch(kind, branch)
    designs = compared = 0
    for _ in range(3):
        m = _draw(kind, rng)
        th = np.linspace(0.0, 360.0, 25) + rng.uniform(0.0, 10.0)
        scene = _scene(kind, m, scene_branch, th.size, damping=0.5)
        a, b = _analyze(m, th, scene, "numpy"), _analyze(m, th, scene, "numba")
        assert a.not_assembled == b.not_assembled
        ok = ~np.isnan(a["TORQ"])
        if not ok.any():
            continue
        designs += 1
        # the conditioning at each position, as the engine has it: its dyads' margins
        s = np.prod([_engine_margin(kind, m, a, j) for j in range(2 if kind in (
            "watt", "stephenson") else 1)], axis=0)
        tension = max(float(np.nanmax(np.abs(a[n]))) for n in a if n.endswith("_F"))
        scales, ratio = _scales(m, kind, abs(complex(LOAD["fx"], LOAD["fy"])) + tension
                                + abs(FEX) + abs(LOAD["torque"]) / 2.0)
        dyads = 2 if kind in ("watt", "stephenson") else 1
        for name in a:
            x, y = np.asarray(a[name], float), np.asarray(b[name], float)
            assert np.array_equal(np.isnan(x), np.isnan(y)), (kind, name)
            u = unit(name)
            if u == "-" or name.startswith("N"):  # counts (NLOADS, N<element>)
                assert np.array_equal(x, y, equal_nan=True), name
                compared += 1
                continue
            if name[0] == "D" and u == "deg" and name[1:] in a:  # a vector's direction
                mag = np.asarray(a[name[1:]], float)
                k = KIND_OF_UNIT[unit(name[1:])]
                limit = 2 * chain_bound(k, ratio, dyads, s, scales) / mag
                err = np.radians(np.abs((x - y + 180.0) % 360.0 - 180.0))
                err = np.where(mag > 0.0, err, 0.0)
            elif u == "deg":  # an angle, modulo a revolution
                limit = 2 * chain_bound("angle", ratio, dyads, s, scales)
                err = np.radians(np.abs((x - y + 180.0) % 360.0 - 180.0))
            else:
                limit = 2 * chain_bound(KIND_OF_UNIT[u], ratio, dyads, s, scales)
                err = np.abs(x - y)
            bad = ok & ~(err <= limit)
            assert not bad.any(), (kind, branch, name, err[bad], limit[bad])
            compared += 1
    assert designs >= 2
    assert compared >= designs * (len(model_for(EXAMPLES[kind]).outputs) - 1)


def _engine_margin(kind, m, r, j):
    """Dyad j's conditioning from the numpy engine's own outputs (see _margins)."""
    if kind == "slider":
        return np.abs(np.cos(np.radians(r["ATH3"])))
    if kind == "inverted":
        return np.abs(r["S"]) / np.hypot(r["XA"] - m.R1, r["YA"])
    return np.abs(np.sin(np.radians(r["GAMMAB" if j == 0 else "GAMMAD"])))
