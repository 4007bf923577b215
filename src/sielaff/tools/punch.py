"""``sielaff punch SPEC.toml [-o DECK]``: the 80-column deck a TOML spec describes.

The spec's format and the punching rules are in ``sielaff.tools.spec`` (shared with the
commands that read a spec directly: ``table``, ``check`` and ``plot``).  A spec's
``[scene]`` (gravity, loads, crank acceleration), ``[motor]``, ``[sweep]``,
``[synthesis]`` and ``[tolerance]`` are for the modern tools: a 1966 deck cannot carry
them, ``punch`` leaves them out, and one warning on stderr names those the spec has.
"""

from __future__ import annotations


def cmd_punch(args) -> int:
    """``sielaff punch SPEC.toml [-o DECK]``."""
    import sys

    from sielaff.tools.common import CommandError, read_spec, refuse_bad_output
    from sielaff.tools.output import atomic_output
    from sielaff.tools.spec import PunchError, punch_deck
    from sielaff.tools.spec_fields import OTHER_TABLES

    refuse_bad_output(args.output, [args.spec])
    try:
        spec = read_spec(args.spec)
        text = punch_deck(spec, args.spec)
    except PunchError as exc:
        raise CommandError(str(exc), exc.status) from None
    left = [f"[{t}]" for t in OTHER_TABLES if t in spec]
    if left:
        print(f"sielaff: warning: {args.spec}: the deck leaves out {', '.join(left)} (a 1966 "
              "deck cannot carry them; the modern tools read them from the spec)",
              file=sys.stderr)
    with atomic_output(args.output) as out:
        out.write(text)
    return 0
