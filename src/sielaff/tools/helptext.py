"""``sielaff help TOPIC``: what an engineer needs without the README.

Each topic is plain text; ``sielaff help`` lists them.  The exit statuses are
stated here once and every command's ``--help`` ends with them.
"""

from __future__ import annotations

import argparse

from sielaff.quantities import CONVENTIONS
from sielaff.tools.common import CommandError

#: The exit status of every command, the same everywhere.
EXIT_STATUS = """\
exit status (every command):
  0    done; for check: the deck is usable
  1    diff: the listings differ
  2    bad input or output: a deck, spec or option that cannot be used (one line
       names the card and columns, or the field), a range that never ends, a
       program deck past the interpreter's limits (docs/robustness.md), an
       output file that cannot be written
  3    not a crank-rocker where one is required: run and run --program (the
       1966 program's test; they print its message) and check --crank-rocker
  130  interrupted (Ctrl-C); no output file was changed (a signal that comes
       while a set of outputs is renamed into place waits for it; the message
       then names the files written)
  143  ended by SIGTERM (timeout, kill); 129 by SIGHUP: as for Ctrl-C"""

#: The report's example deck, as decks/example.dat has it (a test checks they agree).
EXAMPLE_CARDS = """\
     3.0     8.0     6.0
     0.0     0.5     0.4
    12.0     4.0    16.0    12.0
     0.0   -15.0    15.0
     2.0     8.0     6.0
    50.0
    10.0    10.0   360.0"""

DECK = f"""\
A deck is a text file of 80-column cards, one card per line, read with the
1966 program's FORMAT(4F8.4): four 8-column number fields in columns 1-8, 9-16,
17-24 and 25-32; columns 33-80 are not read (73-80 often hold a sequence number).

Type every number right-justified in its field WITH a decimal point ("    12.0").
A field with no decimal point has 4 implied decimals: "      12" reads as 0.0012
(a warning names the card and columns); "   30000" reads as 3.0.

card  columns 1-8   9-16        17-24       25-32
  1   W2  lb        W3  lb      W4  lb                  weights of links 2, 3, 4
  2   ZI2           ZI3         ZI4                     moments of inertia about each
                                                        link's G, in-lb-sec^2
  3   R1  in        R2  in      R3  in      R4  in      frame O2-O4, crank O2-A,
                                                        coupler A-B, rocker O4-B
  4   ADEL2 deg     ADEL3 deg   ADEL4 deg               angle from the link's line to
                                                        its G, CCW +
  5   RG2 in        RG3 in      RG4 in                  distance O2-G2, A-G3, O4-G4
  6   TH2D rad/sec                                      crank speed, constant, CCW +
  7+  THZERO deg    DELTA deg   THMAX deg               a range card: one sheet at
                                                        THETA 2 = THZERO, THZERO +
                                                        DELTA, ... (as many range
                                                        cards as you like)

The 1966 program needs a crank-rocker: with A = R3/R2, B = R4/R2, C = R1/R2,
A > 1, B > 1, C > 1, C < A + B - 1 and C > |B - A| + 1.  `sielaff check DECK`
prints each condition with its margin.  The 1966 loop also prints one sheet past
THMAX (docs/quirks.md).

The report's example (decks/example.dat in the source tree; save these seven
lines as example.dat to run it anywhere):

{EXAMPLE_CARDS}

`sielaff punch SPEC.toml` writes a deck from named values with units."""

ARITH = """\
--arith MODEL: the number model the 1966 port runs on (sielaff run):
  float64        IEEE double precision (the default)
  float32        IEEE single precision
  ibm1410[:K]    the IBM 1410's decimal floating point: K significant decimal
                 digits, truncated after every operation (never rounded), exponent
                 -99..99.  K = 8, the default, is the 1410 FORTRAN's (manual
                 C28-0328-3) and reproduces all 82 printed fields of the report's
                 Figures 10 and 11; K may be 3 to 40, to see how the 1966 numbers
                 converge as digits are added.
  ibm1410:K,VARIANT
                 another reconstruction of the lost 1410 library (SIN, COS, ATAN,
                 SQRT), e.g. ibm1410:8,taylor; docs/accuracy.md lists them."""

