"""``sielaff report DECK|SPEC -o report.html``: the page an engineer forwards.

One self-contained HTML file: every image inline (``data:`` URIs), the style inline, no
script, and a Content-Security-Policy that lets the page load nothing from anywhere, so
it reads the same offline in any browser and prints to PDF from it.  It holds:

* the deck or spec with units, the kind of linkage, its Grashof margin, toggles and
  reachable arcs (``sielaff check``'s report, which also carries the transmission
  angle, the peak loads with their angles, the cycle work, the flywheel, the bearings
  and every 1966 quirk the deck triggers);
* the scene (gravity, crank acceleration, loads, TEX, the branch);
* a table of peaks, each with the crank angle where it occurs, in the mechanism's units;
* the linkage drawn at a chosen angle, and one cycle of it animated (a GIF);
* the report's figures (driving torque, the polar diagrams of the bearing forces and of
  the shaking force) and the bearing picture;
* the balancing answer (Berkof-Lowen counterweights and what they cost);
* for a spec with a ``[sweep]``: the Pareto front of its two figures as a table, and the
  Pareto picture;
* a footer with the version and the command that made the page.

This command composes the others' pages (check, plot, balance): it is the one command
that imports other commands (docs/architecture.md), and nothing imports it.  The page is
written whole or not at all (``tools/output.py``); bad input is one line, as for every
command.
"""

from __future__ import annotations

import base64
import html
import io
import os
import sys
from typing import Any

import numpy as np

from sielaff.emulator.cards import Deck
from sielaff.engine.scene import Scene  # noqa: TC001

#: The page's style: print-friendly, no web fonts (nothing is fetched).
STYLE = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 2em auto;
       max-width: 62em; color: #111; line-height: 1.4; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.25em; border-bottom: 1px solid #ccc; margin-top: 2em; }
