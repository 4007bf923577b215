"""Gravity: each link's weight at its centre of mass, and the pin forces and drive torque
it takes.  ``Scene(gravity=(gx, gy))`` is the acceleration of gravity in the frame's axes,
in the mechanism's length unit per sec^2 (``(0.0, -386.088)`` for y up in the report's
in-lb-sec system, ``(0.0, -9.80665)`` in SI; ``"down"`` is standard gravity along -y in
the mechanism's units); off (None) as in 1966, and then no step here runs.  Its part of
TORQ is ``TORQ_GRAVITY``."""

from __future__ import annotations

from typing import Any

from sielaff.engine.declare import Fact, Param, SpecForm
from sielaff.engine.registry import Effect, step, step_of
from sielaff.engine.values import LIMIT
from sielaff.mechanism import STANDARD_GRAVITY


@step(provides=("gravity_loads",), needs=("GX", "GY", "GW", "links"), zero_when=("GX", "GY"),
      per_link=True)
def _gravity(k, GX, GY, GW, links):
    """Link k's weight m g at its centre of mass, as a force and its moment about the
    link's base point (m = W / GW: the W fields are weights in the report's system, masses
    in SI)."""
    link = links[k - 1]
    fx, fy = link.W / GW * GX, link.W / GW * GY
    return fx, fy, link.RG * (link.cd * fy - link.sd * fx)


def _seed(scene: Any, mechanism: Any) -> dict[str, Any]:
    g = scene.gravity
    if g is None:
        return {"GX": 0.0, "GY": 0.0}
    if isinstance(g, str):  # "down": standard gravity along -y
        return {"GX": 0.0, "GY": -STANDARD_GRAVITY[mechanism.units]}
    return {"GX": g[0], "GY": g[1]}


def check_gravity(g: Any) -> Any:
    """``Scene.gravity`` checked: None, ``"down"`` or a finite vector (gx, gy)."""
    if g is None or (isinstance(g, str) and g == "down"):
        return g
    try:
        gx, gy = (float(x) for x in g)
    except (TypeError, ValueError):
        raise ValueError(f"Scene.gravity = {g!r}: give None, 'down', or the vector (gx, gy) "
                         "in the mechanism's length unit per sec^2") from None
    for axis, x in (("gx", gx), ("gy", gy)):
        if not (abs(x) <= LIMIT):
            raise ValueError(f"Scene.gravity {axis} = {x!r}: not a finite acceleration "
                             f"within {LIMIT:g}")
    return (gx, gy)


def _describe(scene: Any, units: str) -> list[Fact]:
    g = scene.gravity
    if isinstance(g, str):
        system = "SI" if units == "SI" else "in-lb-sec"
        return [Fact("", "gravity", "standard, along -y"),
                Fact("", "g", STANDARD_GRAVITY[system], "acceleration")]
    return [Fact("", "gravity gx", g[0], "acceleration"),
            Fact("", "gravity gy", g[1], "acceleration")]


def _read(table: Any, path: str, reader: Any) -> dict[str, Any]:
    gravity = table.get("gravity")
    if gravity is None:
        return {}
    if gravity == "down":
        return {"gravity": "down"}
    if not (isinstance(gravity, list) and len(gravity) == 2):
        raise reader.error(f"{path}: [scene] gravity = {gravity!r}: \"down\" or [gx, gy]")
    return {"gravity": tuple(reader.number(f"{path}: [scene] gravity", g) for g in gravity)}


def _write(scene: Any) -> dict[str, Any]:
    g = scene.gravity
    return {} if g is None else {"gravity": g if isinstance(g, str) else list(g)}


EFFECT = Effect("gravity", (step_of(_gravity),), _seed,
                torque="TORQ_GRAVITY", applies="gravity_loads",
                params=(Param("gravity", None, check_gravity,
                              'None, "down" or (gx, gy)\n    The acceleration of gravity in '
                              "the frame's axes [length unit/sec^2]; ``\"down\"``\n    is "
                              "standard gravity along -y in the mechanism's unit system."),),
                outputs={"TORQ_GRAVITY": ("torque", "the part of TORQ gravity takes")},
                on=lambda scene: scene.gravity is not None,
                summary=lambda scene, units: "gravity", describe=_describe,
                spec=SpecForm(("gravity",), _read, _write,
                              'gravity = "down"              # or [gx, gy] in length/sec^2; '
                              "absent: off"))
