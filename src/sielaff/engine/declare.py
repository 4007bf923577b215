"""What an effect declares about itself, besides its steps: its scene parameters, its
spec form, and the words and figures the tools show for it.

An effect's module builds one :class:`~sielaff.engine.registry.Effect` with these; the
Scene (its fields and their checks), the spec reader (its keys), the catalogue of units
(:mod:`sielaff.quantities`), the table's columns, the torque parts, ``check``'s text and
JSON, the report's scene section and the compiled backend's refusal are all derived from
them (docs/architecture.md walks through adding one).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from sielaff.engine.values import check_value

__all__ = ["Fact", "Param", "SpecForm", "SpecReader", "fact_lines", "number_effect",
           "number_param",
           "varying"]


@dataclass(frozen=True)
class Param:
    """One field of the Scene, owned by the effect (or the model) that declares it.

    ``check(value)`` returns the value as the Scene keeps it, or raises a ValueError
    naming ``Scene.<name>``: the one check of that value, for the API and the spec reader
    alike.  ``doc``: its numpydoc entry (type line, then the meaning with its unit in
    brackets).  ``varies(value)``: the (label, array) pairs of it that vary with the crank
    angle; ``block(value, part)``: the value for a block of positions, ``part(label, v)``
    slicing each such array (``analyze(..., out=)`` works a block at a time).
    """

    name: str
    default: Any
    check: Callable[[Any], Any]
    doc: str
    varies: Callable[[Any], list[tuple[str, Any]]] | None = None
    block: Callable[[Any, Callable[[str, Any], Any]], Any] | None = None


def varying(name: str) -> tuple[Callable[[Any], list[tuple[str, Any]]],
                                Callable[[Any, Callable[[str, Any], Any]], Any]]:
    """``varies`` and ``block`` for a field that is a number, an array along the crank
    angles or a callable."""
    def varies(v: Any) -> list[tuple[str, Any]]:
        return [] if callable(v) or not np.ndim(v) else [(name, v)]

    def block(v: Any, part: Callable[[str, Any], Any]) -> Any:
        return part(name, v)

    return varies, block


def number_param(name: str, doc: str) -> Param:
    """A field that is a number, an array broadcasting with the crank angles or a
    callable (checked finite and within the bound when not a callable), default 0."""
    def check(v: Any) -> Any:
        return v if callable(v) else check_value(f"Scene.{name}", v)

    varies, block = varying(name)
    return Param(name, 0.0, check, doc, varies, block)


def number_effect(field: str, name: str, of: str, label: str, kind: str, key: str,
                  help: str) -> dict[str, Any]:
    """What an effect of one :func:`number_param` field declares besides its steps: its
    seed (``name``, or ``field + "_fn"`` for a function of ``of``), its on rule (a function,
    or a value not zero), its words (``label`` and the number in the unit of ``kind``)
    and its spec form (the key ``key``, a number; ``help`` its line).  TEX and TH2DD."""
    def seed(scene: Any, mechanism: Any) -> dict[str, Any]:
        v = getattr(scene, field)
        return {f"{field}_fn": v} if callable(v) else {name: v}

    def on(scene: Any) -> bool:
        v = getattr(scene, field)
        return callable(v) or bool(np.any(np.asarray(v) != 0.0))

    def summary(scene: Any, units: str) -> str:
        from sielaff.quantities import unit

        v = getattr(scene, field)
        if callable(v):
            return f"{name} a function of {of}"
        if np.ndim(v):
            return f"{name} varying with THETA 2"
        return f"{name} = {v:g} {unit(name, units)}"

    def describe(scene: Any, units: str) -> list[Fact]:
        v = getattr(scene, field)
        if callable(v) or np.ndim(v):
            return [Fact("", name, summary(scene, units).removeprefix(name + " "))]
        return [Fact("", label, float(v), kind)]

    def read(table: Any, path: str, reader: Any) -> dict[str, Any]:
        return {field: reader.number(f"{path}: [scene] {key}", table[key])} \
            if key in table else {}

    def write(scene: Any) -> dict[str, Any]:
        v = getattr(scene, field)
        return {key: float(v)} if not callable(v) and not np.ndim(v) and v else {}

    return {"seed": seed, "on": on, "summary": summary, "describe": describe,
            "spec": SpecForm((key,), read, write, help)}


@dataclass(frozen=True)
class Fact:
    """One thing the tools say about an effect: ``value`` (a number in the unit of
    ``kind``, a kind of :data:`sielaff.quantities.KINDS`, or text when ``kind`` is None)
    under ``label``; facts of one ``group`` (a pin, a spring) print on one line."""

    group: str
    label: str
    value: float | str
    kind: str | None = None


def fact_lines(facts: list[Fact], units: str, indent: str = "    ") -> list[str]:
    """The facts as text, one line per group: ``"O2: mu = 0.1, radius = 0.25 in"``."""
    from sielaff.quantities import fmt

    groups: dict[str, list[str]] = {}
    for f in facts:
        text = (str(f.value) if f.kind is None or isinstance(f.value, str)
                else fmt(f.value, f.kind, units, ".6g"))
        groups.setdefault(f.group, []).append(f"{f.label} = {text}")
    return [f"{indent}{g + ': ' if g else ''}{', '.join(items)}" for g, items in groups.items()]


class SpecReader(Protocol):
    """What the spec reader lends an effect's reader (the spec's own number rules)."""

    def number(self, where: str, value: Any) -> float: ...

    def name(self, where: str, value: Any, names: Any, say: str | None = None) -> Any: ...

    def table(self, where: str, value: Any) -> dict[str, Any]: ...

    def unknown(self, where: str, table: Mapping[str, Any], known: Any) -> None: ...

    def error(self, message: str) -> Exception: ...


@dataclass(frozen=True)
class SpecForm:
    """How the effect appears in a spec's ``[scene]``.

    ``keys``: the keys of ``[scene]`` it owns; ``read(scene_table, path, reader)``: the
    Scene fields they give (a dict; raise ``reader.error(...)`` naming the key);
    ``write(scene)``: the keys back, as parsed TOML (a dict, empty when off), so that
    ``read(write(scene))`` is the same scene; ``help``: its lines of ``sielaff help spec``
    (TOML with comments).
    """

    keys: tuple[str, ...]
    read: Callable[[Mapping[str, Any], str, SpecReader], dict[str, Any]]
    write: Callable[[Any], dict[str, Any]]
    help: str
