"""Slider-cranks for a stroke and a time ratio, and the crank-and-slotted-lever shaper.

**The offset slider-crank** (:class:`~sielaff.slider_crank.SliderCrank`: the crank O2-A,
R2, about the origin; the rod A-B, R3; the slider at B on the line y = ``offset`` along
+x, B right of A: the engine's ``"open"`` branch).  At its two dead centres the crank and
rod lie in one line: B1, the outer one, with them stretched (|O2 B1| = L1 = R3 + R2), B2,
the inner one, folded (|O2 B2| = L2 = R3 - R2).  Between them the crank turns 180 +
alpha one way and 180 - alpha the other, so the time ratio Q (the slow stroke's crank
angle over the quick one's) fixes

    alpha = 180 (Q - 1) / (Q + 1)    [deg], the angle B1 O2 B2.

B1 and B2 lie on the slider's line S apart (S the stroke), so O2 lies on a circle
through B1 and B2 on which the chord B1 B2 subtends alpha; any point of it gives L1, L2
and the offset, the distance of O2 from the line (twice the triangle's area over its
base):

    R2 = (L1 - L2) / 2,   R3 = (L1 + L2) / 2,   |offset| = L1 L2 sin(alpha) / S.

Not every point of the arc will do: on the open branch B is right of A, so at the
inner dead centre, where A is behind O2, B2 is right of O2's foot on the line; that
holds where the triangle's angle at B2 is 90 deg or more: L2 <= L1 cos(alpha).

**The free choice** is the rod/crank ratio lambda = R3/R2 = (L1 + L2)/(L1 - L2): with
it the cosine rule S^2 = L1^2 + L2^2 - 2 L1 L2 cos(alpha) gives

    R2 = S / (2 sqrt(lambda^2 sin^2(alpha/2) + cos^2(alpha/2))),   R3 = lambda R2,

and the family is 1 < lambda < cot^2(alpha/2) (:attr:`SliderCrankFamily.ratio_limit`):
at lambda -> 1 the rod is as long as the crank and O2 falls on B2; at the other end R3
= R2 + |offset|, the rod square to the line at the inner dead centre, a toggle of the
two branches (beyond it the crank cannot turn fully).  So alpha < 90 deg: an offset
slider-crank's time ratio is below 3.  With Q = 1 (alpha = 0) the circle becomes the
line itself: the in-line slider-crank, R2 = S/2, offset 0, any lambda > 1.

Which stroke is the slow one: with the offset's sign the frame is mirrored and the two
strokes swap.  ``working`` names the slider's direction during the slow (working)
stroke, ``"outward"`` (B moving along +x, away from O2: the inner dead centre to the
outer) or ``"inward"``, with the crank turning as TH2D's sign says; the offset is then
negative for an outward working stroke with TH2D > 0 (and for an inward one with TH2D
< 0), positive otherwise.

**The best member** is the one whose least transmission angle (the angle between the rod
and the slider line's normal, 90 - |ATH3|; |ATH3| is the pressure angle at the slider)
is largest.  Over a turn sin|ATH3| = |offset - R2 sin th2| / R3 peaks at (R2 +
|offset|)/R3, so the search minimises that over lambda (``scipy.optimize.minimize_scalar``,
bounded, where scipy is installed: the ``synthesis`` extra; otherwise a golden-section
search).  For Q = 1 it is R2/R3 = 1/lambda, which keeps falling as the rod grows: the
search stops at ``ratio_max`` and ``best`` is the member there.

**The crank-and-slotted-lever shaper** (:class:`~sielaff.inverted_slider_crank.
InvertedSliderCrank`, offset 0: the crank O2-A, R2; the lever pivoted at O4 = (R1, 0),
its slot carrying the block pinned at A; the ram driven by the lever's end P, |O4 P| the
lever's length).  The lever turns back where it is tangent to the crank circle, the
crank square to it: there cos(th2) = R2/R1.  The return stroke is the crank's arc 2 beta
between those two positions that passes nearest O4, the cutting stroke the other, so

    beta = 180 / (Q + 1) [deg],   R1 = R2 / cos(beta),   the lever's swing 2 (90 - beta),

and P's two extremes lie a chord 2 |O4 P| sin(90 - beta) = 2 |O4 P| cos(beta) apart,
the ram's stroke S when the ram's line is that chord's: |O4 P| = S / (2 cos beta).  The
lever's length follows from S and Q alone; the crank (or R1) sets the scale.  This is
Khurmi and Gupta's construction (*Theory of Machines*, 14th ed., ch. 5, Example 5.3,
p. 112), written as algebra instead of a drawing.

Masses (as :func:`~sielaff.synthesis.common.masses` does for the four-bar): the crank,
the rod and the lever are uniform bars of one cross-section, pin to pin (W = density x
area x L, G half-way, ZI = (W / divisor) L^2 / 12); a slider or block is a piece of the
same bar as long as the crank, its centre of mass at its pin.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from sielaff.engine.assembly import golden
from sielaff.inverted_slider_crank import InvertedSliderCrank
from sielaff.mechanism import MASS_DIVISOR, STANDARD_GRAVITY
from sielaff.slider_crank import SliderCrank, validate_slider
from sielaff.slider_crank import stroke as dead_centres  # the parameters here are strokes
from sielaff.synthesis.common import AREA, DENSITY

__all__ = ["CrankShaper", "SliderCrankDesign", "SliderCrankFamily", "WORKING", "crank_shaper",
           "offset_slider_crank"]

#: The slider's direction during the slow (working) stroke (module doc).
WORKING = ("outward", "inward")
#: How close (relative) the search gets to the best ratio; the criterion is flat there, so
#: this pins the ratio, not only the criterion.
_XTOL = 1e-10


@dataclass(frozen=True)
class SliderCrankDesign:
    """One member of a :class:`SliderCrankFamily`.

    ``mechanism``: the :class:`~sielaff.slider_crank.SliderCrank` (default masses);
    ``branch``: the engine's branch it is built on (``"open"``, B right of A).  ``ratio``:
    R3/R2 [-], the free choice.  ``stroke`` [in or m] and ``time_ratio`` [-]: computed
    from its lengths (:func:`sielaff.slider_crank.stroke`).  ``working``: the slider's
    direction in the slow stroke (:data:`WORKING`); ``dead_centres``: THETA 2 [deg] where
    that stroke starts and ends, the crank turning as TH2D's sign says; ``working_arc``
    and ``return_arc``: the crank's turn [deg] in each stroke.  ``min_transmission``: the
    least transmission angle over a turn [deg], 90 - max |ATH3|.
    """

    mechanism: SliderCrank
    branch: str
    ratio: float
    stroke: float
    time_ratio: float
    working: str
    dead_centres: tuple[float, float]
    working_arc: float
    return_arc: float
    min_transmission: float


@dataclass(frozen=True)
class SliderCrankFamily:
    """The offset slider-cranks of one stroke and time ratio (module doc).

    ``stroke`` [in or m], ``time_ratio`` [-], ``alpha`` [deg]: the crank angle B1 O2 B2
    between the dead centres.  ``ratio_limit``: the family is 1 < R3/R2 < ratio_limit [-]
    (inf when Q = 1); ``ratio_range``: the part :meth:`members` samples and the search
    covers, (1, min(ratio_limit, ratio_max)).  ``best``: the member with the largest least
    transmission angle in that range.  ``working``, ``th2d`` [rad/sec], ``units``,
    ``density`` and ``area`` go into every member.
    """

    stroke: float
    time_ratio: float
    alpha: float
    working: str
    th2d: float
    units: str
    ratio_limit: float
    ratio_range: tuple[float, float]
    best: SliderCrankDesign
    density: float | None = None
    area: float | None = None

    def member(self, ratio: float) -> SliderCrankDesign:
        """The member whose rod is ``ratio`` [-] times its crank; ValueError (one line) if
        no member has that ratio."""
        r = _number("ratio", ratio)
        if not 1.0 < r < self.ratio_limit:
            raise ValueError(f"ratio = {r:g}: outside the family, 1 < R3/R2 < "
                             f"{self.ratio_limit:.6g} for time ratio {self.time_ratio:g}")
        return _design(self.stroke, self.alpha, r, self.working, self.th2d, self.units,
                       self.density, self.area)

    def members(self, n: int = 9) -> list[SliderCrankDesign]:
        """``n`` members spread evenly over :attr:`ratio_range` (its ends left out)."""
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise ValueError(f"n = {n!r}: a whole number of members, 1 or more")
        lo, hi = self.ratio_range
        return [self.member(lo + (hi - lo) * (i + 0.5) / n) for i in range(n)]


@dataclass(frozen=True)
class CrankShaper:
    """A crank-and-slotted-lever quick return (module doc).

    ``mechanism``: the :class:`~sielaff.inverted_slider_crank.InvertedSliderCrank`
    (offset 0, default masses, the lever's bar ``lever`` long); ``branch``: ``"open"``
    (A ahead of O4 along the lever).  ``stroke`` [in or m]: the ram's; ``time_ratio``
    [-]; ``crank`` = R2 and ``centres`` = R1 = |O2 O4| [in or m]; ``lever`` = |O4 P|
    [in or m]; ``swing``: the lever's swing [deg].  ``extremes``: THETA 2 [deg] where the
    lever turns back, the cutting stroke running from the first to the second with the
    crank turning as TH2D's sign says; ``lever_angles``: ATH4 [deg] there.
    ``cutting_arc`` and ``return_arc``: the crank's turn [deg] in each stroke.
    """

    mechanism: InvertedSliderCrank
    branch: str
    stroke: float
    time_ratio: float
    crank: float
    centres: float
    lever: float
    swing: float
    extremes: tuple[float, float]
    lever_angles: tuple[float, float]
    cutting_arc: float
    return_arc: float


def offset_slider_crank(stroke: float, time_ratio: float, *, working: str = "outward",
                        th2d: float = 1.0, units: str = "in-lb-sec", ratio_max: float = 10.0,
                        density: float | None = None,
                        area: float | None = None) -> SliderCrankFamily:
    """The offset slider-cranks whose slider travels ``stroke`` with time ratio
    ``time_ratio`` (module doc), and the best of them.

    Parameters
    ----------
    stroke : float
        The slider's travel between its dead centres [in or m], > 0.
    time_ratio : float
        The slow stroke's crank angle over the quick one's [-], 1 <= Q < 3 (Q = 1: the
        in-line slider-crank).
    working : {"outward", "inward"}
        The slider's direction in the slow stroke [-]: along +x (away from O2) or back.
    th2d : float
        The crank speed [rad/sec] put in each member, not 0; its sign is the way the
        crank turns, which ``working`` refers to.
    units : str
        The unit system [-], ``"in-lb-sec"`` or ``"SI"``.
    ratio_max : float
        [-] Where the sampling and the search of R3/R2 stop, > 1 (the family itself goes
        on to :attr:`SliderCrankFamily.ratio_limit`, infinite when Q = 1).
    density, area : float, optional
        The bars' material [lb/in^3 or kg/m^3] and cross-section [in^2 or m^2]; default
        steel, 0.5 in^2 or 3.125E-4 m^2 (:mod:`sielaff.synthesis.common`).

    Returns
    -------
    SliderCrankFamily
        Raises ValueError in one line naming the argument when there is no such family.
    """
    S, Q = _number("stroke", stroke), _number("time_ratio", time_ratio)
    if not S > 0.0:
        raise ValueError(f"stroke = {S:g}: the slider's travel must be > 0")
    if not 1.0 <= Q < 3.0:
        raise ValueError(f"time_ratio = {Q:g}: an offset slider-crank's time ratio is 1 or "
                         "more and below 3 (its dead centres are less than 90 deg apart)")
    if working not in WORKING:
        raise ValueError(f"working = {working!r}: one of {', '.join(WORKING)}")
    _check_common(th2d, units, density, area)
    rmax = _number("ratio_max", ratio_max)
    if not rmax > 1.0:
        raise ValueError(f"ratio_max = {rmax:g}: the rod/crank ratio's bound must be > 1")
    alpha = 180.0 * (Q - 1.0) / (Q + 1.0)
    h = math.radians(alpha) / 2.0
    limit = math.inf if alpha == 0.0 else (math.cos(h) / math.sin(h)) ** 2
    if not limit > 1.0:  # Q a rounding below 3
        raise ValueError(f"time_ratio = {Q!r}: too close to 3, the family is empty")
    hi = min(limit, rmax)

    def g(r: float) -> float:  # sin of the largest pressure angle, (R2 + |offset|)/R3
        R2, e = _lengths(S, alpha, r)
        return (R2 + e) / (r * R2)

    r = _bounded_min(g, 1.0, hi)
    if rmax < limit and g(rmax) <= g(r):  # the criterion still falling at the bound
        r = rmax
    best = _design(S, alpha, r, str(working), float(th2d), units, density, area)
    return SliderCrankFamily(S, Q, alpha, str(working), float(th2d), units, limit, (1.0, hi),
                             best, density, area)


def crank_shaper(stroke: float, time_ratio: float, *, crank: float | None = None,
                 centres: float | None = None, th2d: float = 1.0, units: str = "in-lb-sec",
                 density: float | None = None, area: float | None = None) -> CrankShaper:
    """The crank-and-slotted-lever shaper whose ram travels ``stroke`` with time ratio
    ``time_ratio`` (module doc), scaled by its crank or its centre distance.

    Parameters
    ----------
    stroke : float
        The ram's travel [in or m], > 0.
    time_ratio : float
        The cutting stroke's crank angle over the return's [-], > 1.
    crank : float, optional
        The crank R2 [in or m]; give it or ``centres``, not both.
    centres : float, optional
        R1 = |O2 O4| [in or m], the lever's pivot from the crank's.
    th2d : float
        The crank speed [rad/sec], not 0; its sign is the way the crank turns.
    units : str
        The unit system [-], ``"in-lb-sec"`` or ``"SI"``.
    density, area : float, optional
        The bars' material [lb/in^3 or kg/m^3] and cross-section [in^2 or m^2].

    Returns
    -------
    CrankShaper
        Raises ValueError in one line naming the argument when there is no such shaper:
        among others a crank so long that the block would run past the lever's end
        (R1 + R2 > |O4 P|, i.e. R2 > S / (2 (1 + cos beta))).
    """
    S, Q = _number("stroke", stroke), _number("time_ratio", time_ratio)
    if not S > 0.0:
        raise ValueError(f"stroke = {S:g}: the ram's travel must be > 0")
    if not Q > 1.0:
        raise ValueError(f"time_ratio = {Q:g}: a slotted lever's quick return has a time "
                         "ratio above 1 (at 1 its pivot would be infinitely far)")
    _check_common(th2d, units, density, area)
    if (crank is None) == (centres is None):
        raise ValueError(f"crank = {crank!r}, centres = {centres!r}: give one of them (the "
                         "other follows)")
    beta = 180.0 / (Q + 1.0)
    cb = math.cos(math.radians(beta))
    if crank is not None:
        R2 = _number("crank", crank)
        if not R2 > 0.0:
            raise ValueError(f"crank = {R2:g}: the crank's length must be > 0")
        R1 = R2 / cb
    else:
        R1 = _number("centres", centres)
        if not R1 > 0.0:
            raise ValueError(f"centres = {R1:g}: the distance O2-O4 must be > 0")
        R2 = R1 * cb
    lever = S / (2.0 * cb)
    if R1 + R2 > lever:
        name, value = ("crank", R2) if crank is not None else ("centres", R1)
        raise ValueError(f"{name} = {value:g}: the block would run past the lever's end "
                         f"(R1 + R2 = {R1 + R2:.6g} > lever {lever:.6g}); at most crank = "
                         f"{S / (2.0 * (1.0 + cb)):.6g} for this stroke and time ratio")
    rho, a = _material(units, density, area)
    w2, zi2 = _bar(R2, rho, a, units)
    w3, zi3 = _bar(R2, rho, a, units)
    w4, zi4 = _bar(lever, rho, a, units)
    m = InvertedSliderCrank(W2=w2, W3=w3, W4=w4, ZI2=zi2, ZI3=zi3, ZI4=zi4, R1=R1, R2=R2,
                            offset=0.0, ADEL2=0.0, ADEL3=0.0, ADEL4=0.0, RG2=R2 / 2.0,
                            RG3=0.0, RG4=lever / 2.0, TH2D=float(th2d), units=units)
    m.check()
    # with the crank at +-beta the lever (O4 -> A) points at 90 + beta and 270 - beta; the
    # CCW arc from beta to 360 - beta runs the far side of O2, the slow one
    ends, angles = (beta, 360.0 - beta), (90.0 + beta, 270.0 - beta)
    if th2d < 0.0:
        ends, angles = ends[::-1], angles[::-1]
    return CrankShaper(m, "open", S, Q, R2, R1, lever, 180.0 - 2.0 * beta, ends, angles,
                       360.0 - 2.0 * beta, 2.0 * beta)


def _number(name: str, value: object) -> float:
    """``value`` as a finite float, else a one-line ValueError naming ``name``."""
    try:
        if isinstance(value, bool):
            raise TypeError
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {value!r}: a number") from None
    if not math.isfinite(x):
        raise ValueError(f"{name} = {x:g}: a finite number")
    return x


def _check_common(th2d: float, units: str, density: float | None,
                  area: float | None) -> None:
    if not _number("th2d", th2d) != 0.0:
        raise ValueError("th2d = 0: the crank speed's sign says which stroke is the slow one")
    _material(units, density, area)


def _material(units: str, density: float | None, area: float | None) -> tuple[float, float]:
    if units not in STANDARD_GRAVITY:
        raise ValueError(f"units = {units!r}: the unit systems are {', '.join(STANDARD_GRAVITY)}")
    rho = DENSITY[units] if density is None else _number("density", density)
    a = AREA[units] if area is None else _number("area", area)
    if not rho > 0.0:
        raise ValueError(f"density = {rho:g}: it must be > 0")
    if not a > 0.0:
        raise ValueError(f"area = {a:g}: it must be > 0")
    return rho, a


def _bar(L: float, rho: float, a: float, units: str) -> tuple[float, float]:
    """W and ZI about its centre of a uniform bar of length ``L`` (module doc)."""
    w = rho * a * L
    return w, w / MASS_DIVISOR[units] * L * L / 12.0


def _lengths(S: float, alpha: float, r: float) -> tuple[float, float]:
    """R2 and |offset| of the member with R3/R2 = ``r`` (module doc; written without the
    difference L1^2 + L2^2 - 2 L1 L2 cos alpha, which cancels for a long rod)."""
    h = math.radians(alpha) / 2.0
    R2 = S / (2.0 * math.hypot(r * math.sin(h), math.cos(h)))
    return R2, R2 * R2 * (r * r - 1.0) * math.sin(2.0 * h) / S


def _design(S: float, alpha: float, r: float, working: str, th2d: float, units: str,
            density: float | None, area: float | None) -> SliderCrankDesign:
    R2, e = _lengths(S, alpha, r)
    R3 = r * R2
    # offset > 0 makes the inward stroke the slow one when the crank turns CCW (module doc)
    sign = 1.0 if (working == "inward") == (th2d > 0.0) else -1.0
    rho, a = _material(units, density, area)
    w2, zi2 = _bar(R2, rho, a, units)
    w3, zi3 = _bar(R3, rho, a, units)
    m = SliderCrank(W2=w2, W3=w3, W4=rho * a * R2, ZI2=zi2, ZI3=zi3, R2=R2, R3=R3,
                    offset=sign * e + 0.0, ADEL2=0.0, ADEL3=0.0, RG2=R2 / 2.0, RG3=R3 / 2.0,
                    TH2D=th2d, units=units)
    validate_slider(m)
    st = dead_centres(m)
    ends = (st.at_inner, st.at_outer) if working == "outward" else (st.at_outer, st.at_inner)
    arc = (math.copysign(1.0, th2d) * (ends[1] - ends[0])) % 360.0
    gamma = math.degrees(math.acos(min(1.0, (R2 + e) / R3)))
    return SliderCrankDesign(m, "open", r, st.length, arc / (360.0 - arc), working, ends, arc,
                             360.0 - arc, gamma)


def _bounded_min(f: Callable[[float], float], lo: float, hi: float) -> float:
    """Where ``f`` is least on (lo, hi): scipy's bounded Brent search where scipy is
    installed, else a golden-section search (``f`` has one minimum there)."""
    tol = _XTOL * max(1.0, abs(hi))
    try:
        from scipy.optimize import minimize_scalar
    except ImportError:
        return golden(f, lo, hi, tol)[0]
    res = minimize_scalar(f, bounds=(lo, hi), method="bounded",
                          options={"xatol": tol, "maxiter": 500})
    return float(res.x)
