"""What the plot command's drawings share: matplotlib (Agg, loaded only when asked for),
text boxes as the renderer measures them, the subtitle, and writing the files."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from sielaff.engine.scene import Scene

import os

from sielaff.emulator.cards import Deck


def _pyplot():
    try:
        import matplotlib
    except ImportError:
        raise ImportError("sielaff plot needs matplotlib: pip install -e \".[plot]\"") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def text_boxes(fig) -> list[tuple[str, tuple[float, float, float, float]]]:
    """Every visible, non-empty text of ``fig`` with its box in display pixels
    (x0, y0, x1, y1), as the renderer draws it: titles, tick labels, legend entries,
    annotations.  The tests check that no two of them intersect."""
    fig.draw_without_rendering()  # the layout and the texts' sizes, no pixels
    renderer = fig.canvas.get_renderer()
    from matplotlib.text import Text

    # Ticks outside the view limits keep a label that is never drawn: leave those out.
    seen, out = set(), []
    for ax in fig.axes:
        try:  # matplotlib's own list of the ticks it draws (private, since 3.x)
            axes_axes = list(ax._axis_map.values())
            drawn = {id(t) for axis in axes_axes for t in axis._update_ticks()}
        except AttributeError:  # pragma: no cover - a matplotlib without it: count all
            continue
        for axis in axes_axes:
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                if id(tick) not in drawn:
                    seen.update((id(tick.label1), id(tick.label2)))

    for t in fig.findobj(Text):  # Text and Annotation; a legend's TextArea holds a Text
        if id(t) in seen or not t.get_visible() or not str(t.get_text()).strip():
            continue
        seen.add(id(t))
        bb = Text.get_window_extent(t, renderer)  # an annotation's text, not its leader
        if bb.width > 0 and bb.height > 0:
            out.append((str(t.get_text()), (bb.x0, bb.y0, bb.x1, bb.y1)))
    return out


def overlapping(boxes) -> list[tuple[str, str]]:
    """Pairs of texts whose boxes intersect."""
    pairs = []
    for i, (ta, a) in enumerate(boxes):
        for tb, b in boxes[i + 1:]:
            if a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]:
                pairs.append((ta, tb))
    return pairs


def _subtitle(deck: Deck, scene: Scene | None = None) -> str:
    from sielaff.quantities import unit
    from sielaff.tools.common import describe_scene

    m = deck.mechanism
    system = getattr(m, "units", "in-lb-sec")
    length = unit("R1", system)
    effects = describe_scene(scene, system)
    lengths = [n for n in ("R1", "R2", "R3", "R4", "R5", "R6", "offset")
               if n in m.as_dict() and (n != "offset" or float(m.offset))]
    return (f"{os.path.basename(deck.path)}: "
            + ", ".join(f"{n} {float(getattr(m, n)):g}" for n in lengths)
            + f" {length}; TH2D {m.TH2D:g} {unit('TH2D', system)}"
            + (f"; {effects}" if effects else ""))


def write_files(images: dict[str, bytes]) -> None:
    """Write every file, all or none: temporary files first, renamed only when every one
    is written (an interruption or a failure changes no file)."""
    from sielaff.tools.output import atomic_files

    paths = list(images)
    with atomic_files(paths) as temps:
        for tmp, path in zip(temps, paths):
            with open(tmp, "wb") as f:
                f.write(images[path])


