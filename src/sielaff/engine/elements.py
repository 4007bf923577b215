"""Springs and dampers between any two points of the linkage (the frame included).

``Spring(a, b, k, length)`` and ``Damper(a, b, c)`` in ``Scene(elements=[...])``.  A
point is ``(link, r, angle)``, placed as RG and ADEL place a centre of mass: ``r`` from
the link's base pin (link 1, the frame: O2; link 2: O2; link 3: A; link 4: O4) at
``angle`` degrees CCW from the link's line (the frame's line runs from O2 to O4).  With
L the distance between the points and dL/dt its rate, each element pulls its two points
together with the tension (negative: it pushes them apart)

    spring:  T = k (L - length)          damper:  T = c dL/dt

so the link of point a feels ``T u`` at a and the link of point b ``-T u`` at b (u the
unit vector from a to b); a point on the frame passes its force to the frame directly
(it is not in FOA or FOB, which are what links 2 and 4 put on the frame).  The model is
linear in these loads, so the effect adds its parts to the superposed pin forces and
TORQ (``TORQ_ELEMENTS``, its share).  Outputs per element: ``SPRINGk_L``,
``SPRINGk_LD``, ``SPRINGk_F`` for the k-th spring (k = 1, 2, ... in the order of
``elements``), ``DAMPERk_...`` likewise; L in in or m, LD in in/sec or m/s, F in lb
or N; an element the scene does not have reads 0 (the outputs are declared for
:data:`MAX_ELEMENTS` of each kind; count the scene's own).  Their power on the linkage is
``-T dL/dt`` each.  At most :data:`MAX_ELEMENTS` of each kind.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from sielaff.engine.declare import Fact, Param, SpecForm
from sielaff.engine.links import FOUR_BAR_LINKS, link_words, links_by_name
from sielaff.engine.registry import Effect, Step, step, step_of
from sielaff.engine.values import check_value

__all__ = ["MAX_ELEMENTS", "Damper", "Spring", "check_elements"]

#: How many springs, and how many dampers, a scene may have (each has its own outputs).
MAX_ELEMENTS = 8


def _point(name: str, p: Any) -> tuple[int, float, float]:
    try:
        link, r, angle = p
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {p!r}: a point (link, r, angle)") from None
    if isinstance(link, bool) or not isinstance(link, int | np.integer) or link < 1:
        raise ValueError(f"{name} link = {link!r}: 1 (the frame), 2 (the crank) or more")
    return (int(link), _number(f"{name} r", r), _number(f"{name} angle", angle))


def _number(name: str, v: Any, minimum: float | None = None) -> float:
    if isinstance(v, bool) or callable(v) or np.ndim(v) != 0:
        raise ValueError(f"{name} = {v!r}: a number")
    x = float(check_value(name, v))
    if minimum is not None and x < minimum:
        raise ValueError(f"{name} = {x!r}: must be >= {minimum:g}")
    return x


@dataclass(frozen=True)
class Spring:
    """A linear spring between two points (see the module doc).

    Parameters
    ----------
    a, b : (link, r, angle)
        The points: link 1-4, r [in or m] from the link's base pin, angle [deg].
    k : float
        Stiffness [lb/in or N/m].
    length : float
        Free length [in or m], >= 0.
    """

    a: Any
    b: Any
    k: float
    length: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "a", _point("Spring.a", self.a))
        object.__setattr__(self, "b", _point("Spring.b", self.b))
        object.__setattr__(self, "k", _number("Spring.k", self.k))
        object.__setattr__(self, "length", _number("Spring.length", self.length, 0.0))


@dataclass(frozen=True)
class Damper:
    """A linear (viscous) damper between two points (see the module doc).

    Parameters
    ----------
    a, b : (link, r, angle)
        The points: link 1-4, r [in or m] from the link's base pin, angle [deg].
    c : float
        Damping coefficient [lb sec/in or N s/m].
    """

    a: Any
    b: Any
    c: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "a", _point("Damper.a", self.a))
        object.__setattr__(self, "b", _point("Damper.b", self.b))
        object.__setattr__(self, "c", _number("Damper.c", self.c))


def check_elements(v: Any) -> tuple[Spring | Damper, ...]:
    """``Scene.elements`` checked: a sequence of Spring and Damper, at most
    :data:`MAX_ELEMENTS` of each."""
    if isinstance(v, Spring | Damper | str | bytes):
        raise ValueError(f"Scene.elements = {v!r}: a sequence of sielaff.Spring and "
                         "sielaff.Damper")
    try:
        items = tuple(v)
    except TypeError:
        raise ValueError(f"Scene.elements = {v!r}: a sequence of sielaff.Spring and "
                         "sielaff.Damper") from None
    for i, e in enumerate(items):
        if not isinstance(e, Spring | Damper):
            raise ValueError(f"Scene.elements[{i}] = {e!r} is not a sielaff.Spring or "
                             "sielaff.Damper")
    for kind in (Spring, Damper):
        if sum(isinstance(e, kind) for e in items) > MAX_ELEMENTS:
            raise ValueError(f"Scene.elements: more than {MAX_ELEMENTS} "
                             f"{kind.__name__.lower()}s")
    return items


class ElementValues(NamedTuple):
    """A spring or a damper as the steps take it: ``spring`` 1.0 (tension k (L - length))
    or 0.0 (a damper: tension c dL/dt), its points a and b as (link, r, angle)."""

    spring: float
    a_link: float
    a_r: float
    a_angle: float
    b_link: float
    b_r: float
    b_angle: float
    k: float
    length: float
    c: float


# the fields that choose which links and which law, not values: the compiled backend
# compiles them in as constants (engine/compiled.py; set here, as a NamedTuple body holds
# only fields)
setattr(ElementValues, "STRUCTURE", ("spring", "a_link", "b_link"))  # noqa: B010


def _values(e: Spring | Damper) -> ElementValues:
    spring = isinstance(e, Spring)
    return ElementValues(1.0 if spring else 0.0, float(e.a[0]), e.a[1], e.a[2], float(e.b[0]),
                         e.b[1], e.b[2], e.k if spring else 0.0,  # type: ignore[union-attr]
                         e.length if spring else 0.0,  # type: ignore[union-attr]
                         0.0 if spring else e.c)  # type: ignore[union-attr]


def _place(link, r, angle, links, rates):
    """(offset from the base pin, position, velocity) of a point, each as x and y."""
    a = np.radians(angle)
    ca, sa = np.cos(a), np.sin(a)
    ln, rt = links[int(link) - 1], rates[int(link) - 1]
    c, s, w = ln.c, ln.s, rt.w
    px, py = r * (c * ca - s * sa), r * (s * ca + c * sa)
    return px, py, ln.x + px, ln.y + py, rt.vx - w * py, rt.vy + w * px


def _element(e, links, rates):
    """The element's offsets of a and b, L, dL/dt, tension and unit vector a -> b."""
    pax, pay, xax, xay, vax, vay = _place(e.a_link, e.a_r, e.a_angle, links, rates)
    pbx, pby, xbx, xby, vbx, vby = _place(e.b_link, e.b_r, e.b_angle, links, rates)
    dx, dy = xbx - xax, xby - xay
    length = np.hypot(dx, dy)
    ux, uy = dx / length, dy / length
    rate = ux * (vbx - vax) + uy * (vby - vay)
    tension = e.k * (length - e.length) if e.spring == 1.0 else e.c * rate
    return pax, pay, pbx, pby, length, rate, tension, ux, uy


