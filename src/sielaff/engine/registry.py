"""Models made of steps: each step declares what it needs and provides; a plan runs only
the steps the asked-for outputs depend on.

``@step(provides=..., needs=..., zero_when=...)`` marks a function as a step (its
parameters must be its ``needs``); it registers nothing.  A :class:`Model` holds steps
(``Model.add``) and :class:`Effect` s (``Model.add_effect``): an effect is declared once,
in its own module, with what it seeds from the :class:`~sielaff.engine.scene.Scene`, its
steps and the parts it adds to the superposed pin forces and drive torque; the model
derives from the effects the step that sums those parts, the step that takes their
public torques out of TORQ (``TORQ_INERTIA``), the outputs it can give and the inputs
whose being zero skips steps.  The 1966 four-bar is one model (``fourbar.FOURBAR``); a
second model (another linkage) is another ``Model`` with its own steps, and nothing is
global but the default.

``Model.plan`` computes the dependency closure of the wanted names in dependency order,
skips a step whose ``zero_when`` inputs are all zero (a massless link, an effect that is
off), and says after which step each intermediate can be dropped.  ``Model.calls``
counts the runs (tests prove an effect that is off costs nothing); ``Model.replacing``
gives a copy with some step functions swapped (how tests inject a spy or a fault).
"""

from __future__ import annotations

import inspect
from collections import Counter
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from dataclasses import replace as dataclasses_replace
from types import ModuleType
from typing import Any

import numpy as np

from sielaff.engine.declare import Fact, Param, SpecForm
from sielaff.engine.statics import plus

__all__ = ["Effect", "Model", "Plan", "Step", "step", "step_of", "steps_of"]


@dataclass(frozen=True)
class Step:
    """One unit of work: ``fn(*needs)`` returns the ``provides`` values, in order."""

    name: str
    fn: Callable[..., Any]
    provides: tuple[str, ...]
    needs: tuple[str, ...]
    zero_when: tuple[str, ...] = ()  # every name any group below uses
    zero_groups: tuple[tuple[str, ...], ...] = ()  # zero if all of one group are zero
    per_link: bool = False  # written for one link: fn(k, *needs), k the link's number
    #: (names, fn): after the step, on either backend, ``fn(*values of names)`` (some of
    #: its outputs) issues the step's warnings (compiled code cannot warn)
    warns: tuple[tuple[str, ...], Callable[..., None]] | None = None
    #: (pass, state values): an iterated step (engine/iterate.py), ``fn`` its numpy form
    iterates: tuple[Callable[..., Any], int] | None = None
    #: (flag, names): where the need ``flag`` is 0.0 the step's outputs are the needs
    #: ``names``, one per output, so the compiled kernel calls a serial step only where
    #: ``flag`` holds (its loop over a chunk is otherwise a call at every position)
    only_where: tuple[str, tuple[str, ...]] | None = None


def zero_when_of(zero_when: Iterable[Any]
                 ) -> tuple[tuple[str, ...], tuple[tuple[str, ...], ...]]:
    """``zero_when`` of :func:`step` (see there) as Step holds it: every name any group
    uses, and the groups."""
    items = tuple(zero_when)
    if all(isinstance(x, str) for x in items):
        groups: tuple[tuple[str, ...], ...] = (items,) if items else ()
    else:
        groups = tuple((g,) if isinstance(g, str) else tuple(g) for g in items)
    return tuple(dict.fromkeys(n for g in groups for n in g)), groups


