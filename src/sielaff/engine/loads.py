"""External loads: forces and torques on links 2, 3 and 4, placed like RG and ADEL.

``Load(link, r, angle, fx, fy, torque)``: the force (fx, fy), in the frame's axes, acts
at the point ``r`` from the link's base pin (O2, A, O4) at ``angle`` degrees CCW from
the link's line; ``torque`` is a pure torque on the link, CCW +.  Each of r, angle, fx,
fy and torque may be a constant, an array that broadcasts with the crank angles, or a
function of THETA 2 in degrees.  ``Scene(loads=[...])`` sums them per link and solves
the pin forces and drive torque they take (``statics.pins``): the effect's part
``TORQ_LOADS`` of TORQ.
"""

from __future__ import annotations

from dataclasses import dataclass
from dataclasses import replace as dataclasses_replace
from typing import Any, NamedTuple

import numpy as np

from sielaff.engine.declare import Fact, Param, SpecForm
from sielaff.engine.links import FOUR_BAR_LINKS, link_words, links_by_name
from sielaff.engine.registry import Effect, step, step_of
from sielaff.engine.values import at, call_checked, check_value


@dataclass(frozen=True)
class Load:
    """A force and a torque on one moving link (see the module doc).

    Parameters
    ----------
    link : {2, 3, 4}
        The link it acts on.
    r : float, array or callable
        Distance of the point of application from the link's base pin [in or m].
    angle : float, array or callable
        Angle of that point from the link's line [deg], CCW +.
    fx, fy : float, array or callable
        The force in the frame's axes [lb or N].
    torque : float, array or callable
        A pure torque on the link [in-lb or N m], CCW +.
    """

    link: int
    r: Any = 0.0
    angle: Any = 0.0
    fx: Any = 0.0
    fy: Any = 0.0
    torque: Any = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.link, bool) or not isinstance(self.link, int | np.integer) \
                or self.link < 2:
            raise ValueError(f"Load.link = {self.link!r}: loads act on a moving link, 2 "
                             "(the crank) or more")
        for name in ("r", "angle", "fx", "fy", "torque"):
            v = getattr(self, name)
            if not callable(v):
                object.__setattr__(self, name, check_value(f"Load.{name}", v))

    def value(self, name: str, ath2: Any) -> Any:
        """The field ``name`` at crank angles ``ath2`` [deg] (a callable is called, and
        its answer checked where the angle is a number)."""
        v = getattr(self, name)
        if not callable(v):
            return np.asarray(v, dtype=float)
        return call_checked(f"Load.{name}", v, ath2)


class LoadValues(NamedTuple):
    """A Load as the step takes it: its link's number and its fields (numbers, arrays or
    functions of ATH2)."""

    link: float
    r: Any
    angle: Any
    fx: Any
    fy: Any
    torque: Any


# the field that chooses which link, not a value: the compiled backend compiles it in as
# a constant (engine/compiled.py; set here, as a NamedTuple body holds only fields)
setattr(LoadValues, "STRUCTURE", ("link",))  # noqa: B010


@step(provides=("external_loads",), needs=("loads", "NLOADS", "ATH2", "links"),
      zero_when=("NLOADS",), per_link=True)
def _loads(k, loads, NLOADS, ATH2, links):
    """The loads on link k summed: each force and its moment about the link's base point,
    plus the pure torques."""
    link = links[k - 1]
    c, s = link.c, link.s
    fx_k, fy_k, m_k = 0.0, 0.0, 0.0
    for load in loads:
        if load.link == k:
            r, fx = at("Load.r", load.r, ATH2), at("Load.fx", load.fx, ATH2)
            fy = at("Load.fy", load.fy, ATH2)
            a = np.radians(at("Load.angle", load.angle, ATH2))
            px = r * (c * np.cos(a) - s * np.sin(a))  # the point, from the base pin
            py = r * (s * np.cos(a) + c * np.sin(a))
            fx_k = fx_k + fx
            fy_k = fy_k + fy
            m_k = m_k + (px * fy - py * fx) + at("Load.torque", load.torque, ATH2)
    return fx_k, fy_k, m_k


def _seed(scene: Any, mechanism: Any) -> dict[str, Any]:
    links = len(link_words(scene))
    for load in scene.loads:
        if load.link > links:
            raise ValueError(f"Load.link = {load.link}: this linkage's moving links are 2 to "
                             f"{links}")
    values = tuple(LoadValues(float(ld.link), ld.r, ld.angle, ld.fx, ld.fy, ld.torque)
                   for ld in scene.loads)
    return {"loads": values, "NLOADS": float(len(values))}


#: The fields of a Load that may vary with the crank angle.
FIELDS = ("r", "angle", "fx", "fy", "torque")
#: The four-bar's links a spec names (the moving ones); another model's: its link_names.
LINKS_BY_NAME = links_by_name(FOUR_BAR_LINKS)


