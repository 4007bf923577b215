"""``sielaff tolerance SPEC.toml [-o TABLE.txt] [--workers N]``: tolerances to the forces.

The spec's mechanism and ``[scene]`` are the nominal design; its ``[tolerance]`` table
says how each field may deviate (:func:`sielaff.design.tolerance`; decks/tolerance.toml)::

    [tolerance]
    n = 2000                     # samples
    seed = 1                     # the same seed, the same table, wherever it runs
    distribution = "normal"      # or "uniform"
    angles = 360                 # crank angles per revolution
    cf = 0.05                    # coefficient of speed fluctuation (FLYWHEEL_I)
    [tolerance.deviations]       # listing names; the standard deviation (normal) or the
    R1 = 0.005                   # half-width (uniform), in the field's unit
    ADEL3 = 0.5

Prints, per design figure with its unit: the nominal, the sampled mean, standard
deviation and 5th/95th percentiles, and the standard deviation the first-order
sensitivities predict; then the sensitivities d figure / d field.  ``--workers N`` (N > 1)
runs the blocks on dask's local threads when dask is installed (the same numbers).
"""

from __future__ import annotations

from decimal import Decimal


def read_tolerance(spec: dict, path: str, fields: tuple[str, ...] | None = None) -> dict:
    """The ``[tolerance]`` table checked (PunchError naming the key); ``fields``: the
    names a deviation may have (the spec's kind's fields; the four-bar's by default)."""
    from sielaff.design.sweep import MAX_ANGLES
    from sielaff.design.tolerance import DISTRIBUTIONS, MAX_SAMPLES
    from sielaff.mechanism import FIELD_NAMES
    from sielaff.tools.spec import PunchError, spec_whole

    FIELD_NAMES = FIELD_NAMES if fields is None else fields  # noqa: N806

    table = spec.get("tolerance")
    where = f"{path}: [tolerance]"
    if not isinstance(table, dict) or not table:
        raise PunchError(f"{path}: no [tolerance] table (decks/tolerance.toml has one)")
    from sielaff.tools.spec_tables import tolerance_keys

    keys = [k.name for k in tolerance_keys()]
    extra = [k for k in table if k not in keys]
    if extra:
        raise PunchError(f"{where}: unknown key {extra[0]!r} (expected: {', '.join(keys)})")
    out = {}
    for key, default, lo, hi in (("n", 1000, 2, MAX_SAMPLES), ("seed", 0, 0, 2 ** 63 - 1),
                                 ("angles", 360, 8, MAX_ANGLES)):
        out[key] = spec_whole(where, key, table.get(key, default), lo, hi, key == "angles")
    dist = table.get("distribution", "normal")
    if dist not in DISTRIBUTIONS:
        raise PunchError(f"{where} distribution = {dist!r}: \"normal\" or \"uniform\"")
    out["distribution"] = dist
    cf = table.get("cf", Decimal("0.05"))
    if isinstance(cf, bool) or not isinstance(cf, int | Decimal) or not 0 < float(cf) < 2:
        raise PunchError(f"{where} cf = {cf!r}: between 0 and 2 (0.05 is usual)")
    out["cf"] = float(cf)
    devs = table.get("deviations")
    if not isinstance(devs, dict) or not devs:
        raise PunchError(f"{where}.deviations: name at least one field and its deviation")
    out["deviations"] = {}
    for k, v in devs.items():
        if k not in FIELD_NAMES:
            raise PunchError(f"{where}.deviations: {k!r} is not a field "
                             f"({' '.join(FIELD_NAMES)})")
        if isinstance(v, bool) or not isinstance(v, int | Decimal) or not v >= 0 \
                or not Decimal(v).is_finite() or v > Decimal("1E12"):
            raise PunchError(f"{where}.deviations {k} = {v!r}: a number, 0 or more")
        out["deviations"][k] = float(v)
    return out


def _g(v: float) -> str:
    return f"{v:12.5g}"


