"""The scene: everything that acts on a mechanism besides its geometry and masses.

``Scene(tex=0.0, th2dd=0.0, gravity=None, loads=(), branch="open")`` is one frozen,
validated object; ``analyze(..., scene=...)``, the design answers, sweeps and every
command take it, and a spec's ``[scene]`` table is read into one.  The default is the
1966 program's scene: the crank at constant speed, no gravity, no load but TEX on the
rocker, the open branch.  Each value is checked once, here, for the API and the spec
reader alike: a NaN, an infinity, a magnitude past :data:`LIMIT` or a wrong type is a
ValueError naming the field.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from dataclasses import replace as dataclasses_replace
from typing import Any

import numpy as np

from sielaff.engine.elements import Damper, Spring, check_elements
from sielaff.engine.friction import PinFriction, check_friction
from sielaff.engine.loads import Load
from sielaff.engine.values import LIMIT, check_value

__all__ = ["BRANCHES", "LIMIT", "Scene"]

#: The two assemblies of a four-bar: ``open`` (the 1966 program's: B above the line A-O4
#: for the report's example) and ``crossed`` (B mirrored about that line).
BRANCHES = ("open", "crossed")

@dataclass(frozen=True)
class Scene:
    """What acts on the mechanism (each effect off by default, as in 1966).

    Parameters
    ----------
    tex : float, array or callable
        External torque on link 4 [in-lb or N m], CCW +; a constant, an array
        broadcasting against the crank angles, or a function of ATH4 [deg].
    th2dd : float, array or callable
        The crank's angular acceleration [rad/sec^2], CCW +; TH2D is then the crank
        speed at each position.  A constant, an array or a function of ATH2 [deg].
    gravity : None, "down" or (gx, gy)
        The acceleration of gravity in the frame's axes [length unit/sec^2]; ``"down"``
        is standard gravity along -y in the mechanism's unit system.
    loads : sequence of :class:`~sielaff.engine.loads.Load`
        Forces and torques on links 2-4.
    branch : {"open", "crossed"}
        Which assembly of the loop.
    friction : None, PinFriction or mapping
        Coulomb friction in the pins: one :class:`~sielaff.engine.friction.PinFriction`
        for all four, or ``{"O2": ..., "A": ..., "B": ..., "O4": ...}`` (a pin left out
        has none).
    elements : sequence of Spring and Damper
        Springs and dampers between points of the links and the frame.
    """

    tex: Any = 0.0
    th2dd: Any = 0.0
    gravity: Any = None
    loads: tuple[Load, ...] = ()
    branch: str = "open"
    friction: PinFriction | dict[str, PinFriction] | None = None
    elements: tuple[Spring | Damper, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "tex", _value("tex", self.tex))
        object.__setattr__(self, "th2dd", _value("th2dd", self.th2dd))
        object.__setattr__(self, "gravity", _gravity(self.gravity))
        if isinstance(self.loads, Load | str | bytes) or not _iterable(self.loads):
            raise ValueError(f"Scene.loads = {self.loads!r}: a sequence of sielaff.Load")
        loads = tuple(self.loads)
        for i, load in enumerate(loads):
            if not isinstance(load, Load):
                raise ValueError(f"Scene.loads[{i}] = {load!r} is not a sielaff.Load")
        object.__setattr__(self, "loads", loads)
        if self.branch not in BRANCHES:
            raise ValueError(f"Scene.branch = {self.branch!r}: 'open' (the 1966 program's) "
                             "or 'crossed'")
        object.__setattr__(self, "friction", check_friction(self.friction))
        object.__setattr__(self, "elements", check_elements(self.elements))

    def replace(self, **changes: Any) -> Scene:
        """A copy with some fields changed (validated again)."""
        unknown = sorted(set(changes) - {f.name for f in fields(self)})
        if unknown:
            raise TypeError(f"Scene has no field {', '.join(unknown)}")
        return dataclasses_replace(self, **changes)

    @property
    def is_1966(self) -> bool:
        """Whether this is the 1966 program's scene (TEX aside): no effect is on."""
        return (not callable(self.th2dd) and not np.any(self.th2dd)
                and self.gravity is None and not self.loads and not self.has_friction
                and not self.elements)

    @property
    def has_friction(self) -> bool:
        """Whether some pin has friction (mu r > 0)."""
        f = self.friction
        pins = [] if f is None else [f] if isinstance(f, PinFriction) else list(f.values())
        return any(p.mu * p.radius > 0.0 for p in pins)

    def per_position(self) -> list[tuple[str, Any]]:
        """The (field, array) pairs that vary with the crank angle (arrays of ndim > 0)."""
        out: list[tuple[str, Any]] = []
        for name in ("tex", "th2dd"):
            v = getattr(self, name)
            if not callable(v) and np.ndim(v):
                out.append((name, v))
        for i, load in enumerate(self.loads):
            for name in ("r", "angle", "fx", "fy", "torque"):
                v = getattr(load, name)
                if not callable(v) and np.ndim(v):
                    out.append((f"loads[{i}].{name}", v))
        return out

    def block(self, i: int, j: int, shape: tuple[int, ...]) -> Scene:
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

        loads = tuple(dataclasses_replace(load, **{n: part(f"loads[{k}].{n}", getattr(load, n))
                                                   for n in ("r", "angle", "fx", "fy",
                                                             "torque")})
                      for k, load in enumerate(self.loads))
        return dataclasses_replace(self, tex=part("tex", self.tex),
                                   th2dd=part("th2dd", self.th2dd), loads=loads)


def _iterable(v: Any) -> bool:
    try:
        iter(v)
    except TypeError:
        return False
    return True


def _value(name: str, v: Any) -> Any:
    """A callable as it is; a number or an array checked finite and within LIMIT."""
    if callable(v):
        return v
    return check_value(f"Scene.{name}", v)


def _gravity(g: Any) -> Any:
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


#: The keyword arguments ``analyze`` still takes, each building the same Scene field.
KEYWORDS = ("tex", "th2dd", "gravity", "loads", "branch")


def scene_from(scene: Scene | None, given: dict[str, Any],
               where: str = "analyze") -> Scene:
    """The Scene of a call: ``scene``, or one built from the keywords ``given``; both at
    once is a ValueError naming them."""
    if scene is not None:
        if not isinstance(scene, Scene):
            raise ValueError(f"{where}: scene = {scene!r} is not a sielaff.Scene")
        if given:
            raise ValueError(f"{where}: give scene= or {', '.join(sorted(given))}, not both "
                             "(put them in the Scene)")
        return scene
    return Scene(**given)

