"""Grids of designs, evaluated a block at a time, in process or on dask.

In:  a base mechanism, the swept fields (``{name: 1-D array of values}``, a Cartesian
     grid in the order given, the last varying fastest), the scene, ``n`` angles, ``cf``.
Out: per design its grid values and :data:`~sielaff.design.figures.FIGURES`, block by
     block (``iter_blocks``), so memory stays flat however many designs there are.

Each block is ``BLOCK`` designs (or fewer at the end), evaluated by :func:`block`, a
pure function of the block's index range.  The in-process path and the dask path cut
the same blocks and call the same function, so their results are identical, bit for
bit.  On dask each block is one task of a ``dask.array`` (chunks over designs; the
angles of a design stay in one chunk, since its figures reduce over them): with no
client, dask's local threads (numpy releases the GIL), with a ``dask.distributed``
client, its workers.  A block's memory: about ``BLOCK * n * 8 bytes`` per engine
array, some 60 arrays (docs/design.md measures it).

The swept names are the mechanism's fields (W2 ... TH2D), ``TEX`` (the scene's torque on
the rocker, in-lb or N m), ``BALANCE`` (0 or 1: the design with Berkof-Lowen counterweights
merged in, design.balance) and ``CW_R2``, ``CW_R4`` (the counterweights' radii from O2 and
O4 when BALANCE is 1; default R2 and R4).

A sweep of another kind of linkage (a slider-crank, a six-bar, ...) varies that kind's own
fields (:func:`sweepable`; TEX and the counterweights are the four-bar's) and gives its
figures (:func:`sielaff.design.figures.figure_table`), in its own Scene.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import numpy as np

from sielaff.design.balance import balance
from sielaff.design.figures import FIGURES, figure_base, figure_table, figures, maximised
from sielaff.design.kinds import fields_of, is_four_bar, kind_name
from sielaff.engine.analysis import model_for
from sielaff.engine.scene import Scene, scene_of
from sielaff.mechanism import FIELD_NAMES

__all__ = ["BLOCK", "BLOCK_MEMORY", "BYTES_PER_POSITION", "MAX_ANGLES", "NO_WORKER_SECONDS",
           "SENSES", "SWEEPABLE", "ClusterLost", "Grid",
           "block", "column_units", "iter_blocks", "pareto_pair", "sweep_frame", "sweepable"]

#: Designs per block: with 360 angles, about 90,000 positions (some 40 MB of arrays).
BLOCK = 256
#: The memory one block's figures may take [bytes].
BLOCK_MEMORY = 1 << 30
#: The most one position of one design costs the figures [bytes]: 218 measured with the
#: 1966 scene, 699 with every effect at its limit (8 springs, 8 dampers, 5 loads, pin
#: friction, gravity, TEX, TH2DD); tests/test_size_bounds.py measures it again.
BYTES_PER_POSITION = 1024
#: The most crank angles a sweep, a tolerance study or a synthesis ranking takes: a block
#: of BLOCK designs within BLOCK_MEMORY (4096).
MAX_ANGLES = BLOCK_MEMORY // (BLOCK * BYTES_PER_POSITION)
SWEEPABLE = tuple(FIELD_NAMES) + ("TEX", "BALANCE", "CW_R2", "CW_R4")
#: Swept names that are not mechanism fields.
_OTHER = ("TEX", "BALANCE", "CW_R2", "CW_R4")


def sweepable(mechanism: Any) -> tuple[str, ...]:
    """The names a sweep of ``mechanism`` [any kind, its unit system] can vary:
    :data:`SWEEPABLE` for a four-bar, the kind's own fields for any other."""
    return SWEEPABLE if is_four_bar(mechanism) else fields_of(mechanism)


class Grid:
    """A Cartesian grid of designs around ``base`` (any kind): ``axes`` maps swept names
    to values [each name's unit]."""

    def __init__(self, base: Any, axes: dict[str, Any]) -> None:
        names = sweepable(base)
        for name in axes:
            if name not in names:
                if not is_four_bar(base):
                    raise ValueError(f"{name}: not a field a sweep of a {kind_name(base)} "
                                     f"can vary (fields: {' '.join(names)})")
                raise ValueError(f"{name}: not a field a sweep can vary "
                                 f"(fields: {' '.join(SWEEPABLE)})")
        self.base = base
        self.names = list(axes)
        self.values = [np.asarray(v, dtype=float).ravel() for v in axes.values()]
        self.shape = tuple(len(v) for v in self.values)
        self.size = math.prod(self.shape)

    def designs(self, start: int, stop: int) -> dict[str, np.ndarray]:
        """The swept values of designs start..stop-1 (C order)."""
        idx = np.unravel_index(np.arange(start, stop), self.shape)
        return {name: vals[i] for name, vals, i in zip(self.names, self.values, idx)}


