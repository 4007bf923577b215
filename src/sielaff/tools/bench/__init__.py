"""``sielaff bench``: accuracy against cost of the number models, ARCCOS and step size.

``study`` computes (the references, every model, the ARCCOS and step studies; its doc
explains the three questions); ``report`` writes docs/accuracy.md, its figure and the
headline table.  ``cmd_bench`` is the user command (a table on stdout, a report only
where ``-o`` says); ``main`` is ``benchmarks/accuracy.py``, which regenerates docs/.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

from sielaff.tools.common import CommandError


def _need(module: str, extra: str, what: str) -> None:
    import importlib

    try:
        importlib.import_module(module)
    except ImportError:
        raise CommandError(f"sielaff: {what} needs {module}, which is not installed "
                           f"(pip install -e \".[{extra}]\")") from None


def cmd_bench(args: argparse.Namespace) -> int:
    if args.output == "-":
        raise CommandError("sielaff: -o -: bench writes a report and its PNG figure, which "
                           "standard output cannot hold: name the report's file")
    effects = getattr(args, "effects", False)
    if effects:
        _need("scipy", "dynamics", "bench --effects (simulate)")
    else:
        _need("mpmath", "bench", "bench (its 50-digit reference)")
    if args.output:
        _need("matplotlib", "bench", "bench -o (the report's figure)")
        figure = os.path.splitext(args.output)[0] + ".png"
        if os.path.realpath(figure) == os.path.realpath(args.output):
            raise CommandError(f"sielaff: -o {args.output}: the report and its figure would "
                               f"both be {figure}: name the report .md (its figure is the "
                               "same name with .png)")
        if os.path.isdir(args.output):
            raise CommandError(f"sielaff: {args.output}: is a folder; -o names the report "
                               "file (its PNG goes beside it)")
        folder = os.path.dirname(os.path.abspath(args.output))
        try:
            os.makedirs(folder, exist_ok=True)
        except OSError as exc:
            raise CommandError(f"sielaff: {args.output}: cannot create its folder "
                               f"({exc.strerror})") from exc
        if not os.access(folder, os.W_OK):
            raise CommandError(f"sielaff: {args.output}: its folder is not writable")
        from sielaff.tools.output import check_targets

        try:  # before the study: a folder in the way of the figure, say
            check_targets([args.output, figure])
        except OSError as exc:
            raise CommandError(f"sielaff: {exc.filename}: {exc.strerror}") from None
    if effects:
        return _effects(args)
    from sielaff.tools.bench import study as s
    from sielaff.tools.bench.report import headline, write_report

    res = s.study(args.quick, progress=lambda s: print(f"sielaff bench: {s}", file=sys.stderr))
    print(headline(res))
    if args.output:
        write_report(res, args.output,
                     command="sielaff bench" + (" --quick" if args.quick else ""))
        print(f"sielaff bench: wrote {args.output} and "
              f"{os.path.splitext(args.output)[0]}.png", file=sys.stderr)
    return 0



def _effects(args: argparse.Namespace) -> int:
    """``--effects``: the friction solve's and simulate's accuracy against time (a small
    grid, one round; ``benchmarks/effects_cost.py`` runs the full one into docs/)."""
    from sielaff.tools.bench.effects import effects_study, headline, markdown, plot
    from sielaff.tools.output import atomic_files

    res = effects_study(True, progress=lambda t: print(f"sielaff bench: {t}", file=sys.stderr))
    print(headline(res))
    if args.output:
        figure = os.path.splitext(args.output)[0] + ".png"
        text = "# What accuracy costs for the effects\n\n" + markdown(
            res, os.path.basename(figure), "sielaff bench --effects")
        with atomic_files([args.output, figure]) as temps:
            with open(temps[0], "w") as f:
                f.write(text)
            plot(res, temps[1])
        print(f"sielaff bench: wrote {args.output} and {figure}", file=sys.stderr)
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """``benchmarks/accuracy.py``: the full study, written into docs/ (or ``-o``)."""
    from sielaff.tools.bench import study as s
    from sielaff.tools.bench.report import write_report

    p = argparse.ArgumentParser(description="the accuracy/cost study (docs/accuracy.md)")
    p.add_argument("--quick", action="store_true", help="fewer ARCCOS points and port steps")
    p.add_argument("-o", "--output", default=os.path.join(s.ROOT, "docs", "accuracy.md"))
    args = p.parse_args(argv)
    res = s.study(args.quick, progress=lambda t: print(f"bench: {t}", file=sys.stderr))
    write_report(res, args.output, command="python benchmarks/accuracy.py"
                 + (" --quick" if args.quick else ""))
    print(f"wrote {args.output}", file=sys.stderr)
    return 0
