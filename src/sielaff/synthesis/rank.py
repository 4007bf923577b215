"""Candidates ranked by what they will cost to run: torque, shaking, bearings, flywheel.

In:  candidates (:class:`~sielaff.mechanism.Mechanism`\\ s, or synthesis results carrying
     ``.mechanism`` and ``.branch``), the user's :class:`~sielaff.Scene`, the figures to
     rank ``by`` (:data:`~sielaff.design.figures.FIGURES`), an optional mass model.
Out: a :class:`Ranking`: per figure an array over the candidates (in the order given),
     the ``order`` (best first) and the Pareto front of two figures.

Each candidate is analysed over one revolution (``n`` crank angles) by
:func:`sielaff.design.figures.figures`, the function a sweep calls, in the user's scene on
the candidate's own branch (a synthesis result's ``branch``; a bare Mechanism takes the
scene's).  Every figure is minimised except ``GAMMA_MIN``, the smallest transmission
angle, which is maximised.  ``order`` sorts on ``by[0]``, ties going to ``by[1]`` and so
on (a lexicographic order: weigh figures against each other with the Pareto front
instead); a candidate whose crank cannot turn fully has NaN figures and comes last, in
the order given.  The Pareto front is the set of candidates no other candidate matches or
beats in both ``pareto`` figures and beats in one.

Large sets go the sweep's way (:mod:`sielaff.design.sweep`): blocks of
:data:`~sielaff.design.sweep.BLOCK` candidates, each one call of ``figures``, in this
process or as dask tasks (local threads, or a dask.distributed ``client``); the blocks and
the function are the same on every path, so the figures are too, bit for bit.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.design.figures import FIGURES, figures
from sielaff.design.sweep import BLOCK
from sielaff.engine.scene import Scene
from sielaff.mechanism import FIELD_NAMES, Mechanism
from sielaff.synthesis.common import masses

__all__ = ["MAXIMISED", "RANKABLE", "Ranking", "pareto_front", "rank"]

#: The figures a ranking can use (KIND is a label, not a figure of merit).
RANKABLE = tuple(f for f in FIGURES if f != "KIND")
#: Figures where more is better.
MAXIMISED = ("GAMMA_MIN",)
#: A candidate set larger than this goes to dask (when installed) with backend="auto".
SMALL = 1024


@dataclass(frozen=True)
class Ranking:
    """The ranked candidates.

    ``candidates``: as given; ``mechanisms``: what was analysed (the mass model applied);
    ``branches``: each one's branch.  ``figures``: ``{figure: array (N,)}`` in the
    mechanisms' units (:data:`~sielaff.design.figures.FIGURES`), candidates in the order
    given.  ``by``: the ranking figures; ``order``: candidate indices, best first;
    ``pareto``: the indices on the Pareto front of the two ``pareto_by`` figures, sorted
    by the first.  ``units``: the unit system.
    """

    candidates: tuple
    mechanisms: tuple[Mechanism, ...]
    branches: tuple[str, ...]
    figures: dict[str, np.ndarray]
    by: tuple[str, ...]
    order: np.ndarray
    pareto: np.ndarray
    pareto_by: tuple[str, str]
    units: str

    def __len__(self) -> int:
        return len(self.mechanisms)

    def to_frame(self) -> Any:
        """The ranking as a pandas DataFrame (the ``frames`` extra): one row per candidate,
        best first (``RANK`` 1, 2, ...), indexed by the candidate's position as given, one
        column per figure; units in ``frame.attrs["units"]``."""
        import pandas as pd

        from sielaff.design.sweep import column_units

        order = np.asarray(self.order, dtype=int)
        frame = pd.DataFrame({f: np.asarray(v)[order] for f, v in self.figures.items()},
                             index=pd.Index(order, name="CANDIDATE"))
        frame.insert(0, "RANK", np.arange(1, len(order) + 1))
        frame.attrs["units"] = column_units(list(self.figures), self.units)
        frame.attrs["units"]["RANK"] = "-"
        return frame

    def best(self, k: int = 1) -> list[Any]:
        """The ``k`` best candidates (as given), best first."""
        return [self.candidates[i] for i in self.order[:k]]


def _key(name: str, values: np.ndarray) -> np.ndarray:
    """The value to minimise for figure ``name``."""
    return -values if name in MAXIMISED else values


def pareto_front(x: Any, y: Any) -> np.ndarray:
    """Indices of the points no other point matches or beats in both ``x`` and ``y`` while
    beating it in one (both minimised); NaNs are never on it.  Sorted by x, then y."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    ok = np.flatnonzero(np.isfinite(x) & np.isfinite(y))
    order = ok[np.lexsort((y[ok], x[ok]))]
    front: list[int] = []
    best = np.inf
    for i in order:
        if y[i] < best or (front and x[i] == x[front[-1]] and y[i] == y[front[-1]]):
            front.append(int(i))  # a duplicate of a point on the front is on it too
            best = y[i]
    return np.array(front, dtype=int)


