"""Manufacturing tolerances carried through to the forces: a seeded Monte Carlo.

In:  a mechanism (one design), the deviations of its fields (``{field: size}``: lengths
     and distances [length unit], angles ADEL [deg], weights or masses W [lb or kg],
     inertias ZI, the speed TH2D), the scene, ``n`` samples, a seed and a distribution.
Out: a :class:`Tolerance`: for each design figure (:data:`~sielaff.design.figures.FIGURES`)
     the nominal, the sampled mean, standard deviation and 5th/95th percentiles, the
     first-order sensitivities d figure / d field and the spread they predict.

Sampling.  ``distribution="normal"``: each field is nominal + size x z, z standard normal
(``size`` is the standard deviation); ``"uniform"``: nominal + size x u, u uniform on
[-1, 1] (``size`` is the half-width, the standard deviation size / sqrt 3).  Fields are
independent.  Sample j lives in block j // BLOCK; block b draws its numbers from its own
``numpy.random.Generator`` seeded with ``SeedSequence(seed, spawn_key=(b,))`` (what
``SeedSequence(seed).spawn`` gives), the fields in the order of ``FIELD_NAMES`` (another
kind's: its own fields' order).  A block's numbers therefore depend only on the seed and
the block, never on where or in what order the blocks run: in this process, on dask
threads or on a dask.distributed cluster the samples and the figures are the same, bit
for bit.

Any kind of linkage may be toleranced over its own fields (a slider-crank's offset, a
six-bar's X6): its figures are :func:`sielaff.design.figures.figure_table`'s, its lengths
those of its topology (and the kind's other positive fields), its crank's full turn its
model's ``full_turn`` (:mod:`sielaff.design.kinds`), its scene of its own Scene type.

A sample whose lengths are not all positive, or whose weights or inertias are negative,
is not a linkage and is counted in ``invalid`` (its figures NaN); a sample whose crank
cannot turn fully has NaN figures (design.figures) and is counted in ``not_turning``.
Statistics are over the finite samples.  The mean and standard deviation are taken of
the differences from the nominal, so with zero deviations every sample is the nominal and
mean, percentiles and nominal agree exactly (std 0).

Sensitivities: central differences, d F / d x_i ~ (F(x + h_i) - F(x - h_i)) / (2 h_i),
h_i = :data:`STEP` x size_i (the deviation sets the scale, so a length and an angle are
stepped alike).  The first-order spread is ``predicted_std = sqrt(sum_i (dF/dx_i
sigma_i)^2)``, sigma_i the field's standard deviation; for small deviations the sampled
std agrees with it within sampling error (tests/test_tolerance.py states the bound).  A
peak figure (a max over the cycle's grid) is not smooth where its argmax jumps: there
the two disagree, which the table shows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.design.figures import FIGURES, figure_table, figures
from sielaff.design.kinds import (
    fields_of,
    is_four_bar,
    kind_name,
    nonnegative_fields,
    positive_fields,
)
from sielaff.design.sweep import BLOCK
from sielaff.engine.analysis import model_for
from sielaff.engine.scene import Scene, scene_of
from sielaff.mechanism import FIELD_NAMES, LENGTHS, NONNEGATIVE, Mechanism

__all__ = ["DISTRIBUTIONS", "STEP", "TOLERANCED", "Tolerance", "tolerance", "toleranced"]

DISTRIBUTIONS = ("normal", "uniform")
#: Central-difference step as a fraction of each field's deviation.
STEP = 1e-3
#: The figures a tolerance study reports (KIND is a label).
TOLERANCED = tuple(f for f in FIGURES if f != "KIND")
#: Samples a study may ask for.
MAX_SAMPLES = 10_000_000


def toleranced(mechanism: Any) -> tuple[str, ...]:
    """The figures a tolerance study of ``mechanism`` [any kind, its unit system] reports:
    :data:`TOLERANCED` for a four-bar, its kind's figures for another (``figure_table``;
    none of them a label)."""
    if is_four_bar(mechanism):
        return TOLERANCED
    return tuple(f for f in figure_table(mechanism) if f != "KIND")


def _rules(base: Any) -> tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
    """(fields, those that must be > 0, those that must be >= 0) of ``base``'s kind."""
    if is_four_bar(base):
        return FIELD_NAMES, LENGTHS, NONNEGATIVE
    return fields_of(base), positive_fields(base), nonnegative_fields(base)