.sub { color: #444; margin-top: 0; }
pre { background: #f6f6f6; padding: 0.8em; overflow-x: auto; font-size: 0.82em;
      white-space: pre-wrap; }
table { border-collapse: collapse; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th:first-child, td:first-child { text-align: left; }
figure { margin: 1em 0; page-break-inside: avoid; }
figure img { max-width: 100%; border: 1px solid #eee; }
figcaption { color: #444; font-size: 0.9em; }
footer { margin-top: 3em; color: #555; font-size: 0.85em; border-top: 1px solid #ccc; }
@media print { body { margin: 0; max-width: none; } h2 { page-break-after: avoid; } }
"""

#: The peaks the table shows: (label, output, how).
PEAKS = (
    ("driving torque, largest", "TORQ", "max"),
    ("driving torque, smallest", "TORQ", "min"),
    ("shaking force", "SHAK", "max"),
    ("shaking moment, largest magnitude", "SHAKM", "maxabs"),
    ("load on pin O2 (FOA)", "FOA", "max"),
    ("load on pin A (FA32)", "FA32", "max"),
    ("load on pin B (FB34)", "FB34", "max"),
    ("load on pin O4 (FOB)", "FOB", "max"),
    ("transmission angle, least", "GAMMA", "min"),
    ("transmission angle, greatest", "GAMMA", "max"),
)


def _img(data: bytes, mime: str, alt: str) -> str:
    b64 = base64.b64encode(data).decode("ascii")
    return f'<img src="data:{mime};base64,{b64}" alt="{html.escape(alt)}">'


def _figure(data: bytes, mime: str, caption: str) -> str:
    return (f"<figure>{_img(data, mime, caption)}<figcaption>{html.escape(caption)}"
            "</figcaption></figure>")


def _png(fig: Any) -> bytes:
    from sielaff.tools.plot.render import _pyplot

    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png")
    finally:
        _pyplot().close(fig)
    return buf.getvalue()


def peak_rows(deck: Deck, scene: Scene, n: int = 3600) -> list[tuple[str, float, str, float]]:
    """(label, value, unit, THETA 2 [deg]) of each of :data:`PEAKS` over the angles the
    linkage reaches (a whole revolution when the crank turns fully)."""
    from sielaff.engine import analyze, reachable
    from sielaff.quantities import unit

    m = deck.mechanism
    th = reachable(m, n)
    names = sorted({p[1] for p in PEAKS})
    with np.errstate(all="ignore"):
        import warnings

        from sielaff.engine import AssemblyWarning

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AssemblyWarning)
            r = analyze(m, th, names, scene=scene)
    rows = []
    for label, name, how in PEAKS:
        v = np.where(np.isfinite(r[name]), r[name], np.nan)
        if not np.any(np.isfinite(v)):
            continue
        i = int(np.nanargmax(np.abs(v) if how == "maxabs" else -v if how == "min" else v))
        rows.append((label, float(v[i]), unit(name, m.units), float(th[i])))
    return rows


def _peaks_table(rows: list[tuple[str, float, str, float]]) -> str:
    out = ["<table><tr><th>peak</th><th>value</th><th>unit</th><th>at THETA 2</th></tr>"]
    for label, value, u, at in rows:
        out.append(f"<tr><td>{html.escape(label)}</td><td>{value:.5g}</td>"
                   f"<td>{html.escape(u)}</td><td>{at:.1f} deg</td></tr>")
    out.append("</table>")
    return "\n".join(out)


#: A sweep larger than this is summarised by ``sielaff sweep``, not run for a page.
SWEEP_LIMIT = 20_000
#: Rows of the Pareto front shown.
FRONT_ROWS = 15


def sweep_section(path: str, deck: Deck, scene: Scene) -> list[str]:
    """For a spec with a ``[sweep]``: its Pareto front as a table (the designs no other
    beats in both figures, by the first) and the Pareto picture; nothing otherwise."""
    from sielaff.design.sweep import Grid, column_units, columns, iter_blocks
    from sielaff.tools.spec import read_spec, sweep_of
    from sielaff.tools.sweep import _pareto, _plot

    if not path.endswith(".toml"):
        return []
    spec = read_spec(path)
    if "sweep" not in spec:
        return []
    sw = sweep_of(spec, path)
    grid = Grid(deck.mechanism, sw["axes"])
    out = ["<h2>The sweep</h2>"]
    if grid.size > SWEEP_LIMIT:
        return out + [f"<p>{grid.size:,} designs: more than a page runs "
                      f"({SWEEP_LIMIT:,}); <code>sielaff sweep</code> evaluates them.</p>"]
    cols = columns(grid)
    data = np.concatenate(list(iter_blocks(grid, sw["angles"], sw["cf"], scene)), axis=0)
    px, py = sw["pareto"]
    x, y = data[:, cols.index(px)], data[:, cols.index(py)]
    front = _pareto(x, y)
    units = column_units(cols, deck.mechanism.units)
    shown = ["DESIGN", *grid.names, px, py]
    out.append(f"<p>{grid.size:,} designs ({' x '.join(str(n) for n in grid.shape)}: "
               f"{html.escape(', '.join(grid.names))}); the Pareto front of {px} and {py} "
               f"(both minimised) has {len(front)} designs; the first "
               f"{min(len(front), FRONT_ROWS)} by {px}:</p>")
    rows = ["<table><tr>" + "".join(
        f"<th>{html.escape(c)}" + (f" [{html.escape(units[c])}]" if units[c] != "-" else "")
        + "</th>" for c in shown) + "</tr>"]
    for i in front[:FRONT_ROWS]:
        rows.append("<tr>" + "".join(f"<td>{data[i, cols.index(c)]:.5g}</td>" for c in shown)
                    + "</tr>")
    rows.append("</table>")
    buf = io.BytesIO()
    _plot(buf, x, y, (px, py), deck.mechanism.units, grid.size)
    return out + rows + [_figure(buf.getvalue(), "image/png",
                                 f"The sweep's designs and the Pareto front of {px} and {py}")]


def report_html(deck: Deck, scene: Scene, command: str, at: float = 40.0) -> str:
    """The whole page for ``deck`` in ``scene`` (see the module doc)."""
    from sielaff.design.balance import balance
    from sielaff.design.report import balance_lines
    from sielaff.engine import linkage_class
    from sielaff.tools.check import check_deck
    from sielaff.tools.common import describe_scene
    from sielaff.tools.plot import plot_data, render_png
    from sielaff.tools.plot.bearings import bearings_figure
    from sielaff.tools.plot.linkage import _animation, _draw_linkage, linkage_data
    from sielaff.tools.plot.render import _pyplot
    from sielaff.version import __version__

    m = deck.mechanism
    name = os.path.basename(deck.path)
    c = linkage_class(m)
    effects = describe_scene(scene, m.units) or "the 1966 scene (constant crank speed, " \
        "no gravity, TEX = 0 the only load, the open branch)"
    parts = [
        "<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
        # nothing may load from anywhere: images are data: URIs, the style is inline
        '<meta http-equiv="Content-Security-Policy" content="default-src \'none\'; '
        'img-src data:; style-src \'unsafe-inline\'">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>sielaff report: {html.escape(name)}</title>",
        f"<style>{STYLE}</style>", "</head>", "<body>",
        f"<h1>sielaff report: {html.escape(name)}</h1>",
        f'<p class="sub">A {html.escape(c.kind)} in {html.escape(m.units)} units; '
        f"scene: {html.escape(effects)}.</p>",
    ]
    plt = _pyplot()
    # the linkage, drawn and animated
    parts.append("<h2>The linkage</h2>")
    fig = _draw_linkage(plt, linkage_data(deck, (at,), (), scene.branch))
    parts.append(_figure(_png(fig), "image/png",
                         f"The linkage at THETA 2 = {at:g} deg ({scene.branch} branch)"))
    # 24 frames (15 degrees apart): each costs a full redraw, and a page is read, not played
    parts.append(_figure(_animation(plt, deck, (), scene.branch, frames=24), "image/gif",
                         "One cycle of the linkage (the angles it reaches, 24 frames)"))
    # peaks
    rows = peak_rows(deck, scene)
    if rows:
        parts.append("<h2>Peaks</h2>")
        parts.append(_peaks_table(rows))
    # the report's figures and the bearings (they need a crank that turns fully)
    if c.turns_fully:
        parts.append("<h2>Figures</h2>")
        for d in plot_data(deck, None, scene).values():
            parts.append(_figure(render_png(d), "image/png", d.title.split("\n")[0]))
        fig, _ = bearings_figure(deck, scene)
        parts.append(_figure(_png(fig), "image/png",
                             "Bearing loads relative to each member (shaded: never loaded)"))
    else:
        parts.append("<p>The crank cannot turn a whole revolution: the revolution figures, "
                     "the flywheel and the bearing cycle do not apply.</p>")
    # check's report: values with units, kind, margins, toggles, quirks, flywheel, bearings
    parts.append("<h2>The check report</h2>")
    parts.append(f"<pre>{html.escape(check_deck(deck, scene=scene).text)}</pre>")
    # balancing
    if c.turns_fully:
        try:
            balanced = balance(m)
            lines = balance_lines(m, balanced, scene=scene)
        except ValueError as exc:
            lines = [f"not balanced: {exc}"]
        parts.append("<h2>Balancing</h2>")
        parts.append(f"<pre>{html.escape(chr(10).join(lines))}</pre>")
    parts += sweep_section(deck.path, deck, scene)
    parts.append(f"<footer>Made by sielaff {html.escape(__version__)} with "
                 f"<code>{html.escape(command)}</code>.</footer>")
    parts += ["</body>", "</html>", ""]
    return "\n".join(parts)


def cmd_report(args: Any) -> int:
    """``sielaff report DECK|SPEC -o FILE.html`` (``-o -``: stdout)."""
    from sielaff.tools.common import CommandError, load_scene, refuse_bad_output
    from sielaff.tools.output import atomic_output

    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise CommandError("sielaff: report needs matplotlib: pip install -e \".[plot]\"") \
            from None
    if args.output != "-":
        refuse_bad_output(args.output, [args.deck])
    deck, scene = load_scene(args.deck, any_linkage=True)
    if args.branch:
        scene = scene.replace(branch=args.branch)
    import shlex

    command = "sielaff " + shlex.join(getattr(args, "argv", ["report", args.deck, "-o",
                                                              args.output]))
    with np.errstate(all="ignore"):
        page = report_html(deck, scene, command, at=args.at)
    if args.output == "-":
        sys.stdout.write(page)
        return 0
    with atomic_output(args.output) as out:
        out.write(page)
    return 0
