"""The figures a designer compares, per design, over one revolution.

In:  a mechanism whose fields are arrays over designs (shape (D,)), the scene, ``n``
     crank angles per revolution, the coefficient of speed fluctuation ``cf``.
Out: ``{figure: array (D,)}``, in the mechanism's units (:data:`FIGURES`):

    TORQ_PEAK   largest |TORQ|                  TORQ_RMS   root mean square of TORQ
    FLYWHEEL_I  flywheel inertia for cf at TH2D (design.flywheel)
    FOA_PEAK FA32_PEAK FB34_PEAK FOB_PEAK       largest load on each pin
    SHAK_PEAK   largest shaking force           SHAKM_PEAK largest |shaking moment|
    GAMMA_MIN   smallest transmission angle, min(GAMMA, 180 - GAMMA) over the cycle
    KIND        the linkage's kind, as an index into classify.KINDS

A design whose crank cannot turn fully gets NaN figures (and its KIND): a sweep over a
range of lengths may cross out of the crank-rockers.  Peaks are taken on the grid (the
grid's own resolution; ``check`` refines single designs further).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sielaff.design.flywheel import flywheel_from_torque
from sielaff.engine.analysis import analyze
from sielaff.engine.classify import KINDS, linkage_class
from sielaff.engine.scene import Scene, scene_from
from sielaff.mechanism import Mechanism

__all__ = ["FIGURES", "figures"]

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
    "KIND": (None, "kind of four-bar (index into KINDS)"),
}

_NEED = ["TORQ", "FOA", "FA32", "FB34", "FOB", "SHAK", "SHAKM", "GAMMA"]


def figures(mechanism: Mechanism, n: int = 360, cf: float = 0.05, *,
            scene: Scene | None = None, **keywords: Any) -> dict[str, np.ndarray]:
    """The :data:`FIGURES` of each design of ``mechanism`` (fields of shape (D,) or
    scalars) in ``scene`` (a TEX of shape (D, 1) is one per design)."""
    sc = scene_from(scene, keywords, "figures")
    fields = {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in
              mechanism.as_dict().items()}
    d = np.broadcast_shapes(*(v.shape for v in fields.values()))
    if len(d) != 1:
        raise ValueError("figures: the mechanism's fields must be 1-D over designs")
    fields = {k: np.broadcast_to(v, d) for k, v in fields.items()}
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
    torq = r["TORQ"]
    out["TORQ_PEAK"][ok] = np.max(np.abs(torq), axis=1)
    out["TORQ_RMS"][ok] = np.sqrt(np.mean(torq * torq, axis=1))
    finite = np.all(np.isfinite(torq), axis=1)
    if finite.any():
        fw = flywheel_from_torque(torq[finite], fields["TH2D"][ok][finite], cf)
        inertia = np.full(int(ok.sum()), np.nan)
        inertia[finite] = fw.inertia
        out["FLYWHEEL_I"][ok] = inertia
    for name in ("FOA", "FA32", "FB34", "FOB", "SHAK"):
        out[name + "_PEAK"][ok] = np.max(r[name], axis=1)
    out["SHAKM_PEAK"][ok] = np.max(np.abs(r["SHAKM"]), axis=1)
    g = r["GAMMA"]
    out["GAMMA_MIN"][ok] = np.min(np.minimum(g, 180.0 - g), axis=1)
    return out
