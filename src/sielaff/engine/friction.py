"""Coulomb friction in the four pins: the torque it takes, and the power it loses.

``Scene(friction=PinFriction(mu, radius))`` puts the same friction in the four pins;
a mapping ``{"O2": PinFriction(...), "A": ..., "B": ..., "O4": ...}`` gives each pin its
own (a pin left out has none).  At a pin of radius r carrying the force F the members
exert on each other a couple ``mu r |F|`` opposing their relative rotation: at O2 the
crank's w2, at A w3 - w2, at B w4 - w3, at O4 w4 (rad/sec, CCW +).  Those couples, as
pure torques on links 2-4, change the pin forces (``statics.pins``, linear) and so their
own size: per position the fixed point

    T = mu r |F0 + C(T)|

is iterated from the frictionless pin forces F0 (C: the pin forces the couples T take)
until no pin's torque changes by more than ``tol`` times the largest at that position,
at most ``max_iter`` times.  The map contracts when ``mu r`` is small beside the links
and the transmission is good (friction_solve.contraction below 1: then the law has one
solution).  Elsewhere (near a toggle, where sin(th3 - th4) -> 0 and C grows without
bound) :mod:`sielaff.engine.friction_solve` solves the law by Newton, finds every
solution it has (``FRICTION_SOLUTIONS``) and takes the one continuous from mu = 0
(``FRICTION_STATUS`` 0), or the least friction of the others (3); only where none exists
does the linkage self-lock: NaN in every output friction changes (``FRICTION_STATUS``
2, and a :class:`FrictionWarning` says how many).  A pin whose relative rotation is
zero to within roundoff (a crank at rest, a rocker at its dead point: :func:`rest_sign`)
has static friction of unknown size, taken as zero there (``FRICTION_STATUS`` 1).

Friction is not superposable: the effect ``corrects`` the model's totals (pin forces
and TORQ) after the other effects are summed.  Outputs: ``TORQ_FRICTION`` (TORQ with
friction less TORQ without), ``PLOSS_O2``, ``PLOSS_A``, ``PLOSS_B``, ``PLOSS_O4`` (each
pin's friction power loss, ``mu r |F| |relative rotation|`` with the reported pin force,
>= 0, in-lb/sec or W), ``FRICTION_ITERATIONS`` (0 where the fixed point did not give the
answer), ``FRICTION_STATUS`` and ``FRICTION_SOLUTIONS``.  With mu = 0 at
every pin (or no friction) no step here runs and every output is bit for bit as
without friction.

The effect's steps are written once for both engines: the start, the frame (each pin's
sign and the geometry every pass takes as it is), the fixed point's pass (an iterated
step, :mod:`sielaff.engine.iterate`: over arrays the positions still iterating, in the
compiled kernel passes over a chunk), the check of where the law need not contract, the
solve there (array code, given an array of one by the kernel, which calls it only at
those positions: ``only_where``) and the losses, compiled by the numba backend for one
position with :mod:`sielaff.engine.arith`'s operations in
their one-position forms.  The FrictionWarning is declared with the solve's step
(``warns``) and issued by the model after it, on either backend.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.engine.arith import (
    batch,
    filled,
    flat,
    none,
    pick,
    positions,
    put,
    scatter,
    shape_of,
    shaped,
    unbatch,
)
from sielaff.engine.declare import Fact, Param, SpecForm
from sielaff.engine.friction_solve import contraction, solve
from sielaff.engine.iterate import iterated
from sielaff.engine.registry import Effect, step, step_of
from sielaff.engine.statics import pins, pins_on
from sielaff.engine.values import check_value

__all__ = ["PINS", "FrictionWarning", "PinFriction"]

#: The four pins, in the order of the chain: frame-crank, crank-coupler, coupler-rocker,
#: rocker-frame.
PINS = ("O2", "A", "B", "O4")

#: The frictionless totals the fixed point starts from, and what it corrects.
TOTALS = ("FA32X", "FA32Y", "FB34X", "FB34Y", "FOAX", "FOAY", "FOBX", "FOBY", "TORQ")


#: What the friction outputs every model shares mean (one text each, for every model).
MEANINGS = {
    "TORQ_FRICTION": "the part of TORQ friction takes (TORQ with it less TORQ without)",
    "FRICTION_ITERATIONS": "iterations of the friction solve (0 where it was not iterated)",
    "FRICTION_STATUS": "friction: 0 solved, 1 a joint at rest (to within roundoff), 2 no "
                       "solution (self-locking, NaN), 3 a solution not reached from mu = 0",
}

#: A joint's relative rate within STILL of the position's rates is zero (rest_sign).
STILL = 1e-12


def rest_sign(rel, scale):
    """The sign of a joint's relative rate, 0 where the joint is at rest to within roundoff.

    Parameters
    ----------
    rel : float or array
        The relative rate [rad/sec at a pin, in/sec or m/s at a slide].
    scale : float or array
        The sum of the sizes of the position's link rates [rad/sec] (at a slide, times
        a length of the linkage [in or m]): what its rates' roundoff is relative to.

    Returns
    -------
    0 where ``|rel| <= STILL * scale``, else the sign of ``rel`` (NaN for NaN) [-].

    Notes
    -----
    Coulomb friction's direction is the sign of the relative motion, which is not
    determined where that motion is zero.  A joint at rest by the mechanism's geometry (a
    rocker at its dead point, TH3D = TH4D at the 1966 example's THETA 2 = 180 deg) has a
    computed rate of a few ulps of its rates, of either sign, which may differ between
    machines; taking it as zero (static friction, taken as zero: FRICTION_STATUS 1) makes
    the answer the same everywhere.  Away from a dead point the relative rate grows in
    proportion to the crank's turn from it, so a joint in motion passes 1e-12 of the rates
    within some 1e-12 rad of crank angle (times the link ratios) of its dead point, where
    either answer is as right as the angle given.  One test for both engines, every kind
    and the dynamics' friction tables.
    """
    return np.where(np.abs(rel) <= STILL * scale, 0.0, np.sign(rel))


def loss_meaning(joint: str) -> str:
    """What ``PLOSS_<joint>`` means."""
    return f"power friction loses at {joint}, >= 0"


class FrictionWarning(UserWarning):
    """Some positions' pin friction did not converge: their results are NaN."""