def check_loads(v: Any) -> tuple[Load, ...]:
    """``Scene.loads`` checked: a sequence of Load."""
    if isinstance(v, Load | str | bytes):
        raise ValueError(f"Scene.loads = {v!r}: a sequence of sielaff.Load")
    try:
        loads = tuple(v)
    except TypeError:
        raise ValueError(f"Scene.loads = {v!r}: a sequence of sielaff.Load") from None
    for i, load in enumerate(loads):
        if not isinstance(load, Load):
            raise ValueError(f"Scene.loads[{i}] = {load!r} is not a sielaff.Load")
    return loads


def _varies(loads: tuple[Load, ...]) -> list[tuple[str, Any]]:
    return [(f"loads[{i}].{n}", getattr(load, n)) for i, load in enumerate(loads)
            for n in FIELDS if not callable(getattr(load, n)) and np.ndim(getattr(load, n))]


def _block(loads: tuple[Load, ...], part: Any) -> tuple[Load, ...]:
    return tuple(dataclasses_replace(load, **{n: part(f"loads[{k}].{n}", getattr(load, n))
                                              for n in FIELDS})
                 for k, load in enumerate(loads))


def _text(v: Any, kind: str) -> tuple[Any, str | None]:
    return ("a function of THETA 2", None) if callable(v) else \
        ("varying with THETA 2", None) if np.ndim(v) else (float(v), kind)


def _describe(scene: Any, units: str) -> list[Fact]:
    facts = []
    for i, load in enumerate(scene.loads, 1):
        g = f"load {i} on the {link_words(scene).get(load.link, f'link {load.link}')}"
        for label, name, kind in (("r", "r", "length"), ("angle", "angle", "angle"),
                                  ("fx", "fx", "force"), ("fy", "fy", "force"),
                                  ("torque", "torque", "torque")):
            facts.append(Fact(g, label, *_text(getattr(load, name), kind)))
    return facts


def _read(table: Any, path: str, reader: Any) -> dict[str, Any]:
    loads = table.get("load", [])
    if not isinstance(loads, list):
        raise reader.error(f"{path}: write each load as [[scene.load]]")
    out = []
    for n, item in enumerate(loads, 1):
        where = f"{path}: [[scene.load]] {n}"
        item = reader.table(where, item)
        reader.unknown(where, item, ("link", "distance", "angle", "force", "torque"))
        names = getattr(reader, "links", None) or LINKS_BY_NAME
        words = [n for n in names if isinstance(n, str)]
        link = names[reader.name(f"{where} link", item.get("link"), names,
                                 ", ".join(words[:-1]) + " or " + words[-1])]
        force = item.get("force", [0.0, 0.0])
        if not (isinstance(force, list) and len(force) == 2):
            raise reader.error(f"{where} force = {force!r}: [fx, fy]")
        fx, fy = (reader.number(f"{where} force", f) for f in force)
        values = (reader.number(f"{where} distance", item.get("distance", 0)),
                  reader.number(f"{where} angle", item.get("angle", 0)), fx, fy,
                  reader.number(f"{where} torque", item.get("torque", 0)))
        try:
            out.append(Load(link, *values))
        except ValueError as exc:
            raise reader.error(f"{where}: {exc}") from None
    return {"loads": out} if out else {}


def _write(scene: Any) -> dict[str, Any]:
    words = link_words(scene)
    items = [{"link": words[ld.link], "distance": float(ld.r), "angle": float(ld.angle),
              "force": [float(ld.fx), float(ld.fy)], "torque": float(ld.torque)}
             for ld in scene.loads
             if not any(callable(getattr(ld, n)) or np.ndim(getattr(ld, n)) for n in FIELDS)]
    return {"load": items} if items else {}


_HELP = """\
[[scene.load]]
link = "coupler"              # crank, coupler or rocker
distance = 8.0                # from the link's base pin (O2, A, O4)
angle = 10.0                  # degrees CCW from the link's line
force = [80.0, 0.0]           # frame axes, lb or N
torque = 0.0                  # CCW +, in-lb or N m"""


EFFECT = Effect("loads", (step_of(_loads),), _seed,
                torque="TORQ_LOADS", applies="external_loads",
                params=(Param("loads", (), check_loads,
                              "sequence of :class:`~sielaff.engine.loads.Load`\n"
                              "    Forces and torques on links 2-4.", _varies, _block),),
                outputs={"TORQ_LOADS": ("torque", "the part of TORQ the external loads take")},
                on=lambda scene: bool(scene.loads),
                summary=lambda scene, units: (f"{len(scene.loads)} load"
                                              f"{'s' if len(scene.loads) > 1 else ''}"),
                describe=_describe, spec=SpecForm(("load",), _read, _write, _HELP))
