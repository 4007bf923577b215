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
motion is zero to within roundoff (engine/friction.py's ``rest_sign``: within 1e-12 of the
sum of the links' rates, at a slide times the linkage's length scale) has static friction
of unknown size, taken as zero (``FRICTION_STATUS`` 1).

How it runs: three steps, each written out for the topology by engine/unroll.py (so the
numpy engine and the compiled kernel run the same code, but for the linear solve of each
Newton step, joints.linear: LAPACK in numpy, engine/kernel_math.py's in the kernel): the
system's entries and the friction loads' geometry at each position; Newton's method, an
iterated step (engine/iterate.py) of one Newton iteration a pass, whose state carries the
ramp's level and the iterations at it (level 0: mu itself; after NEWTON iterations there
without converging, or at once on a step that is not finite, levels 1 to RAMP from the
frictionless forces); the corrections, the losses and the status.

Outputs: ``TORQ_FRICTION`` (TORQ with friction less TORQ without), ``PLOSS_<pin>`` for each
pin and ``PLOSS_S<label>`` for each slide (the power friction loses there, >= 0:
mu r |F| |relative rotation| and mu |FN| |VS|), ``FRICTION_ITERATIONS`` (the position's
Newton iterations, the ramp's included) and ``FRICTION_STATUS``.  With every mu = 0 no
step here runs.
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
    rest_sign,
)
from sielaff.engine.friction import per_joint as per_joint_of
from sielaff.engine.iterate import iterated_step
from sielaff.engine.registry import Effect, Step
from sielaff.engine.unroll import Sym, call, skeleton, unrolled
from sielaff.linkage import Topology

__all__ = ["RAMP", "effect"]

#: The continuation's steps in mu where Newton alone does not converge.
RAMP = 16
#: Newton's iterations per solve (at mu, then at each step of the ramp).
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
        ns["joint_friction_passes"] = float(NEWTON * (RAMP + 1))
        return ns

    provides = tuple(s + "_f" for s in slot_names[:-1]) + ("TORQ_FRICTION",) + losses + (
        "FRICTION_STATUS", "FRICTION_ITERATIONS")
    steps = _steps(topology, pins, slides, seeds, tuple(totals), provides)

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
        "joint friction", steps, seed, torque="TORQ_FRICTION",
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


class _Layout:
    """Where each value of the solve sits: the unknowns (each pin's force, each slide's FN
    and MN, TORQ; couples and TORQ in the system's scale), the system's entries that
    depend on the position (the others are numbers, written into the code), and the
    friction loads' geometry, each a name of the effect's steps (lower case: not outputs)."""

    def __init__(self, topology: Topology, pins: list[joints.Joint],
                 slides: list[joints.Slide], constant: dict[tuple[int, int], float]) -> None:
        self.topology, self.pins, self.slides = topology, pins, slides
        self.size = 3 * (topology.links - 1)
        self.n_pin = 2 * len(pins)
        #: the unknowns in scale (a couple's and TORQ's: divided by L)
        self.scaled = tuple(range(self.n_pin + 1, self.n_pin + 2 * len(slides), 2)) + (
            self.size - 1,)
        self.constant = constant
        self.entries = tuple((r, c) for r in range(self.size) for c in range(self.size)
                             if (r, c) not in constant)
        self.arm_links = [tuple(k for k in (s.slider, s.guide) if k != 1) for s in slides]
        self.x0 = tuple(f"jf_x0_{i}" for i in range(self.size))
        self.geometry = (
            tuple(f"jf_a{r}_{c}" for r, c in self.entries) + ("jf_l",)
            + tuple(f"jf_{w}{j}" for j in range(len(pins)) for w in ("ps", "pr"))
            + tuple(f"jf_{w}{i}" for i, ks in enumerate(self.arm_links)
                    for w in ("ux", "uy", "ss", "sr", *(f"arm{k}_" for k in ks))))

    def unpack(self, g: tuple[Any, ...]) -> tuple[Any, ...]:
        """The geometry's values (in :attr:`geometry`'s order) as (A's rows, L, each pin's
        (sign, rate), each slide's (ux, uy, sign, rate, {link: arm}))."""
        it = iter(g)
        got = {e: next(it) for e in self.entries}
        rows = [[self.constant.get((r, c), got.get((r, c))) for c in range(self.size)]
                for r in range(self.size)]
        L = next(it)
        pins = [(next(it), next(it)) for _ in self.pins]
        slides = []
        for ks in self.arm_links:
            ux, uy, sign, rate = next(it), next(it), next(it), next(it)
            slides.append((ux, uy, sign, rate, {k: next(it) for k in ks}))
        return rows, L, pins, slides


