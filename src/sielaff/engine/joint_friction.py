"""Coulomb friction in the pins and the slides of a linkage of dyads (engine/joints.py).

``Scene(friction=PinFriction(mu, radius))`` puts the same friction in every pin and every
slide (a slide takes its mu); a mapping ``{"O2": PinFriction(...), "A": ..., "slide":
...}`` gives each its own (one left out has none; a slide labelled L is ``"slide L"``).
At a pin of radius r carrying the force F the members exert on each other a couple
``mu r |F|`` opposing their relative rotation; at a slide the guide exerts on the slider a
force ``mu |FN|`` along the guide, opposing the slider's velocity relative to the guide
(the slide's rate VS), at the slider's pin.  Those loads change the joint forces, and so
their own size: per position the joint forces x solve

    A x + b + Phi(x) = 0

(A x + b = 0 the frictionless system, Phi the friction loads), by Newton's method from the
frictionless forces, with Phi's Jacobian (d|F|/dF = F / |F|, d|FN|/dFN = sgn FN).  Where
Newton does not converge in one go, mu is raised from 0 to its value in :data:`RAMP`
steps, each solve starting from the last (continuation from mu = 0, so the answer is the
one that grows continuously from the frictionless forces).  A position no step of that
reaches is self-locking as far as the solve can tell: NaN in every output friction
changes (``FRICTION_STATUS`` 2; a FrictionWarning says how many).  A joint whose relative
motion is exactly zero has static friction of unknown size, taken as zero
(``FRICTION_STATUS`` 1).

Outputs: ``TORQ_FRICTION`` (TORQ with friction less TORQ without), ``PLOSS_<pin>`` for each
pin and ``PLOSS_S<label>`` for each slide (the power friction loses there, >= 0:
mu r |F| |relative rotation| and mu |FN| |VS|), ``FRICTION_ITERATIONS`` (Newton's, in all)
and ``FRICTION_STATUS``.  With every mu = 0 no step here runs.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from sielaff.engine import joints
from sielaff.engine.declare import Fact, Param, SpecForm
from sielaff.engine.friction import (
    FRICTION_KEYS,
    MEANINGS,
    FrictionWarning,
    PinFriction,
    check_friction,
    loss_meaning,
)
from sielaff.engine.friction import per_joint as per_joint_of
from sielaff.engine.registry import Effect, Step
from sielaff.engine.unroll import structured
from sielaff.linkage import Topology

__all__ = ["RAMP", "effect"]

#: The continuation's steps in mu where Newton alone does not converge.
RAMP = 16
#: Newton's iterations per solve.
NEWTON = 40


def _names(topology: Topology) -> tuple[list[joints.Joint], list[joints.Slide], list[str]]:
    pins, slides = joints.joints(topology)
    keys = [j.point for j in pins] + [f"slide {s.label}".rstrip() for s in slides]
    return list(pins), list(slides), keys


def effect(topology: Topology, rename: Any) -> Effect:
    """The friction effect of ``topology`` (its pins and slides); ``rename`` gives the
    model's name of a generic output."""
    pins, slides, keys = _names(topology)
    slot_names = joints.slots(topology)
    totals = _totals(pins, slides, rename)
    seeds = tuple(f"MUR_{k.replace(' ', '_')}" for k in keys)
    losses = tuple(f"PLOSS_{j.point}" for j in pins) + tuple(
        f"PLOSS_S{s.label}" for s in slides)

    def check(v: Any) -> Any:
        return check_friction(v, tuple(keys), "joint")

    def per_joint(friction: Any) -> dict[str, PinFriction | None]:
        return per_joint_of(friction, tuple(keys))

    def coefficients(scene: Any) -> dict[str, float]:
        """Each pin's mu r [in or m], each slide's mu [-]."""
        out = {}
        for k, f in per_joint(scene.friction).items():
            out[k] = 0.0 if f is None else f.mu if k.startswith("slide") else f.mu * f.radius
        return out

    def seed(scene: Any, mechanism: Any) -> dict[str, Any]:
        given = [f for f in per_joint(scene.friction).values() if f is not None]
        ns: dict[str, Any] = dict(zip(seeds, coefficients(scene).values(), strict=True))
        ns["friction_tol"] = min((f.tol for f in given), default=1e-13)
        return ns

    def _friction(pos: Any, vel: Any, friction_tol: Any, *args: Any) -> Any:
        mu = args[:len(seeds)]
        x0 = args[len(seeds):]
        pos, vel = structured(topology, "pos", pos), structured(topology, "vel", vel)
        return solve(topology, pos, vel, mu, x0, friction_tol, pins, slides)

    provides = tuple(s + "_f" for s in slot_names[:-1]) + ("TORQ_FRICTION",) + losses + (
        "FRICTION_ITERATIONS", "FRICTION_STATUS")
    step = Step("_joint_friction", _friction, provides,
                ("pos", "vel", "friction_tol") + seeds + tuple(t + "_0" for t in totals),
                seeds, (seeds,))

    def describe(scene: Any, units: str) -> list[Fact]:
        facts = []
        for k, f in per_joint(scene.friction).items():
            if f is None:
                facts.append(Fact(k, "friction", "none"))
            elif k.startswith("slide"):
                facts.append(Fact(k, "mu", f.mu, "number"))
            else:
                facts += [Fact(k, "mu", f.mu, "number"),
                          Fact(k, "pin radius", f.radius, "length")]
        return facts

    def figures(r: Any, scene: Any, units: str, speed: float) -> list[Fact]:
        facts = []
        total = 0.0
        for name in losses:
            loss = float(np.mean(np.asarray(r[name])))
            total += loss
            facts.append(Fact(f"loss at {name[6:]}", "mean", loss, "power"))
        facts.append(Fact("loss in all", "mean", total, "power"))
        if speed:
            facts.append(Fact("loss in all", "per revolution", total * 2.0 * np.pi / speed,
                              "work"))
        n = int(np.count_nonzero(np.asarray(r["FRICTION_STATUS"]) == 2.0))
        if n:
            facts.append(Fact("self-locking (no solution: NaN)", "positions of the grid", str(n)))
        return facts

    def read(table: Any, path: str, reader: Any) -> dict[str, Any]:
        if "friction" not in table:
            return {}
        where = f"{path}: [scene.friction]"
        t = reader.table(where, table["friction"])
        named = [k for k in t if k in keys]
        if named and any(k in FRICTION_KEYS for k in t):
            raise reader.error(f"{where}: give mu and radius for every joint, or a table per "
                               f"joint ({', '.join(keys)}), not both")
        if not named:
            return {"friction": _pin_of(where, t, reader)}
        reader.unknown(where, t, tuple(keys))
        return {"friction": {k: _pin_of(f"{where[:-1]}.{k}]", v, reader)
                             for k, v in t.items()}}

    def write(scene: Any) -> dict[str, Any]:
        def one(f: PinFriction) -> dict[str, Any]:
            return {"mu": f.mu, "radius": f.radius, "tol": f.tol}
        f = scene.friction
        if f is None:
            return {}
        if isinstance(f, PinFriction):
            return {"friction": one(f)}
        return {"friction": {k: one(v) for k, v in f.items()}}

    help_text = ("[scene.friction]              # Coulomb friction, the same in every pin "
                 "and slide ...\nmu = 0.1                      # coefficient of friction\n"
                 "radius = 0.25                 # the pins' radius, in or m\n"
                 "# ... or each its own (one left out has none): [scene.friction.O2] "
                 f"mu = 0.1  radius = 0.5\n#     (joints: {', '.join(keys)})")
    outputs = {"TORQ_FRICTION": ("torque", MEANINGS["TORQ_FRICTION"]),
               **{n: ("power", loss_meaning(n[6:])) for n in losses},
               "FRICTION_ITERATIONS": ("number", MEANINGS["FRICTION_ITERATIONS"]),
               "FRICTION_STATUS": ("number", MEANINGS["FRICTION_STATUS"])}
    return Effect(
        "joint friction", (step,), seed, torque="TORQ_FRICTION",
        corrects={**{t: s + "_f" for t, s in zip(totals[:-1], slot_names[:-1], strict=True)},
                  totals[-1]: "TORQ_FRICTION"},
        switch=seeds,
        params=(Param("friction", None, check,
                      "None, PinFriction or mapping\n    Coulomb friction in the pins and "
                      "slides: one :class:`~sielaff.engine.friction.PinFriction`\n    for all "
                      f"(a slide takes its mu), or a mapping of {', '.join(keys)}\n    to "
                      "PinFriction (one left out has none)."),),
        outputs=outputs, on=lambda scene: any(v > 0.0 for v in coefficients(scene).values()),
        summary=lambda scene, units: "joint friction", describe=describe,
        figure_outputs=lambda scene: losses + ("FRICTION_STATUS",), figures=figures,
        columns=lambda scene: ("TORQ_FRICTION",) + losses + ("FRICTION_STATUS",),
        spec=SpecForm(("friction",), read, write, help_text))


