"""``sielaff balance DECK|SPEC [-o BALANCED.dat|BALANCED.toml]``: full force balance.

Prints the two counterweights (Berkof-Lowen, :mod:`sielaff.design.balance`), the links
with them merged in, and the price: shaking moment, driving torque and pin loads before
and after, over one revolution with the spec's scene.  ``-o`` writes the balanced design
as a deck (``.dat``, any other name) or a spec (``.toml``, keeping the input spec's
[scene] and [deck]).  A deck's fields are F8.4: the merged values are rounded to 4
decimals, which leaves a small shaking force; the residual of the written design is
printed beside the exact balanced design's, and only their difference is called
rounding: with gravity, loads, springs or dampers on, the exact design still shakes the
frame with them.  A spec keeps every value as computed (the shortest decimal
that reads back as the same double): only a deck has F8.4 fields.

A counterweight radius so far from the link's length that a merged field would pass the
IBM 1410's range (1E99, as for any deck) is refused in one line naming the option.
"""

from __future__ import annotations

import sys
from decimal import Decimal

#: Fields a counterweight changes, by the option that places it.
CHANGED = {"--radius2": ("W2", "ZI2", "RG2", "ADEL2"), "--radius4": ("W4", "ZI4", "RG4", "ADEL4")}


def _deck_value(value: float) -> Decimal:
    """``value`` rounded to the most decimals (4 at most) an F8.4 field holds; a value no
    field holds is returned unrounded, for the punch to refuse in words."""
    from sielaff.tools.spec import punch_field

    exact = Decimal(repr(float(value)))
    if not abs(value) < 1e8:
        return exact
    for places in range(4, -1, -1):
        rounded = exact.quantize(Decimal(1).scaleb(-places))
        try:
            punch_field(rounded)
        except ValueError:
            continue
        return rounded
    return exact


def _spec_value(value: float) -> Decimal:
    """``value`` for a spec: its shortest decimal, a magnitude below 1E-99 as 0."""
    return Decimal(repr(float(value))) if abs(value) >= 1e-99 else Decimal(0)


def _too_large(m, path: str, args) -> None:
    """Refuse a balanced design with a field past the 1410's range (1E99)."""
    import math

    from sielaff.quantities import unit
    from sielaff.tools.common import CommandError

    for option, names in CHANGED.items():
        for name in names:
            value = float(getattr(m, name))
            if not (math.isfinite(value) and abs(value) < 1e99):
                radius = getattr(args, option[2:])
                raise CommandError(f"{path}: {option} {radius:g}: the balanced design's {name} "
                                   f"would be {value:.3g} {unit(name, m.units)}, past the IBM "
                                   "1410's range (1E99): choose a radius nearer the link's "
                                   "length")


