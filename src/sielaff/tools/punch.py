"""``sielaff punch SPEC.toml [-o DECK]``: the 80-column deck a TOML spec describes.

The spec's format and the punching rules are in ``sielaff.tools.spec`` (shared with the
commands that read a spec directly: ``table``, ``check`` and ``plot``).  A spec's
``[scene]`` (gravity, loads, crank acceleration) is for the modern tools: a 1966 deck
cannot carry it, and ``punch`` leaves it out.
"""

from __future__ import annotations


def cmd_punch(args) -> int:
    """``sielaff punch SPEC.toml [-o DECK]``."""
    from sielaff.tools.common import CommandError, read_spec, refuse_bad_output
    from sielaff.tools.output import atomic_output
    from sielaff.tools.spec import PunchError, punch_deck

    refuse_bad_output(args.output, [args.spec])
    try:
        text = punch_deck(read_spec(args.spec), args.spec)
    except PunchError as exc:
        raise CommandError(str(exc), exc.status) from None
    with atomic_output(args.output) as out:
        out.write(text)
    return 0