@dataclass(frozen=True)
class PinFriction:
    """Coulomb friction in a pin (see the module doc).

    Parameters
    ----------
    mu : float
        Coefficient of friction [-], >= 0.
    radius : float
        The pin's (journal's) radius [in or m], >= 0.
    tol : float
        The fixed point stops when no pin's friction torque changes by more than
        ``tol`` times the largest at that position [-], > 0 (default 1e-13).
    max_iter : int
        At most this many iterations [-]; positions not converged by then are NaN.
    """

    mu: float
    radius: float
    tol: float = 1e-13
    max_iter: int = 100

    def __post_init__(self) -> None:
        for name in ("mu", "radius", "tol"):
            v = getattr(self, name)
            if isinstance(v, bool) or np.ndim(v) != 0:
                raise ValueError(f"PinFriction.{name} = {v!r}: a number")
            v = check_value(f"PinFriction.{name}", v)
            if v < 0.0 or (name == "tol" and not v > 0.0):
                raise ValueError(f"PinFriction.{name} = {v!r}: must be "
                                 f"{'> 0' if name == 'tol' else '>= 0'}")
            object.__setattr__(self, name, float(v))
        if isinstance(self.max_iter, bool) or not isinstance(self.max_iter, int | np.integer) \
                or not 1 <= self.max_iter <= 10000:
            raise ValueError(f"PinFriction.max_iter = {self.max_iter!r}: an integer, 1 to 10000")


def check_friction(v: Any, keys: tuple[str, ...] = PINS, noun: str = "pin") -> Any:
    """``Scene.friction`` checked: None, a PinFriction, or a mapping joint -> PinFriction
    (returned as a plain dict in the order of ``keys``: the four-bar's :data:`PINS`, or a
    linkage's pins and slides, ``noun`` "joint")."""
    if v is None or isinstance(v, PinFriction):
        return v
    if not isinstance(v, Mapping):
        names = "pin names " if noun == "pin" else ""
        raise ValueError(f"Scene.friction = {v!r}: None, a sielaff.PinFriction or a mapping "
                         f"of {names}{', '.join(keys)} to PinFriction")
    bad = [k for k in v if k not in keys]
    if bad:
        raise ValueError(f"Scene.friction: unknown {noun} {bad[0]!r} ({noun}s: "
                         f"{', '.join(keys)})")
    for k, f in v.items():
        if not isinstance(f, PinFriction):
            raise ValueError(f"Scene.friction[{k!r}] = {f!r} is not a sielaff.PinFriction")
    return {k: v[k] for k in keys if k in v}


def per_joint(friction: Any, keys: tuple[str, ...] = PINS) -> dict[str, PinFriction | None]:
    """Each joint of ``keys`` and its PinFriction (None: none there), from a checked
    ``Scene.friction``."""
    if friction is None:
        return dict.fromkeys(keys)
    if isinstance(friction, PinFriction):
        return dict.fromkeys(keys, friction)
    return {k: friction.get(k) for k in keys}


def _signs(TH2D, TH3D, TH4D):
    """The sign of each pin's relative rotation (O2, A, B, O4), 0 at rest (rest_sign)."""
    scale = np.abs(TH2D) + np.abs(TH3D) + np.abs(TH4D)
    return (rest_sign(TH2D, scale), rest_sign(TH3D - TH2D, scale),
            rest_sign(TH4D - TH3D, scale), rest_sign(TH4D, scale))


