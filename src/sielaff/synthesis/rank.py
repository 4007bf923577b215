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

**Near-ties** do not go by the order given: a figure's values are grouped before
sorting, a gap of more than ``tie`` times the figure's largest magnitude among the
candidates starting a new group (chained: a run of values each within the gap of the
next is one group), so two candidates whose figure differs by less than that (by
rounding, or a mirror image's last bits) are tied on it and the next figure decides.
Candidates tied on every ``by`` figure share a rank (``ranks``: 1, 1, 3, ...); among
them the remaining figures of :data:`RANKABLE`, in that order and grouped the same way,
then the order given, decide who is listed first.

**Constraints** bound any figure of :data:`RANKABLE` or of :data:`LINK_FIGURES` (the
longest and shortest link, and any ratio ``"Ri/Rj"`` of two links): ``{name: (least,
most)}``, ``None`` for no bound, each in the figure's unit.  A candidate that breaks one
is infeasible: ``feasible`` is False, ``violations`` says which bound it broke by how
much, it ranks after every feasible candidate (and before those whose crank cannot
turn) and is never on the Pareto front.

Large sets go the sweep's way (:mod:`sielaff.design.sweep`): blocks of
:data:`~sielaff.design.sweep.BLOCK` candidates, each one call of ``figures``, in this
process or as dask tasks (local threads, or a dask.distributed ``client``); the blocks and
the function are the same on every path, so the figures are too, bit for bit.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.design.figures import FIGURES, MAXIMISED, figures
from sielaff.design.sweep import BLOCK
from sielaff.engine.scene import Scene
from sielaff.mechanism import FIELD_NAMES, Mechanism
from sielaff.synthesis.common import masses

__all__ = ["LINK_FIGURES", "MAXIMISED", "RANKABLE", "Ranking", "constraint_unit",
           "pareto_front", "rank"]

#: The figures a ranking can use (KIND is a label, not a figure of merit).
RANKABLE = tuple(f for f in FIGURES if f != "KIND")
#: What a constraint may bound besides the RANKABLE figures: the longest and shortest link
#: [length unit]; a ratio of two links, "R3/R2" [-], by that name (RATIO).
LINK_FIGURES = {"LONGEST": "the longest of R1 to R4", "SHORTEST": "the shortest of R1 to R4"}
RATIO = re.compile(r"R([1-4])/R([1-4])")
#: Two values of a figure closer than this times its largest magnitude are tied (module doc).
TIE = 1e-9
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
    feasible: np.ndarray
    violations: tuple[str, ...]
    ranks: np.ndarray
    constraints: dict[str, tuple[float | None, float | None]]

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
        frame.insert(0, "RANK", np.asarray(self.ranks)[order])
        frame["FEASIBLE"] = np.asarray(self.feasible)[order]
        frame["VIOLATES"] = [self.violations[i] for i in order]
        for attr in ("k", "side"):  # a crank-rocker family's free choice
            if all(hasattr(c, attr) for c in self.candidates):
                frame[attr.upper()] = [getattr(self.candidates[i], attr) for i in order]
        frame.attrs["units"] = column_units(list(self.figures), self.units)
        frame.attrs["units"].update({c: "-" for c in frame.columns
                                     if c not in frame.attrs["units"]})
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


def constraint_unit(name: str, units: str) -> str:
    """The unit a constraint on ``name`` is written in (ValueError: nothing of that name)."""
    from sielaff.quantities import unit

    if name in RANKABLE:
        return unit(FIGURES[name][0], units)
    if name in LINK_FIGURES:
        return unit("R1", units)
    m = RATIO.fullmatch(name)
    if m and m.group(1) != m.group(2):
        return "-"
    raise ValueError(f"constraint on {name!r}: one of {' '.join(RANKABLE)}, "
                     f"{' '.join(LINK_FIGURES)} or a ratio of two links such as R3/R2")


def _constraint_values(name: str, mechs: Sequence[Mechanism],
                       figs: dict[str, np.ndarray]) -> np.ndarray:
    if name in figs:
        return figs[name]
    lengths = np.array([[float(getattr(m, f"R{j}")) for j in range(1, 5)] for m in mechs])
    if name == "LONGEST":
        return lengths.max(axis=1)
    if name == "SHORTEST":
        return lengths.min(axis=1)
    m = RATIO.fullmatch(name)
    assert m is not None  # constraint_unit checked it
    return lengths[:, int(m.group(1)) - 1] / lengths[:, int(m.group(2)) - 1]


def _checked_constraints(constraints: Mapping[str, Any] | None, units: str
                         ) -> dict[str, tuple[float | None, float | None]]:
    out: dict[str, tuple[float | None, float | None]] = {}
    for name, bounds in (constraints or {}).items():
        constraint_unit(name, units)
        if not (isinstance(bounds, tuple | list) and len(bounds) == 2):
            raise ValueError(f"constraint on {name}: (least, most), None for no bound")
        lo, hi = (None if b is None else float(b) for b in bounds)
        if lo is None and hi is None:
            raise ValueError(f"constraint on {name}: give a least or a most value")
        for b in (lo, hi):
            if b is not None and not np.isfinite(b):
                raise ValueError(f"constraint on {name}: bound {b!r} is not a finite number")
        if lo is not None and hi is not None and lo > hi:
            raise ValueError(f"constraint on {name}: least {lo:g} is above most {hi:g}")
        out[name] = (lo, hi)
    return out


def _violations(constraints: dict[str, tuple[float | None, float | None]],
                mechs: Sequence[Mechanism], figs: dict[str, np.ndarray],
                units: str) -> tuple[np.ndarray, tuple[str, ...]]:
    """Which candidates meet every constraint, and for the others the first one broken."""
    why = [""] * len(mechs)
    for name, (lo, hi) in constraints.items():
        v = _constraint_values(name, mechs, figs)
        u = constraint_unit(name, units)
        u = "" if u == "-" else f" {u}"
        for i, x in enumerate(v):
            if why[i]:
                continue
            if not np.isfinite(x):
                why[i] = f"{name} undefined (the crank does not turn fully)"
            elif lo is not None and x < lo:
                why[i] = f"{name} = {x:.5g}{u} below the least {lo:g}{u}"
            elif hi is not None and x > hi:
                why[i] = f"{name} = {x:.5g}{u} above the most {hi:g}{u}"
    return np.array([not w for w in why], dtype=bool), tuple(why)


def _tie_groups(key: np.ndarray, tie: float) -> np.ndarray:
    """Each value's group number in ascending order (module doc: near-ties); NaN -> 0."""
    out = np.zeros(len(key))
    ok = np.isfinite(key)
    if not ok.any():
        return out
    v = key[ok]
    o = np.argsort(v, kind="stable")
    gap = tie * float(np.max(np.abs(v)))
    groups = np.empty(len(v))
    groups[o] = np.concatenate([[0.0], np.cumsum(np.diff(v[o]) > gap)])
    out[ok] = groups
    return out


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
         workers: int | None = None, size_of_block: int = BLOCK,
         constraints: Mapping[str, Any] | None = None, tie: float = TIE) -> Ranking:
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
    constraints : mapping, optional
        ``{name: (least, most)}`` [the figure's unit; None: no bound] on figures of
        :data:`RANKABLE` or :data:`LINK_FIGURES`, or a ratio ``"Ri/Rj"`` (module doc).
    tie : float
        [-] Values of a figure closer than ``tie`` times its largest magnitude are tied
        (module doc), 0 <= tie < 0.1.
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
    if not (isinstance(tie, int | float) and 0.0 <= tie < 0.1):
        raise ValueError(f"rank: tie = {tie!r}: a fraction from 0 to below 0.1")
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
    limits = _checked_constraints(constraints, units)
    feasible, why = _violations(limits, mechs, figs, units)
    bad = np.zeros(len(cands), dtype=bool)
    for f in by:
        bad |= ~np.isfinite(figs[f])
    ranked = [_tie_groups(_key(f, figs[f]), tie) for f in by]
    after = [_tie_groups(_key(f, figs[f]), tie) for f in RANKABLE if f not in by]
    # np.lexsort sorts on the last key first: NaN last, then the infeasible, then the by
    # figures' groups, then the other figures', then the order given
    primary = [bad.astype(float), (~feasible).astype(float)] + ranked
    order = np.lexsort([np.arange(len(cands))] + list(reversed(after))
                       + list(reversed(primary))).astype(int)
    ranks = np.empty(len(cands), dtype=int)
    table = np.stack(primary, axis=1)
    for pos, i in enumerate(order):
        same = pos > 0 and np.array_equal(table[i], table[order[pos - 1]])
        ranks[i] = ranks[order[pos - 1]] if same else pos + 1
    ok = np.flatnonzero(feasible)
    front = ok[pareto_front(_key(pareto[0], figs[pareto[0]])[ok],
                            _key(pareto[1], figs[pareto[1]])[ok])]
    return Ranking(cands, tuple(mechs), tuple(branches), figs, by, order, front.astype(int),
                   (pareto[0], pareto[1]), units, feasible, why, ranks, limits)
