"""``analyze``: one path in (check and seed the request), then the numpy steps a block at a
time or all at once, or the compiled loop; every path counts the positions that cannot
assemble the same way."""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.engine.fourbar import FOURBAR
from sielaff.engine.inverted_slider_crank import INVERTED_SLIDER_CRANK
from sielaff.engine.registry import Model, Step, warn
from sielaff.engine.scene import Scene, SceneBase, scene_from
from sielaff.engine.sixbar import STEPHENSON, WATT, linkage_for
from sielaff.engine.slider_crank import SLIDER_CRANK
from sielaff.mechanism import EXAMPLE, Mechanism, validate

__all__ = ["MODELS", "AssemblyWarning", "Results", "analyze", "model_for", "model_named", "plan",
           "prepare"]

#: A keyword argument not given (``None`` means no gravity, so it cannot mark absence).
_UNSET: Any = type("Unset", (), {"__repr__": lambda self: "<unset>"})()


class AssemblyWarning(UserWarning):
    """Some positions of an ``analyze`` call cannot assemble: their results are NaN."""


def _warn_not_assembled(count: int, total: int, stacklevel: int, mask: bool = True) -> None:
    """The AssemblyWarning: how many of ``total`` positions cannot assemble."""
    warnings.warn(f"{count} of {total} positions cannot assemble (the loop does not close "
                  "there): their results are NaN"
                  + ("; ask for the ASSEMBLED output for the mask" if mask else ""),
                  AssemblyWarning, stacklevel=stacklevel)