def block(grid: Grid, start: int, stop: int, n: int, cf: float, scene: Scene
          ) -> dict[str, np.ndarray]:
    """Grid values and figures of designs start..stop-1."""
    values = grid.designs(start, stop)
    four_bar = is_four_bar(grid.base)
    fields = {k: v for k, v in values.items() if not (four_bar and k in _OTHER)}
    m = grid.base.replace(**{k: np.broadcast_to(np.asarray(getattr(grid.base, k), float),
                                                (stop - start,)).copy()
                             for k in (FIELD_NAMES if four_bar else fields_of(grid.base))}
                          ).replace(**fields)
    if "BALANCE" in values:
        on = values["BALANCE"] != 0.0
        if on.any():
            part = m.replace(**{k: v[on] for k, v in m.as_dict().items()})
            radii = {name: values[key][on] for key, name in (("CW_R2", "radius2"),
                                                             ("CW_R4", "radius4"))
                     if key in values}
            b = balance(part, **radii)
            merged = {}
            for k in FIELD_NAMES:
                v = np.array(getattr(m, k), dtype=float)
                v[on] = getattr(b, k)
                merged[k] = v
            m = m.replace(**merged)
    if "TEX" in values:
        scene = scene.replace(tex=values["TEX"][:, None])  # one TEX per design
    out = {"DESIGN": np.arange(start, stop, dtype=float)}
    out.update(values)
    out.update(figures(m, n=n, cf=cf, scene=scene))
    return out


#: The senses a Pareto figure can take.
SENSES = ("min", "max")


def pareto_pair(items: Any, table: Any = None) -> tuple[tuple[str, str], tuple[str, str]]:
    """Two Pareto figures, each ``"FIGURE"`` or ``"FIGURE:min"`` / ``"FIGURE:max"``, as
    ((figure, sense), (figure, sense)).  A bare figure takes its usual sense: maximised
    if :func:`~sielaff.design.figures.maximised` (GAMMA_MIN, a six-bar's GAMMAB_MIN),
    else minimised.  ``table``: the figures of the sweep's kind
    (:func:`~sielaff.design.figures.figure_table`; the four-bar's by default).  A
    ValueError says what is wrong in one line."""
    table = FIGURES if table is None else table
    names = " ".join(f for f in table if f != "KIND")
    if isinstance(items, str):
        items = [p.strip() for p in items.split(",")]
    if not (isinstance(items, list | tuple) and len(items) == 2
            and all(isinstance(p, str) for p in items)):
        raise ValueError(f"pareto = {items!r}: two figures, each FIGURE or FIGURE:min or "
                         f"FIGURE:max, FIGURE one of {names}")
    out = []
    for item in items:
        name, _, sense = item.partition(":")
        if name not in table or name == "KIND":
            raise ValueError(f"pareto: {name!r} is not a figure (one of {names})")
        sense = sense or ("max" if maximised(name) else "min")
        if sense not in SENSES:
            raise ValueError(f"pareto: {item!r}: the sense is min or max, not {sense!r}")
        out.append((name, sense))
    return out[0], out[1]


def columns(grid: Grid) -> list[str]:
    """DESIGN, the swept names, then the figures of the grid's kind."""
    return ["DESIGN"] + grid.names + list(figure_table(grid.base))


def _blocks(size: int, size_of_block: int) -> list[tuple[int, int]]:
    return [(i, min(i + size_of_block, size)) for i in range(0, size, size_of_block)]


#: With a dask.distributed client: seconds the cluster may have no worker (or the client
#: no scheduler) before the sweep stops with :class:`ClusterLost`.
NO_WORKER_SECONDS = 20.0


class ClusterLost(RuntimeError):
    """The dask.distributed cluster lost its scheduler or its last worker mid-sweep."""


