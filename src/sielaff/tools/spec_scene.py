"""A spec's ``[scene]``, read into a :class:`~sielaff.Scene` here and nowhere else.

The keys of ``[scene]`` besides ``units`` and ``branch`` are the model's effects': each
effect's :class:`~sielaff.engine.declare.SpecForm` names its keys, reads them and says
them in ``sielaff help spec`` (:func:`scene_help`).  Every number goes through the spec's
own number rule (:func:`sielaff.tools.spec_fields._float`) and every value through the
Scene's one check; a bad one is one line naming the spec's key.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from sielaff.tools.spec_fields import PunchError, _float, _name, _table, _unknown

if TYPE_CHECKING:
    from sielaff.engine.scene import Scene

__all__ = ["scene_help", "scene_keys", "scene_of", "scene_spec"]

#: The keys of ``[scene]`` that are not an effect's.
OWN_KEYS = ("units", "branch")

_HEAD = """\
[scene]
units = "in-lb-sec"           # or "SI" (the whole spec is then in SI)
branch = "open"               # or "crossed"; a six-bar: one per dyad, ["open", "crossed"]"""


class _Reader:
    """The spec's rules lent to an effect's reader (its errors are PunchErrors)."""

    number = staticmethod(_float)
    name = staticmethod(_name)
    table = staticmethod(_table)
    unknown = staticmethod(_unknown)

    @staticmethod
    def error(message: str) -> Exception:
        return PunchError(message)


def _reader(model: Any) -> type:
    """The reader for ``model``'s spec: its links by name (loads, springs, dampers)."""
    from sielaff.engine.links import links_by_name

    class Reader(_Reader):
        links = links_by_name(model.link_names)
        frame_links = links_by_name(model.link_names, frame=True)
    return Reader


def _model(kind: str | None = None) -> Any:
    from sielaff.engine.analysis import model_named
    from sielaff.tools.spec_fields import FOUR_BAR

    return model_named(kind or FOUR_BAR)


def _effects(kind: str | None = None) -> list[Any]:
    return [e for e in _model(kind).effects if e.spec is not None]


def scene_keys(kind: str | None = None) -> tuple[str, ...]:
    """Every key ``[scene]`` may hold (for the linkage ``kind``, the four-bar by default):
    its own, then each of the kind's effects'."""
    return OWN_KEYS + tuple(k for e in _effects(kind) for k in e.spec.keys)


def scene_help() -> str:
    """``[scene]`` as ``sielaff help spec`` shows it: the table's own keys, then each
    effect's lines (its declaration's ``help``), in the order the effects register."""
    return "\n".join([_HEAD] + [e.spec.help for e in _effects()])


def scene_of(spec: dict, path: str = "<spec>") -> tuple[str, Scene]:
    """The spec's unit system and its ``[scene]`` as a :class:`~sielaff.Scene` (the
    Scene of its ``[linkage] kind``'s model: a ``SliderCrankScene`` for a slider-crank; see
    docs/effects.md and :func:`scene_help`), read here and nowhere else.  Lengths,
    forces and torques are in the spec's unit system; angles in degrees."""
    from sielaff.engine.scene import scene_of as scene_type
    from sielaff.mechanism import STANDARD_GRAVITY
    from sielaff.tools.spec_fields import linkage_kind

    kind = linkage_kind(spec, path)
    scene = _table(f"{path}: [scene]", spec.get("scene", {}))
    _unknown(f"{path}: [scene]", scene, scene_keys(kind))
    units = _name(f"{path}: [scene] units", scene.get("units", "in-lb-sec"),
                  tuple(STANDARD_GRAVITY), " or ".join(STANDARD_GRAVITY))
    branch = scene.get("branch", "open")
    dyads = len(getattr(_model(kind), "topology", None).dyads) \
        if getattr(_model(kind), "topology", None) is not None else 1
    if isinstance(branch, list) and dyads > 1:  # one per dyad, in solve order
        if len(branch) != dyads:
            raise PunchError(f"{path}: [scene] branch = {branch!r}: one of \"open\" and "
                             f"\"crossed\" for each of the {dyads} dyads, or one for all")
        branch = tuple(_name(f"{path}: [scene] branch[{i}]", b, ("open", "crossed"))
                       for i, b in enumerate(branch))
    else:
        branch = _name(f"{path}: [scene] branch", branch, ("open", "crossed"))
    fields: dict = {"branch": branch}
    reader = _reader(_model(kind))
    for effect in _effects(kind):
        fields.update(effect.spec.read(scene, path, reader))
    try:
        return units, scene_type(_model(kind))(**fields)
    except ValueError as exc:
        raise PunchError(f"{path}: [scene] {exc}") from None


def scene_spec(scene: Scene, units: str = "in-lb-sec") -> dict:  # the four-bar's
    """``scene`` as a spec's ``[scene]`` table (parsed TOML): what :func:`scene_of` reads
    back as the same scene (a field that is a function or an array has no TOML form and
    is left out)."""
    table: dict = {"units": units, "branch": scene.branch}
    for effect in _effects():
        table.update(effect.spec.write(scene))
    return table