def couples(t, sg):
    """The moments on links 2, 3, 4 of the friction couples ``t`` (O2, A, B, O4) whose
    relative rotations have signs ``sg``: each opposes its member's rotation relative to
    the other member (on 3 at A: -sgn(w3 - w2) T_A; on 2 the reaction)."""
    m2 = sg[1] * t[1] - sg[0] * t[0]
    m3 = sg[2] * t[2] - sg[1] * t[1]
    m4 = -(sg[2] * t[2]) - sg[3] * t[3]
    return m2, m3, m4


# A position's eight pin-force components (FA32X, FA32Y, FB34X, FB34Y, FOAX, FOAY, FOBX,
# FOBY), four signs (O2, A, B, O4) and ten geometry values (R2, R3, R4, c2, s2, c3, s3, c4,
# s4, s34) travel as tuples; the helpers below are the step's own code (one definition
# for arrays and for one position, arith's operations where they differ).

def _torques(mur, f):
    """mu r |F| at O2 (FOA), A (FA32), B (FB34), O4 (FOB)."""
    return (mur[0] * np.hypot(f[4], f[5]), mur[1] * np.hypot(f[0], f[1]),
            mur[2] * np.hypot(f[2], f[3]), mur[3] * np.hypot(f[6], f[7]))


def _forces(t, sg, g):
    """The pin forces and TORQ share of the couples ``t`` (signs ``sg``, geometry ``g``)."""
    m2, m3, m4 = couples(t, sg)
    return pins(0.0, 0.0, m2, 0.0, 0.0, m3, 0.0, 0.0, m4, g[0], g[1], g[2], g[3], g[4],
                g[5], g[6], g[7], g[8], g[9])


def _forces_on(t, sg, R2, c2, s2, uv):
    """:func:`_forces` given ``uv``, pins_on's (ux, uy, vx, vy, d): the same numbers."""
    m2, m3, m4 = couples(t, sg)
    return pins_on(0.0, 0.0, m2, 0.0, 0.0, m3, 0.0, 0.0, m4, R2, c2, s2, uv[0], uv[1], uv[2],
                   uv[3], uv[4])


def _plus(f, c):
    """The eight pin-force components ``f`` plus the couples' share ``c``."""
    return (f[0] + c[0], f[1] + c[1], f[2] + c[2], f[3] + c[3], f[4] + c[4], f[5] + c[5],
            f[6] + c[6], f[7] + c[7])


def _pick4(v, idx):
    return (pick(v[0], idx), pick(v[1], idx), pick(v[2], idx), pick(v[3], idx))


def _pick8(v, idx):
    return _pick4(v, idx) + (pick(v[4], idx), pick(v[5], idx), pick(v[6], idx),
                             pick(v[7], idx))


def _pick10(v, idx):
    return _pick8(v, idx) + (pick(v[8], idx), pick(v[9], idx))


def _batch4(v, idx):
    return (batch(v[0], idx), batch(v[1], idx), batch(v[2], idx), batch(v[3], idx))


def _batch8(v, idx):
    return _batch4(v, idx) + (batch(v[4], idx), batch(v[5], idx), batch(v[6], idx),
                              batch(v[7], idx))


def _scatter9(dst, idx, c, where):
    """The nine corrections ``dst`` with ``c`` (at ``idx``) put where ``where`` holds."""
    return (scatter(dst[0], idx, c[0], where), scatter(dst[1], idx, c[1], where),
            scatter(dst[2], idx, c[2], where), scatter(dst[3], idx, c[3], where),
            scatter(dst[4], idx, c[4], where), scatter(dst[5], idx, c[5], where),
            scatter(dst[6], idx, c[6], where), scatter(dst[7], idx, c[7], where),
            scatter(dst[8], idx, c[8], where))


def _own9(c, shape):
    """Copies of the nine corrections, the step's own to change (``scatter``)."""
    return (put(filled(shape, 0.0), c[0], True), put(filled(shape, 0.0), c[1], True),
            put(filled(shape, 0.0), c[2], True), put(filled(shape, 0.0), c[3], True),
            put(filled(shape, 0.0), c[4], True), put(filled(shape, 0.0), c[5], True),
            put(filled(shape, 0.0), c[6], True), put(filled(shape, 0.0), c[7], True),
            put(filled(shape, 0.0), c[8], True))


def _largest(a):
    """The largest of four values at each position (NaN if one is)."""
    return np.maximum(np.maximum(np.maximum(a[0], a[1]), a[2]), a[3])


def _warn_status(status):
    """The FrictionWarning where some position has no solution of the law, or only ones
    not reached from mu = 0 (``FRICTION_STATUS`` 2 or 3 at the step's positions): the
    model calls it after the step, on either backend."""
    status = np.asarray(status)
    none_ = int(np.count_nonzero(status == 2.0))
    other = int(np.count_nonzero(status == 3.0))
    if none_ or other:
        warnings.warn(f"pin friction at {status.size} positions: {none_} have no solution of "
                      "the friction law (self-locking: NaN, FRICTION_STATUS 2), "
                      f"{other} only solutions not reached from mu = 0 (the least friction "
                      "taken, FRICTION_STATUS 3)", FrictionWarning, stacklevel=2)


