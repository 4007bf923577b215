"""A spec's ``[sweep]``: the axes of a design sweep, sized before any is built."""

from __future__ import annotations

from decimal import Decimal
from typing import Any

from sielaff.tools.spec_fields import PunchError, _number, _table, _unknown, key_names

__all__ = ["MAX_DESIGNS", "sweep_keys", "sweep_of"]

def sweep_keys() -> tuple:
    """The ``[sweep]`` table's keys, declared (:class:`~sielaff.tools.spec_fields.Key`)."""
    from sielaff.design.sweep import MAX_ANGLES, SWEEPABLE
    from sielaff.tools.spec_fields import Key

    return (
        Key("angles", "integer", "360", f"even, 8 to {MAX_ANGLES}",
            "crank angles per revolution"),
        Key("cf", "number", "0.05", "(0, 2)", "coefficient of speed fluctuation (flywheel)"),
        Key("pareto", "list", '["TORQ_PEAK", "SHAK_PEAK"]', "two FIGURE or FIGURE:min|max",
            "the two figures of the Pareto front"),
        Key("vary", "table", "", f"{MAX_DESIGNS:,} designs in all; names: "
            + " ".join(SWEEPABLE), "[sweep.vary]: NAME = [values] or "
            "{ from, to, n } (evenly spaced, both ends)"),
    )
#: Designs a sweep may ask for (each is one block's share of memory only while it runs).
MAX_DESIGNS = 100_000_000


def sweep_of(spec: dict, path: str = "<spec>", mechanism: Any = None) -> dict:
    """The spec's ``[sweep]``: ``{"axes": {name: values}, "angles", "cf", "pareto",
    "senses"}``::

        [sweep]
        angles = 360                  # crank angles per revolution (default 360)
        cf = 0.05                     # coefficient of speed fluctuation (flywheel)
        pareto = ["TORQ_PEAK", "SHAK_PEAK"]   # the two figures plotted, each FIGURE or
                                      # FIGURE:min|max (bare: GAMMA_MIN max, others min)
        [sweep.vary]                  # listing names (R4, W3, TH2D, ...), TEX, BALANCE,
                                      # CW_R2 and CW_R4 (counterweight radii)
        R4 = { from = 10.0, to = 14.0, n = 41 }   # evenly spaced, both ends
        W3 = [4.0, 8.0, 12.0]                     # or the values themselves
        BALANCE = [0, 1]                          # without and with counterweights

    ``mechanism``: the spec's linkage; another kind than the four-bar varies its own
    fields and ranks on its own figures (:func:`sielaff.design.sweep.sweepable`,
    :func:`sielaff.design.figures.figure_table`).
    """
    import numpy as np

    from sielaff.design.figures import figure_table
    from sielaff.design.sweep import MAX_ANGLES, SWEEPABLE, pareto_pair, sweepable

    names_ok = SWEEPABLE if mechanism is None else sweepable(mechanism)
    table_of = None if mechanism is None else figure_table(mechanism)

    table = _table(f"{path}: [sweep]", spec.get("sweep", {}))
    if not table:
        raise PunchError(f"{path}: no [sweep] table (decks/sweep.toml has one; docs/design.md)")
    _unknown(f"{path}: [sweep]", table, key_names(sweep_keys()))
    angles = table.get("angles", 360)
    if not (isinstance(angles, int) and not isinstance(angles, bool) and 8 <= angles
            <= MAX_ANGLES and angles % 2 == 0):
        raise PunchError(f"{path}: [sweep] angles = {angles!r}: an even whole number "
                         f"from 8 to {MAX_ANGLES} (a block of designs within its memory "
                         "bound, docs/robustness.md)")
    cf = float(_number(f"{path}: [sweep] cf", table.get("cf", Decimal("0.05"))))
    if not 0.0 < cf < 2.0:
        raise PunchError(f"{path}: [sweep] cf = {cf:g}: between 0 and 2 (0.05 is usual)")
    try:  # each "FIGURE" or "FIGURE:min|max" (design.sweep.pareto_pair)
        pair = pareto_pair(table.get("pareto", ["TORQ_PEAK", "SHAK_PEAK"]), table_of)
    except ValueError as exc:
        raise PunchError(f"{path}: [sweep] {exc}") from None
    pareto, senses = [p[0] for p in pair], tuple(p[1] for p in pair)
    vary = _table(f"{path}: [sweep.vary]", table.get("vary", {}))
    if not vary:
        raise PunchError(f"{path}: [sweep.vary] is empty: name at least one field to vary")
    # First the shape of every axis and the grid's size, from the lengths alone: nothing
    # is built before the size is known to be within bounds.
    lengths = {}
    for name, item in vary.items():
        where = f"{path}: [sweep.vary] {name}"
        if name not in names_ok:
            raise PunchError(f"{where}: not a field a sweep can vary "
                             f"({' '.join(names_ok)})")
        if isinstance(item, list):
            if not item:
                raise PunchError(f"{where} = []: give at least one value")
            lengths[name] = len(item)
            continue
        item = _table(where, item)
        _unknown(where, item, ("from", "to", "n"))
        if not {"from", "to", "n"} <= set(item):
            raise PunchError(f"{where}: write {{ from = ..., to = ..., n = ... }} or a "
                             "list of values")
        n = item["n"]
        if not (isinstance(n, int) and not isinstance(n, bool) and n >= 1):
            raise PunchError(f"{where} n = {n!r}: a whole number, 1 or more")
        if n > MAX_DESIGNS:
            raise PunchError(f"{where} n = {n}: more than {MAX_DESIGNS:,} values")
        lengths[name] = n
    size = 1
    for n in lengths.values():
        size *= n
        if size > MAX_DESIGNS:  # stops at once, however many axes follow
            shape = " x ".join(str(k) for k in lengths.values())
            raise PunchError(f"{path}: [sweep.vary] makes {shape} designs, more than "
                             f"{MAX_DESIGNS:,}")
    axes = {}
    for name, item in vary.items():
        where = f"{path}: [sweep.vary] {name}"
        if isinstance(item, list):
            values = np.array([float(_number(where, v)) for v in item])
        else:
            lo = float(_number(where + " from", item["from"]))
            hi = float(_number(where + " to", item["to"]))
            values = np.linspace(lo, hi, item["n"])
        _check_axis(where, name, values, mechanism)
        axes[name] = values
    return {"axes": axes, "angles": angles, "cf": cf, "pareto": pareto, "senses": senses}


def _check_axis(where: str, name: str, values, mechanism: Any = None) -> None:
    """A swept field's values (each already a bounded, finite spec number) that no design
    can have, as one line naming the axis and the first bad value."""
    import numpy as np

    from sielaff.design.kinds import is_four_bar, nonnegative_fields, positive_fields
    from sielaff.mechanism import LENGTHS, NONNEGATIVE

    if mechanism is not None and not is_four_bar(mechanism):
        LENGTHS, NONNEGATIVE = positive_fields(mechanism), nonnegative_fields(mechanism)

    rules = [(name in LENGTHS, values > 0.0, "a link length must be > 0"),
             (name in NONNEGATIVE, values >= 0.0,
              "weights and moments of inertia cannot be negative"),
             (name == "BALANCE", np.isin(values, (0.0, 1.0)), "0 (as designed) or 1 (balanced)"),
             (name in ("CW_R2", "CW_R4"), values > 0.0, "a counterweight's radius must be > 0")]
    for applies, ok, why in rules:
        if applies and not np.all(ok):
            raise PunchError(f"{where} = {float(values[np.argmin(ok)]):g}: {why}")
