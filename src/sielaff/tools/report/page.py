"""The report's page: its style, head and footer, and the inline images every section
uses (no file is fetched: images are ``data:`` URIs, the style is inline)."""

from __future__ import annotations

import base64
import html
import io
import os
from typing import Any

__all__ = ["STYLE", "figure", "head", "made_on", "page", "png"]

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
figure img { max-width: 100%; box-sizing: border-box; border: 1px solid #eee; }
figcaption { color: #444; font-size: 0.9em; }
.wide { overflow-x: auto; }
table.small { font-size: 0.8em; }
footer { margin-top: 3em; color: #555; font-size: 0.85em; border-top: 1px solid #ccc; }
@media print {
  body { margin: 0; max-width: none; } h2 { page-break-after: avoid; }
  /* a printed page cannot scroll: wide tables shrink and wrap to its width */
  .wide { overflow: visible; }
  table { max-width: 100%; }
  table.small { font-size: 0.58em; width: 100%; table-layout: fixed; }
  table.small th, table.small td { padding: 0.1em 0.15em; overflow-wrap: anywhere; }
}
"""

def _img(data: bytes, mime: str, alt: str) -> str:
    b64 = base64.b64encode(data).decode("ascii")
    return f'<img src="data:{mime};base64,{b64}" alt="{html.escape(alt)}">'


def figure(data: bytes, mime: str, caption: str) -> str:
    return (f"<figure>{_img(data, mime, caption)}<figcaption>{html.escape(caption)}"
            "</figcaption></figure>")


def png(fig: Any) -> bytes:
    from sielaff.tools.plot.render import _pyplot

    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png")
    finally:
        _pyplot().close(fig)
    return buf.getvalue()


def head(name: str) -> list[str]:
    """The page's head and its title: ``name`` is the input file's."""
    return [
        "<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
        # nothing may load from anywhere: images are data: URIs, the style is inline
        '<meta http-equiv="Content-Security-Policy" content="default-src \'none\'; '
        'img-src data:; style-src \'unsafe-inline\'">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>sielaff report: {html.escape(name)}</title>",
        f"<style>{STYLE}</style>", "</head>", "<body>",
        f"<h1>sielaff report: {html.escape(name)}</h1>",
    ]


def page(parts: list[str], command: str) -> str:
    """``parts`` (from :func:`head` on) with the footer: the version and the command."""
    from sielaff.version import __version__

    return "\n".join(parts + [
        f"<footer>Made by sielaff {html.escape(__version__)} on {made_on()} with "
        f"<code>{html.escape(command)}</code>.</footer>", "</body>", "</html>", ""])


def made_on() -> str:
    """The page's date: now, or ``SOURCE_DATE_EPOCH`` when set (a page made twice from
    the same input is then the same bytes: reproducible builds' convention)."""
    import time

    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    try:
        when = time.gmtime(int(epoch)) if epoch else time.gmtime()
    except (ValueError, OverflowError, OSError):
        when = time.gmtime()
    return time.strftime("%Y-%m-%d %H:%M UTC", when)


