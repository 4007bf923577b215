"""A :class:`~sielaff.linkage.Topology` as a model: its steps made from the topology, its
effects registered as for the four-bar.

Steps: positions (engine/dyads.py), velocities, accelerations, each link's and point's
outputs, the links as the effects see them (engine/links.py), D'Alembert's inertia loads,
the joint forces and the drive torque by one linear system per position
(engine/joints.py), the shaking force and moment.  Outputs are named generically
(ATHk, THkD, THkDD; XP, YP, VP, AP for each moving point P, its centre of mass Gk
included; a pin force F<pin><by><on>, or F<pivot> on the frame; S, VS, AS, FN, MN and
the slide's label for a slide; GAMMA<pin> an RRR's angle at its inner pin; TORQ, SHAK,
SHAKM), then renamed as the topology says (``Topology.names``: the four-bar's and the
slider-crank's FOA for FO2).

Each step is written here once, over the topology, and unrolled into plain code
(engine/unroll.py: the dictionaries of links and points looked up once, the positions
and rates passed between steps as flat tuples): the numpy engine runs the unrolled
function (the same operations in the same order, so the same bits), and the compiled
backend compiles it for one position as it compiles any step.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from sielaff.engine import dyads, joints
from sielaff.engine.crank import _crank_acceleration
from sielaff.engine.declare import Param, number_param
from sielaff.engine.links import FRAME, FRAME_RATE, Link, LinkRate
from sielaff.engine.outputs import _direction, _magnitude
from sielaff.engine.positions import _angle_deg, _crank_angle
from sielaff.engine.registry import Model, Step, step_of
from sielaff.engine.unroll import Untraceable, call, keep, nested, unrolled
from sielaff.linkage import RPR, RRR, Topology
from sielaff.mechanism import MASS_DIVISOR

__all__ = ["BRANCHES", "finish", "friction_effect", "kind_model", "linkage_model"]

#: The values passed between steps as the flat tuples of their numbers (engine/unroll.py).
_FLAT = frozenset(("pos", "vel", "acc"))
#: The skeletons of each topology's positions and rates (what the effects that read
#: them, pin friction, rebuild them from).
_SKELETONS: dict[Topology, dict[str, Any]] = {}

#: Each dyad's assembly: "open" (+1) or "crossed" (-1) (sielaff.linkage says which is which).
BRANCHES = ("open", "crossed")


def _branch_check(dyads: int) -> Callable[[Any], Any]:
    def check(v: Any) -> Any:
        items = (v,) if isinstance(v, str) else tuple(v) if isinstance(v, list | tuple) \
            else None
        if items is None or not all(isinstance(b, str) and b in BRANCHES for b in items) \
                or len(items) not in (1, dyads):
            raise ValueError(f"Scene.branch = {v!r}: 'open' or 'crossed', or one of them "
                             f"for each of the {dyads} dyads")
        return items[0] if len(items) == 1 else items
    return check


def _signs(branch: Any, dyads: int) -> tuple[float, ...]:
    items = (branch,) * dyads if isinstance(branch, str) else tuple(branch)
    return tuple(1.0 if b == "open" else -1.0 for b in items)


def _moving_points(topology: Topology) -> tuple[str, ...]:
    """The points that move: the pins, the named points, each centre of mass."""
    pins = [topology.crank.pin]
    for d in topology.dyads:
        if not isinstance(d, RPR):
            pins.append(d.joint)
    pins += [p.name for p in topology.points]
    pins += [f"G{k}" for k in range(2, topology.links + 1)]
    return tuple(dict.fromkeys(pins))


def _renamer(topology: Topology) -> Callable[[str], str]:
    names = dict(topology.names)

    def rename(generic: str) -> str:
        if generic in names:
            return names[generic]
        if generic[-1:] in ("X", "Y") and generic[:-1] in names:
            return names[generic[:-1]] + generic[-1]
        if generic[:1] == "D" and generic[1:] in names:
            return "D" + names[generic[1:]]
        return generic
    return rename


def _bare(fn: Callable[..., Any]) -> Callable[..., Any]:
    def one(*args: Any) -> Any:
        r = fn(*args)
        return r[0] if isinstance(r, tuple) and len(r) == 1 else r
    one.__name__ = getattr(fn, "__name__", "step")
    return one


class _Builder:
    """Collects a topology's steps and its outputs' declarations."""

    def __init__(self, topology: Topology) -> None:
        self.topology = topology
        self.rename = _renamer(topology)
        self.steps: list[Step] = []
        self.declared: dict[str, tuple[str, str]] = {}
        #: the skeleton of each input passed as a tuple (engine/unroll.py)
        self.skeletons: dict[str, Any] = {}

    def add(self, name: str, fn: Callable[..., Any], provides: tuple[str, ...],
            needs: tuple[str, ...], zero_when: tuple[str, ...] = ()) -> None:
        """The step ``fn``, unrolled (engine/unroll.py): its structured inputs and
        results (the positions, the rates) passed as flat tuples, their skeletons kept
        here; a step that cannot be unrolled is kept as written (numpy runs it, the
        compiled backend refuses it naming it)."""
        groups = (zero_when,) if zero_when else ()
        inputs = [self.skeletons.get(n) for n in needs]
        flat = [n in _FLAT for n in provides]
        if len(provides) == 1:  # a step of one output returns it bare
            fn = _bare(fn)
        try:
            fn, made = unrolled(name, fn, inputs, len(provides), flat)
        except Untraceable:
            pass
        else:
            self.skeletons.update({n: sk for n, sk in zip(provides, made, strict=True)
                                   if sk is not None})
        self.steps.append(Step(name, fn, provides, needs, zero_when, groups))

    def out(self, generic: str, kind: str, meaning: str) -> str:
        name = self.rename(generic)
        self.declared[name] = (kind, meaning)
        return name

    def vector(self, generic: str, kind: str, meaning: str) -> tuple[str, ...]:
        """The magnitude and direction steps of a vector whose X and Y are provided."""
        mag = self.out(generic, kind, f"magnitude of the {meaning}")
        x = self.out(generic + "X", kind, f"x component of the {meaning}")
        y = self.out(generic + "Y", kind, f"y component of the {meaning}")
        d = self.out("D" + generic, "angle", f"direction of the {meaning}, CCW from +x")
        self.steps.append(Step(f"_magnitude_{mag}", _magnitude, (mag,), (x, y)))
        self.steps.append(Step(f"_direction_{mag}", _direction, (d,), (x, y)))
        return mag, d, x, y


def linkage_model(topology: Topology, name: str, *, mechanism: type | None = None,
                  validate: Callable[[Any], None] | None = None,
                  full_turn: Callable[[Any], str | None] | None = None,
                  results: tuple[str, ...] | None = None) -> Model:
    """The model of ``topology``: its steps, the Scene fields ``branch`` and ``th2dd``, and
    no effect yet (the kind's module registers them, one line each)."""
    b = _Builder(topology)
    links = topology.links
    moving = range(2, links + 1)
    dyads_n = len(topology.dyads)
    fields = topology.fields()
    geometry = tuple(f for f in fields if not f.startswith(("W", "ZI")) and f != "TH2D")
    masses = tuple(f"{p}{k}" for k in moving for p in ("W", "ZI", "RG", "ADEL"))
    points = _moving_points(topology)
    pins, slides = joints.joints(topology)

    branches = tuple(f"BRANCH{i + 1}" for i in range(dyads_n))

    def _positions(c2: Any, s2: Any, *values: Any) -> Any:
        pos = dyads.positions(topology, dict(zip(geometry, values[dyads_n:], strict=True)),
                              c2, s2, values[:dyads_n])
        return pos, pos.margin + 0.0 * c2
    b.add("_positions", _positions, ("pos", "margin"), ("c2", "s2") + branches + geometry)

    def _velocities(pos: Any, TH2D: Any) -> Any:
        return dyads.velocities(topology, pos, TH2D)
    b.add("_velocities", _velocities, ("vel",), ("pos", "TH2D"))

    def _accelerations(pos: Any, vel: Any, TH2DD: Any) -> Any:
        return dyads.accelerations(topology, pos, vel, TH2DD)
    b.add("_accelerations", _accelerations, ("acc",), ("pos", "vel", "TH2DD"))

    # angles and rates of each link
    ath = tuple(b.out(f"ATH{k}", "angle", f"THETA {k}, the line of link {k}, CCW from +x")
                for k in moving if k > 2)
    thd = tuple(b.out(f"TH{k}D", "rate", f"angular velocity of link {k}, CCW +")
                for k in moving if k > 2)
    thdd = tuple(b.out(f"TH{k}DD", "angular acceleration",
                       f"angular acceleration of link {k}, CCW +") for k in moving if k > 2)
    b.add("_link_angles", lambda pos: tuple(call(_angle_deg, None, pos.link[k][1],
                                                 pos.link[k][0]) for k in moving if k > 2),
          ath, ("pos",))
    b.add("_link_rates_out", lambda vel: tuple(vel.w[k] + 0.0 for k in moving if k > 2),
          thd, ("vel",))
    b.add("_link_accelerations", lambda acc: tuple(acc.w[k] + 0.0 for k in moving if k > 2),
          thdd, ("acc",))
    gammas = tuple(d.joint for d in topology.dyads if isinstance(d, RRR))
    if gammas:
        names = tuple(b.out(f"GAMMA{j}", "angle", f"transmission angle at {j}, between its "
                            "two links, 0 to 180") for j in gammas)
        b.add("_transmission", lambda pos: tuple(
            call(_angle_deg, None, pos.gamma[j][0], pos.gamma[j][1]) for j in gammas), names,
            ("pos",))
    b.add("_assembly", np.isfinite, (b.out("ASSEMBLED", "number", "True where the linkage "
                                           "closes at this crank angle"),), ("margin",))

    # points: where, how fast, how accelerated
    where = tuple(n for p in points for n in (b.out(f"X{p}", "length", f"x of {p}"),
                                              b.out(f"Y{p}", "length", f"y of {p}")))
    b.add("_coordinates", lambda pos: tuple(pos.pt[p][i] + 0.0 for p in points for i in (0, 1)),
          where, ("pos",))
    v_xy, a_xy = [], []
    for p in points:
        v_xy += list(b.vector(f"V{p}", "speed", f"velocity of {p}")[2:])
        a_xy += list(b.vector(f"A{p}", "acceleration", f"acceleration of {p}")[2:])
    b.add("_point_velocities", lambda vel: tuple(vel.v[p][i] + 0.0 for p in points
                                                 for i in (0, 1)), tuple(v_xy), ("vel",))
    b.add("_point_accelerations", lambda acc: tuple(acc.v[p][i] + 0.0 for p in points
                                                    for i in (0, 1)), tuple(a_xy), ("acc",))
    for s in slides:
        sl = s.label
        b.add(f"_slide_{sl}", lambda pos, vel, acc, sl=sl: (
            pos.slide[sl] + 0.0, vel.s[sl] + 0.0, acc.s[sl] + 0.0),
            (b.out(f"S{sl}", "length", f"slide {sl}'s position along its guide"),
             b.out(f"VS{sl}", "speed", f"slide {sl}'s rate along its guide"),
             b.out(f"AS{sl}", "acceleration", f"slide {sl}'s acceleration along its guide")),
            ("pos", "vel", "acc"))

    # the links as the effects see them
    def _links(pos: Any, *m: Any) -> Any:
        out: list[Any] = [FRAME]
        for i, k in enumerate(moving):
            W, _, RG, ADEL = m[4 * i:4 * i + 4]
            c, s, bx, by = pos.link[k]
            a = np.radians(ADEL)
            ca, sa = np.cos(a), np.sin(a)
            out.append(Link(c, s, bx, by, W, RG, c * ca - s * sa, s * ca + c * sa))
        return tuple(out)
    b.add("_links", _links, ("links",), ("pos",) + masses)

    def _link_rates(pos: Any, vel: Any) -> Any:
        out: list[Any] = [FRAME_RATE]
        for k in moving:
            base = dyads._base(topology, k)
            vx, vy = vel.v.get(base, (0.0, 0.0))
            out.append(LinkRate(vel.w[k], vx, vy))
        return tuple(out)
    b.add("_link_rates", _link_rates, ("link_rates",), ("pos", "vel"))

    def _inertia_loads(pos: Any, acc: Any, GW: Any, *m: Any) -> Any:
        out = []
        for i, k in enumerate(moving):
            W, ZI = m[4 * i], m[4 * i + 1]
            ax, ay = acc.v[f"G{k}"]
            fx, fy = ax * (-W / GW), ay * (-W / GW)
            gx, gy = pos.pt[f"G{k}"]
            _, _, bx, by = pos.link[k]
            out.append((fx, fy, (gx - bx) * fy - (gy - by) * fx - ZI * acc.w[k]))
        return tuple(out)
    b.add("_inertia_loads", _inertia_loads, ("inertia_loads",), ("pos", "acc", "GW") + masses)

    slots = joints.slots(topology)

    def statics(loads: Any, pos: Any) -> Any:
        """The slots for loads on the links, one (fx, fy, m) per moving link in order."""
        return joints.solve(topology, dict(zip(moving, loads, strict=True)), pos)
    b.skeletons["inertia_loads"] = nested(((None,) * 3,) * len(moving))
    b.add("_inertia_forces", statics, tuple(s + "_i" for s in slots), ("inertia_loads", "pos"))
    statics = b.steps[-1].fn  # unrolled: an effect's loads are of the inertia loads' shape

    totals = []
    for j in pins:
        on = "the frame" if j.on == 1 else f"link {j.on}"
        totals += list(b.vector(j.name, "force", f"force of link {j.by} on {on} at "
                                f"{j.point}")[2:])
    for s in slides:
        totals += [b.out(f"FN{s.label}", "force", f"the guide's force on the slider of slide "
                         f"{s.label or '(the slide)'}, along its normal (+90 deg from the "
                         "guide's line)"),
                   b.out(f"MN{s.label}", "torque", "the guide's couple on the slider, CCW +")]
    totals.append(b.out("TORQ", "torque", "driving torque the drive puts on the crank, CCW +"))
    n_slots = len(slots)
    b.add("_totals", lambda *v: tuple(v[i] + v[i + n_slots] for i in range(n_slots)),
          tuple(totals), tuple(s + "_i" for s in slots) + tuple(s + "_e" for s in slots))

    frame_pins = [(i, j) for i, j in enumerate(pins) if j.on == 1]
    frame_slides = [(i, s) for i, s in enumerate(slides) if s.guide == 1]
    fn_at = 2 * len(pins)

    def _shaking(pos: Any, *t: Any) -> Any:
        """What the moving links put on the frame: the pivots' forces and each slide's
        reaction -FN on its guide (the reactions of applied loads are not in it, as the
        four-bar's SHAK leaves TEX's out); its moment about O2 with the drive's -TORQ."""
        fx: Any = 0.0
        fy: Any = 0.0
        m: Any = -t[-1]
        for i, j in frame_pins:
            x, y = t[2 * i], t[2 * i + 1]
            px, py = pos.pt[j.point]
            fx, fy, m = fx + x, fy + y, m + (px * y - py * x)
        for i, s in frame_slides:
            fn, mn = t[fn_at + 2 * i], t[fn_at + 2 * i + 1]
            u = pos.guide[s.label][3]
            x, y = fn * u[1], -fn * u[0]  # -FN along the normal (-u_y, u_x)
            px, py = pos.pt[s.point]
            fx, fy, m = fx + x, fy + y, m + (px * y - py * x) - mn
        zero = 0.0 * pos.margin
        return fx + zero, fy + zero, m + zero
    shake = b.vector("SHAK", "force", "shaking force on the frame")
    b.add("_shaking", _shaking, (shake[2], shake[3], b.out(
        "SHAKM", "torque", "shaking moment on the frame about O2, CCW +")),
        ("pos",) + tuple(totals))

    def _seed(mech: Any, ath2: Any, scene: Any) -> dict[str, Any]:
        values = mech.as_dict()
        ns: dict[str, Any] = dict(zip(branches, _signs(scene.branch, dyads_n), strict=True))
        for f in fields:
            v = np.asarray(values.get(f, 0.0), dtype=float)
            ns[f] = float(v) if v.ndim == 0 else v
        ns["ATH2"] = np.atleast_1d(np.asarray(ath2, dtype=float))
        ns["GW"] = MASS_DIVISOR[mech.units]
        th2dd = scene.th2dd
        if callable(th2dd):
            ns["th2dd_fn"] = th2dd
        else:
            ns["TH2DD"] = th2dd
        return ns

    from sielaff.quantities import declare, describe

    for out, (kind, meaning) in b.declared.items():
        try:
            describe(out)
        except KeyError:
            declare(out, kind, meaning)
    public = tuple(dict.fromkeys(n for s in b.steps for n in s.provides if n[0].isupper()))
    default = results or (("ATH2",) + public)
    model = Model(name, seed=_seed, results=default,
                  sums={slot: slot + "_e" for slot in slots},
                  breakdown=("TORQ_INERTIA", "TORQ"), counts="margin",
                  params=(Param("branch", "open", _branch_check(dyads_n),
                                '{"open", "crossed"} or one per dyad\n    Which assembly '
                                "of each dyad (sielaff.linkage says which is which)."),
                          number_param("th2dd", "float, array or callable\n    The crank's "
                                       "angular acceleration [rad/sec^2], CCW +; a "
                                       "constant, an\n    array or a function of ATH2 "
                                       "[deg].")),
                  statics=(statics, ("pos",)), mechanism=mechanism, validate=validate,
                  full_turn=full_turn)
    model.add(step_of(_crank_angle), step_of(_crank_acceleration), b.steps)
    model.topology = topology  # type: ignore[attr-defined]
    for name in _FLAT:
        keep(topology, name, b.skeletons.get(name))
    model.link_names = {k: topology.link_name(k) for k in range(1, links + 1)}
    return model


def friction_effect(model: Model) -> Any:
    """The joint-friction effect of ``model``'s pins and slides (engine/joint_friction.py),
    with the model's names of its totals."""
    from sielaff.engine.joint_friction import effect

    topology: Topology = model.topology  # type: ignore[attr-defined]
    return effect(topology, _renamer(topology))


def finish(model: Model) -> Model:
    """Once the effects are registered: the results that need no force analysis (none of
    the weights, inertias or the inertia loads)."""
    topology: Topology = model.topology  # type: ignore[attr-defined]
    masses = frozenset(f for f in topology.fields() if f.startswith(("W", "ZI")))
    model.kinematics = tuple(n for n in model.results if not model.depends_on(
        n, masses | {"inertia_loads"}))
    return model


def kind_model(kind: type, *, full_turn: Callable[[Any], str | None] | None = None,
               results: tuple[str, ...] | None = None, name: str | None = None,
               topology: Topology | None = None) -> Model:
    """The model of a kind of linkage (a :class:`~sielaff.linkage.Kind`, or ``Linkage``):
    the kind's checks of its fields, then, for one design (scalar fields), that every dyad
    closes somewhere; its ``full_turn`` (by default the dyads' margins over a
    revolution, engine/assembly.py); gravity, loads, springs and dampers registered."""
    from sielaff.engine.assembly import assembly_failure, never_assembles

    def topology_of(m: Any) -> Topology:
        return m.topology if hasattr(m, "topology") else m.TOPOLOGY

    def scalar_values(m: Any) -> dict[str, float] | None:
        values = m.as_dict()
        if any(np.ndim(v) for v in values.values()):
            return None
        return {k: float(v) for k, v in values.items()}

    def validate(m: Any) -> None:
        m.check()
        values = scalar_values(m)
        if values is not None:
            why = never_assembles(topology_of(m), values)
            if why:
                raise ValueError(f"{type(m).__name__}: {why}")

    def turns(m: Any) -> str | None:
        if full_turn is not None:
            return full_turn(m)
        values = scalar_values(m)
        if values is None:
            raise ValueError("whether the crank turns fully is asked of one design "
                             "(scalar fields)")
        return assembly_failure(topology_of(m), values)

    topology = topology or kind.TOPOLOGY  # type: ignore[attr-defined]
    return linkage_model(topology, name or kind.KIND,  # type: ignore[attr-defined]
                         mechanism=kind, validate=validate, full_turn=turns, results=results)
