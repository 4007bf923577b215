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
exactly zero (a crank at rest, a rocker at its dead point) has static friction of
unknown size, taken as zero there (``FRICTION_STATUS`` 1).

Friction is not superposable: the effect ``corrects`` the model's totals (pin forces
and TORQ) after the other effects are summed.  Outputs: ``TORQ_FRICTION`` (TORQ with
friction less TORQ without), ``PLOSS_O2``, ``PLOSS_A``, ``PLOSS_B``, ``PLOSS_O4`` (each
pin's friction power loss, ``mu r |F| |relative rotation|`` with the reported pin force,
>= 0, in-lb/sec or W), ``FRICTION_ITERATIONS`` (0 where the fixed point did not give the
answer), ``FRICTION_STATUS`` and ``FRICTION_SOLUTIONS``.  With mu = 0 at
every pin (or no friction) no step here runs and every output is bit for bit as
without friction.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.engine.declare import Fact, Param, SpecForm
from sielaff.engine.friction_solve import contraction, solve
from sielaff.engine.registry import Effect, step, step_of
from sielaff.engine.statics import pins
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
    "FRICTION_STATUS": "friction: 0 solved, 1 a relative motion is zero, 2 no solution "
                       "(self-locking, NaN), 3 a solution not reached from mu = 0",
}


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
    """The sign of each pin's relative rotation (O2, A, B, O4)."""
    return (np.sign(TH2D), np.sign(TH3D - TH2D), np.sign(TH4D - TH3D), np.sign(TH4D))


def couples(t, sg):
    """The moments on links 2, 3, 4 of the friction couples ``t`` (O2, A, B, O4) whose
    relative rotations have signs ``sg``: each opposes its member's rotation relative to
    the other member (on 3 at A: -sgn(w3 - w2) T_A; on 2 the reaction)."""
    m2 = sg[1] * t[1] - sg[0] * t[0]
    m3 = sg[2] * t[2] - sg[1] * t[1]
    m4 = -(sg[2] * t[2]) - sg[3] * t[3]
    return m2, m3, m4


@step(provides=("fa32x_f", "fa32y_f", "fb34x_f", "fb34y_f", "foax_f", "foay_f", "fobx_f",
                "foby_f", "TORQ_FRICTION", "PLOSS_O2", "PLOSS_A", "PLOSS_B", "PLOSS_O4",
                "FRICTION_ITERATIONS", "FRICTION_STATUS"),
      needs=("MUR_O2", "MUR_A", "MUR_B", "MUR_O4", "friction_tol", "friction_max_iter",
             "FA32X_0", "FA32Y_0", "FB34X_0", "FB34Y_0", "FOAX_0", "FOAY_0", "FOBX_0",
             "FOBY_0", "TH2D", "TH3D", "TH4D", "R2", "R3", "R4", "c2", "s2", "c3", "s3",
             "c4", "s4", "s34"),
      zero_when=("MUR_O2", "MUR_A", "MUR_B", "MUR_O4"))
