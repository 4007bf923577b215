"""Both engines against a 40-digit reference: the error bound derived from the conditioning.

engine/accuracy.py derives ``|error| <= C eps (L / l) S / s^p`` (s = |sin GAMMA|, l the
shorter of coupler and rocker, L the sum of the lengths, S and p by the output's kind).
Here the numpy engine and the compiled backend (where numba is installed) are held to it
against an independent solve in 40 digits (tests/linkage_reference.py: B from the
intersection of two circles, the rates and accelerations by differentiating the
positions in time, the forces by Newton-Euler, mpmath.lu_solve), on drawn four-bars of
every Grashof kind and triple rockers, on both branches, at positions spread over where
they assemble and approaching each toggle (down to a thousandth of a degree of crank
angle), with short couplers and rockers (to 1/50 of the longest link), a crank
acceleration, TEX and gravity.  Each draw is checked to be of its kind, and what was
drawn is counted (hypothesis events).  The bound is also shown not to be vacuous: on a
double rocker with a short coupler near its toggles it is used to a few per cent.
"""

from __future__ import annotations

import importlib.util
import math
import warnings

import mpmath as mp
import numpy as np
import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st

import linkage_reference as ref
from sielaff import EXAMPLE, Scene, analyze
from sielaff.engine import AssemblyWarning, linkage_class
from sielaff.engine.accuracy import bound, scales
from sielaff.quantities import G

#: Each output compared, its kind, and how the reference gives it.
OUTPUTS = {
    "ATH3": "angle", "ATH4": "angle", "TH3D": "rate", "TH4D": "rate",
    "TH3DD": "angular acceleration", "TH4DD": "angular acceleration",
    "VBX": "velocity", "VBY": "velocity", "VG3X": "velocity", "VG3Y": "velocity",
    "AG3X": "acceleration", "AG3Y": "acceleration", "ABX": "acceleration",
    "ABY": "acceleration", "FA32X": "force", "FA32Y": "force", "FB34X": "force",
    "FB34Y": "force", "FOAX": "force", "FOAY": "force", "FOBX": "force", "FOBY": "force",
    "TORQ": "torque", "SHAKM": "torque",
}

#: Where a Grashof kind's shortest link is (R1 frame, R2 crank, R3 coupler, R4 rocker).
SHORTEST_AT = {"double-crank": 0, "crank-rocker": 1, "double-rocker": 2, "rocker-crank": 3}
KINDS = sorted(SHORTEST_AT) + ["triple-rocker"]


@st.composite
def _lengths(draw, kind):
    """(R1, R2, R3, R4) of ``kind``: the shortest f min(p, q) with f down to 1/50 (a
    short coupler or rocker where the kind puts one there), the longest l between max(p,
    q) and p + q - s (Grashof) or past it (a triple rocker)."""
    p, q = draw(st.floats(1.0, 20.0)), draw(st.floats(1.0, 20.0))
    s = draw(st.sampled_from([0.02, 0.1, 0.3, 0.6])) * min(p, q)
    t = draw(st.floats(0.1, 0.9))
    lo = max(p, q)
    longest = lo + t * (p + q - s - lo) if kind != "triple-rocker" else p + q - s + t * s
    rest = draw(st.permutations([longest, p, q]))
    rest.insert(SHORTEST_AT.get(kind, draw(st.integers(0, 3))), s)
    return tuple(rest)


def _angles(m) -> np.ndarray:
    """Crank angles over each arc where the loop closes, and approaching each end (a
    toggle) to 1, 1e-1, 1e-2 and 1e-3 degrees."""
    out = []
    for a, b in linkage_class(m).arcs:
        w = (b - a) % 360.0 or 360.0
        out += list(a + w * np.linspace(0.02, 0.98, 7))
        if w < 360.0:
            for d in (1.0, 1e-1, 1e-2, 1e-3):
                out += [a + d, b - d]
    return np.mod(np.array(out), 360.0)


def _reference(m, th, branch, th2dd, tex, gravity):
    """The 40-digit answers at the crank angles ``th`` (the reference's conventions)."""
    sign = 1 if branch == "open" else -1
    loads = [(4, mp.mpc(0), mp.mpc(0), tex)] if tex else []
    rows = []
    for x in th:
        o = ref.newton_euler("fourbar", m, float(x), float(m.TH2D), th2dd, (sign, 1),
                             gravity=gravity, loads=loads)
        mo = o["motion"]
        ath3, ath4 = (float(mo[f"th{k}"][0]) for k in (3, 4))
        fob = o[("O4", 4, 1)]
        row = {"ATH3": ath3, "ATH4": ath4,
               "TH3D": mo["th3"][1], "TH4D": mo["th4"][1],
               "TH3DD": mo["th3"][2], "TH4DD": mo["th4"][2],
               "VBX": mo["B"][1].real, "VBY": mo["B"][1].imag,
               "VG3X": mo["G3"][1].real, "VG3Y": mo["G3"][1].imag,
               "AG3X": mo["G3"][2].real, "AG3Y": mo["G3"][2].imag,
               "ABX": mo["B"][2].real, "ABY": mo["B"][2].imag,
               "TORQ": o["TORQ"], "SHAKM": ref.f(m.R1) * fob.imag - o["TORQ"]}
        for name, key in (("FA32", ("A", 3, 2)), ("FB34", ("B", 3, 4)),
                          ("FOA", ("O2", 2, 1)), ("FOB", ("O4", 4, 1))):
            row[name + "X"], row[name + "Y"] = o[key].real, o[key].imag
        rows.append({k: float(v) for k, v in row.items()})
    return {k: np.array([r[k] for r in rows]) for k in OUTPUTS}


