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
        [scene.friction]              # Coulomb friction, the same in the four pins ...
        mu = 0.1                      # coefficient of friction
        radius = 0.25                 # the pin's radius, in or m
        tol = 1e-13                   # optional: the fixed point's tolerance ...
        max_iter = 100                # ... and its iterations (PinFriction)
        # ... or each pin its own (a pin left out has none):
        # [scene.friction.O2]  mu = 0.1  radius = 0.5      (pins O2, A, B, O4)
        [[scene.spring]]              # tension k (L - length) between two points
        a = { link = "frame", distance = 6.0, angle = 90.0 }   # placed like the mass
        b = { link = "rocker", distance = 12.0, angle = 0.0 }  # centres; frame: from O2
        k = 30.0                      # lb/in or N/m                 along O2-O4
        length = 5.0                  # free length, in or m
        [[scene.damper]]              # tension c dL/dt between two points
        a = { link = "crank", distance = 2.0, angle = 0.0 }
        b = { link = "rocker", distance = 6.0, angle = 0.0 }
        c = 0.5                       # lb sec/in or N s/m

    Every value is checked by the Scene itself (finite, within its bound), and a bad
    one is one line naming the spec's key.  Lengths, forces and torques are in the
    spec's unit system; angles in degrees.
    """
    from sielaff.engine.loads import Load
    from sielaff.engine.scene import Scene
    from sielaff.mechanism import STANDARD_GRAVITY

    scene = _table(f"{path}: [scene]", spec.get("scene", {}))
    _unknown(f"{path}: [scene]", scene, ("units", "branch", "gravity", "crank_acceleration",
                                         "tex", "load", "friction", "spring", "damper"))
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
    if "friction" in scene:
        fields["friction"] = _friction_of(f"{path}: [scene.friction]", scene["friction"])
    fields["elements"] = _elements_of(path, scene)
    try:
        return units, Scene(**fields)
    except ValueError as exc:
        raise PunchError(f"{path}: [scene] {exc}") from None


#: A pin's friction keys: mu and radius, and the fixed point's tol and max_iter (optional).
FRICTION_KEYS = ("mu", "radius", "tol", "max_iter")


def _friction_of(where: str, table):
    """``[scene.friction]`` with mu and radius (every pin alike), or one table per pin
    (``[scene.friction.O2]``, ...), as Scene.friction."""
    from sielaff.engine.friction import PINS

    table = _table(where, table)
    pins = [k for k in table if k in PINS]
    if pins and any(k in FRICTION_KEYS for k in table):
        raise PunchError(f"{where}: give mu and radius for every pin, or a table per pin "
                         f"({', '.join(PINS)}), not both")
    if not pins:
        return _pin_friction(where, table)
    _unknown(where, table, PINS)
    return {pin: _pin_friction(f"{where[:-1]}.{pin}]", t) for pin, t in table.items()}


def _pin_friction(where: str, table):
    from sielaff.engine.friction import PinFriction

    table = _table(where, table)
    _unknown(where, table, FRICTION_KEYS)
    for key in ("mu", "radius"):
        if key not in table:
            raise PunchError(f"{where} has no {key} (write mu = ..., radius = ...)")
    extra = {}
    if "tol" in table:
        extra["tol"] = _float(f"{where} tol", table["tol"])
    if "max_iter" in table:
        n = table["max_iter"]
        if isinstance(n, bool) or not isinstance(n, int):
            raise PunchError(f"{where} max_iter = {n!r}: a whole number, 1 to 10000")
        extra["max_iter"] = n
    try:
        return PinFriction(_float(f"{where} mu", table["mu"]),
                           _float(f"{where} radius", table["radius"]), **extra)
    except ValueError as exc:
        raise PunchError(f"{where}: {exc}") from None


#: The links a spring's or damper's point may be on (the frame is link 1).
POINT_LINKS = {"frame": 1, **LINKS_BY_NAME, 1: 1}
#: Each element's keys besides its points a and b, in the engine's order.
ELEMENT_KEYS = {"spring": ("k", "length"), "damper": ("c",)}


def _elements_of(path: str, scene: dict) -> list:
    """``[[scene.spring]]`` (a, b, k, length) and ``[[scene.damper]]`` (a, b, c), springs
    first, as Scene.elements; a point is ``{ link, distance, angle }``."""
    from sielaff.engine.elements import Damper, Spring

    out = []
    for kind, keys in ELEMENT_KEYS.items():
        items = scene.get(kind, [])
        if not isinstance(items, list):
            raise PunchError(f"{path}: write each {kind} as [[scene.{kind}]]")
        for n, item in enumerate(items, 1):
            where = f"{path}: [[scene.{kind}]] {n}"
            item = _table(where, item)
            _unknown(where, item, ("a", "b", *keys))
            points = [_point(f"{where} {key}", item.get(key)) for key in ("a", "b")]
            values = []
            for key in keys:
                if key not in item:
                    raise PunchError(f"{where} has no {key}")
                values.append(_float(f"{where} {key}", item[key]))
            try:
                out.append((Spring if kind == "spring" else Damper)(*points, *values))
            except ValueError as exc:
                raise PunchError(f"{where}: {exc}") from None
    return out


def _point(where: str, p) -> tuple[int, float, float]:
    """A point ``{ link = "frame", distance = ..., angle = ... }`` as (link, r, angle)."""
    if p is None:
        raise PunchError(f"{where}: missing (write {{ link = ..., distance = ..., "
                         "angle = ... }})")
    p = _table(where, p)
    _unknown(where, p, ("link", "distance", "angle"))
    link = p.get("link")
    if isinstance(link, bool) or link not in POINT_LINKS:
        raise PunchError(f"{where} link = {link!r}: frame, crank, coupler or rocker")
    return (POINT_LINKS[link], _float(f"{where} distance", p.get("distance", 0)),
            _float(f"{where} angle", p.get("angle", 0)))