@dataclass(frozen=True)
class Tolerance:
    """A tolerance study (module doc).  Per figure (dicts keyed by :data:`TOLERANCED`,
    values in the figure's unit): ``nominal``, ``mean``, ``std``, ``p5``, ``p95``,
    ``predicted_std``; ``sensitivity[figure][field]`` [figure unit per field unit].
    ``deviations`` [field units], ``sigma`` (each field's standard deviation), ``n``,
    ``seed``, ``distribution``, ``valid`` (finite samples per figure), ``invalid`` and
    ``not_turning`` (sample counts), ``units``."""

    nominal: dict[str, float]
    mean: dict[str, float]
    std: dict[str, float]
    p5: dict[str, float]
    p95: dict[str, float]
    predicted_std: dict[str, float]
    sensitivity: dict[str, dict[str, float]]
    deviations: dict[str, float]
    sigma: dict[str, float]
    n: int
    seed: int
    distribution: str
    valid: dict[str, int]
    invalid: int
    not_turning: int
    units: str
    samples: np.ndarray | None = None

    def to_frame(self) -> Any:
        """The study as a pandas DataFrame (the ``frames`` extra): one row per figure,
        columns nominal, mean, std, p5, p95, predicted_std; each row's unit in
        ``frame.attrs["units"]``."""
        import pandas as pd

        from sielaff.design.sweep import column_units

        cols = ("nominal", "mean", "std", "p5", "p95", "predicted_std")
        names = list(self.nominal)
        frame = pd.DataFrame({c: [getattr(self, c)[f] for f in names] for c in cols},
                             index=pd.Index(names, name="FIGURE"))
        frame.attrs["units"] = column_units(names, self.units)
        return frame


def _draw(seed: int, b: int, k: int, m: int, distribution: str) -> np.ndarray:
    """Block ``b``'s (k, m) standardised draws."""
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(b,)))
    if distribution == "normal":
        return rng.standard_normal((k, m))
    return rng.uniform(-1.0, 1.0, (k, m))