def _mechanism_of(c: Any) -> tuple[Mechanism, str | None]:
    if isinstance(c, Mechanism):
        return c, None
    m = getattr(c, "mechanism", None)
    if not isinstance(m, Mechanism):
        raise ValueError(f"rank: candidate {c!r:.60} is neither a Mechanism nor a synthesis "
                         "result with .mechanism")
    return m, getattr(c, "branch", None)


def _apply_masses(m: Mechanism, model: Any) -> Mechanism:
    if model is None:
        return m
    if callable(model):
        out = model(m)
        if not isinstance(out, Mechanism):
            raise ValueError("rank: mass_model returned something that is not a Mechanism")
        return out
    if isinstance(model, dict):
        unknown = set(model) - {"density", "area"}
        if unknown:
            raise ValueError(f"rank: mass_model keys {sorted(unknown)}: density and area")
        return masses(m, **model)
    raise ValueError(f"rank: mass_model = {model!r}: None (as given), "
                     "{'density': ..., 'area': ...} or a function of a Mechanism")


def _evaluate(mechs: list[Mechanism], scene: Scene, n: int, cf: float, backend: str,
              client: Any, workers: int | None, size_of_block: int) -> dict[str, np.ndarray]:
    """figures() of ``mechs`` (one branch, one unit system) a block at a time."""
    units = mechs[0].units
    stacked = {k: np.array([float(getattr(m, k)) for m in mechs]) for k in FIELD_NAMES}
    spans = [(i, min(i + size_of_block, len(mechs)))
             for i in range(0, len(mechs), size_of_block)]
    names = list(FIGURES)

    def run(start: int, stop: int) -> np.ndarray:
        part = Mechanism(**{k: v[start:stop] for k, v in stacked.items()}, units=units)
        r = figures(part, n=n, cf=cf, scene=scene)
        return np.stack([r[f] for f in names], axis=1)

    if backend == "process":
        rows = [run(s, e) for s, e in spans]
    else:
        import dask

        tasks = [dask.delayed(run)(s, e) for s, e in spans]
        if client is not None:
            rows = list(client.gather(client.compute(tasks)))
        else:
            rows = list(dask.compute(*tasks, scheduler="threads", num_workers=workers))
    table = np.concatenate(rows, axis=0)
    return {f: table[:, j] for j, f in enumerate(names)}