def _steps(topology: Topology, pins: list[joints.Joint], slides: list[joints.Slide],
           seeds: tuple[str, ...], totals: tuple[str, ...], provides: tuple[str, ...],
           ) -> tuple[Step, ...]:
    """The solve's three steps, each written out by engine/unroll.py for the topology (so
    that the compiled kernel runs them as the numpy engine does): the system and the
    friction loads' geometry at each position; Newton's method, an iterated step
    (engine/iterate.py) of one Newton iteration a pass; the corrections, the losses and
    the status."""
    pos_sk, vel_sk = skeleton(topology, "pos"), skeleton(topology, "vel")
    found: dict[tuple[int, int], float] = {}

    def probe(pos: Any) -> Any:  # which of the system's entries are numbers
        rows, L = joints.entries(topology, pos)
        found.update({(r, c): float(v) for r, row in enumerate(rows)
                      for c, v in enumerate(row) if not isinstance(v, Sym)})
        return L
    unrolled("_probe", probe, [pos_sk], 1)
    lay = _Layout(topology, pins, slides, found)
    n_mu = len(seeds)

    def system(pos: Any, vel: Any, *x0: Any) -> tuple[Any, ...]:
        rows, L = joints.entries(topology, pos)
        xs = [v / L if i in lay.scaled else v for i, v in enumerate(x0)]
        finite: Any = True
        for v in xs + [rows[r][c] for r, c in lay.entries]:
            finite = finite & np.isfinite(v)
        geometry: list[Any] = [rows[r][c] for r, c in lay.entries] + [L]
        still: Any = False
        rates: Any = 0.0  # what the rates' roundoff is relative to
        for k in sorted(vel.w):
            rates = rates + np.abs(vel.w[k])
        for j in pins:
            rel = vel.w[j.by] - vel.w[j.on]
            sign = rest_sign(rel, rates)
            geometry += [sign, np.abs(rel)]
            still = still | (sign == 0.0)
        for s, ks in zip(slides, lay.arm_links, strict=True):
            rate = vel.s[s.label]
            ux, uy = pos.guide[s.label][3]
            px, py = pos.pt[s.point]
            sign = rest_sign(rate, rates * L)
            geometry += [ux, uy, sign, np.abs(rate)]
            for k in ks:  # the moment / L of a unit force along u at the pin, about k's base
                _, _, bx, by = pos.link[k]
                geometry.append(((px - bx) * uy - (py - by) * ux) / L)
            still = still | (sign == 0.0)
        go = np.where(finite, 1.0, 0.0)
        return (*xs, *geometry, go, np.where(still, 1.0, 0.0), 0.0)

    made = tuple(lay.x0) + lay.geometry + ("jf_go", "jf_still", "jf_0")
    fn, _ = unrolled("_joint_friction_system", system, [pos_sk, vel_sk] + [None] * len(totals),
                     len(made))
    first = Step("_joint_friction_system", fn, made, ("pos", "vel") + tuple(
        t + "_0" for t in totals), seeds, (seeds,))

    def newton(*v: Any) -> tuple[Any, ...]:
        """One Newton iteration on A (x - x0) + Phi(x) = 0 (Phi the friction loads at mu
        times the level's fraction), and the level's and the iterations' bookkeeping."""
        n = lay.size
        x, level, its = v[:n], v[n], v[n + 1]
        x0 = v[n + 2:2 * n + 2]
        rows, L, pin_geo, slide_geo = lay.unpack(v[2 * n + 2:-n_mu - 1])
        mus, tol = v[-n_mu - 1:-1], v[-1]
        scale = np.where(level == 0.0, 1.0, level / RAMP)
        phi: list[Any] = [0.0] * n
        jac: dict[tuple[int, int], Any] = {}

        def add(r: int, c: int, dphi: Any, d: Any) -> None:
            if dphi is not None:
                phi[r] = phi[r] + dphi
            jac[(r, c)] = jac.get((r, c), 0.0) + d

        for j, (pin, (sign, _)) in enumerate(zip(pins, pin_geo, strict=True)):
            mur = mus[j] * scale
            fx, fy = x[2 * j], x[2 * j + 1]
            mag = np.hypot(fx, fy)
            some = mag > 0.0
            c = mur * mag * sign / L  # the couple on `on` (on `by` the opposite), / L
            dx = np.where(some, mur * sign * fx / np.where(some, mag, 1.0) / L, 0.0)
            dy = np.where(some, mur * sign * fy / np.where(some, mag, 1.0) / L, 0.0)
            for k, sg in ((pin.on, 1.0), (pin.by, -1.0)):
                if k != 1:
                    row = 3 * (k - 2) + 2
                    add(row, 2 * j, sg * c, sg * dx)
                    add(row, 2 * j + 1, None, sg * dy)
        for i, (s, (ux, uy, sign, _, arms)) in enumerate(zip(slides, slide_geo, strict=True)):
            mu = mus[len(pins) + i] * scale
            col = lay.n_pin + 2 * i
            fn = x[col]
            f = -mu * np.abs(fn) * sign  # along u, on the slider; the guide the opposite
            df = -mu * np.sign(fn) * sign
            for k, sg in ((s.slider, 1.0), (s.guide, -1.0)):
                if k != 1:
                    row = 3 * (k - 2)
                    for r, comp in ((row, ux), (row + 1, uy), (row + 2, arms[k])):
                        add(r, col, sg * f * comp, sg * df * comp)
        residual = []
        for r in range(n):
            total: Any = 0.0
            for c in range(n):
                if not (isinstance(rows[r][c], float) and rows[r][c] == 0.0):  # a zero drops
                    total = total + rows[r][c] * (x[c] - x0[c])
            residual.append(total + phi[r])
        system_rows = [[rows[r][c] + jac[(r, c)] if (r, c) in jac else rows[r][c]
                        for c in range(n)] for r in range(n)]
        step = call(joints.linear, n, system_rows, residual)
        new = [x[i] - step[i] for i in range(n)]
        big, largest = np.abs(new[0]), np.abs(step[0])
        finite = np.isfinite(step[0])
        for i in range(1, n):
            big, largest = np.maximum(big, np.abs(new[i])), np.maximum(largest, np.abs(step[i]))
            finite = finite & np.isfinite(step[i])
        conv = finite & (largest <= tol * (big + 1e-300))  # an infinite step is no answer
        last = (level == 0.0) | (level == float(RAMP))
        give_up = (finite == False) | ((conv == False) & (its + 1.0 >= NEWTON))  # noqa: E712
        restart = give_up & (level == 0.0)  # Newton alone failed: the ramp from mu = 0
        failed = give_up & (level > 0.0)
        done = (conv & last) | failed
        up = (conv & (last == False)) | restart  # noqa: E712
        state = [np.where(restart, x0[i], new[i]) for i in range(n)]
        return (*state, np.where(up, level + 1.0, level), np.where(up, 0.0, its + 1.0),
                *new, np.where(failed, 1.0, 0.0), done, done == False)  # noqa: E712

    results = tuple(f"jf_x{i}" for i in range(lay.size)) + ("jf_failed",)
    consts = lay.x0 + lay.geometry + seeds + ("friction_tol",)
    body, _ = unrolled("_joint_friction_newton", newton, [None] * (
        lay.size + 2 + len(consts)), 2 * lay.size + 5)
    second = iterated_step("_joint_friction_newton", body, results + ("FRICTION_ITERATIONS",),
                           "joint_friction_passes", "jf_go", lay.x0 + ("jf_0", "jf_0"),
                           consts, (seeds,))

    def finish(*v: Any) -> tuple[Any, ...]:
        n = lay.size
        failed, go, still = v[n], v[n + 1], v[n + 2]
        x0 = v[n + 3:2 * n + 3]
        _, L, pin_geo, slide_geo = lay.unpack(v[2 * n + 3:-n_mu])
        mus = v[-n_mu:]
        bad = (go == 0.0) | (failed != 0.0)
        x = [np.where(bad, np.nan, v[i]) for i in range(n)]
        corr = [(x[i] - x0[i]) * L if i in lay.scaled else x[i] - x0[i] for i in range(n)]
        losses = [np.where(sign == 0.0, 0.0, mus[j] * np.hypot(x[2 * j], x[2 * j + 1]) * rate)
                  for j, (sign, rate) in enumerate(pin_geo)]
        losses += [np.where(sign == 0.0, 0.0,
                            mus[len(pins) + i] * np.abs(x[lay.n_pin + 2 * i]) * rate)
                   for i, (_, _, sign, rate, _) in enumerate(slide_geo)]
        status = np.where(go == 0.0, 0.0, np.where(failed != 0.0, 2.0,
                                                   np.where(still != 0.0, 1.0, 0.0)))
        return (*corr, *losses, status)

    needs = results + ("jf_go", "jf_still") + lay.x0 + lay.geometry + seeds
    fn, _ = unrolled("_joint_friction_losses", finish, [None] * len(needs),
                     len(provides) - 1)
    third = Step("_joint_friction_losses", fn, tuple(p for p in provides if p !=
                                                    "FRICTION_ITERATIONS"),
                 needs, seeds, (seeds,), warns=(("FRICTION_STATUS",), _warn_locked))
    return first, second, third


def _warn_locked(status: Any) -> None:
    """The FrictionWarning where some position reaches no solution from mu = 0
    (``FRICTION_STATUS`` 2): the model calls it after the step, on either backend."""
    status = np.asarray(status)
    dead = int(np.count_nonzero(status == 2.0))
    if dead:
        warnings.warn(f"joint friction at {status.size} positions: {dead} reach no solution "
                      "of the friction law from mu = 0 (self-locking: NaN, FRICTION_STATUS 2)",
                      FrictionWarning, stacklevel=2)
