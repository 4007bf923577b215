"""The figures a designer compares, per design, over one revolution.

In:  a mechanism whose fields are arrays over designs (shape (D,)), the scene, ``n``
     crank angles per revolution, the coefficient of speed fluctuation ``cf``.
Out: ``{figure: array (D,)}``, in the mechanism's units (:data:`FIGURES`):

    TORQ_PEAK   largest |TORQ|                  TORQ_RMS   root mean square of TORQ
    FLYWHEEL_I  flywheel inertia for cf at TH2D (design.flywheel)
    FOA_PEAK FA32_PEAK FB34_PEAK FOB_PEAK       largest load on each pin
    SHAK_PEAK   largest shaking force           SHAKM_PEAK largest |shaking moment|
    GAMMA_MIN   smallest transmission angle, min(GAMMA, 180 - GAMMA) over the cycle
    GAMMA_MAX   largest transmission angle GAMMA over the cycle (the usual guideline
                keeps GAMMA between 40 and 140 deg: GAMMA_MIN >= 40, GAMMA_MAX <= 140)
    KIND        the linkage's kind, as an index into classify.KINDS

A design whose crank cannot turn fully gets NaN figures (and its KIND): a sweep over a
range of lengths may cross out of the crank-rockers.  Peaks are taken on the grid (the
grid's own resolution; ``check`` refines single designs further).

Another kind of linkage (a slider-crank, an inverted slider-crank, a six-bar, any
``Linkage``) has the figures its own outputs give (:func:`figure_table`): TORQ_PEAK,
TORQ_RMS, FLYWHEEL_I; ``<F>_PEAK`` for the force F of each of its pins (the largest
load) and each slide's guide force FN (the largest magnitude); SHAK_PEAK, SHAKM_PEAK;
and for each transmission angle GAMMA<pin> of an RRR dyad ``GAMMA<pin>_MIN`` and
``GAMMA<pin>_MAX`` as the four-bar's GAMMA_MIN and GAMMA_MAX.  It has no KIND (that is
the four-bar's class); whether its crank turns fully is its model's ``full_turn``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sielaff.design.flywheel import flywheel_from_torque
from sielaff.design.kinds import gammas, is_four_bar, pins, scene_of_kind, slides, turn_failures
from sielaff.engine.analysis import analyze
from sielaff.engine.classify import KINDS, linkage_class
from sielaff.engine.scene import Scene, scene_from
from sielaff.mechanism import Mechanism

__all__ = ["FIGURES", "MAXIMISED", "figure_base", "figure_table", "figures", "maximised"]

#: figure -> (the output whose unit it has, what it is)
FIGURES = {
    "TORQ_PEAK": ("TORQ", "largest |driving torque|"),
    "TORQ_RMS": ("TORQ", "RMS driving torque"),
    "FLYWHEEL_I": ("ZI2", "flywheel inertia for the sweep's cf"),
    "FOA_PEAK": ("FOA", "largest load on pin O2"),
    "FA32_PEAK": ("FA32", "largest load on pin A"),
    "FB34_PEAK": ("FB34", "largest load on pin B"),
    "FOB_PEAK": ("FOB", "largest load on pin O4"),
    "SHAK_PEAK": ("SHAK", "largest shaking force"),
    "SHAKM_PEAK": ("SHAKM", "largest |shaking moment|"),
    "GAMMA_MIN": ("GAMMA", "smallest transmission angle"),
    "GAMMA_MAX": ("GAMMA", "largest transmission angle"),
    "KIND": (None, "kind of four-bar (index into KINDS)"),
}

#: Figures where more is better (maximised by a ranking and, unless told otherwise, by a
#: sweep's Pareto front); every other figure is minimised.
MAXIMISED = ("GAMMA_MIN",)

_NEED = ["TORQ", "FOA", "FA32", "FB34", "FOB", "SHAK", "SHAKM", "GAMMA"]


def maximised(name: str) -> bool:
    """Whether more of the figure ``name`` [-] is better: :data:`MAXIMISED`, and any kind's
    smallest transmission angle (GAMMA<pin>_MIN)."""
    return name in MAXIMISED or (name.startswith("GAMMA") and name.endswith("_MIN"))


def figure_table(mechanism: Any) -> dict[str, tuple[str | None, str]]:
    """The figures of the kind of ``mechanism`` [any kind, its unit system]: ``{figure:
    (the output whose unit it has, what it is)}``, :data:`FIGURES` for a four-bar (module
    doc for the others)."""
    if is_four_bar(mechanism):
        return FIGURES
    table = {k: FIGURES[k] for k in ("TORQ_PEAK", "TORQ_RMS", "FLYWHEEL_I")}
    for name, point, _, _ in pins(mechanism):
        table[f"{name}_PEAK"] = (name, f"largest load on pin {point}")
    for name in slides(mechanism):
        table[f"{name}_PEAK"] = (name, f"largest |guide force| {name} on the slider")
    table["SHAK_PEAK"] = FIGURES["SHAK_PEAK"]
    table["SHAKM_PEAK"] = FIGURES["SHAKM_PEAK"]
    for g in gammas(mechanism):
        at = f" at {g[len('GAMMA'):]}" if g != "GAMMA" else ""
        table[f"{g}_MIN"] = (g, f"smallest transmission angle{at}")
        table[f"{g}_MAX"] = (g, f"largest transmission angle{at}")
    return table


def figure_base(name: str) -> str | None:
    """The output whose unit the figure ``name`` [-] has (None for KIND), for any kind's
    figures: :data:`FIGURES`' own, else the name less _PEAK, _MIN or _MAX; None for a name
    that is not a figure."""
    if name in FIGURES:
        return FIGURES[name][0]
    for suffix in ("_PEAK", "_MIN", "_MAX"):
        if name.endswith(suffix) and len(name) > len(suffix):
            return name[:-len(suffix)]
    return None


def _columns(mechanism: Any) -> tuple[dict[str, np.ndarray], tuple[int, ...]]:
    fields = {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in
              mechanism.as_dict().items()}
    d = np.broadcast_shapes(*(v.shape for v in fields.values()))
    if len(d) != 1:
        raise ValueError("figures: the mechanism's fields must be 1-D over designs")
    return {k: np.broadcast_to(v, d) for k, v in fields.items()}, d


def _torque_figures(out: dict[str, np.ndarray], ok: np.ndarray, torq: np.ndarray,
                    th2d: np.ndarray, cf: float) -> None:
    """TORQ_PEAK, TORQ_RMS [in-lb or N m] and FLYWHEEL_I [in-lb-sec^2 or kg m^2] of the
    designs ``ok`` from their TORQ over a revolution (designs x angles), into ``out``."""
    out["TORQ_PEAK"][ok] = np.max(np.abs(torq), axis=1)
    out["TORQ_RMS"][ok] = np.sqrt(np.mean(torq * torq, axis=1))
    finite = np.all(np.isfinite(torq), axis=1)
    if finite.any():
        fw = flywheel_from_torque(torq[finite], th2d[ok][finite], cf)
        inertia = np.full(int(ok.sum()), np.nan)
        inertia[finite] = fw.inertia
        out["FLYWHEEL_I"][ok] = inertia


def _kind_figures(mechanism: Any, n: int, cf: float, scene: Any,
                  keywords: dict[str, Any]) -> dict[str, np.ndarray]:
    """:func:`figures` of a kind other than the four-bar (:func:`figure_table`)."""
    sc = scene_of_kind(mechanism, scene, keywords, "figures")
    table = figure_table(mechanism)
    fields, d = _columns(mechanism)
    m = mechanism.replace(**fields)
    out = {name: np.full(d, np.nan) for name in table}
    ok = np.array([why is None for why in turn_failures(m)], dtype=bool)
    if not ok.any():
        return out
    sub = m.replace(**{k: v[ok][:, None] for k, v in fields.items()})
    loads = [name for name, _, _, _ in pins(m)]
    guides, angles = list(slides(m)), list(gammas(m))
    th = np.arange(n) * (360.0 / n)
    with np.errstate(all="ignore"):
        r = analyze(sub, th, ["TORQ", "SHAK", "SHAKM"] + loads + guides + angles, scene=sc)
    _torque_figures(out, ok, r["TORQ"], fields["TH2D"], cf)
    for name in loads + ["SHAK"]:
        out[name + "_PEAK"][ok] = np.max(r[name], axis=1)
    for name in guides + ["SHAKM"]:
        out[name + "_PEAK"][ok] = np.max(np.abs(r[name]), axis=1)
    for name in angles:
        g = r[name]
        out[name + "_MIN"][ok] = np.min(np.minimum(g, 180.0 - g), axis=1)
        out[name + "_MAX"][ok] = np.max(g, axis=1)
    return out


def figures(mechanism: Any, n: int = 360, cf: float = 0.05, *,
            scene: Scene | None = None, **keywords: Any) -> dict[str, np.ndarray]:
    """The figures of each design of ``mechanism`` in ``scene``.

    Parameters
    ----------
    mechanism : Mechanism or another kind (SliderCrank, WattII, ..., Linkage)
        Its fields of shape (D,) or scalars [its unit system].
    n : int
        Crank angles per revolution [-].
    cf : float
        The coefficient of speed fluctuation for FLYWHEEL_I [-].
    scene : Scene, optional
        Of the kind's Scene type [-] (a four-bar's TEX of shape (D, 1) is one per
        design); or ``analyze``'s keywords.

    Returns
    -------
    dict
        ``{figure: array (D,)}`` [each figure's unit], the figures of
        :func:`figure_table` (:data:`FIGURES` for a four-bar).
    """
    if not isinstance(mechanism, Mechanism):
        return _kind_figures(mechanism, n, cf, scene, keywords)
    sc = scene_from(scene, keywords, "figures")
    fields, d = _columns(mechanism)
    m = mechanism.replace(**fields)
    cls = linkage_class(m)
    kind = np.array([KINDS.index(k) for k in cls.kind], dtype=float)
    out = {name: np.full(d, np.nan) for name in FIGURES}
    out["KIND"] = kind
    ok = np.asarray(cls.turns_fully, dtype=bool)
    if not ok.any():
        return out
    sub = m.replace(**{k: v[ok][:, None] for k, v in fields.items()})
    if not callable(sc.tex) and np.ndim(sc.tex) == 2:  # a sweep's TEX, one per design
        sc = sc.replace(tex=np.asarray(sc.tex)[ok])
    th = np.arange(n) * (360.0 / n)
    with np.errstate(all="ignore"):
        r = analyze(sub, th, _NEED, scene=sc)
    _torque_figures(out, ok, r["TORQ"], fields["TH2D"], cf)
    for name in ("FOA", "FA32", "FB34", "FOB", "SHAK"):
        out[name + "_PEAK"][ok] = np.max(r[name], axis=1)
    out["SHAKM_PEAK"][ok] = np.max(np.abs(r["SHAKM"]), axis=1)
    g = r["GAMMA"]
    out["GAMMA_MIN"][ok] = np.min(np.minimum(g, 180.0 - g), axis=1)
    out["GAMMA_MAX"][ok] = np.max(g, axis=1)
    return out