def _worst(got, want, m, s, scale) -> tuple[float, str]:
    """The largest error over the bound, and which output; angles on the circle."""
    worst, which = 0.0, ""
    for name, kind in OUTPUTS.items():
        a, b = np.asarray(got[name], dtype=float), want[name]
        if kind == "angle":
            diff = np.abs(np.angle(np.exp(1j * (np.radians(a) - b))))
        else:
            diff = np.abs(a - b)
        q = diff / bound(kind, m, s, scale)
        if not np.all(np.isfinite(q)):
            return math.inf, name
        k = int(np.argmax(q))
        if q[k] > worst:
            worst, which = float(q[k]), name
    return worst, which


BACKENDS = ["numpy", pytest.param("numba", marks=pytest.mark.skipif(
    importlib.util.find_spec("numba") is None, reason="numba not installed"))]


def _check(m, branch, backend, th2dd=0.0, tex=0.0, gravity=False):
    """(the largest error over the bound, its output, the least |sin GAMMA| drawn)."""
    th = _angles(m)
    g = (0.0, -G) if gravity else (0.0, 0.0)
    scene = Scene(branch=branch, th2dd=th2dd, tex=tex, gravity=g if gravity else None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AssemblyWarning)
        got = analyze(m, th, [*OUTPUTS, "GAMMA"], scene=scene, backend=backend)
    s = np.abs(np.sin(np.radians(got["GAMMA"])))
    keep = s > 1e-6  # at a toggle itself the rates are infinite: no bound is claimed
    want = _reference(m, th[keep], branch, th2dd, tex, g)
    scale = scales(m, th2dd=abs(th2dd), tex=tex, gravity=G if gravity else 0.0)
    worst, which = _worst({k: np.asarray(v)[keep] for k, v in got.items()}, want, m,
                          s[keep], scale)
    return worst, which, float(s[keep].min())


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("branch", ["open", "crossed"])
@pytest.mark.parametrize("kind", KINDS)
@settings(max_examples=3, derandomize=True, deadline=None)
@given(data=st.data(), w=st.floats(1.0, 200.0), th2dd=st.sampled_from([0.0, -300.0]),
       tex=st.sampled_from([0.0, 40.0]), gravity=st.booleans())
def test_both_engines_within_the_derived_bound(kind, branch, backend, data, w, th2dd, tex,
                                               gravity):
    r = data.draw(_lengths(kind))
    m = EXAMPLE.replace(R1=r[0], R2=r[1], R3=r[2], R4=r[3], TH2D=w)
    assert linkage_class(m).kind == kind
    worst, which, least = _check(m, branch, backend, th2dd, tex, gravity)
    event(f"{kind}, {branch}: least |sin GAMMA| below "
          f"{10.0 ** math.ceil(math.log10(max(least, 1e-12))):g}")
    short = min(r[2], r[3]) / max(r)
    event(f"shorter of coupler and rocker / longest link {'below' if short < 0.05 else 'above'}"
          " 1/20")
    assert worst <= 1.0, (which, worst)


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_bound_is_not_vacuous(backend):
    """A double rocker with a coupler a hundredth of its length, approaching its toggles:
    the worst output uses a fair share of the bound, so the bound says how far off a
    result is, not only that it is."""
    m = EXAMPLE.replace(R1=12.0, R2=10.0, R3=0.3, R4=9.0, TH2D=50.0)
    worst, which, least = _check(m, "open", backend, -300.0, 40.0, True)
    assert least < 0.05 and 1e-3 <= worst <= 1.0, (which, worst, least)


def test_the_four_bar_and_a_chain_of_dyads_share_one_scale_model():
    """accuracy.scales (the four-bar's fields) and accuracy.chain_scales (any kind, read
    from its fields and topology) are one model: the four-bar handed to chain_scales as a
    chain of its one dyad (links 3 and 4), its TEX among the applied loads as the
    four-bar's bound takes it (over the shorter of coupler and rocker), gives the same
    scales, and its L / l is the four-bar's."""
    from sielaff.engine.accuracy import chain_scales

    class OneDyad:  # the four-bar's fields, as a kind of linkage carries them
        TOPOLOGY = type("T", (), {"lengths": staticmethod(lambda: ("R2", "R3", "R4"))})

        def __init__(self, m):
            self.m = m

        def as_dict(self):
            return self.m.as_dict()

    m = EXAMPLE
    short = min(abs(m.R3), abs(m.R4))
    four = scales(m, th2dd=35.0, tex=4.0, gravity=G, applied=20.0, reach=9.0)
    chain, ratio = chain_scales(OneDyad(m), th2dd=35.0, gravity=G,
                                applied=20.0 + 4.0 / short, reach=9.0)
    assert four.keys() == chain.keys()
    for kind, value in four.items():
        assert chain[kind] == pytest.approx(value, rel=4 * np.finfo(float).eps), kind
    assert ratio == (abs(m.R1) + abs(m.R2) + abs(m.R3) + abs(m.R4)) / short
