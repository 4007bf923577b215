"""``sielaff balance DECK|SPEC [-o BALANCED.dat|BALANCED.toml]``: full force balance.

Prints the two counterweights (Berkof-Lowen, :mod:`sielaff.design.balance`), the links
with them merged in, and the price: shaking moment, driving torque and pin loads before
and after, over one revolution with the spec's scene.  ``-o`` writes the balanced design
as a deck (``.dat``, any other name) or a spec (``.toml``, keeping the input spec's
[scene] and [deck]).  A deck's fields are F8.4: the merged values are rounded to 4
decimals, which leaves a small shaking force; the residual of the written design is
printed beside the exact one.
"""

from __future__ import annotations

import sys
from decimal import Decimal


def _rounded(value: float) -> Decimal:
    return Decimal(repr(float(value))).quantize(Decimal("0.0001"))


def cmd_balance(args) -> int:
    import os

    import numpy as np

    from sielaff.design.balance import balance
    from sielaff.design.report import balance_lines
    from sielaff.engine.analysis import analyze
    from sielaff.mechanism import FIELD_NAMES
    from sielaff.quantities import unit
    from sielaff.tools.common import CommandError, load_scene, refuse_overwriting_inputs
    from sielaff.tools.output import atomic_output
    from sielaff.tools.spec import PunchError, punch_deck, read_spec, spec_dict, spec_text

    path = args.deck
    refuse_overwriting_inputs(args.output, [path])
    if args.output and os.path.isdir(args.output):
        raise CommandError(f"sielaff: {args.output} is a folder: name the file to write")
    deck, scene = load_scene(path, ["SHAK"])
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
        values = {n: deck.exact.get(n, _rounded(getattr(m, n))) for n in FIELD_NAMES}
        values.update({n: _rounded(getattr(balanced, n)) for n in
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
        th = np.arange(3600) * 0.1
        before = float(np.max(analyze(m, th, ["SHAK"], scene=scene)["SHAK"]))
        after = float(np.max(analyze(written, th, ["SHAK"], scene=scene)["SHAK"]))
        lines += ["", f"Written to {args.output} with its fields to 4 decimals (F8.4): "
                  f"residual peak shaking force {after:.3g} {unit('SHAK', m.units)} "
                  f"({100.0 * after / before:.2g}% of the unbalanced {before:.4g})"]
        with atomic_output(args.output) as out:
            out.write(text)
    sys.stdout.write("\n".join(lines) + "\n")
    return 0