_MUR = ("MUR_O2", "MUR_A", "MUR_B", "MUR_O4")
_F0 = ("FA32X_0", "FA32Y_0", "FB34X_0", "FB34Y_0", "FOAX_0", "FOAY_0", "FOBX_0", "FOBY_0")
_GEO = ("R2", "R3", "R4", "c2", "s2", "c3", "s3", "c4", "s4", "s34")
_RATES = ("TH2D", "TH3D", "TH4D")
# each pin's sign of rotation (_signs) and pins_on's geometry: the same at every pass
_SG = ("sg_o2", "sg_a", "sg_b", "sg_o4")
_UV = ("fr_ux", "fr_uy", "fr_vx", "fr_vy", "fr_d")
# the nine corrections (the eight pin-force components, TORQ's) of the fixed point, then
# of the solve where the law need not contract
_FIXED = ("fa32x_p", "fa32y_p", "fb34x_p", "fb34y_p", "foax_p", "foay_p", "fobx_p",
          "foby_p", "torq_p")
_SOLVED = tuple(n[:-2] + "_h" for n in _FIXED)

# The effect runs in six steps, so that the compiled kernel vectorises all but the
# solve where the law need not contract (array code, rare): the start, the frame (what
# every pass takes as it is, computed once), the fixed point (an iterated step:
# engine/iterate.py), the check of where the law need not contract (vectorised, so that
# the kernel calls the solve only there: only_where), that solve, and the losses.


def _all_finite(values):
    """Where every one of ``values`` (arrays or numbers) is finite: where the friction's
    solve runs (a pin force or an angle that is NaN or infinite stops it)."""
    finite = np.isfinite(values[0])
    for v in values[1:]:
        finite = finite & np.isfinite(v)
    return finite


@step(provides=("ft_o2_0", "ft_a_0", "ft_b_0", "ft_o4_0", "friction_go"),
      needs=_MUR + _F0 + ("c2", "s2", "c3", "s3", "c4", "s4", "s34"), zero_when=_MUR)
def _friction_start(MUR_O2, MUR_A, MUR_B, MUR_O4, FA32X_0, FA32Y_0, FB34X_0, FB34Y_0,
                    FOAX_0, FOAY_0, FOBX_0, FOBY_0, c2, s2, c3, s3, c4, s4, s34):
    """The fixed point's start, the frictionless pins' couples mu r |F0|, and where it
    runs (1.0: every force and angle finite)."""
    f0 = (FA32X_0, FA32Y_0, FB34X_0, FB34Y_0, FOAX_0, FOAY_0, FOBX_0, FOBY_0)
    finite = _all_finite(f0 + (c2, s2, c3, s3, c4, s4, s34))
    t = _torques((MUR_O2, MUR_A, MUR_B, MUR_O4), f0)
    return t[0], t[1], t[2], t[3], np.where(finite, 1.0, 0.0)


@step(provides=_SG + _UV, needs=_MUR + _RATES + ("R3", "R4", "c3", "s3", "c4", "s4", "s34"),
      zero_when=_MUR)
def _friction_frame(MUR_O2, MUR_A, MUR_B, MUR_O4, TH2D, TH3D, TH4D, R3, R4, c3, s3, c4, s4,
                    s34):
    """What every pass of the fixed point takes as it is: the pins' signs (_signs) and
    pins_on's u = B - A, v = B - O4 and d = v x u, as statics.pins computes them."""
    sg = _signs(TH2D, TH3D, TH4D)
    return (sg[0], sg[1], sg[2], sg[3], R3 * c3, R3 * s3, R4 * c4, R4 * s4,
            s34 * (R3 * R4))


@iterated(provides=_FIXED + ("iterations_p",), limit="friction_max_iter",
          go="friction_go", start=("ft_o2_0", "ft_a_0", "ft_b_0", "ft_o4_0"),
          consts=_F0 + _SG + ("R2", "c2", "s2") + _UV + _MUR + ("friction_tol",),
          zero_when=_MUR)