def cmd_balance(args) -> int:

    import numpy as np

    from sielaff.design.balance import balance
    from sielaff.design.report import balance_lines
    from sielaff.mechanism import FIELD_NAMES, Mechanism
    from sielaff.tools.common import (
        CommandError,
        is_spec,
        load_scene,
        read_spec,
        refuse_bad_output,
        write_stdout,
    )
    from sielaff.tools.kinds import other_kinds
    from sielaff.tools.output import atomic_output
    from sielaff.tools.spec import (
        PunchError,
        punch_deck,
        spec_deck,
        spec_dict,
        spec_text,
    )

    path = args.deck
    refuse_bad_output(args.output, [path])
    deck, scene = load_scene(path, ["SHAK"], branch=getattr(args, "branch", None),
                             any_kind=True, kinds=other_kinds(), note=False)
    m = deck.mechanism
    if not isinstance(m, Mechanism):
        return _another_kind(args, deck, scene)
    try:
        with np.errstate(all="ignore"):  # a field past 1E99 is refused just below
            balanced = balance(m, args.radius2, args.radius4)
    except ValueError as exc:
        raise CommandError(f"{path}: {exc}") from None
    _too_large(balanced, path, args)
    lines = [f"sielaff balance: {path} (units {m.units})", ""]
    with np.errstate(all="ignore"):  # a design near 1E99 may overflow a product: nan
        lines += balance_lines(m, balanced, args.radius2, args.radius4, scene=scene)
    loading = _loading(scene)
    if loading:
        lines.append(f"  (the scene's forces reach the frame besides the links' inertia "
                     f"({loading}): counterweights cancel the inertia forces only)")
    to_stdout = args.output == "-"  # the balanced design on stdout, the report on stderr
    where = "standard output" if to_stdout else args.output
    if args.output:
        # -o -: the design in the input's form (a spec for a spec, a deck for a deck)
        as_spec = is_spec(path) if to_stdout else args.output.endswith(".toml")
        value = _spec_value if as_spec else _deck_value
        values = {n: deck.exact.get(n, value(getattr(m, n))) for n in FIELD_NAMES}
        values.update({n: value(getattr(balanced, n)) for names in CHANGED.values()
                       for n in names})
        base = read_spec(path) if is_spec(path) else {}
        spec = spec_dict(values, deck.exact_ranges, base)
        try:
            if as_spec:
                spec_deck(spec, where)  # what table and check will read back
                text = spec_text(spec, f"{path} balanced by sielaff balance (Berkof-Lowen)")
            else:
                text = punch_deck(spec, where, True)
        except PunchError as exc:
            raise CommandError(f"{where}: the balanced design cannot be written: "
                               f"{exc}") from None
        written = m.replace(**{n: float(values[n]) for n in FIELD_NAMES})
        lines += ["", _written_line(where, as_spec, m, balanced, written, scene)]
        if to_stdout:
            if not write_stdout(text):
                return 0  # the reader went away: nothing more to say
            print("\n".join(lines), file=sys.stderr)
            return 0
        with atomic_output(args.output) as out:
            out.write(text)
    sys.stdout.write("\n".join(lines) + "\n")
    return 0


def _written_line(path: str, as_spec: bool, m, exact, written, scene) -> str:
    """The written design's residual shaking force, beside the exact balanced design's:
    only their difference is rounding (gravity and loads shake the frame in both)."""
    import numpy as np

    from sielaff.engine.analysis import analyze
    from sielaff.quantities import fmt

    th = np.arange(3600) * 0.1
    with np.errstate(all="ignore"):  # a linkage that cannot turn fully: where it assembles
        peak = {name: float(np.nanmax(np.where(np.isfinite(v), v, np.nan)))
                for name, d in (("before", m), ("exact", exact), ("written", written))
                for v in [analyze(d, th, ["SHAK"], scene=scene)["SHAK"]]}
    f = "SHAK"
    how = ("every value as computed" if as_spec else
           "its fields rounded to fit F8.4 (4 decimals at most)")
    text = (f"Written to {path} with {how}: residual peak shaking force "
            f"{fmt(peak['written'], f, m.units, '.3g')} "
            f"({100.0 * peak['written'] / peak['before']:.2g}% of the unbalanced "
            f"{peak['before']:.4g}); the exact balanced design's is "
            f"{fmt(peak['exact'], f, m.units, '.3g')}")
    if not as_spec:
        rounding = abs(peak["written"] - peak["exact"])
        text += f", so rounding to F8.4 accounts for {fmt(rounding, f, m.units, '.2g')}"
    loading = _loading(scene)
    if loading:
        text += (f"; the rest is the scene's forces ({loading}), which no counterweight "
                 "cancels (not a rounding residual)")
    return text


def _loading(scene) -> str:
    """The effects of ``scene`` that put forces on the links (each effect says whether it
    does: ``applies``), in their own words: "" if none."""
    return ", ".join(e.summary(scene, "in-lb-sec") if e.summary else e.name
                     for e in scene.effects if e.applies)


