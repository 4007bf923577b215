"""What a crank counterweight does for a slider-crank's shaking force, and what it leaves.

In:  a slider-crank (one design; weights in lb, or masses in kg in SI: the W fields) at
     constant crank speed TH2D, the fraction of the reciprocating primary to balance and
     the counterweight's radius from O2.
Out: the reciprocating mass and its shaking-force harmonics along the line of stroke,
     the counterweight (a point mass merged into the crank), and the shaking force before
     and after it over one revolution (peaks of SHAKX and SHAKY; the primary along and
     across the stroke; the secondary), the engine's own numbers.

Unlike the four-bar's (Berkof-Lowen, design/balance.py), a slider-crank's shaking force
cannot be cancelled by counterweights: the slider's motion along its line is not a
rotation.  The rod's centre of mass G3 = A + c (B - A), c = (RG3 / R3) e^{i ADEL3} (complex,
in the rod's frame), so with A = R2 e^{i th2} and B = XB + i offset, the first moment of
the moving links is

    W2 RG2 e^{i ADEL2} e^{i th2} + W3 (1 - c) R2 e^{i th2} + (W4 + W3 c) XB + constant.

The first two terms turn with the crank: the rotating first moment, ``u = W2 RG2 e^{i
ADEL2} + W3 (1 - c) R2`` in the crank's frame.  The third moves along the stroke: the
reciprocating weight ``W_rec = W4 + W3 Re(c)`` along it (and ``W3 Im(c)`` across it, when G3
is off the line A-B).  At constant speed w the shaking force SHAK = -sum m a is (g the
unit system's mass divisor, 386.088 in/sec^2 or 1)

    SHAKX + i SHAKY = (w^2 / g) u e^{i th2} - ((W4 + W3 c) / g) AXB.

With XB = Re sum_k X_k e^{i k th2} (its Fourier series over a revolution), AXB = -w^2 sum
k^2 X_k e^{i k th2}, so the reciprocating mass's shaking force along the stroke has the
harmonics ``H_k = (W_rec / g) k^2 w^2 X_k``: the primary H_1 (1x crank speed), the secondary
H_2 (2x), and so on.  With no offset X_1 = R2 exactly and X_2 = R2 (l + l^3 / 4 + ...) / 4,
l = R2 / R3: the textbook's primary W_rec R2 w^2 cos th2 / g and secondary W_rec R2 w^2
(R2 / R3) cos 2 th2 / g (tests/test_design_kinds.py checks both, and the exact series
with an offset).

A counterweight on the crank with first moment P (crank frame) adds (w^2 / g) P e^{i th2}.
``P = -u - fraction W_rec X_1`` cancels the rotating unbalance and ``fraction`` of the
reciprocating primary along the stroke, and puts ``fraction`` of it across the stroke:
the residual primary is (1 - fraction) |H_1| along and fraction |H_1| across (0.5 makes
it a vector of constant length turning with the crank, the least peak).  The secondary
and every higher harmonic are untouched.  With no offset and both centres of mass on
their links' lines (ADEL2 = ADEL3 = 0) P is opposite the crank pin (180 deg); an offset
gives X_1 a sine part and turns it by its phase.

The counterweight is merged into link 2 as :func:`sielaff.design.balance` merges the
four-bar's (W2, ZI2 by the parallel-axis theorem, RG2, ADEL2), and the shaking force
before and after is the engine's (``analyze``: SHAKX, SHAKY, SHAK) over ``n`` crank angles;
the harmonics of XB come from the engine's XB by FFT over the same angles.  The scene is
the inertial one (no gravity, no loads, constant speed): a counterweight answers inertia.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.design.balance import Counterweight, _merge
from sielaff.design.kinds import is_slider_crank, kind_name
from sielaff.engine.analysis import analyze, model_for
from sielaff.engine.scene import scene_of
from sielaff.mechanism import MASS_DIVISOR

__all__ = ["HARMONICS", "SAMPLES", "Shaking", "SliderBalance", "slider_balance"]

#: Crank angles per revolution by default [-].
SAMPLES = 720
#: Harmonics of the reciprocating force kept in :attr:`SliderBalance.harmonics` (0 .. 8).
HARMONICS = 8


@dataclass(frozen=True)
class Shaking:
    """The shaking force over one revolution [lb or N]: the largest ``|SHAKX|`` (along the
    stroke) and ``|SHAKY|`` (across it) and ``SHAK``; the amplitude of SHAKX's and
    SHAKY's first harmonic (``primary_along``, ``primary_across``) and second
    (``secondary_along``, ``secondary_across``)."""

    peak_x: float
    peak_y: float
    peak: float
    primary_along: float
    primary_across: float
    secondary_along: float
    secondary_across: float


@dataclass(frozen=True)
class SliderBalance:
    """A slider-crank's crank counterweight and what it leaves (module doc).

    ``fraction`` [-] of the reciprocating primary balanced; ``reciprocating`` W_rec and
    ``reciprocating_across`` W3 Im(c) [lb or kg, as the W fields]; ``rotating``, |u| the
    crank's rotating first moment before the counterweight [lb in or kg m];
    ``harmonics[k]`` the complex H_k of the reciprocating mass's shaking force along the
    stroke, ``Re(H_k e^{i k th2})`` [lb or N], k = 0 .. :data:`HARMONICS`; ``primary`` =
    |H_1| and ``secondary`` = |H_2| [lb or N]; ``counterweight`` on link 2 (weight [lb or
    kg] at ``radius`` [in or m], ``angle`` [deg] from the crank's line O2->A, CCW);
    ``product`` its weight times radius [lb in or kg m]; ``mechanism`` the slider-crank
    with it merged into the crank, ``unbalanced`` the one given; ``before`` and ``after``
    the engine's shaking force (:class:`Shaking`); ``theta2`` [deg], ``shakx`` and
    ``shaky`` [lb or N] after, on the sample grid."""

    fraction: float
    reciprocating: float
    reciprocating_across: float
    rotating: float
    harmonics: np.ndarray
    primary: float
    secondary: float
    counterweight: Counterweight
    product: float
    mechanism: Any
    unbalanced: Any
    before: Shaking
    after: Shaking
    theta2: np.ndarray
    shakx: np.ndarray
    shaky: np.ndarray


def _coefficients(samples: np.ndarray, upto: int) -> np.ndarray:
    """c_k, k = 0 .. upto, with samples = Re sum_k c_k e^{i k th} on th = 2 pi j / n."""
    n = samples.shape[-1]
    spectrum = np.fft.rfft(samples) / n
    c = 2.0 * spectrum[:upto + 1]
    c[0] = spectrum[0]
    return c


def _shaking(r: dict[str, np.ndarray]) -> Shaking:
    x, y = _coefficients(r["SHAKX"], 2), _coefficients(r["SHAKY"], 2)
    return Shaking(float(np.max(np.abs(r["SHAKX"]))), float(np.max(np.abs(r["SHAKY"]))),
                   float(np.max(r["SHAK"])), float(abs(x[1])), float(abs(y[1])),
                   float(abs(x[2])), float(abs(y[2])))


def _number(name: str, value: Any, low: float, high: float) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not low <= float(value) <= high:
        raise ValueError(f"slider_balance: {name} = {value!r}: a number from {low:g} to "
                         f"{high:g}")
    return float(value)


def slider_balance(mechanism: Any, fraction: float = 0.5, radius: float | None = None,
                   n: int = SAMPLES, *, branch: str = "open") -> SliderBalance:
    """The crank counterweight of a slider-crank and the shaking force it leaves.

    Parameters
    ----------
    mechanism : SliderCrank
        One design (scalar fields) whose crank turns fully [in-lb-sec or SI]; the crank
        speed TH2D [rad/sec] is taken as constant.
    fraction : float
        The fraction of the reciprocating primary (along the stroke) the counterweight
        balances besides the rotating unbalance [-], 0 to 1 (0: the rotating unbalance
        alone; 0.5, the default: the least peak primary).
    radius : float, optional
        The counterweight's distance from O2 [in or m], > 0; default R2.
    n : int
        Crank angles over the revolution [-], even, 8 or more.
    branch : {"open", "crossed"}
        The slider's assembly [-] (sielaff.linkage says which is which).

    Raises ValueError in one line for another kind of linkage, arrays of designs, a crank
    that cannot turn fully, or a shaking force that is not finite over the revolution.
    """
    m = mechanism
    if not is_slider_crank(m):
        raise ValueError(f"slider_balance: for a SliderCrank, not a {kind_name(m)} (a "
                         "four-bar's counterweights: sielaff.design.balance)")
    if any(np.ndim(v) for v in m.as_dict().values()):
        raise ValueError("slider_balance: one design at a time (the mechanism's fields are "
                         "arrays)")
    f = _number("fraction", fraction, 0.0, 1.0)
    r_cw = float(m.R2) if radius is None else _number("radius", radius, 0.0, math.inf)
    if not r_cw > 0.0:
        raise ValueError(f"slider_balance: radius = {radius!r}: a counterweight's radius "
                         "must be > 0")
    if isinstance(n, bool) or not isinstance(n, int) or n < 8 or n % 2:
        raise ValueError(f"slider_balance: n = {n!r}: an even whole number, 8 or more")
    model = model_for(m)
    why = model.full_turn(m) if model.full_turn is not None else None
    if why:
        raise ValueError(f"slider_balance: {why}: no revolution to balance over")
    sc = scene_of(model)(branch=branch)
    th = np.arange(n) * (360.0 / n)

    c = float(m.RG3) / float(m.R3) * np.exp(1j * math.radians(float(m.ADEL3)))
    u = (float(m.W2) * float(m.RG2) * np.exp(1j * math.radians(float(m.ADEL2)))
         + float(m.W3) * (1.0 - c) * float(m.R2))
    w_rec = float(m.W4) + float(m.W3) * c.real
    xb = analyze(m, th, ["XB"], scene=sc)["XB"]
    before = analyze(m, th, ["SHAKX", "SHAKY", "SHAK"], scene=sc)
    if not (np.all(np.isfinite(xb)) and all(np.all(np.isfinite(v)) for v in before.values())):
        raise ValueError("slider_balance: the shaking force is not finite over the "
                         "revolution (the rod reaches its toggle): nothing to balance")
    x = _coefficients(xb, HARMONICS)
    k = np.arange(HARMONICS + 1)
    w = float(m.TH2D)
    divisor = MASS_DIVISOR[m.units]
    harmonics = (w_rec / divisor) * k * k * w * w * x

    # P = -u - fraction W_rec X_1: the rotating unbalance and part of the primary
    p = -u - f * w_rec * x[1]
    # + 0.0: a -0.0 sine part would print the opposite pin as -180 deg
    angle = math.degrees(math.atan2(p.imag + 0.0, p.real)) if abs(p) > 0.0 else 180.0
    cw = Counterweight(2, float(abs(p)) / r_cw, r_cw, angle)
    w2, zi2, rg2, adel2 = _merge(m.W2, m.ZI2, m.RG2, m.ADEL2, cw, divisor)
    balanced = m.replace(W2=float(w2), ZI2=float(zi2), RG2=float(rg2), ADEL2=float(adel2))
    after = analyze(balanced, th, ["SHAKX", "SHAKY", "SHAK"], scene=sc)
    return SliderBalance(f, w_rec, float(m.W3) * c.imag, float(abs(u)), harmonics,
                         float(abs(harmonics[1])), float(abs(harmonics[2])), cw,
                         float(abs(p)), balanced, m, _shaking(before), _shaking(after), th,
                         after["SHAKX"], after["SHAKY"])