def _friction_fixed_point(t_O2, t_A, t_B, t_O4, FA32X_0, FA32Y_0, FB34X_0, FB34Y_0, FOAX_0,
                          FOAY_0, FOBX_0, FOBY_0, sg_o2, sg_a, sg_b, sg_o4, R2, c2, s2,
                          fr_ux, fr_uy, fr_vx, fr_vy, fr_d, MUR_O2, MUR_A, MUR_B, MUR_O4,
                          friction_tol):
    """One pass of the fixed point: the couples T give the pin forces, and those the new
    couples; done where no couple changed by more than tol times the largest."""
    t = (t_O2, t_A, t_B, t_O4)
    c = _forces_on(t, (sg_o2, sg_a, sg_b, sg_o4), R2, c2, s2,
                   (fr_ux, fr_uy, fr_vx, fr_vy, fr_d))
    new = _torques((MUR_O2, MUR_A, MUR_B, MUR_O4), _plus(
        (FA32X_0, FA32Y_0, FB34X_0, FB34Y_0, FOAX_0, FOAY_0, FOBX_0, FOBY_0), c))
    change = _largest((np.abs(new[0] - t[0]), np.abs(new[1] - t[1]),
                       np.abs(new[2] - t[2]), np.abs(new[3] - t[3])))
    scale = _largest(new)
    blown = ~np.isfinite(scale)
    done = (change <= friction_tol * scale) & ~blown  # False for NaN and inf
    return (new[0], new[1], new[2], new[3], c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7],
            c[8], done, ~done & ~blown)


@step(provides=("friction_status_0", "friction_hard"),
      needs=_MUR + ("friction_go",) + _RATES + ("R3", "R4", "s34"), zero_when=_MUR)
def _friction_check(MUR_O2, MUR_A, MUR_B, MUR_O4, friction_go, TH2D, TH3D, TH4D, R3, R4,
                    s34):
    """The status where the fixed point answers (1.0 where a pin is at rest, else 0.0),
    and where the law need not contract (1.0: the solve's array code runs there)."""
    sg = _signs(TH2D, TH3D, TH4D)
    status = np.where((sg[0] == 0.0) | (sg[1] == 0.0) | (sg[2] == 0.0) | (sg[3] == 0.0),
                      1.0, 0.0)
    hard = (friction_go != 0.0) & ~(contraction((MUR_O2, MUR_A, MUR_B, MUR_O4), R3, R4, s34)
                                    < 1.0)
    return status, np.where(hard, 1.0, 0.0)


@step(provides=_SOLVED + ("FRICTION_ITERATIONS", "FRICTION_STATUS"),
      needs=_MUR + _FIXED + ("iterations_p", "friction_status_0", "friction_hard")
      + _F0 + _RATES + _GEO,
      zero_when=_MUR, warns=(("FRICTION_STATUS",), _warn_status),
      only_where=("friction_hard", _FIXED + ("iterations_p", "friction_status_0")))
def _friction_solve(MUR_O2, MUR_A, MUR_B, MUR_O4, fa32x_p, fa32y_p, fb34x_p, fb34y_p,
                    foax_p, foay_p, fobx_p, foby_p, torq_p, iterations_p, friction_status_0,
                    friction_hard, FA32X_0, FA32Y_0, FB34X_0, FB34Y_0, FOAX_0, FOAY_0,
                    FOBX_0, FOBY_0, TH2D, TH3D, TH4D, R2, R3, R4, c2, s2, c3, s3, c4, s4,
                    s34):
    """The fixed point's answer, or the solve's where the law need not contract
    (``friction_hard``), and the status of each position: elsewhere the fixed point's
    corrections, count and status as they are (``only_where``)."""
    shape = shape_of((fa32x_p, friction_hard, FA32X_0, FA32Y_0, FB34X_0, FB34Y_0, FOAX_0,
                      FOAY_0, FOBX_0, FOBY_0, R2, R3, R4, c2, s2, c3, s3, c4, s4, s34, TH2D,
                      TH3D, TH4D))
    geo = (flat(R2, shape), flat(R3, shape), flat(R4, shape), flat(c2, shape),
           flat(s2, shape), flat(c3, shape), flat(s3, shape), flat(c4, shape),
           flat(s4, shape), flat(s34, shape))
    f0 = (flat(FA32X_0, shape), flat(FA32Y_0, shape), flat(FB34X_0, shape),
          flat(FB34Y_0, shape), flat(FOAX_0, shape), flat(FOAY_0, shape),
          flat(FOBX_0, shape), flat(FOBY_0, shape))
    mur = (MUR_O2, MUR_A, MUR_B, MUR_O4)
    corr = (flat(fa32x_p, shape), flat(fa32y_p, shape), flat(fb34x_p, shape),
            flat(fb34y_p, shape), flat(foax_p, shape), flat(foay_p, shape),
            flat(fobx_p, shape), flat(foby_p, shape), flat(torq_p, shape))
    iterations = flat(iterations_p, shape)
    status = put(filled(shape, 0.0), flat(friction_status_0, shape), True)  # its own
    # where the law need not be a contraction, every solution it has (friction_solve.py)
    hard = positions(flat(friction_hard, shape) != 0.0)
    if not none(hard):
        signs = _signs(TH2D, TH3D, TH4D)
        sg = (flat(signs[0], shape), flat(signs[1], shape), flat(signs[2], shape),
              flat(signs[3], shape))
        x0, x1, _, found = solve(_batch8(f0, hard), mur, _batch4(sg, hard),
                                 batch(geo[1], hard), batch(geo[2], hard),
                                 batch(geo[5], hard), batch(geo[6], hard),
                                 batch(geo[7], hard), batch(geo[8], hard),
                                 batch(geo[9], hard))
        x0, x1, found = unbatch(x0), unbatch(x1), unbatch(found)
        fixed0, fixed1 = pick(corr[2], hard), pick(corr[3], hard)  # the fixed point's x
        same = (pick(iterations, hard) > 0.0) & (found == 0.0) & (
            np.hypot(fixed0 - np.where(np.isnan(x0), 0.0, x0),
                     fixed1 - np.where(np.isnan(x1), 0.0, x1))
            <= 1e-8 * (np.hypot(fixed0, fixed1) + np.hypot(pick(f0[2], hard),
                                                            pick(f0[3], hard))))
        new_x = ~same  # the fixed point's answer is kept where it is the continuous one
        f_h = _pick8(f0, hard)
        t_new = _torques(mur, (f_h[0] + x0 * -1.0, f_h[1] + x1 * -1.0, f_h[2] + x0 * 1.0,
                               f_h[3] + x1 * 1.0, f_h[4] + x0 * -1.0, f_h[5] + x1 * -1.0,
                               f_h[6] + x0 * 1.0, f_h[7] + x1 * 1.0))
        corr = _scatter9(_own9(corr, shape), hard,
                         _forces(t_new, _pick4(sg, hard), _pick10(geo, hard)), new_x)
        iterations = scatter(put(filled(shape, 0.0), iterations, True), hard, 0.0, new_x)
        status = scatter(status, hard, np.where(found == 0.0, pick(status, hard), found),
                         new_x)
    return (shaped(corr[0], shape), shaped(corr[1], shape), shaped(corr[2], shape),
            shaped(corr[3], shape), shaped(corr[4], shape), shaped(corr[5], shape),
            shaped(corr[6], shape), shaped(corr[7], shape), shaped(corr[8], shape),
            shaped(iterations, shape), shaped(status, shape))


