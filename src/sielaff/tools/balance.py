"""``sielaff balance DECK|SPEC [-o BALANCED.dat|BALANCED.toml]``: full force balance.

Prints the two counterweights (Berkof-Lowen, :mod:`sielaff.design.balance`), the links
with them merged in, and the price: shaking moment, driving torque and pin loads before
and after, over one revolution with the spec's scene.  ``-o`` writes the balanced design
as a deck (``.dat``, any other name) or a spec (``.toml``, keeping the input spec's
[scene] and [deck]).  A spec keeps every value as computed (the shortest decimal that
reads back as the same float); a deck's fields are F8.4, so there the merged values are
rounded to 4 decimals, which leaves a small shaking force.  The written design's peak
shaking force is printed beside the exact balanced design's, and only their difference
is called rounding: with gravity or loads on, the exact design still shakes the frame
with the links' weight and the loads.
"""

from __future__ import annotations

import sys
from decimal import Decimal


def _rounded(value: float) -> Decimal:
    """A value for a deck's F8.4 field [the field's unit]."""
    return Decimal(repr(float(value))).quantize(Decimal("0.0001"))


def _exact(value: float) -> Decimal:
    """A value for a spec: the shortest decimal that reads back as ``value``."""
    return Decimal(repr(float(value)))


def cmd_balance(args) -> int:
    import os

    from sielaff.design.balance import balance
    from sielaff.design.report import balance_lines
    from sielaff.mechanism import FIELD_NAMES
    from sielaff.tools.common import CommandError, load_scene, refuse_overwriting_inputs
    from sielaff.tools.output import atomic_output
    from sielaff.tools.spec import PunchError, punch_deck, read_spec, spec_dict, spec_text

    path = args.deck
    refuse_overwriting_inputs(args.output, [path])
    if args.output and os.path.isdir(args.output):
        raise CommandError(f"sielaff: {args.output} is a folder: name the file to write")
    deck, scene = load_scene(path, ["SHAK"], branch=getattr(args, "branch", None),
                             any_kind=True)
    m = deck.mechanism
    try:
        balanced = balance(m, args.radius2, args.radius4)
    except ValueError as exc:
        raise CommandError(f"{path}: {exc}") from None
    lines = [f"sielaff balance: {path} (units {m.units})", ""]
    lines += balance_lines(m, balanced, args.radius2, args.radius4, scene=scene)
    if scene.gravity is not None or scene.loads:
        lines.append("  (the spec's weights and loads still reach the frame: counterweights "
                     "cancel the inertia forces only)")
    if args.output:
        as_spec = args.output.endswith(".toml")
        keep = _exact if as_spec else _rounded
        values = {n: deck.exact.get(n, keep(getattr(m, n))) for n in FIELD_NAMES}
        values.update({n: keep(getattr(balanced, n)) for n in
                       ("W2", "ZI2", "RG2", "ADEL2", "W4", "ZI4", "RG4", "ADEL4")})
        base = read_spec(path) if path.endswith(".toml") else {}
        spec = spec_dict(values, deck.exact_ranges, base)
        try:
            text = (spec_text(spec, f"{path} balanced by sielaff balance (Berkof-Lowen)")
                    if args.output.endswith(".toml") else punch_deck(spec, path, True))
        except PunchError as exc:
            raise CommandError(f"{args.output}: the balanced design cannot be written: "
                               f"{exc}") from None
        written = m.replace(**{n: float(values[n]) for n in FIELD_NAMES})
        lines += ["", _written_line(args.output, as_spec, m, balanced, written, scene)]
        with atomic_output(args.output) as out:
            out.write(text)
    sys.stdout.write("\n".join(lines) + "\n")
    return 0


def _written_line(path: str, as_spec: bool, m, exact, written, scene) -> str:
    """What the written design's shaking force is, beside the exact balanced design's: only
    the difference is rounding (gravity and loads shake the frame in both)."""
    import numpy as np

    from sielaff.engine.analysis import analyze
    from sielaff.quantities import fmt

    th = np.arange(3600) * 0.1
    with np.errstate(all="ignore"):  # a linkage that cannot turn fully: where it assembles
        peak = {name: float(np.nanmax(np.where(np.isfinite(v), v, np.nan)))
                for name, d in (("before", m), ("exact", exact), ("written", written))
                for v in [analyze(d, th, ["SHAK"], scene=scene)["SHAK"]]}
    f = "SHAK"
    if as_spec:
        head = f"Written to {path} with every value as computed (full precision)"
    else:
        head = f"Written to {path} with its fields to 4 decimals (F8.4)"
    text = (f"{head}: peak shaking force {fmt(peak['written'], f, m.units, '.4g')} against "
            f"{fmt(peak['exact'], f, m.units, '.4g')} for the exact balanced design and "
            f"{fmt(peak['before'], f, m.units, '.4g')} unbalanced")
    rounding = abs(peak["written"] - peak["exact"])
    if not as_spec:
        text += (f"; rounding to F8.4 accounts for {fmt(rounding, f, m.units, '.2g')} "
                 f"({100.0 * rounding / peak['before']:.2g}% of the unbalanced)")
    if scene.gravity is not None or scene.loads:
        text += "; the rest is the links' weight and the loads, which no counterweight cancels"
    return text