def _totals(pins: list[joints.Joint], slides: list[joints.Slide], rename: Any) -> list[str]:
    """The model's names of the slots, in the slots' order."""
    out = [rename(j.name + axis) for j in pins for axis in "XY"]
    out += [rename(f"{kind}{s.label}") for s in slides for kind in ("FN", "MN")]
    return out + ["TORQ"]


def _pin_of(where: str, table: Any, reader: Any) -> PinFriction:
    table = reader.table(where, table)
    reader.unknown(where, table, FRICTION_KEYS)
    if "mu" not in table:
        raise reader.error(f"{where} has no mu (write mu = ..., radius = ...)")
    extra: dict[str, Any] = {}
    if "tol" in table:
        extra["tol"] = reader.number(f"{where} tol", table["tol"])
    try:
        return PinFriction(reader.number(f"{where} mu", table["mu"]),
                           reader.number(f"{where} radius", table.get("radius", 0.0)), **extra)
    except ValueError as exc:
        raise reader.error(f"{where}: {exc}") from None


def solve(topology: Topology, pos: Any, vel: Any, mu: tuple[Any, ...], x0: tuple[Any, ...],
          tol: float, pins: list[joints.Joint], slides: list[joints.Slide]) -> tuple[Any, ...]:
    """The corrections to the slots (every pin force, FN, MN; TORQ), each joint's loss, the
    iterations and the status, at every position (see the module doc)."""
    shape = np.broadcast_shapes(*(np.shape(x) for x in x0), np.shape(pos.margin))
    A, L = joints.matrix(topology, pos, shape)
    size = A.shape[-1]
    n = int(np.prod(shape))
    A = A.reshape(n, size, size)
    # the unknowns in the system's scale (couples and TORQ / L)
    x_start = np.stack([np.broadcast_to(np.asarray(v, dtype=float), shape).reshape(-1)
                        for v in x0], axis=-1)
    n_pin = 2 * len(pins)
    for i in list(range(n_pin + 1, n_pin + 2 * len(slides), 2)) + [size - 1]:
        x_start[:, i] /= L
    geo = _friction_geometry(topology, pos, vel, pins, slides, shape, L)
    mus = [float(m) for m in mu]
    finite = np.isfinite(x_start).all(axis=1) & np.isfinite(A).all(axis=(1, 2))
    x = np.where(finite[:, None], x_start, 0.0)
    status = np.where(geo["still"] & finite, 1.0, 0.0)
    iterations = np.zeros(n)
    todo = np.flatnonzero(finite)
    solved, its = _newton(A[todo], x_start[todo], x[todo], geo, todo, mus, 1.0, tol, n_pin)
    iterations[todo] += its
    ok = np.isfinite(solved).all(axis=1)
    x[todo[ok]] = solved[ok]
    left = todo[~ok]
    if left.size:  # continuation: mu raised from 0, each solve from the last
        y = x_start[left].copy()
        alive = np.ones(left.size, dtype=bool)
        for k in range(1, RAMP + 1):
            idx = np.flatnonzero(alive)
            got, its = _newton(A[left[idx]], x_start[left[idx]], y[idx], geo, left[idx], mus,
                               k / RAMP, tol, n_pin)
            iterations[left[idx]] += its
            good = np.isfinite(got).all(axis=1)
            y[idx[good]] = got[good]
            alive[idx[~good]] = False
        x[left[alive]] = y[alive]
        dead = left[~alive]
        x[dead] = np.nan
        status[dead] = 2.0
        if dead.size:
            warnings.warn(f"joint friction at {n} positions: {dead.size} reach no solution of "
                          "the friction law from mu = 0 (self-locking: NaN, FRICTION_STATUS 2)",
                          FrictionWarning, stacklevel=2)
    x[~finite] = np.nan
    corr = x - x_start
    for i in list(range(n_pin + 1, n_pin + 2 * len(slides), 2)) + [size - 1]:
        corr[:, i] *= L
    losses = _losses(x, geo, mus, n_pin, len(pins), len(slides))
    out = [corr[:, i] for i in range(size)] + losses + [iterations, status]
    return tuple(np.reshape(v, shape) for v in out)


