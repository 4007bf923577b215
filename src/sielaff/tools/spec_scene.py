"""A spec's ``[scene]``, read into a :class:`~sielaff.Scene` here and nowhere else.

The scene's keys, tables and units are in :func:`scene_of`'s doc (and docs/effects.md);
every value is checked by the engine's own check (:mod:`sielaff.engine.values`) and a bad
one is one line naming the spec's key.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from sielaff.tools.spec_fields import PunchError, _float, _table, _unknown

if TYPE_CHECKING:
    from sielaff.engine.scene import Scene

__all__ = ["scene_of"]

LINKS_BY_NAME = {"crank": 2, "coupler": 3, "rocker": 4, 2: 2, 3: 3, 4: 4}


def scene_of(spec: dict, path: str = "<spec>") -> tuple[str, Scene]:
    """The spec's unit system and its ``[scene]`` as a :class:`~sielaff.Scene` (see
    docs/effects.md), read here and nowhere else::

        [scene]
        units = "in-lb-sec"           # or "SI" (the whole spec is then in SI)
        branch = "open"               # or "crossed"
        gravity = "down"              # or [gx, gy] in length/sec^2; absent: off
        crank_acceleration = -40.0    # TH2DD, rad/sec^2
        tex = 0.0                     # torque on the rocker, CCW +
        [[scene.load]]
        link = "coupler"              # crank, coupler or rocker
        distance = 8.0                # from the link's base pin (O2, A, O4)
        angle = 10.0                  # degrees CCW from the link's line
        force = [80.0, 0.0]           # frame axes
        torque = 0.0                  # CCW +

    Every value is checked by the Scene itself (finite, within its bound), and a bad
    one is one line naming the spec's key.
    """
    from sielaff.engine.loads import Load
    from sielaff.engine.scene import Scene
    from sielaff.mechanism import STANDARD_GRAVITY

    scene = _table(f"{path}: [scene]", spec.get("scene", {}))
    _unknown(f"{path}: [scene]", scene, ("units", "branch", "gravity", "crank_acceleration",
                                         "tex", "load"))
    units = scene.get("units", "in-lb-sec")
    if units not in STANDARD_GRAVITY:
        raise PunchError(f"{path}: [scene] units = {units!r}: {' or '.join(STANDARD_GRAVITY)}")
    fields: dict = {}
    branch = scene.get("branch", "open")
    if branch not in ("open", "crossed"):
        raise PunchError(f"{path}: [scene] branch = {branch!r}: \"open\" or \"crossed\"")
    fields["branch"] = branch
    gravity = scene.get("gravity")
    if gravity == "down":
        fields["gravity"] = "down"
    elif gravity is not None:
        if not (isinstance(gravity, list) and len(gravity) == 2):
            raise PunchError(f"{path}: [scene] gravity = {gravity!r}: \"down\" or [gx, gy]")
        fields["gravity"] = tuple(_float(f"{path}: [scene] gravity", g) for g in gravity)
    for key, name in (("crank_acceleration", "th2dd"), ("tex", "tex")):
        if key in scene:
            fields[name] = _float(f"{path}: [scene] {key}", scene[key])
    loads = scene.get("load", [])
    if not isinstance(loads, list):
        raise PunchError(f"{path}: write each load as [[scene.load]]")
    fields["loads"] = []
    for n, item in enumerate(loads, 1):
        where = f"{path}: [[scene.load]] {n}"
        item = _table(where, item)
        _unknown(where, item, ("link", "distance", "angle", "force", "torque"))
        link = LINKS_BY_NAME.get(item.get("link"))
        if link is None:
            raise PunchError(f"{where} link = {item.get('link')!r}: crank, coupler or rocker")
        force = item.get("force", [0.0, 0.0])
        if not (isinstance(force, list) and len(force) == 2):
            raise PunchError(f"{where} force = {force!r}: [fx, fy]")
        fx, fy = (_float(f"{where} force", f) for f in force)
        values = (_float(f"{where} distance", item.get("distance", 0)),
                  _float(f"{where} angle", item.get("angle", 0)), fx, fy,
                  _float(f"{where} torque", item.get("torque", 0)))
        try:
            fields["loads"].append(Load(link, *values))
        except ValueError as exc:
            raise PunchError(f"{where}: {exc}") from None
    try:
        return units, Scene(**fields)
    except ValueError as exc:
        raise PunchError(f"{path}: [scene] {exc}") from None