class Results(dict):
    """``analyze``'s answer: ``{name: array}``, and how many positions could not assemble.

    ``not_assembled`` counts the positions (elements of the broadcast shape) where the
    loop cannot close, whose results are NaN; it is None when no position was solved
    (inputs only).  Ask for the ``ASSEMBLED`` output for the mask itself.
    """

    not_assembled: int | None = None
    #: The unit system of the numbers (the mechanism's) and the crank angles asked for.
    units: str = "in-lb-sec"
    ath2: Any = None

    def to_frame(self) -> Any:
        """The results as a pandas DataFrame (the ``frames`` extra): THETA 2 [deg] as the
        index, one column per name, each column's unit in ``frame.attrs["units"]`` (and
        its meaning in ``frame.attrs["descriptions"]``).  One-dimensional results only
        (one design over crank angles); a sweep's arrays are a ValueError."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Results.to_frame needs pandas: pip install -e "
                              "\".[frames]\"") from None
        from sielaff.quantities import describe, unit

        columns = {name: np.asarray(v) for name, v in self.items()}
        th = np.atleast_1d(np.asarray(self.ath2, dtype=float))
        for name, v in columns.items():
            if v.ndim != 1 or v.shape != th.shape:
                raise ValueError(f"to_frame: {name} has shape {v.shape}; a frame holds one "
                                 f"design over the crank angles, shape {th.shape}")
        frame = pd.DataFrame(columns, index=pd.Index(th, name="ATH2"))
        frame.attrs["units"] = {n: _unit_or_dash(unit, n, self.units) for n in columns}
        frame.attrs["units"]["ATH2"] = "deg"
        frame.attrs["descriptions"] = {n: _unit_or_dash(describe, n) for n in columns}
        return frame


def _unit_or_dash(fn: Any, *args: Any) -> str:
    try:
        return str(fn(*args))
    except KeyError:  # a name the catalogue does not describe (an effect's own part)
        return "-"


def _common_shape(named: list[tuple[str, tuple[int, ...]]]) -> tuple[int, ...]:
    """The broadcast shape of ``named`` inputs; a ValueError naming the two that clash."""
    try:
        return np.broadcast_shapes(*(shape for _, shape in named))
    except ValueError:
        pass
    so_far: tuple[int, ...] = ()
    names: list[str] = []
    for name, shape in named:
        try:
            so_far = np.broadcast_shapes(so_far, shape)
        except ValueError:
            clash = [n for n, s in named[:len(names)] if not _broadcastable(s, shape)]
            raise ValueError(
                f"cannot broadcast {name} (shape {shape}) with {', '.join(clash)} "
                f"(shape {dict(named)[clash[0]]}): give the fields a sweep varies shapes "
                "that broadcast, e.g. R4 of shape (n, 1) against ath2 of shape (m,)"
            ) from None
        names.append(name)
    return so_far


def _broadcastable(a: tuple[int, ...], b: tuple[int, ...]) -> bool:
    try:
        np.broadcast_shapes(a, b)
    except ValueError:
        return False
    return True


def _check_outputs(outputs: Iterable[str] | str | None, model: Model) -> tuple[str, ...]:
    if outputs is None:
        return model.results
    if isinstance(outputs, str):
        outputs = (outputs,)
    wanted = tuple(dict.fromkeys(outputs))
    unknown = [n for n in wanted if n not in model.outputs]
    if unknown:
        raise ValueError(f"unknown output(s) {unknown}; valid names: "
                         f"{', '.join(model.outputs)}")
    return wanted


@dataclass
class Request:
    """A checked request, what every backend consumes: the model, the mechanism (checked),
    the crank angles as given, the Scene (checked when built), the wanted names, and the
    shape of the answer (``shape``: of every result, ``None`` until known)."""

    model: Model
    mechanism: Mechanism
    ath2: Any
    scene: Scene
    wanted: tuple[str, ...]
    shape: tuple[int, ...] | None = None


#: The models ``analyze`` knows, each for its type of mechanism (the first that fits).
MODELS: list[Model] = [FOURBAR, SLIDER_CRANK, INVERTED_SLIDER_CRANK, WATT, STEPHENSON]


def model_named(name: str) -> Model:
    """The registered model called ``name`` (a spec's ``[linkage] kind``)."""
    for model in MODELS:
        if model.name == name:
            return model
    raise KeyError(f"no model {name!r} (models: {', '.join(m.name for m in MODELS)})")


def model_for(mechanism: Any) -> Model:
    """The model of ``mechanism``: the registered one whose mechanism type it is (the
    four-bar's for a :class:`~sielaff.mechanism.Mechanism`; a :class:`~sielaff.Linkage`'s
    made from its topology)."""
    from sielaff.linkage import Linkage

    if isinstance(mechanism, Linkage):
        return linkage_for(mechanism.topology)
    for model in MODELS:
        if model.mechanism is not None and isinstance(mechanism, model.mechanism):
            return model
    raise ValueError(f"no model analyses a {type(mechanism).__name__}: give a sielaff "
                     "Mechanism, SliderCrank, InvertedSliderCrank, WattII, StephensonIII or "
                     "Linkage (or model=)")


def prepare(mechanism: Mechanism, ath2: Any, outputs: Iterable[str] | str | None,
            scene: Scene, model: Model | None = None, *, broadcast: bool = True) -> Request:
    """The one validation of ``analyze``'s inputs, shared by every backend.

    The mechanism by its model's ``validate`` (:func:`~sielaff.mechanism.validate` for
    the four-bar), the outputs against the model,
    the Scene (validated when it was built), and, with ``broadcast``, that the crank
    angles, the fields and the scene's arrays broadcast together (a ValueError naming
    the two that clash).
    """
    model = model_for(mechanism) if model is None else model
    if not isinstance(model, Model):
        raise ValueError(f"model = {model!r} is not a sielaff Model")
    if not isinstance(scene, SceneBase):
        raise ValueError(f"scene = {scene!r} is not a sielaff.Scene")
    missing = [p.name for p in model.params if not hasattr(scene, p.name)]
    if missing:  # another model's scene
        raise ValueError(f"scene has no field {missing[0]}, which model {model.name} "
                         "takes: make it with engine.scene.scene_type(model)")
    if model.mechanism is not None and not isinstance(mechanism, model.mechanism):
        raise ValueError(f"model {model.name} analyses a {model.mechanism.__name__}, not a "
                         f"{type(mechanism).__name__}")
    wanted = _check_outputs(outputs, model)
    (model.validate or validate)(mechanism)
    req = Request(model, mechanism, ath2, scene, wanted)
    if broadcast:
        named = [("ath2", np.shape(ath2))]
        named += [(n, np.shape(v)) for n, v in mechanism.as_dict().items()]
        named += [(n, np.shape(v)) for n, v in scene.per_position()]
        req.shape = _common_shape(named)
    return req


def _scene(scene: Scene | None, mechanism: Any, model: Model | None,
           **keywords: Any) -> Scene:
    """The call's Scene: ``scene``, or the keywords in the model's own Scene type."""
    if model is None:
        model = model_for(EXAMPLE if mechanism is None else mechanism)
    return scene_from(scene, {k: v for k, v in keywords.items() if v is not _UNSET},
                      model=model)


def plan(outputs: Iterable[str] | str | None = None, mechanism: Mechanism | None = None,
         tex: Any = _UNSET, *, scene: Scene | None = None, th2dd: Any = _UNSET,
         gravity: Any = _UNSET, loads: Any = _UNSET, branch: Any = _UNSET,
         model: Model | None = None) -> list[str]:
    """Names of the steps ``analyze`` would run (skipped zero steps marked ``name=0``)."""
    sc = _scene(scene, mechanism, model, tex=tex, th2dd=th2dd, gravity=gravity, loads=loads,
                branch=branch)
    req = prepare(EXAMPLE if mechanism is None else mechanism, 0.0, outputs, sc, model,
                  broadcast=False)
    ns = req.model.seed(req.mechanism, 0.0, sc)
    order = req.model.plan(req.wanted, frozenset(ns), req.model.zero_seeds(ns))
    return [st.name + ("=0" if skipped else "") for st, skipped, _ in order]


def analyze(mechanism: Mechanism, ath2: Any, outputs: Iterable[str] | str | None = None,
            tex: Any = _UNSET, *, scene: Scene | None = None, th2dd: Any = _UNSET,
            gravity: Any = _UNSET, loads: Any = _UNSET, branch: Any = _UNSET,
            out: dict[str, np.ndarray] | None = None, block: int | None = None,
            backend: str = "numpy", model: Model | None = None) -> Results:
    """Analyse ``mechanism`` at crank angles ``ath2`` [deg] in the scene ``scene``.

    Parameters
    ----------
    mechanism : Mechanism
        Geometry, masses and crank speed; any field may be an array (a sweep).
    ath2 : float or array
        Crank angles [deg], any shape, any value (400 and 40 are the same position).
    outputs : names, optional
        Names wanted (any of ``OUTPUTS``); None means ``RESULTS``.  Only the steps these
        depend on are run.
    scene : Scene, optional
        What acts on the mechanism (:class:`sielaff.Scene`: TEX, the crank's
        acceleration, gravity, loads, the branch); the 1966 scene by default.
    tex, th2dd, gravity, loads, branch
        The Scene's fields as keywords (the same Scene, bit for bit); giving one of
        them and ``scene`` is a ValueError naming both.
    out : dict of arrays, optional
        Arrays to write the results into, ``{name: array}`` (float64, the shape of
        ``ath2``; the names are the outputs, ``outputs`` is then ignored).  The
        positions are then analysed :data:`BLOCK` (or ``block``) at a time, small enough
        for the cache, and no result array is allocated.  With ``out`` the mechanism
        describes one design (scalar fields); the scene's arrays (TEX, TH2DD, a load's
        fields) are of ``ath2``'s shape and sliced per block alike.
    backend : {"numpy", "numba"}
        ``"numba"`` runs the compiled loop (``sielaff[fast]``) where it covers the scene.
    model : Model, optional
        The model to run (``fourbar.FOURBAR`` by default).

    Returns
    -------
    Results
        ``{name: array}`` for the wanted names, every array of the broadcast shape of
        ``ath2``, the mechanism's fields and the scene's arrays; ``not_assembled`` counts
        the positions where the loop cannot close (their results are NaN; an
        :class:`AssemblyWarning` says how many).  TORQ is the total drive torque;
        ``TORQ_INERTIA``, ``TORQ_GRAVITY``, ``TORQ_LOADS``, ``TORQ_TEX``,
        ``TORQ_ELEMENTS`` and ``TORQ_FRICTION`` are its parts (docs/effects.md).

    Shapes that do not broadcast are a ValueError naming the fields, and so is a
    mechanism no linkage can have (:func:`sielaff.mechanism.validate`) or a scene value
    that is not finite (:class:`sielaff.Scene`).
    """
    sc = _scene(scene, mechanism, model, tex=tex, th2dd=th2dd, gravity=gravity, loads=loads,
                branch=branch)
    if backend not in ("numpy", "numba"):
        raise ValueError(f"backend = {backend!r}: 'numpy' or 'numba'")
    if out is not None:
        if backend != "numpy":
            return _analyze_compiled(prepare(mechanism, ath2, list(out), sc, model), out)
        return _analyze_into(mechanism, ath2, out, BLOCK if block is None else block, sc,
                             model)
    req = prepare(mechanism, ath2, outputs, sc, model)
    if backend != "numpy":
        return _analyze_compiled(req, None)
    return _analyze_numpy(req)


def _analyze_numpy(req: Request) -> Results:
    model, final_shape = req.model, req.shape
    assert final_shape is not None
    ns = model.seed(req.mechanism, req.ath2, req.scene)
    seeded = frozenset(ns)
    shape = np.broadcast_shapes(ns["ATH2"].shape, final_shape)  # differs only if final is ()
    # Crank angles of the full shape make every derived array full-shaped, so the
    # steps may update arrays in place with mechanism fields of any shape.
    ns["ATH2"] = np.broadcast_to(ns["ATH2"], shape)
    order = model.plan(req.wanted, seeded, model.zero_seeds(ns))
    with np.errstate(all="ignore"):  # NaN where the loop cannot close, inf at a toggle
        not_assembled = model.run(order, ns)
    out = Results()
    out.units, out.ath2 = req.mechanism.units, req.ath2
    if not_assembled is not None:
        out.not_assembled = not_assembled
        if not_assembled:
            _warn_not_assembled(not_assembled, int(np.prod(shape)), stacklevel=4)
    seen: set[int] = set()
    mask = ns.get("_not_assembled")
    for name in req.wanted:
        v = ns[name]
        if (name in seeded or id(v) in seen or not isinstance(v, np.ndarray)
                or v.shape != shape):
            v = np.array(np.broadcast_to(v, shape), dtype=float)
        if (mask is not None and v.dtype != bool and name not in seeded
                and model.needs_assembly(name)):
            np.copyto(v, np.nan, where=mask)  # a skipped step's 0.0 is no answer there
        seen.add(id(v))
        out[name] = v.reshape(final_shape)
    return out


#: Positions per block of ``analyze(..., out=...)``: long enough to spread the call's
#: fixed cost (about 0.5 ms: the plan, checks, seeding), short enough that the work
#: arrays come from the allocator's free lists, not fresh pages (docs/performance.md).
BLOCK = 16384


def _check_out(out: dict[str, np.ndarray], shape: tuple[int, ...]) -> None:
    for name, array in out.items():
        if not (isinstance(array, np.ndarray) and array.dtype == np.float64
                and array.shape == shape and array.flags.writeable):
            raise ValueError(f"out[{name!r}]: a writeable float64 array of ath2's shape "
                             f"{shape}")
        if not np.shares_memory(array.reshape(-1), array):  # a copy would not be written
            raise ValueError(f"out[{name!r}] must be contiguous (it is written in place)")


def _analyze_into(mechanism: Mechanism, ath2: Any, out: dict[str, np.ndarray], block: Any,
                  scene: Scene, model: Model | None) -> Results:
    """``analyze(..., out=out)``: blocks of ``block`` positions written into ``out``."""
    if isinstance(block, bool) or not isinstance(block, int) or block < 1:
        raise ValueError(f"block = {block!r}: a number of positions, 1 or more")
    th = np.asarray(ath2, dtype=float)
    req = prepare(mechanism, th, list(out), scene, model, broadcast=False)
    _check_out(out, th.shape)
    for name, v in mechanism.as_dict().items():
        if np.ndim(v):
            raise ValueError(f"out= analyses one design: {name} is an array (shape "
                             f"{np.shape(v)})")
    flat_th = th.reshape(-1)
    n = flat_th.size
    varying = scene.per_position()
    scene.block(0, 0, th.shape)  # every per-position array of ath2's shape, or refused
    flat = {name: out[name].reshape(-1) for name in req.wanted}
    # One design: seeded and planned once when nothing varies along the angles; each block
    # then brings only its angles, so a block costs its arithmetic alone.
    m = req.model
    base = m.seed(mechanism, flat_th[:1], scene)
    seeded = frozenset(base)
    order = None if varying else m.plan(req.wanted, seeded, m.zero_seeds(base))
    missing: int | None = 0
    for i in range(0, n, block):
        j = min(i + block, n)
        if varying:
            ns = m.seed(mechanism, flat_th[i:j], scene.block(i, j, th.shape))
        else:
            ns = dict(base)
            ns["ATH2"] = flat_th[i:j]
        plan_ = order or m.plan(req.wanted, seeded, m.zero_seeds(ns))
        with np.errstate(all="ignore"):
            count = m.run(plan_, ns)
        missing = None if count is None else (missing or 0) + count
        mask = ns.get("_not_assembled")
        for name in req.wanted:
            flat[name][i:j] = ns[name]
            if (mask is not None and name not in seeded and m.needs_assembly(name)
                    and flat[name].dtype != bool):
                np.copyto(flat[name][i:j], np.nan, where=mask)
    result = Results((name, out[name]) for name in req.wanted)
    result.not_assembled = missing
    result.units, result.ath2 = mechanism.units, th
    if missing:
        _warn_not_assembled(missing, n, stacklevel=4)
    return result


def _warning_steps(req: Request) -> list[Step]:
    """The steps the plan of ``req`` runs that issue warnings (``Step.warns``): the
    compiled backend writes the outputs they warn from, then calls them."""
    model = req.model
    if not any(st.warns for e in model.effects_on(req.scene) for st in e.steps) and \
            not any(st.warns for st in model.steps):
        return []
    th = np.asarray(req.ath2, dtype=float)
    shape = th.shape if req.shape is None else req.shape
    ns = model.seed(req.mechanism, np.broadcast_to(th, shape).reshape(-1), req.scene)
    order = model.plan(req.wanted, frozenset(ns), model.zero_seeds(ns))
    return [st for st, skipped, _ in order if not skipped and st.warns is not None]


def _analyze_compiled(req: Request, out: dict[str, np.ndarray] | None) -> Results:
    """``analyze(..., backend="numba")``: the kernel compiled from the model's own plan for
    the wanted names, writing straight into ``out``'s arrays (or fresh ones); see
    engine/compiled.py."""
    from sielaff.engine.compiled import run

    if out is not None:
        _check_out(out, np.shape(req.ath2))
    warned = _warning_steps(req)
    extra = tuple(dict.fromkeys(n for st in warned for n in st.warns[0]  # type: ignore[index]
                                if n not in req.wanted))
    got, bad, shape = run(dataclasses.replace(req, wanted=req.wanted + extra) if extra
                          else req, out)
    for st in warned:  # the steps' warnings, from the outputs the kernel wrote
        warn(st, got)
    result = Results()
    result.units, result.ath2 = req.mechanism.units, req.ath2
    for name in req.wanted:
        result[name] = out[name] if out is not None else got[name].reshape(shape)
    result.not_assembled = bad
    if bad:  # no ASSEMBLED output from this backend to point to
        _warn_not_assembled(bad, math.prod(shape), stacklevel=4, mask=False)
    return result