def _friction_geometry(topology: Topology, pos: Any, vel: Any, pins: list[joints.Joint],
                       slides: list[joints.Slide], shape: tuple[int, ...], L: float
                       ) -> dict[str, Any]:
    """What the friction loads need per position, flat: each pin's links and the sign of
    its relative rotation, each slide's direction, arm and the sign of its rate."""
    def flat(v: Any) -> np.ndarray:
        return np.broadcast_to(np.asarray(v, dtype=float), shape).reshape(-1)

    g: dict[str, Any] = {"pins": [], "slides": []}
    still = np.zeros(int(np.prod(shape)), dtype=bool)
    for j in pins:
        rel = flat(vel.w[j.by] - vel.w[j.on])
        g["pins"].append((j.by, j.on, np.sign(rel), np.abs(rel)))
        still |= rel == 0.0
    for s in slides:
        rate = flat(vel.s[s.label])
        u = pos.guide[s.label][3]
        ux, uy = flat(u[0]), flat(u[1])
        px, py = (flat(c) for c in pos.pt[s.point])
        arms = {}
        for k in (s.slider, s.guide):
            if k != 1:
                _, _, bx, by = pos.link[k]
                # the moment / L of a unit force along u at the pin, about link k's base
                arms[k] = ((px - flat(bx)) * uy - (py - flat(by)) * ux) / L
        g["slides"].append((s.slider, s.guide, ux, uy, arms, np.sign(rate), np.abs(rate)))
        still |= rate == 0.0
    g["still"] = still
    g["L"] = L
    return g


