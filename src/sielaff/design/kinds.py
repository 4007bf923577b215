"""What the design answers need to know of a kind of linkage besides the four-bar.

The four-bar (:class:`~sielaff.mechanism.Mechanism`) keeps its own paths in each answer
(``linkage_class``, the 1966 names); every other kind (the slider-crank, the inverted
slider-crank, the six-bars, any ``Linkage``) is asked of its model
(:func:`sielaff.engine.model_for`): its fields, its Scene type, whether its crank turns a
full revolution (``Model.full_turn``), its pins and slides (from its topology, named as
its outputs are), its transmission angles, and where it assembles.

Nothing here imports a kind's module (the design layer sits on the engine): a kind is
known by its model.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sielaff.engine.analysis import model_for
from sielaff.engine.registry import Model
from sielaff.engine.scene import scene_from, scene_of
from sielaff.mechanism import Mechanism

__all__ = ["Pin", "arcs_where_assembled", "fields_of", "four_bar_only", "gammas",
           "is_four_bar", "is_slider_crank", "kind_name", "nonnegative_fields", "pins",
           "positive_fields", "scene_of_kind", "slides", "spread", "turn_failures"]

#: Angles per revolution the assembly arcs are first found on [-] (engine.assembly's grid).
GRID = 3600
#: Bisection steps that locate each end of an arc (3600 grid -> 0.1 deg / 2^48 ~ 4e-16).
BISECTIONS = 48

#: A pin as the answers use it: (its force's output name, its point, the link whose force
#: it reports (by), the link it acts on (on)).
Pin = tuple[str, str, int, int]


def is_four_bar(mechanism: Any) -> bool:
    """Whether ``mechanism`` [any kind] is the 1966 four-bar (a :class:`Mechanism`)."""
    return isinstance(mechanism, Mechanism)


def is_slider_crank(mechanism: Any) -> bool:
    """Whether ``mechanism`` [any kind] is a slider-crank (its model is the
    slider-crank's)."""
    from sielaff.engine.slider_crank import SLIDER_CRANK

    return not is_four_bar(mechanism) and model_for(mechanism) is SLIDER_CRANK


def kind_name(mechanism: Any) -> str:
    """The kind of ``mechanism`` [any kind but the four-bar] in a message: its type and its
    model's title (``SliderCrank (slider-crank)``)."""
    title = getattr(model_for(mechanism), "topology", None)
    title = getattr(title, "title", None)
    name = type(mechanism).__name__
    return f"{name} ({title})" if title and title.lower() != name.lower() else name


def four_bar_only(mechanism: Any, what: str) -> None:
    """ValueError in one line naming ``mechanism``'s kind [any kind] if it is not a
    four-bar; ``what`` [-] names the answer that is the four-bar's."""
    if not is_four_bar(mechanism):
        raise ValueError(f"{what} is for the four-bar, not a {kind_name(mechanism)}")


def fields_of(mechanism: Any) -> tuple[str, ...]:
    """The names of the fields of ``mechanism`` [any kind] (its ``as_dict`` keys, in
    order)."""
    return tuple(mechanism.as_dict())


def scene_of_kind(mechanism: Any, scene: Any, keywords: dict[str, Any], where: str) -> Any:
    """The Scene of a call on ``mechanism``.

    Parameters
    ----------
    mechanism : any kind
        The linkage [its unit system].
    scene : Scene or None
        Given (it must be of the kind's Scene type) [-].
    keywords : dict
        Else the kind's Scene is made of these (``analyze``'s keywords) [each field's unit].
    where : str
        The answer's name in a message [-].
    """
    if is_four_bar(mechanism):
        return scene_from(scene, keywords, where)
    model = model_for(mechanism)
    sc = scene_from(scene, keywords, where, model=model)
    if not isinstance(sc, scene_of(model)):
        raise ValueError(f"{where}: the scene is not a {kind_name(mechanism)}'s: make it "
                         "with sielaff.scene_for(mechanism)")
    return sc


def _topology(model: Model) -> Any:
    topology = getattr(model, "topology", None)
    if topology is None:
        raise ValueError(f"model {model.name} has no topology: its pins are not known")
    return topology


def pins(mechanism: Any) -> tuple[Pin, ...]:
    """Each pin of the kind of ``mechanism`` [not a four-bar] in solve order: (the output
    naming its force, the point, by, on), the force being link ``by``'s on link ``on``."""
    from sielaff.engine.joints import joints

    topology = _topology(model_for(mechanism))
    names = dict(topology.names)
    found, _ = joints(topology)
    return tuple((names.get(j.name, j.name), j.point, j.by, j.on) for j in found)


def slides(mechanism: Any) -> tuple[str, ...]:
    """The output naming each slide's guide force (FN and its label) of ``mechanism`` [not
    a four-bar], in solve order."""
    from sielaff.engine.joints import joints

    topology = _topology(model_for(mechanism))
    names = dict(topology.names)
    _, found = joints(topology)
    return tuple(names.get(f"FN{s.label}", f"FN{s.label}") for s in found)


def gammas(mechanism: Any) -> tuple[str, ...]:
    """The transmission angles the model of ``mechanism`` [not a four-bar] gives (GAMMA<pin>
    of each RRR dyad, or as its topology renames them)."""
    model = model_for(mechanism)
    return tuple(n for n in model.outputs if n.startswith("GAMMA"))


def positive_fields(mechanism: Any) -> tuple[str, ...]:
    """The fields of ``mechanism`` [not a four-bar] that must be > 0: its topology's link
    lengths and the kind's own (``POSITIVE``)."""
    topology = _topology(model_for(mechanism))
    return tuple(dict.fromkeys(topology.lengths()
                               + tuple(getattr(type(mechanism), "POSITIVE", ()))))


def nonnegative_fields(mechanism: Any) -> tuple[str, ...]:
    """The fields of ``mechanism`` [any kind] that cannot be below 0: the weights (masses)
    and moments of inertia Wk, ZIk."""
    return tuple(n for n in fields_of(mechanism)
                 if n.rstrip("0123456789") in ("W", "ZI") and n[-1:].isdigit())


def turn_failures(mechanism: Any) -> np.ndarray:
    """Why the crank cannot turn a full revolution, per design, or None.

    Parameters
    ----------
    mechanism : any kind but the four-bar
        Its fields scalars or arrays [its unit system].

    Returns
    -------
    numpy.ndarray
        An object array of the fields' broadcast shape: the model's ``full_turn`` asked of
        each design alone (a model without that test says None: its torque's finiteness
        then decides).
    """
    model = model_for(mechanism)
    values = {k: np.asarray(v, dtype=float) for k, v in mechanism.as_dict().items()}
    shape = np.broadcast_shapes(*(v.shape for v in values.values()))
    out = np.empty(shape, dtype=object)
    if model.full_turn is None:
        out.fill(None)
        return out
    flat = {k: np.broadcast_to(v, shape).reshape(-1) for k, v in values.items()}
    for i in range(out.size):
        one = mechanism.replace(**{k: float(v[i]) for k, v in flat.items()})
        out.reshape(-1)[i] = model.full_turn(one)
    return out


def _assembled(model: Model, values: dict[str, float], th: np.ndarray, branch: Any
               ) -> np.ndarray:
    from sielaff.engine.assembly import margins

    m = margins(_topology(model), values, th, branch)
    return np.all(np.isfinite(m), axis=0)


def arcs_where_assembled(mechanism: Any, branch: Any = "open") -> list[tuple[float, float]]:
    """The arcs of THETA 2 where every dyad of ``mechanism`` closes on ``branch``.

    Parameters
    ----------
    mechanism : any kind but the four-bar
        One design (scalar fields) [its unit system].
    branch : str or tuple of str
        The scene's branch, "open" or "crossed", or one per dyad [-].

    Returns
    -------
    list of (float, float)
        (from, to) [deg], CCW: ``[(0, 360)]`` for a whole revolution, ``[]`` where it never
        assembles.  Each end is located by bisection between the grid's last angle that
        closes and its first that does not (a toggle, to ~1e-13 deg).
    """
    model = model_for(mechanism)
    values = {k: float(v) for k, v in mechanism.as_dict().items()}
    th = np.arange(GRID) * (360.0 / GRID)
    ok = _assembled(model, values, th, branch)
    if ok.all():
        return [(0.0, 360.0)]
    if not ok.any():
        return []
    step = 360.0 / GRID

    def edge(inside: float, outside: float) -> float:
        for _ in range(BISECTIONS):
            mid = 0.5 * (inside + outside)
            if _assembled(model, values, np.array([mid]), branch)[0]:
                inside = mid
            else:
                outside = mid
        return inside

    out = []
    n = len(ok)
    first_bad = int(np.argmin(ok))
    start = None
    for k in range(1, n + 1):
        i = (first_bad + k) % n
        if ok[i] and start is None:
            start = i
        if not ok[i] and start is not None:
            last = (i - 1) % n
            a = edge(float(th[start]), float(th[start]) - step)
            b = edge(float(th[last]), float(th[last]) + step)
            out.append((a % 360.0, b % 360.0))
            start = None
    return out


def spread(arcs: list[tuple[float, float]], n: int) -> np.ndarray:
    """``n`` [-] crank angles [deg] over ``arcs`` ((from, to) [deg], CCW) in proportion to
    their lengths, each arc's ends included (a whole revolution: 0 to 360, 360 left out),
    as ``engine.reachable`` spreads a four-bar's."""
    if arcs == [(0.0, 360.0)]:
        return np.linspace(0.0, 360.0, n, endpoint=False)
    spans = [((b - a) % 360.0, a) for a, b in arcs]
    total = sum(w for w, _ in spans)
    out: list[np.ndarray] = []
    for k, (w, a) in enumerate(spans):
        m = n - sum(len(o) for o in out) if k == len(spans) - 1 \
            else max(2, round(n * w / total))
        out.append(np.mod(a + np.linspace(0.0, w, m), 360.0))
    return np.concatenate(out) if out else np.array([])