def _friction(MUR_O2, MUR_A, MUR_B, MUR_O4, friction_tol, friction_max_iter,
              FA32X_0, FA32Y_0, FB34X_0, FB34Y_0, FOAX_0, FOAY_0, FOBX_0, FOBY_0,
              TH2D, TH3D, TH4D, R2, R3, R4, c2, s2, c3, s3, c4, s4, s34):
    geo = (R2, R3, R4, c2, s2, c3, s3, c4, s4, s34)
    f0 = (FA32X_0, FA32Y_0, FB34X_0, FB34Y_0, FOAX_0, FOAY_0, FOBX_0, FOBY_0)
    shape = np.broadcast_shapes(*(np.shape(x) for x in f0 + geo + (TH2D, TH3D, TH4D)))
    n = int(np.prod(shape))

    def flat(x):
        return np.broadcast_to(np.asarray(x, dtype=float), shape).reshape(-1)

    geo_f = [flat(x) for x in geo]
    f0_f = [flat(x) for x in f0]
    sg = [flat(x) for x in _signs(TH2D, TH3D, TH4D)]

    def torques(f):
        """mu r |F| at O2 (FOA), A (FA32), B (FB34), O4 (FOB)."""
        return (MUR_O2 * np.hypot(f[4], f[5]), MUR_A * np.hypot(f[0], f[1]),
                MUR_B * np.hypot(f[2], f[3]), MUR_O4 * np.hypot(f[6], f[7]))

    def forces(t, idx):
        """The pin forces and TORQ share of the couples t at positions idx."""
        m2, m3, m4 = couples(t, [s[idx] for s in sg])
        return pins(0.0, 0.0, m2, 0.0, 0.0, m3, 0.0, 0.0, m4, *[g[idx] for g in geo_f])

    corr = [np.zeros(n) for _ in range(9)]
    iterations = np.zeros(n)
    idx = np.flatnonzero(np.all(np.isfinite(np.array(f0_f + geo_f[3:])), axis=0))
    t = torques([f[idx] for f in f0_f])
    for k in range(1, friction_max_iter + 1):
        c = forces(t, idx)
        new = torques([f0_f[i][idx] + c[i] for i in range(8)])
        change = np.max(np.abs(np.array(new) - np.array(t)), axis=0)
        scale = np.max(np.array(new), axis=0)
        blown = ~np.isfinite(scale)
        done = (change <= friction_tol * scale) & ~blown  # False for NaN and inf
        for i in range(9):
            corr[i][idx[done]] = c[i][done]
        iterations[idx[done]] = k
        keep = ~done & ~blown
        idx, t = idx[keep], [x[keep] for x in new]
        if not idx.size:
            break
    status = np.where(np.any(np.array(sg) == 0.0, axis=0), 1.0, 0.0)
    finite = np.all(np.isfinite(np.array(f0_f + geo_f[3:])), axis=0)
    # where the law need not be a contraction, every solution it has (friction_solve.py)
    mur = (MUR_O2, MUR_A, MUR_B, MUR_O4)
    hard, pairs, solved = _where_not_contracting(
        mur, finite, f0_f, sg, [geo_f[j] for j in (1, 2, 5, 6, 7, 8, 9)])
    if solved is not None:
        x, _, found = solved
        fixed = np.stack([corr[2][hard], corr[3][hard]], axis=-1)  # the fixed point's x
        same = (iterations[hard] > 0.0) & (found == 0.0) & (
            np.hypot(*(fixed - np.nan_to_num(x)).T)
            <= 1e-8 * (np.hypot(*fixed.T) + np.hypot(*pairs[1].T)))
        new = hard[~same]  # the fixed point's answer is kept where it is the continuous one
        xn = x[~same]
        t_new = torques([f0_f[j][new] + (xn[:, j % 2] * (1.0 if j in (2, 3, 6, 7) else -1.0))
                         for j in range(8)])
        c = forces(t_new, new)
        for i in range(9):
            corr[i][new] = c[i]
        iterations[new] = 0.0
        status[new] = np.where(found[~same] == 0.0, status[new], found[~same])
    failed = ~finite | (status == 2.0)
    for x_ in corr:
        x_[failed] = np.nan
    bad = finite & (status >= 2.0)
    if np.any(bad):
        none = int(np.count_nonzero(status == 2.0))
        other = int(np.count_nonzero(status == 3.0))
        warnings.warn(f"pin friction at {n} positions: {none} have no solution of the "
                      f"friction law (self-locking: NaN, FRICTION_STATUS 2), {other} only "
                      "solutions not reached from mu = 0 (the least friction taken, "
                      "FRICTION_STATUS 3)", FrictionWarning, stacklevel=2)
    # each pin's loss from the reported force: mu r |F| |relative rotation|
    final = torques([f0_f[i] + corr[i] for i in range(8)])
    rel = [np.abs(flat(w)) for w in (TH2D, TH3D - TH2D, TH4D - TH3D, TH4D)]
    loss = [np.where(sg[i] == 0.0, 0.0, final[i] * rel[i]) for i in range(4)]
    for x in loss:
        x[failed] = np.nan
    out = corr + loss + [iterations, status]
    return tuple(x.reshape(shape) for x in out)


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
    geo = (R3, R4, c3, s3, c4, s4, s34)
    f0 = (FA32X_0, FA32Y_0, FB34X_0, FB34Y_0, FOAX_0, FOAY_0, FOBX_0, FOBY_0)
    shape = np.broadcast_shapes(*(np.shape(x) for x in f0 + geo + (TH2D, TH3D, TH4D)))

    def flat(x):
        return np.broadcast_to(np.asarray(x, dtype=float), shape).reshape(-1)

    geo_f, f0_f = [flat(x) for x in geo], [flat(x) for x in f0]
    sg = [flat(x) for x in _signs(TH2D, TH3D, TH4D)]
    mur = (MUR_O2, MUR_A, MUR_B, MUR_O4)
    finite = np.all(np.isfinite(np.array(f0_f + geo_f)), axis=0)
    count = np.where(finite, 1.0, 0.0)
    hard, _, solved = _where_not_contracting(mur, finite, f0_f, sg, geo_f, count_all=True)
    if solved is not None:
        count[hard] = solved[1]
    return count.reshape(shape)


def _where_not_contracting(mur, finite, f0_f, sg, geo, count_all=False):
    """The positions where the law need not contract (friction_solve.contraction >= 1),
    the frictionless pin forces there as (FA32, FB34, FOA, FOB) pairs, and ``solve``'s
    answer there (None where there is no such position); ``geo``: R3, R4, c3, s3, c4,
    s4, s34, flat."""
    R3, R4, c3, s3, c4, s4, s34 = geo
    with np.errstate(all="ignore"):
        hard = np.flatnonzero(finite & ~(contraction(mur, R3, R4, s34) < 1.0))
    if not hard.size:
        return hard, [], None
    pairs = [np.stack([f0_f[j][hard], f0_f[j + 1][hard]], axis=-1) for j in (0, 2, 4, 6)]
    return hard, pairs, solve(pairs, mur, [s_[hard] for s_ in sg], R3[hard], R4[hard],
                              c3[hard], s3[hard], c4[hard], s4[hard], s34[hard],
                              count_all=count_all)


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


EFFECT = Effect("pin friction", (step_of(_friction), step_of(_friction_solutions)), _seed,
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