@step(provides=("element_loads",), needs=("elements", "NELEMENTS", "links", "link_rates"),
      zero_when=("NELEMENTS",), per_link=True)
def _elements(k, elements, NELEMENTS, links, link_rates):
    """The elements' pulls on their points on link k, summed (a point on the frame passes
    its force to the ground)."""
    fx_k, fy_k, m_k = 0.0, 0.0, 0.0
    for e in elements:
        if e.a_link == k or e.b_link == k:
            pax, pay, pbx, pby, _, _, t, ux, uy = _element(e, links, link_rates)
            if e.a_link == k:
                fx, fy = t * ux, t * uy
                fx_k = fx_k + fx
                fy_k = fy_k + fy
                m_k = m_k + (pax * fy - pay * fx)
            if e.b_link == k:
                fx, fy = -1.0 * t * ux, -1.0 * t * uy
                fx_k = fx_k + fx
                fy_k = fy_k + fy
                m_k = m_k + (pbx * fy - pby * fx)
    return fx_k, fy_k, m_k


#: The per-element outputs: SPRINGk_L, SPRINGk_LD, SPRINGk_F, then DAMPERk_... .
ELEMENT_OUTPUTS = tuple(f"{kind}{k}_{q}" for kind in ("SPRING", "DAMPER")
                        for k in range(1, MAX_ELEMENTS + 1) for q in ("L", "LD", "F"))


def _element_output(element, present, links, link_rates):
    """One element's length L, its rate dL/dt and its tension (times ``present``: 1, or 0
    for a slot the scene leaves empty, whose step the plan skips)."""
    _, _, _, _, length, rate, tension, _, _ = _element(element, links, link_rates)
    return length * present, rate * present, tension * present


