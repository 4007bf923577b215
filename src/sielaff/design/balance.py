"""Counterweights on links 2 and 4 that cancel the shaking force at every position.

In:  a mechanism (weights in lb, or masses in kg in SI: the W fields), and optionally the
     radius of each counterweight from its pivot (length unit; default R2 and R4).
Out: the balanced mechanism, each counterweight a point mass merged into its link.

The method of linearly independent vectors (Berkof and Lowen, "A new method for
completely force balancing simple linkages", J. Eng. Ind. 91(1), 1969).  The total
centre of mass of links 2-4 is, with the loop closure
``R2 e^{i th2} + R3 e^{i th3} = R1 + R4 e^{i th4}`` solved for e^{i th3},

    M rG = e^{i th2} [P2 + W3 R2 (1 - (RG3/R3) e^{i d3})]
         + e^{i th4} [P4 + W3 RG3 (R4/R3) e^{i d3}] + constant

(P_k = W_k RG_k e^{i d_k}, d_k = ADEL_k: each link's first moment in its own frame).
e^{i th2} and e^{i th4} are independent, so rG stands still, and the shaking force is zero
at every position and speed, exactly when both brackets vanish:

    P2* = W3 R2 ((RG3/R3) e^{i d3} - 1),   P4* = -W3 RG3 (R4/R3) e^{i d3}

A counterweight on link k supplies ``P_k* - P_k`` at the chosen radius.  Merged in, it gives
W_k' = W_k + Wc, RG_k' e^{i ADEL_k'} = P_k* / W_k', and ZI_k' about the new G by the
parallel-axis theorem (the counterweight a point mass).  The shaking moment and the
driving torque are not balanced: they usually grow, the price
:func:`sielaff.design.report.balance_lines` shows.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.mechanism import MASS_DIVISOR, Mechanism

__all__ = ["Counterweight", "balance", "counterweights"]


@dataclass(frozen=True)
class Counterweight:
    """A point counterweight on link 2 or 4: ``weight`` (lb, or kg in SI), ``radius``
    from the link's pivot (length unit) and ``angle`` (degrees, CCW from the link's line,
    like ADEL)."""

    link: int
    weight: Any
    radius: Any
    angle: Any


def _refuse(mechanism: Any) -> None:
    """One line for any kind but the four-bar: the method needs its two independent
    rotating links (a slider-crank's slider does not turn: design.slider_balance)."""
    if isinstance(mechanism, Mechanism):
        return
    from sielaff.design.kinds import is_slider_crank, kind_name

    where = ("; a slider-crank's shaking force cannot be cancelled by counterweights: "
             "sielaff.design.slider_balance gives what a crank counterweight leaves"
             if is_slider_crank(mechanism) else "")
    raise ValueError(f"balance: Berkof-Lowen counterweights are for the four-bar, not a "
                     f"{kind_name(mechanism)}{where}")


def _required(m: Mechanism) -> tuple[Any, Any]:
    d3 = np.exp(1j * np.radians(np.asarray(m.ADEL3, dtype=float)))
    p2 = m.W3 * m.R2 * (m.RG3 / m.R3 * d3 - 1.0)
    p4 = -m.W3 * m.RG3 * (m.R4 / m.R3) * d3
    return p2, p4


def _moment(w, rg, adel):
    return w * rg * np.exp(1j * np.radians(np.asarray(adel, dtype=float)))


def counterweights(mechanism: Mechanism, radius2: Any = None, radius4: Any = None
                   ) -> tuple[Counterweight, Counterweight]:
    """The two counterweights (links 2 and 4) that balance ``mechanism`` fully.

    Parameters
    ----------
    mechanism : Mechanism
        A four-bar [its unit system]; any other kind is refused in one line (a
        slider-crank's answer is :func:`sielaff.design.slider_balance.slider_balance`).
    radius2, radius4 : float or array, optional
        Each counterweight's distance from its pivot [in or m]; default R2 and R4.
    """
    _refuse(mechanism)
    m = mechanism
    r2 = m.R2 if radius2 is None else radius2
    r4 = m.R4 if radius4 is None else radius4
    for name, r in (("radius2", r2), ("radius4", r4)):
        if not np.all(np.asarray(r, dtype=float) > 0.0):
            raise ValueError(f"{name} = {r!r}: a counterweight's radius must be > 0")
    p2, p4 = _required(m)
    c2 = p2 - _moment(m.W2, m.RG2, m.ADEL2)
    c4 = p4 - _moment(m.W4, m.RG4, m.ADEL4)
    return (Counterweight(2, np.abs(c2) / r2, r2, np.degrees(np.angle(c2))),
            Counterweight(4, np.abs(c4) / r4, r4, np.degrees(np.angle(c4))))


def _merge(w, zi, rg, adel, c: Counterweight, divisor: float):
    """(W, ZI, RG, ADEL) of a link with the point counterweight ``c`` merged in."""
    g_old = _moment(1.0, rg, adel)
    g_c = _moment(1.0, c.radius, c.angle)
    w_new = w + c.weight
    with np.errstate(all="ignore"):
        # real fractions of the weight: a complex division by a subnormal weight scales
        # by its reciprocal (inf) and turns 0 into NaN
        g_new = np.where(w_new > 0, (w / w_new) * g_old + (c.weight / w_new) * g_c, 0.0)
    zi_new = zi + (w * np.abs(g_old - g_new) ** 2 + c.weight * np.abs(g_c - g_new) ** 2) / divisor
    rg_new = np.abs(g_new)
    adel_new = np.where(rg_new > 0, np.degrees(np.angle(g_new)), 0.0)
    return w_new, zi_new, rg_new, adel_new


def balance(mechanism: Mechanism, radius2: Any = None, radius4: Any = None) -> Mechanism:
    """``mechanism`` fully force-balanced: counterweights at ``radius2`` on the crank and
    ``radius4`` on the rocker (default R2 and R4) merged into links 2 and 4, so that every
    tool runs on the result unchanged.  Fields may be arrays (designs).

    Parameters
    ----------
    mechanism : Mechanism
        A four-bar [its unit system]; any other kind is refused in one line.
    radius2, radius4 : float or array, optional
        Each counterweight's distance from its pivot [in or m]; default R2 and R4.
    """
    _refuse(mechanism)
    m = mechanism
    cw2, cw4 = counterweights(m, radius2, radius4)
    divisor = MASS_DIVISOR[m.units]
    w2, zi2, rg2, adel2 = _merge(m.W2, m.ZI2, m.RG2, m.ADEL2, cw2, divisor)
    w4, zi4, rg4, adel4 = _merge(m.W4, m.ZI4, m.RG4, m.ADEL4, cw4, divisor)
    scalar = all(np.ndim(v) == 0 for v in m.as_tuple())
    out = {"W2": w2, "ZI2": zi2, "RG2": rg2, "ADEL2": adel2,
           "W4": w4, "ZI4": zi4, "RG4": rg4, "ADEL4": adel4}
    if scalar:
        out = {k: float(v) for k, v in out.items()}
    return m.replace(**out)