def _figures_of(base: Any, fields: dict[str, np.ndarray], scene: Scene, angles: int,
                cf: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(figures (k, F), invalid (k,), not turning (k,)) of the designs ``fields``."""
    k = len(next(iter(fields.values())))
    names, positive, nonnegative = _rules(base)
    wanted = toleranced(base)
    full = {name: np.full(k, float(getattr(base, name))) for name in names}
    full.update(fields)
    bad = np.zeros(k, dtype=bool)
    for name in positive:
        bad |= ~(full[name] > 0.0)
    for name in nonnegative:
        bad |= ~(full[name] >= 0.0)
    out = np.full((k, len(wanted)), np.nan)
    turning = np.zeros(k, dtype=bool)
    ok = ~bad
    if ok.any():
        designs = {n: v[ok] for n, v in full.items()}
        m = Mechanism(**designs, units=base.units) if is_four_bar(base) \
            else base.replace(**designs)
        r = figures(m, n=angles, cf=cf, scene=scene)
        out[ok] = np.stack([r[f] for f in wanted], axis=1)
        turning[ok] = np.isfinite(r["TORQ_PEAK"])
    return out, bad, ok & ~turning


def _block(base: Any, names: list[str], size: np.ndarray, seed: int, b: int,
           start: int, stop: int, distribution: str, scene: Scene, angles: int,
           cf: float) -> np.ndarray:
    """Figures, invalid and not-turning flags of samples start..stop-1 (block b)."""
    z = _draw(seed, b, stop - start, len(names), distribution)
    fields = {name: float(getattr(base, name)) + size[j] * z[:, j]
              for j, name in enumerate(names)}
    f, bad, stuck = _figures_of(base, fields, scene, angles, cf)
    return np.concatenate([f, bad[:, None], stuck[:, None]], axis=1)


def tolerance(mechanism: Any, deviations: dict[str, float], n: int = 1000, *,
              scene: Scene | None = None, seed: int = 0, distribution: str = "normal",
              angles: int = 360, cf: float = 0.05, backend: str = "process",
              client: Any = None, workers: int | None = None, size_of_block: int = BLOCK,
              keep_samples: bool = False) -> Tolerance:
    """A Monte Carlo tolerance study of ``mechanism`` (module doc).

    Parameters
    ----------
    mechanism : Mechanism or another kind (SliderCrank, WattII, ..., Linkage)
        One design [its units].
    deviations : dict
        ``{field: size}``: the standard deviation (normal) or half-width (uniform) of
        each toleranced field [the field's unit: length, deg, lb or kg, ...].
    n : int
        Samples [-].
    scene : Scene, optional
        What acts on the mechanism, of its kind's Scene type [-] (default the 1966
        program's; for another kind its Scene's defaults).
    seed : int
        The seed [-]: the same seed gives the same samples on every path.
    distribution : {"normal", "uniform"}
    angles : int
        Crank angles per revolution [-] (even).
    cf : float
        Coefficient of speed fluctuation for FLYWHEEL_I [-].
    backend : {"process", "dask"}
        Where the blocks run; ``client`` a dask.distributed Client (else dask's local
        threads, ``workers`` of them).
    size_of_block : int
        Samples per block [-]; part of what the samples are (with the seed).
    keep_samples : bool
        Keep the (n, figures) array of sampled figures in ``samples``.
    """
    four_bar = is_four_bar(mechanism)
    kind = Scene if four_bar else scene_of(model_for(mechanism))
    sc = kind() if scene is None else scene
    if not isinstance(sc, kind):
        if four_bar:
            raise ValueError(f"tolerance: scene = {scene!r} is not a sielaff.Scene")
        raise ValueError(f"tolerance: scene = {scene!r} is not a {kind_name(mechanism)}'s "
                         "Scene (sielaff.scene_for(mechanism))")
    values = mechanism.as_tuple() if four_bar else tuple(mechanism.as_dict().values())
    if any(np.ndim(v) for v in values):
        raise ValueError("tolerance: one design at a time (the mechanism's fields are arrays)")
    if not isinstance(deviations, dict) or not deviations:
        raise ValueError("tolerance: deviations = {field: size, ...}, at least one field")
    all_fields = _rules(mechanism)[0]
    wanted = toleranced(mechanism)
    names = [f for f in all_fields if f in deviations]
    unknown = sorted(set(deviations) - set(all_fields))
    if unknown:
        raise ValueError(f"tolerance: {unknown[0]} is not a field "
                         f"(fields: {' '.join(all_fields)})")
    size = np.array([float(deviations[f]) for f in names])
    for f, s in zip(names, size):
        if not (math.isfinite(s) and s >= 0.0):
            raise ValueError(f"tolerance: deviation of {f} = {s:g}: finite and 0 or more")
    if distribution not in DISTRIBUTIONS:
        raise ValueError(f"tolerance: distribution = {distribution!r}: 'normal' or 'uniform'")
    if not (isinstance(n, int) and not isinstance(n, bool) and 2 <= n <= MAX_SAMPLES):
        raise ValueError(f"tolerance: n = {n!r}: a whole number of samples, 2 to "
                         f"{MAX_SAMPLES} (one sample has no spread)")
    if not (isinstance(seed, int) and not isinstance(seed, bool) and seed >= 0):
        raise ValueError(f"tolerance: seed = {seed!r}: a whole number, 0 or more")
    if not (isinstance(angles, int) and angles >= 8 and angles % 2 == 0):
        raise ValueError(f"tolerance: angles = {angles!r}: an even whole number, 8 or more")
    if backend not in ("process", "dask"):
        raise ValueError(f"tolerance: backend = {backend!r}: 'process' or 'dask'")
    if not (isinstance(size_of_block, int) and size_of_block >= 1):
        raise ValueError(f"tolerance: size_of_block = {size_of_block!r}: 1 or more")

    nominal_row, bad, _ = _figures_of(mechanism, {names[0]: np.array(
        [float(getattr(mechanism, names[0]))])}, sc, angles, cf)
    if bad[0]:
        raise ValueError("tolerance: the nominal mechanism is not a linkage")
    nominal = nominal_row[0]
    if not np.isfinite(nominal[wanted.index("TORQ_PEAK")]):
        raise ValueError("tolerance: the nominal crank cannot make a whole revolution")

    spans = [(b, s, min(s + size_of_block, n)) for b, s in
             enumerate(range(0, n, size_of_block))]

    def run(b: int, s: int, e: int) -> np.ndarray:
        return _block(mechanism, names, size, seed, b, s, e, distribution, sc, angles, cf)

    if backend == "process":
        parts = [run(*sp) for sp in spans]
    else:
        import dask

        tasks = [dask.delayed(run)(*sp) for sp in spans]
        if client is not None:
            parts = list(client.gather(client.compute(tasks)))
        else:
            parts = list(dask.compute(*tasks, scheduler="threads", num_workers=workers))
    table = np.concatenate(parts, axis=0)
    samples, invalid, stuck = table[:, :-2], table[:, -2] != 0, table[:, -1] != 0

    sigma = size / math.sqrt(3.0) if distribution == "uniform" else size.copy()
    # sensitivities: all 2 x fields perturbed designs in one call
    active = [j for j in range(len(names)) if size[j] > 0.0]
    sens = {f: {name: 0.0 for name in names} for f in wanted}
    if active:
        h = STEP * size[active]
        plus_minus = {name: np.full(2 * len(active), float(getattr(mechanism, name)))
                      for name in names}
        for k, j in enumerate(active):
            plus_minus[names[j]][2 * k] += h[k]
            plus_minus[names[j]][2 * k + 1] -= h[k]
        fd, _, _ = _figures_of(mechanism, plus_minus, sc, angles, cf)
        for k, j in enumerate(active):
            d = (fd[2 * k] - fd[2 * k + 1]) / (2.0 * h[k])
            for i, f in enumerate(wanted):
                sens[f][names[j]] = float(d[i])
    out: dict[str, dict[str, float]] = {k: {} for k in ("nominal", "mean", "std", "p5", "p95",
                                                         "predicted")}
    valid = {}
    for i, f in enumerate(wanted):
        col = samples[:, i]
        ok = np.isfinite(col)
        valid[f] = int(ok.sum())
        nom = float(nominal[i])
        out["nominal"][f] = nom
        if ok.any():
            d = col[ok] - nom
            out["mean"][f] = nom + float(np.mean(d))
            out["std"][f] = float(np.std(d - np.mean(d), ddof=1)) if ok.sum() > 1 else 0.0
            p5, p95 = np.percentile(col[ok], [5.0, 95.0])
            out["p5"][f], out["p95"][f] = float(p5), float(p95)
        else:
            for stat in ("mean", "std", "p5", "p95"):
                out[stat][f] = math.nan
        out["predicted"][f] = float(math.sqrt(sum((sens[f][names[j]] * sigma[j]) ** 2
                                                  for j in range(len(names)))))
    return Tolerance(out["nominal"], out["mean"], out["std"], out["p5"], out["p95"],
                     out["predicted"], sens, {f: float(s) for f, s in zip(names, size)},
                     {f: float(s) for f, s in zip(names, sigma)}, n, seed, distribution,
                     valid, int(invalid.sum()), int(stuck.sum()), mechanism.units,
                     samples if keep_samples else None)
