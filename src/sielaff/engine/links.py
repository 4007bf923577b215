"""What a model tells the effects about each of its links, whatever the linkage.

An effect that puts loads on the links (gravity, external loads, springs and dampers)
does not know the linkage: it reads ``links`` (each link's line and base point, its
weight and centre of mass) and ``link_rates`` (its angular velocity and its base
point's velocity), which the model provides as steps, each a tuple whose item k - 1 is
link k's, and gives its load on one link k as ``(fx, fy, m)``: a resultant force in the
frame's axes and its moment about the link's base point (its step is written for one
link, its first parameter ``k``; the model calls it for each moving link,
``registry.per_link``).  The model's statics (``Model(statics=...)``) turns the loads,
one triple per moving link in order, into the pin forces and the drive torque.  Link 1
is the frame (its base at the origin, its line along +x, at rest).  Lengths in in or m,
angles as cosines and sines, rates in rad/sec.  Links are named tuples of numbers, so
that the compiled backend compiles the effects as written.
"""

from __future__ import annotations

from typing import Any, NamedTuple

__all__ = ["FOUR_BAR_LINKS", "FRAME", "FRAME_RATE", "Link", "LinkRate", "link_words",
           "links_by_name"]

#: The four-bar's links by number, as a spec and the tools name them.
FOUR_BAR_LINKS = {1: "frame", 2: "crank", 3: "coupler", 4: "rocker"}


def link_words(scene_or_model: Any) -> dict[int, str]:
    """Each link's name in the model of ``scene_or_model`` (a Scene or a Model)."""
    model = getattr(scene_or_model, "_model", scene_or_model)
    return getattr(model, "link_names", FOUR_BAR_LINKS)


def links_by_name(words: dict[int, str], frame: bool = False) -> dict[Any, int]:
    """``{name or number: link}`` for a spec's ``link = ...`` (the moving links; with
    ``frame`` the frame too)."""
    out: dict[Any, int] = {n: k for k, n in words.items() if frame or k != 1}
    out.update({k: k for k in words if frame or k != 1})
    return out


class Link(NamedTuple):
    """One link at the positions of a request (each field a number or an array).

    ``c, s``: the cosine and sine of the link's line; ``x, y``: its base point (the pin a
    point on it is placed from); ``W``: its weight [lb] (in SI its mass [kg]); ``RG,
    cd, sd``: its centre of mass, RG from the base point in the direction (cd, sd).
    """

    c: Any
    s: Any
    x: Any
    y: Any
    W: Any = 0.0
    RG: Any = 0.0
    cd: Any = 1.0
    sd: Any = 0.0


class LinkRate(NamedTuple):
    """One link's angular velocity ``w`` [rad/sec, CCW +] and its base point's velocity
    ``(vx, vy)`` [in/sec or m/s]."""

    w: Any
    vx: Any
    vy: Any


#: The frame: base at the origin, line along +x, massless (its loads are the ground's).
FRAME = Link(1.0, 0.0, 0.0, 0.0)
#: The frame at rest.
FRAME_RATE = LinkRate(0.0, 0.0, 0.0)