def _gather(client: Any, arr: Any, poll: float = 0.5) -> np.ndarray:
    """``arr`` computed on ``client``'s cluster, watched: a cluster with no worker, or a
    client that lost its scheduler, for :data:`NO_WORKER_SECONDS` raises ClusterLost
    (the scheduler itself would wait for a worker for ever)."""
    import time

    future = client.compute(arr)
    since = None
    while True:
        try:
            return future.result(timeout=poll)
        except TimeoutError:
            pass
        try:
            alive = client.status == "running" and bool(client.scheduler_info()["workers"])
        except Exception:  # noqa: BLE001 (no answer is no worker)
            alive = False
        if alive:
            since = None
            continue
        since = time.monotonic() if since is None else since
        if time.monotonic() - since > NO_WORKER_SECONDS:
            future.cancel()
            what = ("the cluster has had no worker" if client.status == "running"
                    else "the scheduler has not answered")
            raise ClusterLost(f"{what} for {NO_WORKER_SECONDS:g} s")


def iter_blocks(grid: Grid, n: int = 360, cf: float = 0.05, scene: Scene | None = None,
                backend: str = "process", client: Any = None, size_of_block: int = BLOCK,
                batch: int = 64, workers: int | None = None) -> Iterator[np.ndarray]:
    """Yield 2-D arrays (designs x :func:`columns`) in design order.

    ``backend``: ``"process"`` (this process, one block after another) or ``"dask"``
    (``client``: a dask.distributed Client, or None for dask's local threads, ``workers``
    of them: default one per core).  Dask runs
    ``batch`` blocks at a time, so results stream out at flat memory.
    """
    if scene is None:
        scene = Scene() if is_four_bar(grid.base) else scene_of(model_for(grid.base))()
    cols = columns(grid)
    spans = _blocks(grid.size, size_of_block)

    def run(start: int, stop: int) -> np.ndarray:
        r = block(grid, start, stop, n, cf, scene)
        return np.stack([r[c] for c in cols], axis=1)

    if backend == "process":
        for start, stop in spans:
            yield run(start, stop)
        return
    if backend != "dask":
        raise ValueError(f"backend = {backend!r}: 'process' or 'dask'")
    import dask
    import dask.array as da

    for b0 in range(0, len(spans), batch):
        part = spans[b0:b0 + batch]
        tasks = [da.from_delayed(dask.delayed(run)(s, e), shape=(e - s, len(cols)),
                                 dtype=float) for s, e in part]
        arr = da.concatenate(tasks, axis=0)
        if client is not None:
            yield _gather(client, arr)
        else:
            yield arr.compute(scheduler="threads", num_workers=workers)


def column_units(names: list[str], system: str) -> dict[str, str]:
    """The unit of each column of a sweep of any kind (``"-"`` for DESIGN, BALANCE and
    KIND): a field's own, a figure's output's."""
    from sielaff.quantities import unit

    out = {}
    for n in names:
        if n in ("DESIGN", "BALANCE", "KIND"):
            out[n] = "-"
            continue
        if n in FIGURES:
            base = FIGURES[n][0]
        else:
            base = {"CW_R2": "R2", "CW_R4": "R4"}.get(n, n)
            try:
                unit(base, system)
            except KeyError:  # another kind's figure: its output's unit
                base = figure_base(n) or n
        out[n] = unit(base, system) if base else "-"
    return out


def sweep_frame(grid: Grid, n: int = 360, cf: float = 0.05, scene: Scene | None = None,
                **kwargs: Any) -> Any:
    """The whole sweep as a pandas DataFrame (the ``frames`` extra): one row per design,
    indexed by DESIGN, KIND by name (a categorical of classify.KINDS) as the CSV writes
    it, the units in ``frame.attrs["units"]`` (``iter_blocks``' keywords choose the
    backend)."""
    import pandas as pd

    cols = columns(grid)
    data = np.concatenate(list(iter_blocks(grid, n, cf, scene, **kwargs)), axis=0)
    frame = pd.DataFrame(data, columns=cols).set_index("DESIGN")
    frame.index = frame.index.astype(int)
    if "KIND" in frame:  # by name, as the CSV writes it (the array holds KINDS' index)
        from sielaff.engine.classify import KINDS

        frame["KIND"] = pd.Categorical([KINDS[int(k)] for k in frame["KIND"]],
                                       categories=list(KINDS))
    if "BALANCE" in frame:
        frame["BALANCE"] = frame["BALANCE"].astype(int)
    frame.attrs["units"] = column_units(cols, grid.base.units)
    return frame