@step(provides=("fa32x_f", "fa32y_f", "fb34x_f", "fb34y_f", "foax_f", "foay_f", "fobx_f",
                "foby_f", "TORQ_FRICTION", "PLOSS_O2", "PLOSS_A", "PLOSS_B", "PLOSS_O4"),
      needs=_MUR + _SOLVED + ("FRICTION_STATUS", "friction_go") + _F0 + _RATES,
      zero_when=_MUR)
def _friction_losses(MUR_O2, MUR_A, MUR_B, MUR_O4, fa32x_h, fa32y_h, fb34x_h, fb34y_h,
                     foax_h, foay_h, fobx_h, foby_h, torq_h, FRICTION_STATUS, friction_go,
                     FA32X_0, FA32Y_0, FB34X_0, FB34Y_0, FOAX_0, FOAY_0, FOBX_0, FOBY_0,
                     TH2D, TH3D, TH4D):
    """The corrections (NaN where the position has no answer) and each pin's loss."""
    failed = (friction_go == 0.0) | (FRICTION_STATUS == 2.0)
    corr = (np.where(failed, np.nan, fa32x_h), np.where(failed, np.nan, fa32y_h),
            np.where(failed, np.nan, fb34x_h), np.where(failed, np.nan, fb34y_h),
            np.where(failed, np.nan, foax_h), np.where(failed, np.nan, foay_h),
            np.where(failed, np.nan, fobx_h), np.where(failed, np.nan, foby_h),
            np.where(failed, np.nan, torq_h))
    # each pin's loss from the reported force: mu r |F| |relative rotation|
    final = _torques((MUR_O2, MUR_A, MUR_B, MUR_O4), _plus(
        (FA32X_0, FA32Y_0, FB34X_0, FB34Y_0, FOAX_0, FOAY_0, FOBX_0, FOBY_0), corr))
    sg = _signs(TH2D, TH3D, TH4D)
    rel = (np.abs(TH2D), np.abs(TH3D - TH2D), np.abs(TH4D - TH3D), np.abs(TH4D))
    loss = (np.where(failed, np.nan, np.where(sg[0] == 0.0, 0.0, final[0] * rel[0])),
            np.where(failed, np.nan, np.where(sg[1] == 0.0, 0.0, final[1] * rel[1])),
            np.where(failed, np.nan, np.where(sg[2] == 0.0, 0.0, final[2] * rel[2])),
            np.where(failed, np.nan, np.where(sg[3] == 0.0, 0.0, final[3] * rel[3])))
    return corr + loss