#: One step per element's outputs (run only for the elements the scene has).
_OUTPUT_STEPS = tuple(
    Step(f"_element_output_{kind}{k}", _element_output,
         tuple(f"{kind}{k}_{q}" for q in ("L", "LD", "F")),
         (f"{kind.lower()}{k}", f"N{kind}{k}", "links", "link_rates"), (f"N{kind}{k}",),
         ((f"N{kind}{k}",),))
    for kind in ("SPRING", "DAMPER") for k in range(1, MAX_ELEMENTS + 1))

#: An empty slot's stand-in: a still element on the frame, a unit long, pulling nothing.
_EMPTY = ElementValues(0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0)


def _seed(scene: Any, mechanism: Any) -> dict[str, Any]:
    links = len(link_words(scene))
    for e in scene.elements:
        for p in (e.a, e.b):
            if p[0] > links:
                raise ValueError(f"a spring's or damper's point on link {p[0]}: this "
                                 f"linkage's links are 1 (the frame) to {links}")
    values = tuple(_values(e) for e in scene.elements)
    ns: dict[str, Any] = {"elements": values, "NELEMENTS": float(len(values))}
    for kind in ("SPRING", "DAMPER"):
        mine = [v for v in values if (v.spring == 1.0) == (kind == "SPRING")]
        for k in range(1, MAX_ELEMENTS + 1):
            ns[f"{kind.lower()}{k}"] = mine[k - 1] if k <= len(mine) else _EMPTY
            ns[f"N{kind}{k}"] = 1.0 if k <= len(mine) else 0.0
    return ns


_QUANTITIES = {"L": ("length", "length"), "LD": ("speed", "rate of change of the length"),
               "F": ("force", "tension (negative: it pushes)")}


def _numbered(scene: Any) -> list[tuple[str, int, Spring | Damper]]:
    """(kind, k, element) with k counted per kind, in the order of ``elements``."""
    count = {"SPRING": 0, "DAMPER": 0}
    out = []
    for e in scene.elements:
        kind = "SPRING" if isinstance(e, Spring) else "DAMPER"
        count[kind] += 1
        out.append((kind, count[kind], e))
    return out


def _columns(scene: Any) -> tuple[str, ...]:
    return ("TORQ_ELEMENTS",) + tuple(f"{kind}{k}_{q}" for kind, k, _ in _numbered(scene)
                                      for q in ("L", "LD", "F"))


def _summary(scene: Any, units: str) -> str:
    words = []
    for kind in (Spring, Damper):
        n = sum(isinstance(e, kind) for e in scene.elements)
        if n:
            words.append(f"{n} {kind.__name__.lower()}{'s' if n > 1 else ''}")
    return ", ".join(words)


def _point_text(p: tuple[int, float, float], units: str, words: dict[int, str]) -> str:
    from sielaff.quantities import fmt

    name = words.get(p[0], f"link {p[0]}")
    return f"{name} {fmt(p[1], 'length', units, '.6g')} at {p[2]:.6g} deg"


def _describe(scene: Any, units: str) -> list[Fact]:
    facts = []
    for kind, k, e in _numbered(scene):
        g = f"{kind.lower()} {k}"
        words = link_words(scene)
        facts += [Fact(g, "a", _point_text(e.a, units, words)),
                  Fact(g, "b", _point_text(e.b, units, words))]
        if isinstance(e, Spring):
            facts += [Fact(g, "k", e.k, "stiffness"), Fact(g, "free length", e.length, "length")]
        else:
            facts.append(Fact(g, "c", e.c, "damping"))
    return facts


def _figure_outputs(scene: Any) -> tuple[str, ...]:
    return tuple(f"{kind}{k}_{q}" for kind, k, _ in _numbered(scene) for q in ("L", "F", "LD"))


def _figures(r: Any, scene: Any, units: str, speed: float) -> list[Fact]:
    """Each spring's length and force range; each damper's energy per revolution (the
    mean over the revolution's grid of c (dL/dt)^2, times the period)."""
    facts = []
    for kind, k, e in _numbered(scene):
        g = f"{kind.lower()} {k}"
        length, force = np.asarray(r[f"{kind}{k}_L"]), np.asarray(r[f"{kind}{k}_F"])
        facts += [Fact(g, "shortest", float(np.min(length)), "length"),
                  Fact(g, "longest", float(np.max(length)), "length"),
                  Fact(g, "least tension", float(np.min(force)), "force"),
                  Fact(g, "most tension", float(np.max(force)), "force")]
        if isinstance(e, Damper) and speed:
            power = float(np.mean(np.asarray(r[f"{kind}{k}_LD"]) * force))
            facts += [Fact(g, "mean power dissipated", power, "power"),
                      Fact(g, "per revolution", power * 2.0 * np.pi / speed, "work")]
    return facts