def _loads(x: np.ndarray, geo: dict[str, Any], idx: np.ndarray, mus: list[float],
           scale: float, n_pin: int) -> tuple[np.ndarray, np.ndarray]:
    """Phi(x), the friction loads as the system's rows, and its Jacobian, at positions
    ``idx`` (x in the system's scale)."""
    m, size = x.shape
    phi = np.zeros((m, size))
    jac = np.zeros((m, size, size))
    L = geo["L"]
    for j, (by, on, sign, _) in enumerate(geo["pins"]):
        mur = mus[j] * scale
        if mur == 0.0:
            continue
        fx, fy = x[:, 2 * j], x[:, 2 * j + 1]
        mag = np.hypot(fx, fy)
        s = sign[idx]
        c = mur * mag * s / L  # the couple on `on` (on `by` the opposite), / L
        dx = np.where(mag > 0.0, mur * s * fx / np.where(mag > 0.0, mag, 1.0) / L, 0.0)
        dy = np.where(mag > 0.0, mur * s * fy / np.where(mag > 0.0, mag, 1.0) / L, 0.0)
        for k, sg in ((on, 1.0), (by, -1.0)):
            if k == 1:
                continue
            row = 3 * (k - 2) + 2
            phi[:, row] += sg * c
            jac[:, row, 2 * j] += sg * dx
            jac[:, row, 2 * j + 1] += sg * dy
    for i, (slider, guide, ux, uy, arms, sign, _) in enumerate(geo["slides"]):
        mu = mus[len(geo["pins"]) + i] * scale
        if mu == 0.0:
            continue
        col = n_pin + 2 * i
        fn = x[:, col]
        f = -mu * np.abs(fn) * sign[idx]  # along u, on the slider; the guide the opposite
        df = -mu * np.sign(fn) * sign[idx]
        for k, sg in ((slider, 1.0), (guide, -1.0)):
            if k == 1:
                continue
            row = 3 * (k - 2)
            for r, comp in ((row, ux[idx]), (row + 1, uy[idx]), (row + 2, arms[k][idx])):
                phi[:, r] += sg * f * comp
                jac[:, r, col] += sg * df * comp
    return phi, jac


def _newton(A: np.ndarray, x0: np.ndarray, start: np.ndarray, geo: dict[str, Any],
            idx: np.ndarray, mus: list[float], scale: float, tol: float, n_pin: int
            ) -> tuple[np.ndarray, int]:
    """Solve A (x - x0) + Phi(x) = 0 at each position from ``start``; NaN rows where it
    does not converge in NEWTON iterations.  Returns x and the iterations run."""
    x = start.copy()
    done = np.zeros(len(idx), dtype=bool)
    out = np.full_like(x, np.nan)
    its = 0
    for _ in range(NEWTON):
        live = np.flatnonzero(~done)
        if not live.size:
            break
        its += 1
        phi, jac = _loads(x[live], geo, idx[live], mus, scale, n_pin)
        residual = np.einsum("nij,nj->ni", A[live], x[live] - x0[live]) + phi
        with np.errstate(all="ignore"):
            try:
                step = np.linalg.solve(A[live] + jac, residual[..., None])[..., 0]
            except np.linalg.LinAlgError:
                step = np.stack([_one(a, r) for a, r in zip(A[live] + jac, residual,
                                                            strict=True)])
        x[live] -= step
        size = np.max(np.abs(x[live]), axis=1) + 1e-300
        conv = np.max(np.abs(step), axis=1) <= tol * size
        blown = ~np.isfinite(step).all(axis=1)
        out[live[conv]] = x[live[conv]]
        done[live[conv | blown]] = True
    return out, its


def _one(a: np.ndarray, r: np.ndarray) -> np.ndarray:
    try:
        return np.linalg.solve(a, r)
    except np.linalg.LinAlgError:
        return np.full_like(r, np.nan)


def _losses(x: np.ndarray, geo: dict[str, Any], mus: list[float], n_pin: int, pins: int,
            slides: int) -> list[np.ndarray]:
    out = []
    for j, (_, _, sign, rate) in enumerate(geo["pins"]):
        mag = np.hypot(x[:, 2 * j], x[:, 2 * j + 1])
        out.append(np.where(sign == 0.0, 0.0, mus[j] * mag * rate))
    for i, (*_, sign, rate) in enumerate(geo["slides"]):
        fn = np.abs(x[:, n_pin + 2 * i])
        out.append(np.where(sign == 0.0, 0.0, mus[pins + i] * fn * rate))
    return out