STREAMS = """\
standard input and output (every command)

  -  as the input reads it from standard input; messages call it <stdin>, with
     the card and columns as for a file:
       sielaff punch decks/example.toml | sielaff check -
       sielaff balance decks/si.toml -o - | sielaff table -
     run, check, table, plot, balance, report read a deck or a TOML spec; stdin
     holds a spec if its first non-blank line begins with [ or # or holds =
     (a TOML table, comment or key), else a deck (4F8.4 cards have none of them).
     sweep, simulate, synth, tolerance and punch read stdin as a spec; diff reads
     one of its two listings there (diff - golden/figure10.asa).  Stdin is read
     as a file is: card by card up to the deck's limit, at most 1 MiB of spec.
  -o -  writes standard output in every command that writes one file: run,
     table, check, punch, balance, sweep, simulate, synth, tolerance, report.
     The data go to stdout, what is said about them to stderr (balance -o -:
     the balanced deck, or spec for a spec, on stdout and the report on stderr;
     sweep -o -: the CSV on stdout, the status on stderr).  plot and bench
     write several files and refuse -o - (exit 2); so do --plot - and
     --write-best -.
  check --format json (with -o FILE or -o -): the report's facts, each number
     as {"value": x, "unit": "lb"}.
  A file named with -o is written whole or not at all; a reader that closes
  the pipe early (| head) ends the run quietly (exit 0; check and diff keep
  their status)."""

def spec_text() -> str:
    """``sielaff help spec``: the spec's tables and keys, made from the readers' own
    tables (the mechanism's keys from the spec reader, ``[scene]``'s from each effect's
    declaration), so a new effect's keys appear here with nothing else edited."""
    from sielaff.quantities import unit
    from sielaff.tools.spec_fields import RANGE_KEYS, SPEC_NAMES
    from sielaff.tools.spec_scene import scene_help

    out = ["A spec (*.toml) is a deck's values by name, and what a deck cannot say: the",
           "scene, a motor, a sweep, a synthesis, a tolerance study.  Units: the report's",
           "(in, lb, sec), or SI with [scene] units = \"SI\" (the first unit below, then",
           "the SI one).  decks/*.toml are worked examples of every table.", ""]
    def units(name: str) -> str:
        a, b = unit(name), unit(name, "SI")
        return f"{name} {a}" if a == b else f"{name} {a} or {b}"

    sections: dict[str, dict[str, list[tuple[str | None, str]]]] = {}
    for (section, key, sub), name in SPEC_NAMES.items():
        sections.setdefault(section, {}).setdefault(key, []).append((sub, name))
    for section, keys in sections.items():
        out.append(f"[{section}]")
        for key, subs in keys.items():
            if subs[0][0] is None:
                out.append(f"{key + ' = ...':<30}# {units(subs[0][1])}")
            else:
                inline = ", ".join(f"{sub} = ..." for sub, _ in sorted(subs, key=str))
                out.append(f"{key} = {{ {inline} }}")
                out.append(f"{'':30}# {'; '.join(units(n) for _, n in sorted(subs, key=str))}")
        out.append("")
    out += ["[[range]]                     # one per range card: THZERO, DELTA, THMAX"]
    out += [f"{k + ' = ...':<30}# deg" for k in RANGE_KEYS]
    out += ["", "[deck]", 'sequence = "SIEL"             # columns 73-80 of the punched cards', ""]
    out += _kinds_help(units)
    out += [scene_help(), ""]
    for table, (command, keys) in other_tables().items():
        out.append(f"{'[' + table + ']':<30}# read by sielaff {command} "
                   f"(decks/{EXAMPLES[table]})")
        for k in keys:
            out.append(f"{k.name + ' = ...':<30}# {key_unit(k)}{k.meaning}")
            out.append(f"{'':30}#   {k.bounds}" + (f"; default {k.default}" if k.default
                                                    else ""))
        out.append("")
    return "\n".join(out).rstrip("\n")


