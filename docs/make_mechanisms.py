"""Regenerate the worked examples of docs/mechanisms.md (the block between its markers).

    PYTHONPATH=src python docs/make_mechanisms.py          # rewrite the block, redraw
    PYTHONPATH=src python docs/make_mechanisms.py --print  # show it, change nothing

It also draws docs/img/mechanisms.png (each kind's example at THETA 2 = 40 deg;
matplotlib).  Every number in the block is the engine's (sielaff.analyze) on the kinds'
examples, printed to 5 significant digits (far from the roundoff of any platform); a
quantity that is zero to roundoff is printed as a bound ("< 1E-09"), never its digits.
tests/test_mechanisms_doc.py regenerates the block and compares it, number by number
within the last printed digit, with the committed one.
"""

from __future__ import annotations

import os
import re
import sys
import warnings

import numpy as np

import sielaff
from sielaff import (
    INVERTED_EXAMPLE,
    SLIDER_EXAMPLE,
    STEPHENSON_EXAMPLE,
    WATT_EXAMPLE,
    analyze,
)
from sielaff.inverted_slider_crank import quick_return
from sielaff.quantities import unit
from sielaff.slider_crank import stroke

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "mechanisms.md")
BEGIN, END = "<!-- BEGIN make_mechanisms.py -->", "<!-- END make_mechanisms.py -->"
AT = 40.0
#: (heading, the example's name in sielaff, the spec under decks/, its outputs shown)
KINDS = [
    ("Slider-crank", "SLIDER_EXAMPLE", "slider-crank.toml", SLIDER_EXAMPLE,
     ["ATH3", "TH3D", "TH3DD", "XB", "VXB", "AXB", "FOA", "FA32", "FB34", "FN", "MN",
      "TORQ", "SHAK"]),
    ("Inverted slider-crank", "INVERTED_EXAMPLE", "inverted-slider-crank.toml",
     INVERTED_EXAMPLE,
     ["ATH4", "TH4D", "TH4DD", "S", "VS", "AS", "FOA", "FA32", "FN", "MN", "FOB", "TORQ",
      "SHAK"]),
    ("Watt II six-bar", "WATT_EXAMPLE", "watt.toml", WATT_EXAMPLE,
     ["ATH3", "ATH4", "ATH5", "ATH6", "TH6D", "TH6DD", "FOA", "FA32", "FOB", "FB34", "FC54",
      "FD56", "FO6", "TORQ", "SHAK"]),
    ("Stephenson III six-bar", "STEPHENSON_EXAMPLE", "stephenson.toml", STEPHENSON_EXAMPLE,
     ["ATH3", "ATH4", "ATH5", "ATH6", "TH6D", "TH6DD", "FOA", "FA32", "FOB", "FB34", "FC53",
      "FD56", "FO6", "TORQ", "SHAK"]),
]


def g(x: float) -> str:
    """5 significant digits."""
    return f"{x:.5g}"


def bound(x: float, unit_: str) -> str:
    """A roundoff-sized quantity as a bound, so no digit of roundoff is printed."""
    for b in (1e-9, 1e-6):
        if abs(x) < b:
            return f"< {b:.0E} {unit_}"
    raise AssertionError(f"{x} is not roundoff")


def cycle_work(m) -> tuple[float, float]:
    """(integral of TORQ, of |TORQ|) d(THETA 2) over a revolution [in-lb], trapezoids on
    a 0.05 deg grid: zero to roundoff with no loss and no load (the energy comes back)."""
    th = np.linspace(0.0, 360.0, 7201)
    t = analyze(m, th, ["TORQ"])["TORQ"]
    h = np.radians(th[1] - th[0])
    return float(np.sum(t[1:] + t[:-1]) * h / 2), float(np.sum(np.abs(t[1:]) + np.abs(t[:-1]))
                                                        * h / 2)