@step(provides=("FRICTION_SOLUTIONS",),
      needs=("MUR_O2", "MUR_A", "MUR_B", "MUR_O4", "FA32X_0", "FA32Y_0", "FB34X_0", "FB34Y_0",
             "FOAX_0", "FOAY_0", "FOBX_0", "FOBY_0", "TH2D", "TH3D", "TH4D", "R3", "R4", "c3",
             "s3", "c4", "s4", "s34"),
      zero_when=("MUR_O2", "MUR_A", "MUR_B", "MUR_O4"))
def _friction_solutions(MUR_O2, MUR_A, MUR_B, MUR_O4, FA32X_0, FA32Y_0, FB34X_0, FB34Y_0,
                        FOAX_0, FOAY_0, FOBX_0, FOBY_0, TH2D, TH3D, TH4D, R3, R4, c3, s3, c4,
                        s4, s34):
    """How many solutions the law has at each position: 1 where it contracts (proved),
    else the search's count (friction_solve.py); asked for, it runs the search everywhere
    the law need not contract, which the solve itself does only where it must."""
    shape = shape_of((FA32X_0, FA32Y_0, FB34X_0, FB34Y_0, FOAX_0, FOAY_0, FOBX_0, FOBY_0,
                      TH2D, TH3D, TH4D, R3, R4, c3, s3, c4, s4, s34))
    f0 = (flat(FA32X_0, shape), flat(FA32Y_0, shape), flat(FB34X_0, shape),
          flat(FB34Y_0, shape), flat(FOAX_0, shape), flat(FOAY_0, shape),
          flat(FOBX_0, shape), flat(FOBY_0, shape))
    geo = (flat(R3, shape), flat(R4, shape), flat(c3, shape), flat(s3, shape),
           flat(c4, shape), flat(s4, shape), flat(s34, shape))
    signs = _signs(TH2D, TH3D, TH4D)
    sg = (flat(signs[0], shape), flat(signs[1], shape), flat(signs[2], shape),
          flat(signs[3], shape))
    mur = (MUR_O2, MUR_A, MUR_B, MUR_O4)
    finite = _all_finite(f0 + geo)
    count = np.where(finite, 1.0, 0.0)
    hard = positions(finite & ~(contraction(mur, geo[0], geo[1], geo[6]) < 1.0))
    if not none(hard):
        found = solve(_batch8(f0, hard), mur, _batch4(sg, hard), batch(geo[0], hard),
                      batch(geo[1], hard), batch(geo[2], hard), batch(geo[3], hard),
                      batch(geo[4], hard), batch(geo[5], hard), batch(geo[6], hard),
                      count_all=True)[2]
        count = scatter(count, hard, unbatch(found), pick(finite, hard))
    return shaped(count, shape)


def mu_r(scene: Any) -> dict[str, float]:
    """Each pin's mu r [in or m] in ``scene`` (0 where it has none): what the effect
    seeds, and what the dynamics' friction tables take."""
    return {k: 0.0 if f is None else f.mu * f.radius for k, f in per_joint(scene.friction).items()}


def _seed(scene: Any, mechanism: Any) -> dict[str, Any]:
    per = per_joint(scene.friction)
    ns: dict[str, Any] = {f"MUR_{k}": v for k, v in mu_r(scene).items()}
    given = [f for f in per.values() if f is not None]
    ns["friction_tol"] = min((f.tol for f in given), default=1e-13)
    ns["friction_max_iter"] = max((f.max_iter for f in given), default=100)
    return ns


def has_friction(scene: Any) -> bool:
    """Whether some pin of ``scene`` has friction (mu r > 0): the effect's one rule."""
    return any(v > 0.0 for v in mu_r(scene).values())


def _describe(scene: Any, units: str) -> list[Fact]:
    facts = []
    for pin, f in per_joint(scene.friction).items():
        if f is None:
            facts.append(Fact(pin, "friction", "none"))
            continue
        facts += [Fact(pin, "mu", f.mu, "number"), Fact(pin, "pin radius", f.radius, "length")]
    return facts


def _figures(r: Any, scene: Any, units: str, speed: float) -> list[Fact]:
    """Each pin's friction loss, and all of it, as a mean power over the revolution's grid
    and as the energy of one revolution at the crank speed."""
    facts = []
    total = 0.0
    for pin in PINS:
        loss = float(np.mean(np.asarray(r[f"PLOSS_{pin}"])))
        total += loss
        facts.append(Fact(f"loss at {pin}", "mean", loss, "power"))
        if speed:
            facts.append(Fact(f"loss at {pin}", "per revolution", loss * 2.0 * np.pi / speed,
                              "work"))
    facts.append(Fact("loss in all", "mean", total, "power"))
    if speed:
        facts.append(Fact("loss in all", "per revolution", total * 2.0 * np.pi / speed, "work"))
    status = np.asarray(r["FRICTION_STATUS"])
    for code, words in ((2.0, "self-locking (no solution: NaN)"),
                        (3.0, "solved off the branch from mu = 0")):
        n = int(np.count_nonzero(status == code))
        if n:
            facts.append(Fact(words, "positions of the grid", str(n)))
    return facts