def _another_kind(args, deck, scene) -> int:
    """A slider-crank's crank counterweight (:func:`sielaff.design.slider_balance`: the
    rotating mass and half the reciprocating primary, the least peak) and what it leaves,
    primary and secondary; ``-o`` writes the spec with it merged into the crank (a spec:
    a 1966 deck is a four-bar's).  Another kind has no balancing: one line says so."""
    import numpy as np

    from sielaff.design.kinds import is_slider_crank, kind_name
    from sielaff.design.report import slider_balance_lines
    from sielaff.design.slider_balance import slider_balance
    from sielaff.tools.common import CommandError, is_spec, read_spec, write_stdout
    from sielaff.tools.output import atomic_output
    from sielaff.tools.spec import spec_text

    path, m = args.deck, deck.mechanism
    if not is_slider_crank(m):
        raise CommandError(f"{path}: sielaff balance has counterweights for a four-bar "
                           f"(Berkof-Lowen) and a slider-crank's crank, not a {kind_name(m)}")
    if args.radius4 is not None:
        raise CommandError(f"--radius4 {args.radius4:g}: a slider-crank has no rocker: its "
                           "counterweight is on the crank (--radius2)")
    branch = scene.branch if isinstance(scene.branch, str) else "open"
    where = path if args.radius2 is None else f"{path}: --radius2 {args.radius2:g}"
    try:
        with np.errstate(all="ignore"):
            b = slider_balance(m, radius=args.radius2, branch=branch)
    except ValueError as exc:
        raise CommandError(f"{where}: {exc}") from None
    for k in ("W2", "ZI2", "RG2"):  # a radius far from the crank's: the 1410's range
        v = float(getattr(b.mechanism, k))
        if not abs(v) < 1e99 or (k != "RG2" and 0.0 < abs(v) < 1e-99):
            from sielaff.quantities import unit

            raise CommandError(f"{where}: the merged crank's {k} would be {v:.3g} "
                               f"{unit(k, m.units)}, past the IBM 1410's range (1E99)")
    lines = [f"sielaff balance: {path} (units {m.units})", ""] + slider_balance_lines(b)
    if args.output:
        to_stdout = args.output == "-"
        if not (to_stdout or args.output.endswith(".toml")) or not is_spec(path):
            raise CommandError(f"-o {args.output}: a balanced slider-crank is written as a "
                               "TOML spec (FILE.toml, or - for a spec): a 1966 deck is a "
                               "four-bar's")
        spec = read_spec(path)
        for (table, key, sub), name in type(m).SPEC_NAMES.items():
            if name in ("W2", "ZI2", "RG2", "ADEL2"):
                value = _spec_value(float(getattr(b.mechanism, name)))
                body = spec.setdefault(table, {})
                if sub is None:
                    body[key] = value
                else:
                    body.setdefault(key, {})[sub] = value
        text = spec_text(spec, f"{path} with the crank counterweight of sielaff balance "
                               "(rotating mass and half the reciprocating primary)")
        _check_written(text, b.mechanism, args.output)
        lines += ["", f"Written to {'standard output' if to_stdout else args.output}: the "
                      "spec with the counterweight merged into the crank (every value as "
                      "computed)"]
        if to_stdout:
            if write_stdout(text):
                print("\n".join(lines), file=sys.stderr)
            return 0
        with atomic_output(args.output) as out:
            out.write(text)
    sys.stdout.write("\n".join(lines) + "\n")
    return 0


def _check_written(text: str, balanced, where: str) -> None:
    """The written spec reads back as the balanced design, field for field (a spec's
    values are each the shortest decimal of the double), or one line says why not."""
    import os
    import tempfile

    from sielaff.tools.common import CommandError, read_spec_deck
    from sielaff.tools.kinds import other_kinds

    fd, tmp = tempfile.mkstemp(suffix=".toml")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        back = read_spec_deck(tmp, other_kinds())[0].mechanism
    except CommandError as exc:
        raise CommandError(f"{where}: the balanced design cannot be written: "
                           f"{str(exc).split(': ', 1)[-1]}") from None
    finally:
        os.unlink(tmp)
    if back.as_dict() != balanced.as_dict():
        raise CommandError(f"{where}: the balanced design does not read back as computed")