def rank(candidates: Sequence[Any], *, scene: Scene | None = None,
         by: Sequence[str] = ("TORQ_PEAK",), pareto: Sequence[str] | None = None,
         mass_model: dict | Callable[[Mechanism], Mechanism] | None = None,
         n: int = 360, cf: float = 0.05, backend: str = "auto", client: Any = None,
         workers: int | None = None, size_of_block: int = BLOCK) -> Ranking:
    """Analyse every candidate under ``scene`` and rank them (module doc).

    Parameters
    ----------
    candidates : sequence
        Mechanisms [units of each], or synthesis results (``.mechanism``, ``.branch``).
        All in one unit system.
    scene : Scene, optional
        What acts on them (default: the 1966 program's scene).  Its branch is used for
        candidates that carry none.
    by : sequence of str
        Figures of :data:`RANKABLE` [their units], the first deciding.
    pareto : two str, optional
        The Pareto front's figures (default ``by[:2]``, or ``by[0]`` and ``SHAK_PEAK``).
    mass_model : None, dict or callable
        None: each mechanism's own masses [lb or kg]; ``{"density": [lb/in^3 or kg/m^3],
        "area": [in^2 or m^2]}`` for :func:`~sielaff.synthesis.masses` (uniform bars);
        or a function of a Mechanism returning one.
    n : int
        Crank angles per revolution [-].
    cf : float
        Coefficient of speed fluctuation for FLYWHEEL_I [-].
    backend : {"auto", "process", "dask"}
        ``auto``: dask when installed and more than :data:`SMALL` candidates.
    client : dask.distributed.Client, optional
        Run on its workers (backend dask).
    workers : int, optional
        dask's local threads (default one per core).
    size_of_block : int
        Candidates per block [-].
    """
    sc = Scene() if scene is None else scene
    if not isinstance(sc, Scene):
        raise ValueError(f"rank: scene = {scene!r} is not a sielaff.Scene")
    by = tuple(by)
    if not by:
        raise ValueError("rank: by = (): name at least one figure")
    for f in by:
        if f not in RANKABLE:
            raise ValueError(f"rank: by {f!r}: one of {' '.join(RANKABLE)}")
    if pareto is None:
        pareto = by[:2] if len(by) >= 2 else (by[0], "SHAK_PEAK" if by[0] != "SHAK_PEAK"
                                                else "TORQ_PEAK")
    pareto = tuple(pareto)
    if len(pareto) != 2 or not all(f in RANKABLE for f in pareto):
        raise ValueError(f"rank: pareto = {pareto!r}: two of {' '.join(RANKABLE)}")
    if not (isinstance(n, int) and n >= 8 and n % 2 == 0):
        raise ValueError(f"rank: n = {n!r}: an even whole number of angles, 8 or more")
    if backend not in ("auto", "process", "dask"):
        raise ValueError(f"rank: backend = {backend!r}: 'auto', 'process' or 'dask'")
    cands = tuple(candidates)
    if not cands:
        raise ValueError("rank: no candidates")
    mechs, branches = [], []
    for c in cands:
        m, b = _mechanism_of(c)
        mechs.append(_apply_masses(m, mass_model))
        branches.append(b or sc.branch)
    units = mechs[0].units
    if any(m.units != units for m in mechs):
        raise ValueError("rank: the candidates are in different unit systems")
    if backend == "auto":
        backend = "process"
        if len(cands) > SMALL or client is not None:
            try:
                import dask  # noqa: F401
            except ImportError:
                pass
            else:
                backend = "dask"
    figs = {f: np.full(len(cands), np.nan) for f in FIGURES}
    for branch in sorted(set(branches)):
        idx = [i for i, b in enumerate(branches) if b == branch]
        got = _evaluate([mechs[i] for i in idx], sc.replace(branch=branch), n, cf, backend,
                        client, workers, size_of_block)
        for f in FIGURES:
            figs[f][idx] = got[f]
    keys = [_key(f, figs[f]) for f in by]
    bad = np.zeros(len(cands), dtype=bool)
    for k in keys:
        bad |= ~np.isfinite(k)
    # np.lexsort sorts on the last key first: the given index, then by[-1] ... by[0], then bad
    order = np.lexsort([np.arange(len(cands))]
                       + [np.where(bad, 0.0, k) for k in reversed(keys)] + [bad])
    front = pareto_front(_key(pareto[0], figs[pareto[0]]), _key(pareto[1], figs[pareto[1]]))
    return Ranking(cands, tuple(mechs), tuple(branches), figs, by, order.astype(int), front,
                   (pareto[0], pareto[1]), units)
