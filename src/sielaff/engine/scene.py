"""The scene: everything that acts on a mechanism besides its geometry and masses.

``Scene(tex=0.0, th2dd=0.0, gravity=None, loads=(), branch="open", friction=None,
elements=())`` is one frozen, validated object; ``analyze(..., scene=...)``, the design
answers, sweeps and every command take it, and a spec's ``[scene]`` table is read into
one.  Its fields are not written here: each is declared by the effect that owns it (a
:class:`~sielaff.engine.declare.Param` in the effect's module) or by the model (the
branch), and :func:`scene_type` makes the dataclass from the model's declarations, so a
new effect's field appears here with nothing else edited.  The default is the 1966
program's scene: the crank at constant speed, no gravity, no load but TEX on the rocker,
the open branch.  Each value is checked once, here (by its declaration's check), for the
API and the spec reader alike: a NaN, an infinity, a magnitude past :data:`LIMIT` or a
wrong type is a ValueError naming the field.
"""

from __future__ import annotations

import dataclasses
from dataclasses import fields
from dataclasses import replace as dataclasses_replace
from typing import TYPE_CHECKING, Any

import numpy as np

from sielaff.engine.fourbar import BRANCHES, FOURBAR
from sielaff.engine.registry import Model
from sielaff.engine.values import LIMIT

__all__ = ["BRANCHES", "LIMIT", "Scene", "SceneBase", "scene_of", "scene_type"]


class SceneBase:
    """What every Scene does, whatever the model's fields (see :func:`scene_type`)."""

    _model: Model

    if TYPE_CHECKING:  # the fields are the model's declarations, made at import
        def __init__(self, **fields: Any) -> None: ...

        def __getattr__(self, name: str) -> Any: ...

    def __post_init__(self) -> None:
        for p in self._model.params:
            object.__setattr__(self, p.name, p.check(getattr(self, p.name)))

    def replace(self, **changes: Any) -> Any:
        """A copy with some fields changed (validated again)."""
        unknown = sorted(set(changes) - {f.name for f in fields(self)})  # type: ignore[arg-type]
        if unknown:
            raise TypeError(f"Scene has no field {', '.join(unknown)}")
        return dataclasses_replace(self, **changes)  # type: ignore[type-var]

    @property
    def effects(self) -> tuple[Any, ...]:
        """The model's effects this scene calls for (each effect's own rule)."""
        return self._model.effects_on(self)

    @property
    def is_1966(self) -> bool:
        """Whether this is the 1966 program's scene (TEX aside): no effect is on."""
        return not any(not e.in_1966 for e in self.effects)

    @property
    def has_friction(self) -> bool:
        """Whether some joint has friction: the rule of the model's friction effect ("pin
        friction" on the four-bar, "joint friction" on a linkage of dyads)."""
        return any(e.is_on(self) for e in self._model.effects
                   if e.name in ("pin friction", "joint friction"))

    def per_position(self) -> list[tuple[str, Any]]:
        """The (field, array) pairs that vary with the crank angle (arrays of ndim > 0)."""
        return [pair for p in self._model.params if p.varies is not None
                for pair in p.varies(getattr(self, p.name))]

    def block(self, i: int, j: int, shape: tuple[int, ...]) -> Any:
        """The scene of positions ``i:j`` of crank angles of ``shape`` (flattened): every
        array of that shape sliced alike (``analyze(..., out=)`` works a block at a time)."""
        def part(name: str, v: Any) -> Any:
            if callable(v) or np.ndim(v) == 0 or np.size(v) == 1:
                return v
            a = np.asarray(v, dtype=float)
            if a.shape != shape:
                raise ValueError(f"with out=, Scene.{name} is a scalar, a callable or an "
                                 f"array of ath2's shape {shape}, not {a.shape}")
            return a.reshape(-1)[i:j]

        return dataclasses_replace(self, **{  # type: ignore[type-var]
            p.name: p.block(getattr(self, p.name), part)
            for p in self._model.params if p.block is not None})


def scene_type(model: Model) -> type[SceneBase]:
    """The frozen dataclass of ``model``'s scene: one field per declared parameter (the
    model's own, then each effect's), its default and its check the declaration's, and a
    numpydoc ``Parameters`` section made of their docs."""
    doc = ("What acts on the mechanism (each effect off by default, as in 1966).\n\n"
           "Parameters\n----------\n"
           + "".join(f"{p.name} : {p.doc}\n" for p in model.params))
    cls = dataclasses.make_dataclass(
        "Scene", [(p.name, Any, dataclasses.field(default=p.default)) for p in model.params],
        bases=(SceneBase,), frozen=True, namespace={"_model": model, "__doc__": doc})
    cls.__module__ = __name__
    return cls


if TYPE_CHECKING:
    Scene = SceneBase
else:
    Scene = scene_type(FOURBAR)


#: The keyword arguments ``analyze`` still takes, each building the same Scene field.
KEYWORDS = ("tex", "th2dd", "gravity", "loads", "branch")


_SCENES: dict[int, type[SceneBase]] = {}


def scene_of(model: Model) -> type[SceneBase]:
    """The Scene type of ``model`` (made once): ``Scene`` for the four-bar."""
    if model is FOURBAR:
        return Scene  # type: ignore[no-any-return]
    if id(model) not in _SCENES:
        _SCENES[id(model)] = scene_type(model)
    return _SCENES[id(model)]


def scene_from(scene: Scene | None, given: dict[str, Any],
               where: str = "analyze", model: Model | None = None) -> Scene:
    """The Scene of a call: ``scene``, or one built from the keywords ``given`` (in
    ``model``'s Scene type, the four-bar's by default); both at once is a ValueError
    naming them, and so is a keyword the model's Scene has no field for."""
    if scene is not None:
        if not isinstance(scene, SceneBase):
            raise ValueError(f"{where}: scene = {scene!r} is not a sielaff.Scene")
        if given:
            raise ValueError(f"{where}: give scene= or {', '.join(sorted(given))}, not both "
                             "(put them in the Scene)")
        return scene
    cls = Scene if model is None else scene_of(model)
    names = {f.name for f in fields(cls)}  # type: ignore[arg-type]
    stray = sorted(set(given) - names)
    if stray:
        raise ValueError(f"{where}: {', '.join(stray)} is not part of a "
                         f"{model.name if model else 'four-bar'}'s scene (its fields: "
                         f"{', '.join(sorted(names))})")
    return cls(**given)  # type: ignore[no-any-return]