def _read(table: Any, path: str, reader: Any) -> dict[str, Any]:
    """``[[scene.spring]]`` (a, b, k, length) and ``[[scene.damper]]`` (a, b, c), springs
    first; a point is ``{ link, distance, angle }``."""
    out: list[Spring | Damper] = []
    for kind, keys in ELEMENT_KEYS.items():
        items = table.get(kind, [])
        if not isinstance(items, list):
            raise reader.error(f"{path}: write each {kind} as [[scene.{kind}]]")
        for n, item in enumerate(items, 1):
            where = f"{path}: [[scene.{kind}]] {n}"
            item = reader.table(where, item)
            reader.unknown(where, item, ("a", "b", *keys))
            points = [_spec_point(f"{where} {key}", item.get(key), reader) for key in ("a", "b")]
            values = []
            for key in keys:
                if key not in item:
                    raise reader.error(f"{where} has no {key}")
                values.append(reader.number(f"{where} {key}", item[key]))
            try:
                out.append(Spring(points[0], points[1], values[0], values[1])
                           if kind == "spring" else Damper(points[0], points[1], values[0]))
            except ValueError as exc:
                raise reader.error(f"{where}: {exc}") from None
    return {"elements": out} if out else {}


#: The four-bar's links a spring's or damper's point may be on (the frame is link 1);
#: another model's: its link_names.
POINT_LINKS = links_by_name(FOUR_BAR_LINKS, frame=True)
#: Each element's keys besides its points a and b, in the engine's order.
ELEMENT_KEYS = {"spring": ("k", "length"), "damper": ("c",)}


def _spec_point(where: str, p: Any, reader: Any) -> tuple[int, float, float]:
    """A point ``{ link = "frame", distance = ..., angle = ... }`` as (link, r, angle)."""
    if p is None:
        raise reader.error(f"{where}: missing (write {{ link = ..., distance = ..., "
                           "angle = ... }})")
    p = reader.table(where, p)
    reader.unknown(where, p, ("link", "distance", "angle"))
    names = getattr(reader, "frame_links", None) or POINT_LINKS
    words = [n for n in names if isinstance(n, str)]
    link = reader.name(f"{where} link", p.get("link"), names,
                       ", ".join(words[:-1]) + " or " + words[-1])
    return (names[link], reader.number(f"{where} distance", p.get("distance", 0)),
            reader.number(f"{where} angle", p.get("angle", 0)))


def _write(scene: Any) -> dict[str, Any]:
    out: dict[str, Any] = {}
    words = link_words(scene)
    for e in scene.elements:
        item: dict[str, Any] = {key: {"link": words[p[0]], "distance": p[1], "angle": p[2]}
                                for key, p in (("a", e.a), ("b", e.b))}
        if isinstance(e, Spring):
            out.setdefault("spring", []).append(item | {"k": e.k, "length": e.length})
        else:
            out.setdefault("damper", []).append(item | {"c": e.c})
    return out


_HELP = """\
[[scene.spring]]              # tension k (L - length) between two points
a = { link = "frame", distance = 6.0, angle = 90.0 }   # placed like the mass
b = { link = "rocker", distance = 12.0, angle = 0.0 }  # centres; frame: from O2
k = 30.0                      # lb/in or N/m                 along O2-O4
length = 5.0                  # free length, in or m
[[scene.damper]]              # tension c dL/dt between two points
a = { link = "crank", distance = 2.0, angle = 0.0 }
b = { link = "rocker", distance = 6.0, angle = 0.0 }
c = 0.5                       # lb sec/in or N s/m"""


EFFECT = Effect("springs and dampers", (step_of(_elements), *_OUTPUT_STEPS), _seed,
                torque="TORQ_ELEMENTS", applies="element_loads",
                params=(Param("elements", (), check_elements,
                              "sequence of Spring and Damper\n    Springs and dampers between "
                              "points of the links and the frame."),),
                outputs={"TORQ_ELEMENTS": ("torque",
                                           "the part of TORQ the springs and dampers take"),
                         **{n: (_QUANTITIES[n.rsplit("_", 1)[1]][0],
                                f"{_QUANTITIES[n.rsplit('_', 1)[1]][1]} of "
                                f"{n.split('_')[0][:6].lower()} {n.split('_')[0][6:]}")
                            for n in ELEMENT_OUTPUTS}},
                on=lambda scene: bool(scene.elements), summary=_summary, describe=_describe,
                figure_outputs=_figure_outputs, figures=_figures, columns=_columns,
                spec=SpecForm(("spring", "damper"), _read, _write, _HELP))