def step(provides: Iterable[str], needs: Iterable[str] = (),
         zero_when: Iterable[Any] = (), per_link: bool = False,
         warns: tuple[tuple[str, ...], Callable[..., None]] | None = None,
         only_where: tuple[str, tuple[str, ...]] | None = None
         ) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Mark the decorated function as a step (``steps_of`` finds it; a model adds it).

    The function's parameters must be exactly ``needs`` (so the declaration can be
    checked against the code) and it returns one value per name in ``provides`` (a bare
    value if there is one).  ``zero_when``: names that, if all identically zero, make
    every provided value zero; or a list of such groups (tuples), any one of which all
    zero suffices (a link's inertia force is zero if it has no mass *or* its centre of
    mass does not accelerate).  A step never changes its inputs (tests run the engine on
    read-only arrays).  ``per_link``: the function is written for one link, its first
    parameter the link's number (not a need); the model calls it for each moving link
    and the step provides the tuple of their answers (:func:`per_link`).  ``warns``:
    ``(names, fn)``, the step's warnings issued by ``fn`` from its outputs ``names``
    after it runs (the model's ``warn``), so that the compiled backend, whose code cannot
    warn, issues the same ones.  ``only_where``: ``(flag, names)``, a promise of the
    step's code that where the need ``flag`` is 0.0 its outputs are the needs ``names``
    (one per output, in order); the compiled kernel then calls a serial step (array code)
    only where ``flag`` is not 0.0 (``tests/test_only_where.py`` holds every step that
    promises it to its promise).
    """
    provides, needs = tuple(provides), tuple(needs)
    flat, groups = zero_when_of(zero_when)
    if only_where is not None:
        flag, through = only_where
        if isinstance(through, str) or flag not in needs:
            raise TypeError(f"only_where {only_where}: the flag must be a need, and the "
                            "names a tuple of them")
        only_where = (flag, tuple(through))
        if not set(only_where[1]) <= set(needs) or len(only_where[1]) != len(provides):
            raise TypeError(f"only_where {only_where}: one need per output of {provides}")

    def decorate(fn: Callable[..., Any]) -> Callable[..., Any]:
        params = tuple(inspect.signature(fn).parameters)[1 if per_link else 0:]
        if params != needs:
            raise TypeError(f"step {fn.__name__}: parameters {params} != needs {needs}")
        if warns is not None and not set(warns[0]) <= set(provides):
            raise TypeError(f"step {fn.__name__}: warns from {warns[0]}, not all provided")
        fn.__sielaff_step__ = Step(fn.__name__, fn, provides, needs, flat, groups,  # type: ignore[attr-defined]
                                   per_link, warns, only_where=only_where)
        return fn

    return decorate


def step_of(fn: Callable[..., Any]) -> Step:
    """The Step ``@step`` made of ``fn``."""
    return fn.__sielaff_step__  # type: ignore[attr-defined,no-any-return]


def steps_of(module: ModuleType) -> tuple[Step, ...]:
    """The steps a module defines with ``@step``, in the order they are written."""
    return tuple(v.__sielaff_step__ for v in vars(module).values()
                 if callable(v) and isinstance(getattr(v, "__sielaff_step__", None), Step)
                 and v.__module__ == module.__name__)


@dataclass(frozen=True)
class Effect:
    """What a scene may call for, declared once (in the effect's own module).

    ``seed(scene, mechanism)`` gives the names it puts in the namespace (all zero when
    the effect is off: its steps are then skipped); ``steps`` compute its parts;
    ``parts`` maps a slot of the model's superposed quantities (``Model(sums=...)``: the
    four-bar's pin forces and drive torque) to the name of the effect's share of that
    quantity (added to the 1966 program's totals); ``torque`` names its
    public share of TORQ, if it has one (taken out of TORQ to leave ``TORQ_INERTIA``).

    An effect that is not superposable (pin friction needs the totals of everything
    else) instead ``corrects`` totals: ``{total: correction}``.  When it is on (some
    seed named in ``switch`` is not zero) the model's steps that provide those totals
    provide ``total + "_0"`` (the totals without it), the effect's steps take those,
    and a derived step ``_corrections`` adds the corrections; when it is off the plan
    is the model's without it, step for step.

    What the tools derive from (:mod:`sielaff.engine.declare`): ``params``, the Scene
    fields it owns (default, check, doc); ``outputs``, ``{name: (kind, description)}``
    for each public name its steps provide (the unit is the kind's, in the unit system
    in force); ``on(scene)``, the one rule of whether the scene calls for it;
    ``summary(scene, units)``, a few words (``"pin friction"``); ``describe(scene,
    units)``, its parameters as :class:`~sielaff.engine.declare.Fact` s;
    ``figure_outputs(scene)`` and ``figures(results, scene, units, speed)``, its
    headline figures over one revolution at the crank speed ``speed``; ``columns(scene)``,
    the outputs a table shows when it is on (all its outputs by default); ``spec``, its
    form in a spec's ``[scene]`` (the compiled backend asks no one: it compiles the
    effect's steps or refuses them); ``in_1966``, whether the 1966 program had it (TEX).

    An effect that puts loads on the links names them in ``applies``: its step provides
    that name as ``{link: (fx, fy, m)}`` (:mod:`sielaff.engine.links`), and the model
    derives the step that turns them into its ``parts`` by the model's own statics, so the
    effect does not know the linkage.
    """

    name: str
    steps: tuple[Step, ...]
    seed: Callable[[Any, Any], dict[str, Any]]
    parts: Mapping[str, str] = field(default_factory=dict)
    torque: str | None = None
    corrects: Mapping[str, str] = field(default_factory=dict)
    switch: tuple[str, ...] = ()
    params: tuple[Param, ...] = ()
    outputs: Mapping[str, tuple[str, str]] = field(default_factory=dict)
    on: Callable[[Any], bool] | None = None
    summary: Callable[[Any, str], str] | None = None
    describe: Callable[[Any, str], list[Fact]] | None = None
    figure_outputs: Callable[[Any], tuple[str, ...]] | None = None
    figures: Callable[[Mapping[str, Any], Any, str, float], list[Fact]] | None = None
    columns: Callable[[Any], tuple[str, ...]] | None = None
    spec: SpecForm | None = None
    in_1966: bool = False
    applies: str | None = None

    def __post_init__(self) -> None:
        if self.corrects and not self.switch:
            raise ValueError(f"effect {self.name}: an effect that corrects totals names "
                             "the seeds that switch it on (switch=)")
        public = {n for s in self.steps for n in s.provides if n[0].isupper()}
        if self.applies:  # its parts come from the model's statics, TORQ's its torque
            if self.parts or not self.torque:
                raise ValueError(f"effect {self.name} applies loads: it names its torque "
                                 "(torque=), the model names its parts")
            public.add(self.torque)
        missing = sorted(public - set(self.outputs))
        if missing:
            raise ValueError(f"effect {self.name}: outputs {missing} have no declared "
                             "(kind, description)")
        stray = sorted(set(self.outputs) - public)
        if stray:
            raise ValueError(f"effect {self.name}: declares outputs {stray} no step provides")
        if self.params and self.on is None:
            raise ValueError(f"effect {self.name}: an effect with parameters says when it "
                             "is on (on=)")

    def __repr__(self) -> str:
        return f"Effect({self.name!r})"

    def is_on(self, scene: Any) -> bool:
        """Whether ``scene`` calls for this effect (its one rule)."""
        return bool(self.on(scene)) if self.on is not None else False

    def shown(self, scene: Any) -> tuple[str, ...]:
        """The outputs a table shows when the effect is on."""
        return self.columns(scene) if self.columns is not None else tuple(self.outputs)


#: A plan: (step, skipped, names to drop after it), in dependency order.
Plan = tuple[tuple[Step, bool, tuple[str, ...]], ...]


class Model:
    """A model of a linkage: its steps, its effects, and how to run what is asked for.

    ``results``: the default outputs, in print order; ``sums``: for each slot of
    :data:`SLOTS` the name the sum of the effects' parts is provided as (the model's
    force steps add it to their totals); ``breakdown``: ``(name, total)``, the total
    torque less every effect's public torque (``("TORQ_INERTIA", "TORQ")``);
    ``counts``: the name whose NaN marks a position that cannot assemble; ``params``: its
    own Scene fields; ``statics``: ``(fn, geometry)``, how loads on its links become its
    sums (:mod:`sielaff.engine.links`); ``mechanism``: the type of mechanism it analyses
    (``analysis.model_for`` finds a mechanism's model by it); ``validate(mechanism)``: the
    one check of such a mechanism's fields (a ValueError in one line naming the field);
    ``full_turn(mechanism)``: why its crank cannot make a whole revolution, or None.
    """

    def __init__(self, name: str, *, seed: Callable[[Any, Any, Any], dict[str, Any]],
                 results: tuple[str, ...], sums: Mapping[str, str] | None = None,
                 breakdown: tuple[str, str] | None = None, counts: str | None = None,
                 params: tuple[Param, ...] = (),
                 statics: tuple[Callable[..., Any], tuple[str, ...]] | None = None,
                 torque_slot: str = "torq", mechanism: type | None = None,
                 validate: Callable[[Any], None] | None = None,
                 full_turn: Callable[[Any], str | None] | None = None) -> None:
        self.name = name
        self.mechanism = mechanism
        self.validate = validate
        self.full_turn = full_turn
        self.own_params = params
        self.statics = statics
        self.torque_slot = torque_slot
        self._seed = seed
        self.results = results
        self.sums = dict(sums or {})
        self.breakdown = breakdown
        self.counts = counts
        #: The results that need no force analysis (set by the model's module).
        self.kinematics: tuple[str, ...] = ()
        self._link_names: dict[int, str] = {1: "frame", 2: "crank", 3: "coupler", 4: "rocker"}
        self.effects: list[Effect] = []
        self._own: list[Step] = []
        self.calls: Counter[str] = Counter()
        self._redo: Callable[[Step], Step] | None = None
        self._derive()

    # -- building ------------------------------------------------------------------------

    def add(self, *items: Step | ModuleType | Iterable[Step]) -> Model:
        """Add steps (a Step, the steps of a module, or an iterable of Steps)."""
        for item in items:
            if isinstance(item, Step):
                self._own.append(item)
            elif isinstance(item, ModuleType):
                self._own.extend(steps_of(item))
            else:
                self._own.extend(item)
        self._derive()
        return self

    def add_effect(self, effect: Effect | str) -> Model:
        """Register an effect: its steps, its seed, its parts in the sums, its outputs'
        units and meanings in :mod:`sielaff.quantities`.  A string names the module of
        ``sielaff.engine`` whose ``EFFECT`` it is (one line registers a new one)."""
        if isinstance(effect, str):
            import importlib

            effect = importlib.import_module(f"sielaff.engine.{effect}").EFFECT
            assert isinstance(effect, Effect)
        if any(e.name == effect.name for e in self.effects):
            raise ValueError(f"effect {effect.name} registered twice in model {self.name}")
        bad = sorted(set(effect.parts) - set(self.sums))
        if bad:
            raise ValueError(f"effect {effect.name}: model {self.name} has no slots {bad} "
                             f"(slots: {tuple(self.sums)})")
        if effect.applies and self.statics is None:
            raise ValueError(f"effect {effect.name} applies loads to the links: model "
                             f"{self.name} has no statics to take them")
        taken = {p.name for p in self.params}
        clash = [p.name for p in effect.params if p.name in taken]
        if clash:
            raise ValueError(f"effect {effect.name}: Scene field {clash[0]} is another's")
        from sielaff.quantities import declare

        for out, (kind, description) in effect.outputs.items():
            declare(out, kind, description)
        self.effects.append(effect)
        self._derive()
        return self

    @property
    def link_names(self) -> dict[int, str]:
        """Each link's name (the frame is link 1), as specs and the tools say them."""
        return self._link_names

    @link_names.setter
    def link_names(self, names: dict[int, str]) -> None:
        self._link_names = dict(names)
        self._derive()  # an effect's loads are one per moving link

    @property
    def params(self) -> tuple[Param, ...]:
        """The Scene's fields: the model's own, then each effect's, in registration order."""
        return self.own_params + tuple(p for e in self.effects for p in e.params)

    def effect(self, name: str) -> Effect:
        """The registered effect called ``name``."""
        for e in self.effects:
            if e.name == name:
                return e
        raise KeyError(f"model {self.name} has no effect {name!r}")

    def effects_on(self, scene: Any) -> tuple[Effect, ...]:
        """The effects ``scene`` calls for, in registration order."""
        return tuple(e for e in self.effects if e.is_on(scene))

    @property
    def torque_parts(self) -> tuple[str, ...]:
        """The parts TORQ is the sum of: the breakdown's rest (``TORQ_INERTIA``), then
        each effect's public share, in registration order."""
        rest = (self.breakdown[0],) if self.breakdown else ()
        return rest + tuple(e.torque for e in self.effects if e.torque)

    def replacing(self, **fns: Callable[..., Any]) -> Model:
        """A copy whose steps named in ``fns`` run the given functions instead."""
        unknown = sorted(set(fns) - {s.name for s in self.steps}
                         - {s.name for e in self.effects for s in e.steps})
        if unknown:
            raise ValueError(f"model {self.name} has no step {', '.join(unknown)}")
        return self.mapping(lambda st: fns.get(st.name, st.fn))

    def mapping(self, wrap: Callable[[Step], Callable[..., Any]], *,
                skip_zeros: bool = True) -> Model:
        """A copy whose every step runs ``wrap(step)`` instead of ``step.fn``; with
        ``skip_zeros=False`` one that never skips a step (what the ``zero_when``
        declarations are checked against)."""
        def redo(s: Step) -> Step:
            fn = wrap(s)  # an iterated step's pass, and a promise, its own only while fn is
            iterates = s.iterates if fn is s.fn else None
            only_where = s.only_where if fn is s.fn else None
            if skip_zeros:
                return dataclasses_replace(s, fn=fn, iterates=iterates, only_where=only_where)
            return dataclasses_replace(s, fn=fn, iterates=iterates, only_where=only_where,
                                       zero_when=(), zero_groups=())

        new = Model(self.name, seed=self._seed, results=self.results, sums=self.sums,
                    breakdown=self.breakdown, counts=self.counts, params=self.own_params,
                    statics=self.statics, torque_slot=self.torque_slot,
                    mechanism=self.mechanism, validate=self.validate,
                    full_turn=self.full_turn)
        new._own = [redo(s) for s in self._own]
        new.effects = [dataclasses_replace(e, steps=tuple(redo(s) for s in e.steps))
                       for e in self.effects]
        new._redo = redo
        new.kinematics = self.kinematics
        new.link_names = self.link_names
        new._derive()
        return new

    def _derive(self) -> None:
        """The steps the effects imply (the sums of their parts, the torque breakdown,
        the corrections), and the index of who provides what, with every corrective
        effect off (``steps``, ``provider``) and for each set of them on (``_variant``)."""
        self._variants: dict[tuple[str, ...], tuple[tuple[Step, ...], dict[str, Step]]] = {}
        self.steps, self.provider = self._variant(())
        self._plans: dict[tuple[Any, ...], Plan] = {}
        names = set(self.provider) | {n for e in self.effects for s in e.steps
                                      for n in s.provides}
        self.outputs: tuple[str, ...] = self.results + tuple(sorted(
            n for n in names if n[0].isupper() and n not in self.results))
        self.zero_candidates = frozenset(n for e in self.effects for n in e.switch) | \
            frozenset(n for s in self.steps for n in s.zero_when)

    def _variant(self, active: tuple[str, ...]) -> tuple[tuple[Step, ...], dict[str, Step]]:
        """The steps and their providers with the corrective effects ``active`` on."""
        if active in self._variants:
            return self._variants[active]
        on = [e for e in self.effects if e.corrects and e.name in active]
        totals = tuple(dict.fromkeys(t for e in on for t in e.corrects))
        own = [s if not set(totals) & set(s.provides) else dataclasses_replace(
            s, provides=tuple(n + "_0" if n in totals else n for n in s.provides))
            for s in self._own]
        derived: list[Step] = [self._statics_step(e) for e in self.effects if e.applies]
        if self.sums:
            derived.append(_sum_step(self.sums, [self.parts_of(e) for e in self.effects]))
        if self.breakdown:
            name, total = self.breakdown
            torques = tuple(e.torque for e in self.effects
                            if e.torque and (not e.corrects or e in on))
            derived.append(Step("_torque_for_inertia", _less(len(torques)), (name,),
                                (total,) + torques))
        if totals:
            corrections = [tuple(e.corrects[t] for e in on if t in e.corrects)
                           for t in totals]
            derived.append(_correction_step(totals, corrections))
        if self._redo is not None:
            derived = [self._redo(s) for s in derived]
        # a corrective effect that is off: its outputs are zero, from a stand-in that needs
        # nothing (its steps need the totals without it, which this variant has not)
        off = [Step(s.name + "_off", _zeros(len(s.provides)), s.provides, (), (), ((),))
               for e in self.effects if e.corrects and e not in on for s in e.steps]
        if self._redo is not None:
            off = [self._redo(s) for s in off]
        links = len(self._link_names)
        steps = tuple(own) + tuple(per_link(s, links) for e in self.effects
                                   if not e.corrects or e in on for s in e.steps
                                   ) + tuple(off) + tuple(derived)
        provider: dict[str, Step] = {}
        for st in steps:
            for name in st.provides:
                if name in provider:
                    raise ValueError(f"{name} provided twice ({provider[name].name}, "
                                     f"{st.name}) in model {self.name}")
                provider[name] = st
        self._variants[active] = (steps, provider)
        return steps, provider

    def parts_of(self, effect: Effect) -> Mapping[str, str]:
        """The effect's part of each slot: as it declares them, or, for an effect that
        applies loads to the links, ``slot + "_" + applies`` from the model's statics
        (its ``torque`` for the drive torque's slot)."""
        if not effect.applies:
            return effect.parts
        return {s: effect.torque if s == self.torque_slot and effect.torque
                else f"{s}_{effect.applies}" for s in self.sums}

    def _statics_step(self, effect: Effect) -> Step:
        """The step turning an effect's loads on the links into its parts of the slots,
        by the model's statics (skipped with the effect: its loads are then zero)."""
        assert self.statics is not None and effect.applies is not None
        fn, geometry = self.statics
        args = ", ".join(f"a{i}" for i in range(len(geometry) + 1))
        _statics = _generated("_statics", (effect.applies,) + geometry, [f"statics({args})"],
                              {"statics": fn})
        parts = self.parts_of(effect)
        provides = tuple(parts[s] for s in self.sums)
        return Step(f"_statics_{effect.applies}", _statics, provides,
                    (effect.applies,) + geometry, (effect.applies,), ((effect.applies,),))

    def active(self, zero_seeds: frozenset[str]) -> tuple[str, ...]:
        """The corrective effects that are on (some seed of their ``switch`` not zero)."""
        return tuple(e.name for e in self.effects
                     if e.corrects and not all(n in zero_seeds for n in e.switch))

    # -- using ---------------------------------------------------------------------------

    def seed(self, mechanism: Any, ath2: Any, scene: Any) -> dict[str, Any]:
        """The namespace the steps start from: the model's inputs, then each effect's."""
        ns = self._seed(mechanism, ath2, scene)
        for effect in self.effects:
            ns.update(effect.seed(scene, mechanism))
        return ns

    def zero_seeds(self, ns: Mapping[str, Any]) -> frozenset[str]:
        """The seeded inputs that are identically zero (a massless link, an effect off)."""
        # a plain number asked as itself: np.any's cost per call, paid for every switch,
        # was a sixth of the time of an analysis of 360 positions
        return frozenset(n for n in self.zero_candidates if n in ns and not (
            ns[n] if isinstance(ns[n], float | int) else np.any(ns[n])))

    def needs_assembly(self, name: str) -> bool:
        """Whether ``name`` is undefined where the loop cannot close (it depends on the
        position of links 3 and 4); a skipped step's zero is then NaN there too."""
        return self.counts is not None and self.depends_on(name, frozenset((self.counts,)))

    def depends_on(self, name: str, inputs: frozenset[str]) -> bool:
        """Whether ``name`` (transitively) needs any of ``inputs``."""
        if name in inputs:
            return True
        st = self.provider.get(name)
        return st is not None and any(self.depends_on(n, inputs) for n in st.needs)

    def plan(self, wanted: tuple[str, ...], seeded: frozenset[str],
             zero_seeds: frozenset[str]) -> Plan:
        """Steps to run, in dependency order, as (step, skipped, names to drop after it).

        Dropping intermediates after their last use lets numpy reuse their memory
        (fresh multi-megabyte arrays cost page faults, more than the arithmetic).
        """
        key = (wanted, seeded, zero_seeds)
        if key not in self._plans:
            if len(self._plans) > 256:
                self._plans.clear()
            self._plans[key] = self._make_plan(wanted, seeded, zero_seeds)
        return self._plans[key]

    def _make_plan(self, wanted: tuple[str, ...], seeded: frozenset[str],
                   zero_seeds: frozenset[str]) -> Plan:
        zero_memo: dict[str, bool] = {}
        provider = self._variant(self.active(zero_seeds))[1]

        def known_zero(name: str) -> bool:
            if name in seeded:
                return name in zero_seeds
            if name not in zero_memo:
                zero_memo[name] = is_zero(provider[name])
            return zero_memo[name]

        def is_zero(st: Step) -> bool:
            return any(all(known_zero(n) for n in g) for g in st.zero_groups)

        order: list[tuple[Step, bool]] = []
        available = set(seeded)
        active: set[str] = set()

        def visit(name: str) -> None:
            if name in available:
                return
            st = provider.get(name)
            if st is None:
                raise ValueError(f"{name} is neither an input nor provided by a step")
            if st.name in active:
                raise RuntimeError(f"dependency cycle through {st.name}")
            skipped = is_zero(st)
            if not skipped:
                active.add(st.name)
                for need in st.needs:
                    visit(need)
                active.discard(st.name)
            order.append((st, skipped))
            available.update(st.provides)

        for name in wanted:
            visit(name)
        last_use: dict[str, int] = {}
        for i, (st, skipped) in enumerate(order):
            for name in () if skipped else st.needs:
                last_use[name] = i
            for name in st.provides:
                last_use.setdefault(name, i)
        drops: list[list[str]] = [[] for _ in order]
        for name, i in last_use.items():
            if name not in wanted and name not in seeded:
                drops[i].append(name)
        return tuple((st, skipped, tuple(d))
                     for (st, skipped), d in zip(order, drops, strict=True))

    def run(self, order: Plan, ns: dict[str, Any]) -> int | None:
        """Run the planned steps in ``ns``; the number of positions that cannot assemble
        (NaN in ``counts``), None if no position was solved.  When some cannot, their mask
        is left in ``ns["_not_assembled"]``."""
        not_assembled = None
        for st, skipped, drop in order:
            if skipped:
                for name in st.provides:
                    ns[name] = 0.0
            else:
                self.calls[st.name] += 1
                result = st.fn(*[ns[n] for n in st.needs])
                if len(st.provides) == 1:
                    result = (result,)
                for name, value in zip(st.provides, result, strict=True):
                    ns[name] = value
                warn(st, ns)
                if self.counts in st.provides:
                    mask = np.isnan(ns[self.counts])
                    not_assembled = int(np.count_nonzero(mask))
                    if not_assembled:
                        ns["_not_assembled"] = mask
            for name in drop:
                del ns[name]
        return not_assembled


def warn(st: Step, values: Mapping[str, Any]) -> None:
    """The warnings of a step that has run (``Step.warns``), from its outputs ``values``."""
    if st.warns is not None:
        names, fn = st.warns
        fn(*[values[n] for n in names])


def _generated(name: str, params: tuple[str, ...], returns: list[str],
               glob: Mapping[str, Any] | None = None) -> Callable[..., Any]:
    """A function ``name(*params)`` returning ``returns`` (expressions; a bare value if
    one), written out as source: a derived step is then plain code, which the compiled
    backend compiles as it compiles any step (no closure, no ``*args``)."""
    args = [f"a{i}" for i in range(len(params))]
    value = returns[0] if len(returns) == 1 else "(" + ", ".join(returns) + ",)"
    src = f"def {name}({', '.join(args)}):\n    return {value}\n"
    ns: dict[str, Any] = {"plus": plus, **(glob or {})}
    exec(compile(src, f"<sielaff derived step {name}>", "exec"), ns)  # noqa: S102
    fn = ns[name]
    fn.__module__ = __name__
    fn.__sielaff_source__ = src  # what the compiled backend's kernel cache hashes
    return fn  # type: ignore[no-any-return]


def per_link(st: Step, links: int) -> Step:
    """A step written for one link (``Step.per_link``: its first parameter the link's
    number) as the step giving one value for each moving link, 2 to ``links``, in order
    (an effect's loads on the links); any other step as it is."""
    if not st.per_link:
        return st
    args = "".join(f", a{i}" for i in range(len(st.needs)))
    calls = [f"one({k}{args})" for k in range(2, links + 1)]
    fn = _generated(st.fn.__name__, st.needs, ["(" + ", ".join(calls) + ",)"],
                    {"one": st.fn})
    return dataclasses_replace(st, fn=fn, per_link=False)


def _sum_step(sums: Mapping[str, str], parts: list[Mapping[str, str]]) -> Step:
    """The step adding each effect's part of each slot (``parts``: each effect's, in
    registration order)."""
    slots = tuple(sums)
    needs_by_slot = [tuple(p[s] for p in parts if s in p) for s in slots]
    needs = tuple(dict.fromkeys(n for ns in needs_by_slot for n in ns))
    totals = []
    for ns in needs_by_slot:
        total = "0.0"
        for n in ns:
            total = f"plus({total}, a{needs.index(n)})"
        totals.append(total)
    provides = tuple(sums[s] for s in slots)
    # with no part at all the sums are always zero: one empty group, trivially all zero
    groups: tuple[tuple[str, ...], ...] = (needs,)
    return Step("_effects", _generated("_effects", needs, totals), provides, needs, needs,
                groups)


def _correction_step(totals: tuple[str, ...],
                     corrections: list[tuple[str, ...]]) -> Step:
    """The step adding the corrective effects' corrections to the totals ``t + "_0"``."""
    needs = tuple(t + "_0" for t in totals) + tuple(
        dict.fromkeys(c for cs in corrections for c in cs))
    out = []
    for k, cs in enumerate(corrections):
        total = f"a{k}"
        for c in cs:
            total = f"plus({total}, a{needs.index(c)})"
        out.append(total)
    return Step("_corrections", _generated("_corrections", needs, out), totals, needs)


def _zeros(k: int) -> Callable[..., Any]:
    """A corrective effect that is off: each of its ``k`` outputs zero."""
    return _generated("_off", (), ["0.0"] * k)


def _less(k: int) -> Callable[..., Any]:
    """The total less each effect's public share (the links' inertia alone)."""
    total = "a0"
    for i in range(k):
        total = f"{total} - a{i + 1}"
    return _generated("_torque_for_inertia", tuple(f"p{i}" for i in range(k + 1)), [total])