def _kinds_help(units) -> list[str]:
    """``[linkage] kind``: the four-bar by default; each other kind with its own keys."""
    from sielaff.tools.spec_fields import FOUR_BAR, kind_names

    out = ['[linkage]', f'kind = "{FOUR_BAR}"             # the default; or '
           + ", ".join(f'"{k}"' for k in kind_names() if k != FOUR_BAR)
           + " (the tables below, with these keys)"]
    for kind, names in kind_names().items():
        if kind == FOUR_BAR:
            continue
        out.append(f"#   {kind}:")
        keys: dict[tuple[str, str], list[tuple[str | None, str]]] = {}
        for (section, key, sub), name in names.items():
            keys.setdefault((section, key), []).append((sub, name))
        for (section, key), subs in keys.items():
            what = "; ".join(units(n) if sub is None else f"{sub}: {units(n)}"
                             for sub, n in sorted(subs, key=str))
            out.append(f"#     [{section}] {key}: {what}")
    return out + [""]


#: The worked example of each of the other tables.
EXAMPLES = {"motor": "motor.toml", "sweep": "sweep.toml", "synthesis": "synth.toml",
            "tolerance": "tolerance.toml"}


def other_tables() -> dict:
    """The tables besides the deck's and [scene], each with the command that reads it and
    its declared keys (each reader's own declaration)."""
    from sielaff.tools.spec_sweep import sweep_keys
    from sielaff.tools.spec_tables import motor_keys, synthesis_keys, tolerance_keys

    return {"motor": ("simulate", motor_keys()), "sweep": ("sweep", sweep_keys()),
            "synthesis": ("synth", synthesis_keys()),
            "tolerance": ("tolerance", tolerance_keys())}


def key_unit(k) -> str:
    """A declared key's unit in both systems, as a prefix (``"in-lb or N m: "``), or
    ``""`` for a key that has none."""
    from sielaff.quantities import KINDS

    if k.kind not in KINDS or k.kind == "number":
        return ""
    a, b = KINDS[k.kind]
    return f"{a}: " if a == b else f"{a} or {b}: "


def spec_markdown() -> str:
    """docs/spec.md: ``sielaff help spec`` as a page (made by ``python -m
    sielaff.tools.helptext spec``; tests/test_spec_reference.py checks it is current)."""
    return ("# The spec: every table and key\n\n"
            "Generated from the readers' own declarations by "
            "`python3 -m sielaff.tools.helptext spec > docs/spec.md` (the same text as "
            "`sielaff help spec`); `tests/test_spec_reference.py` fails when it is not "
            "current.\n\n```toml\n" + spec_text() + "\n```\n")


TOPICS = {
    "deck": ("the card deck: layout, fields, units, the example", DECK),
    "conventions": ("frame, angles, signs, which body each force acts on, units",
                    CONVENTIONS),
    "arith": ("the number models of --arith, and the K of ibm1410[:K]", ARITH),
    "exit": ("exit statuses, the same for every command", EXIT_STATUS),
    "io": ("- for standard input, -o - for standard output, check --format json",
           STREAMS),
    "spec": ("the TOML spec: its tables and keys ([scene]'s from each effect)", spec_text),
}


def topic_list() -> str:
    return "help topics (sielaff help TOPIC):\n" + "\n".join(
        f"  {name:<12} {summary}" for name, (summary, _) in TOPICS.items())


def cmd_help(args: argparse.Namespace) -> int:
    from sielaff.tools.helptext import TOPICS, topic_list

    if args.topic is None:
        print(topic_list())
        return 0
    if args.topic not in TOPICS:
        raise CommandError(f"sielaff: no help topic {args.topic!r} "
                           f"({', '.join(TOPICS)})")
    text = TOPICS[args.topic][1]
    print(text() if callable(text) else text)
    return 0


if __name__ == "__main__":  # python -m sielaff.tools.helptext spec > docs/spec.md
    import sys

    if sys.argv[1:] != ["spec"]:
        sys.exit("usage: python -m sielaff.tools.helptext spec")
    sys.stdout.write(spec_markdown())