#: A pin's friction keys: mu and radius, and the fixed point's tol and max_iter (optional).
FRICTION_KEYS = ("mu", "radius", "tol", "max_iter")


def _read(table: Any, path: str, reader: Any) -> dict[str, Any]:
    """``[scene.friction]`` with mu and radius (every pin alike), or one table per pin
    (``[scene.friction.O2]``, ...), as Scene.friction."""
    if "friction" not in table:
        return {}
    where = f"{path}: [scene.friction]"
    t = reader.table(where, table["friction"])
    pins = [k for k in t if k in PINS]
    if pins and any(k in FRICTION_KEYS for k in t):
        raise reader.error(f"{where}: give mu and radius for every pin, or a table per pin "
                           f"({', '.join(PINS)}), not both")
    if not pins:
        return {"friction": _pin_of(where, t, reader)}
    reader.unknown(where, t, PINS)
    return {"friction": {pin: _pin_of(f"{where[:-1]}.{pin}]", v, reader)
                         for pin, v in t.items()}}


def _pin_of(where: str, table: Any, reader: Any) -> PinFriction:
    table = reader.table(where, table)
    reader.unknown(where, table, FRICTION_KEYS)
    for key in ("mu", "radius"):
        if key not in table:
            raise reader.error(f"{where} has no {key} (write mu = ..., radius = ...)")
    extra: dict[str, Any] = {}
    if "tol" in table:
        extra["tol"] = reader.number(f"{where} tol", table["tol"])
    if "max_iter" in table:
        n = table["max_iter"]
        if isinstance(n, bool) or not isinstance(n, int):
            raise reader.error(f"{where} max_iter = {n!r}: a whole number, 1 to 10000")
        extra["max_iter"] = n
    try:
        return PinFriction(reader.number(f"{where} mu", table["mu"]),
                           reader.number(f"{where} radius", table["radius"]), **extra)
    except ValueError as exc:
        raise reader.error(f"{where}: {exc}") from None


def _write(scene: Any) -> dict[str, Any]:
    def one(f: PinFriction) -> dict[str, Any]:
        return {"mu": f.mu, "radius": f.radius, "tol": f.tol, "max_iter": f.max_iter}

    f = scene.friction
    if f is None:
        return {}
    if isinstance(f, PinFriction):
        return {"friction": one(f)}
    return {"friction": {pin: one(v) for pin, v in f.items()}}


_HELP = """\
[scene.friction]              # Coulomb friction, the same in the four pins ...
mu = 0.1                      # coefficient of friction
radius = 0.25                 # the pin's radius, in or m
tol = 1e-13                   # optional: the fixed point's tolerance ...
max_iter = 100                # ... and its iterations (PinFriction)
# ... or each pin its own (a pin left out has none):
# [scene.friction.O2]  mu = 0.1  radius = 0.5      (pins O2, A, B, O4)"""


EFFECT = Effect("pin friction", (step_of(_friction_start), step_of(_friction_frame),
                                   step_of(_friction_fixed_point),
                                   step_of(_friction_check), step_of(_friction_solve),
                                   step_of(_friction_losses),
                                   step_of(_friction_solutions)), _seed,
                torque="TORQ_FRICTION",
                corrects={**{t: t.lower() + "_f" for t in TOTALS[:-1]},
                          "TORQ": "TORQ_FRICTION"},
                switch=("MUR_O2", "MUR_A", "MUR_B", "MUR_O4"),
                params=(Param("friction", None, check_friction,
                              "None, PinFriction or mapping\n    Coulomb friction in the pins: "
                              "one :class:`~sielaff.engine.friction.PinFriction`\n    for all "
                              'four, or ``{"O2": ..., "A": ..., "B": ..., "O4": ...}`` (a pin '
                              "left out\n    has none)."),),
                outputs={"TORQ_FRICTION": ("torque", MEANINGS["TORQ_FRICTION"]),
                         **{f"PLOSS_{pin}": ("power", loss_meaning(pin)) for pin in PINS},
                         "FRICTION_ITERATIONS": ("number", MEANINGS["FRICTION_ITERATIONS"]),
                         "FRICTION_STATUS": ("number", MEANINGS["FRICTION_STATUS"]),
                         "FRICTION_SOLUTIONS": ("number", "how many solutions the friction "
                                                          "law has at the position")},
                on=has_friction, summary=lambda scene, units: "pin friction",
                describe=_describe,
                figure_outputs=lambda scene: tuple(f"PLOSS_{p}" for p in PINS)
                + ("FRICTION_STATUS",),
                figures=_figures,
                columns=lambda scene: ("TORQ_FRICTION",) + tuple(f"PLOSS_{p}" for p in PINS)
                + ("FRICTION_STATUS", "FRICTION_SOLUTIONS"),
                spec=SpecForm(("friction",), _read, _write, _HELP))