def example(heading: str, name: str, spec: str, m, outputs: list[str]) -> list[str]:
    r = analyze(m, AT, outputs)
    fields = ", ".join(f"{k} = {g(float(v))}" for k, v in m.as_dict().items()
                       if k != "units" and not re.fullmatch(r"(W|ZI|RG|ADEL)\d", k))
    out = [f"### {heading}", "",
           f"`sielaff.{name}` (`decks/{spec}`, in-lb-sec): {fields}; weights, inertias and "
           "mass centres as the spec gives.", "",
           f"At THETA 2 = {AT:g} deg (`analyze(sielaff.{name}, {AT:g})`, the open branch, no "
           "gravity, no loads):", "",
           "| output | value | unit |", "|---|---|---|"]
    for n in outputs:
        v = float(r[n])
        # zero by construction (a slider's couple with its centre of mass on its pin):
        # a bound, never roundoff's digits
        text = bound(v, "") if abs(v) < 1e-9 else g(v)
        out.append(f"| {n} | {text.strip()} | {unit(n, m.units)} |")
    work, absolute = cycle_work(m)
    out += ["", f"Over a revolution: the cycle work of TORQ is "
                f"{bound(work, 'in-lb')} against {g(absolute)} in-lb of its absolute value "
                "(no loss, no load: the energy the drive puts in comes back)."]
    if m is SLIDER_EXAMPLE:
        s = stroke(m)
        out[-1] += (f"  Stroke {g(s.xb_outer - s.xb_inner)} in (XB from {g(s.xb_inner)} to "
                    f"{g(s.xb_outer)} in, the dead centres at THETA 2 = {g(s.at_outer)} and "
                    f"{g(s.at_inner)} deg); the crank turns {g(s.outward)} deg on the "
                    f"outward stroke and {g(s.inward)} on the inward: time ratio "
                    f"{g(max(s.outward, s.inward) / min(s.outward, s.inward))}.")
    if m is INVERTED_EXAMPLE:
        q = quick_return(m)
        out[-1] += (f"  Link 4 reverses at THETA 2 = {g(q.at[0])} and {g(q.at[1])} deg: the "
                    f"crank turns {g(q.forward)} deg on the working stroke and {g(q.back)} on "
                    f"the return, time ratio {g(q.time_ratio)}.")
    return out + [""]


def block() -> str:
    lines: list[str] = []
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for k in KINDS:
            lines += example(*k)
    return "\n".join(lines)


def figure(path: str) -> None:
    """Each kind's example drawn at THETA 2 = 40 deg, with the path of G3 and its guides."""
    from sielaff.emulator.cards import Deck
    from sielaff.tools.plot.kinds import draw, drawing_data, guides
    from sielaff.tools.plot.render import _pyplot

    plt = _pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5), layout="constrained")
    for ax, (heading, name, _, m, _) in zip(axes.flat, KINDS):
        deck = Deck(mechanism=m, ranges=[], range_cards=[], path=name)
        data = drawing_data(deck, np.array([AT]), "open")
        path_ = drawing_data(deck, np.linspace(0.0, 360.0, 361), "open")
        ax.set_aspect("equal")
        guides(ax, path_)
        draw(ax, data, 0, 1.0, labelled=False)
        for p, (x, y) in data["points"].items():
            if not p.startswith("G") and np.isfinite(x[0]):
                ax.annotate(p, (float(x[0]), float(y[0])), xytext=(6, 6),
                            textcoords="offset points", fontsize=9)
        ax.set_title(f"{heading}, THETA 2 = {AT:g} deg", fontsize=10)
        ax.set_xlabel("x (in)")
        ax.set_ylabel("y (in)")
        ax.grid(True, color="0.9")
    fig.savefig(path, dpi=90, metadata={"Software": None})
    plt.close(fig)


def main() -> None:
    text = block()
    if "--print" in sys.argv:
        print(text)
        return
    doc = open(DOC).read()
    head, rest = doc.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    with open(DOC, "w") as f:
        f.write(head + BEGIN + "\n" + text + END + tail)
    print(DOC)
    png = os.path.join(ROOT, "docs", "img", "mechanisms.png")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        figure(png)
    print(png)


if __name__ == "__main__":
    assert sielaff.__version__
    main()