def table_lines(t, path: str) -> list[str]:
    """The printed table (units on every number)."""
    from sielaff.design.sweep import column_units
    from sielaff.quantities import unit

    u = t.units
    units = column_units(list(t.nominal), u)
    lines = [f"sielaff tolerance: {path} (units {u}), {t.n} samples, {t.distribution}, "
             f"seed {t.seed}; {t.invalid} not a linkage, {t.not_turning} not turning fully",
             "  deviations (" + ("standard deviation" if t.distribution == "normal" else
                                 "half-width") + "): "
             + ", ".join(f"{k} {v:g} {unit(k, u)}" for k, v in t.deviations.items()),
             "",
             f"  {'figure':11} {'unit':12} {'nominal':>12} {'mean':>12} {'std':>12} "
             f"{'5%':>12} {'95%':>12} {'1st-order std':>13}"]
    for f in t.nominal:
        fu = units[f]
        lines.append(f"  {f:11} {fu:12} {_g(t.nominal[f])} {_g(t.mean[f])} {_g(t.std[f])} "
                     f"{_g(t.p5[f])} {_g(t.p95[f])} {t.predicted_std[f]:13.5g}")
    lines += ["", "  sensitivities d figure / d field (central differences), in the figure's "
              "unit per the field's:"]
    fields = list(t.deviations)
    lines.append(f"  {'figure':11} " + " ".join(f"{'per ' + unit(k, u) + ' ' + k:>16}"
                                                for k in fields))
    for f in t.nominal:
        lines.append(f"  {f:11} " + " ".join(f"{t.sensitivity[f][k]:16.5g}" for k in fields))
    return lines


def tolerance_spec(path: str):
    """(the nominal deck in the spec's units, its Scene, the checked ``[tolerance]``) of
    the spec at ``path`` (``sielaff tolerance``, and ``sielaff report``'s section);
    bad input is a CommandError of one line, a nominal design that is not a
    crank-rocker (or another kind's whose crank cannot turn fully) exit 3."""
    from sielaff.design.kinds import fields_of
    from sielaff.mechanism import Mechanism
    from sielaff.tools.common import CommandError, mechanism_problem, read_spec_with
    from sielaff.tools.kinds import other_kind, other_kinds
    from sielaff.tools.spec import PunchError

    deck, scene, spec = read_spec_with(path, lambda spec, _: spec, kinds=other_kinds())
    assert deck is not None
    four_bar = isinstance(deck.mechanism, Mechanism)
    try:
        task = read_tolerance(spec, path, None if four_bar else fields_of(deck.mechanism))
    except PunchError as exc:
        raise CommandError(str(exc), exc.status) from None
    if not four_bar:
        return other_kind(deck, scene), scene, task  # its crank turns fully (else exit 3)
    problem = mechanism_problem(deck)  # the nominal design is a crank-rocker (else exit 3)
    if problem is not None:
        raise problem
    return deck, scene, task


def run_tolerance(deck, scene, task: dict, workers: int | None = None):
    """The tolerance study the spec asks for (:func:`sielaff.design.tolerance`), in
    this process or, with ``workers`` > 1 and dask installed, on dask's local threads."""
    from sielaff.design.tolerance import tolerance
    from sielaff.tools.common import CommandError

    backend = "process"
    if workers and workers > 1:
        try:
            import dask  # noqa: F401
        except ImportError:
            workers = None
        else:
            backend = "dask"
    else:
        workers = None
    try:
        return tolerance(deck.mechanism, task["deviations"], task["n"], scene=scene,
                         seed=task["seed"], distribution=task["distribution"],
                         angles=task["angles"], cf=task["cf"], backend=backend,
                         workers=workers)
    except ValueError as exc:
        raise CommandError(f"{deck.path}: {exc}") from None


def cmd_tolerance(args) -> int:
    from sielaff.tools.common import CommandError, refuse_bad_output, spec_path
    from sielaff.tools.output import atomic_output

    path = args.spec
    refuse_bad_output(args.output, [path])
    if not spec_path(path):
        raise CommandError(f"{path}: tolerance reads a TOML spec with a [tolerance] table")
    deck, scene, task = tolerance_spec(path)
    t = run_tolerance(deck, scene, task, args.workers)
    text = "\n".join(table_lines(t, path)) + "\n"
    with atomic_output(args.output) as out:
        out.write(text)
    return 0
