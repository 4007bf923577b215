"""``sielaff plot --linkage``: the linkage itself to scale (the report's Figure 9), and
``--animate``: one cycle as a GIF (drawn by blitting, written by Pillow)."""

from __future__ import annotations

import io
import math
import os
import warnings
from dataclasses import dataclass

import numpy as np

from sielaff.emulator.cards import Deck
from sielaff.tools.plot.render import _pyplot, _subtitle, write_files


@dataclass
class LinkageData:
    """The data behind a drawing of the linkage: for each drawn THETA 2, the joints and
    centres of mass (``joints[name] = (x, y)`` arrays over ``at``), the curves traced by
    G3 and the extra points over the angles the linkage reaches, and its toggles."""

    at: np.ndarray
    joints: dict[str, tuple[np.ndarray, np.ndarray]]
    curves: dict[str, tuple[np.ndarray, np.ndarray]]
    toggles: list[float]
    title: str
    units: str


def linkage_data(deck: Deck, at=(40.0,), points=(), branch: str = "open") -> LinkageData:
    """Joints O2, A, B, O4, G2, G3, G4 at the angles ``at`` (degrees), and the curves of G3
    and of ``points`` ((link, r, angle) tuples) over the angles the linkage reaches."""
    from sielaff.engine import AssemblyWarning, linkage_class, point_motion, reachable
    from sielaff.quantities import unit

    m = deck.mechanism
    at = np.atleast_1d(np.asarray(at, dtype=float))

    def xy(link, r, angle, th):
        p = point_motion(m, th, link, r, angle, branch=branch)
        return p["X"], p["Y"]

    zero = np.zeros_like(at)
    with warnings.catch_warnings():  # the engine's words; the user's are below
        warnings.simplefilter("ignore", AssemblyWarning)
        joints = {"O2": (zero, zero), "O4": (zero + m.R1, zero), "A": xy(2, m.R2, 0.0, at),
                  "B": xy(4, m.R4, 0.0, at), "G2": xy(2, m.RG2, m.ADEL2, at),
                  "G3": xy(3, m.RG3, m.ADEL3, at), "G4": xy(4, m.RG4, m.ADEL4, at)}
    apart = at[~np.isfinite(joints["B"][0])]
    if apart.size:
        warnings.warn(f"{deck.path}: --at {','.join(f'{a:g}' for a in apart)}: the linkage "
                      "cannot be put together at "
                      f"{'this crank angle' if apart.size == 1 else 'these crank angles'} "
                      "(link 3 does not reach link 4 there); the drawing leaves "
                      f"{'it' if apart.size == 1 else 'them'} out", stacklevel=2)
    sweep = reachable(m, 721)
    curves = {"G3": xy(3, m.RG3, m.ADEL3, sweep)}
    for k, (link, r, angle) in enumerate(points, 1):
        curves[f"P{k} (link {link}, {r:g}, {angle:g} deg)"] = xy(link, r, angle, sweep)
    c = linkage_class(m)
    toggles = [float(t) for t in np.ravel(c.toggles) if np.isfinite(t)]
    kind = c.kind
    title = (f"The linkage ({kind}, {branch} branch) at THETA 2 = "
             + ", ".join(f"{a:g}" for a in at) + f" deg\n{_subtitle(deck)}")
    return LinkageData(at, joints, curves, toggles, title,
                       unit("R1", getattr(m, "units", "in-lb-sec")))


def _draw_linkage(plt, d: LinkageData, frame: int | None = None):
    """The drawing: every angle of ``d.at`` (the first solid, the rest faint), or one."""
    fig, ax = plt.subplots(figsize=(9, 6.4), dpi=100, layout="constrained")
    _linkage_axes(ax, d, frame)
    fig.legend(loc="outside lower center", ncol=3, frameon=False, fontsize=9)
    return fig


def _linkage_axes(ax, d: LinkageData, frame: int | None) -> None:
    ax.set_aspect("equal")
    for name, (x, y) in d.curves.items():
        ax.plot(x, y, lw=1.0, ls="--", label=f"path of {name}")
    for k in (range(len(d.at)) if frame is None else [frame]):
        alpha = 1.0 if frame is not None or k == 0 else 0.35
        _links(ax, d, k, alpha, labelled=k == 0)
    _frame_and_toggles(ax, d)
    _names(ax, d, 0 if frame is None else frame)
    ax.set_xlabel(f"x ({d.units}), O2 to O4")
    ax.set_ylabel(f"y ({d.units})")
    ax.set_title(_title(d, frame), fontsize=10)
    ax.grid(True, color="0.9")


def _title(d: LinkageData, frame: int | None) -> str:
    return d.title if frame is None else (d.title.split(" at THETA 2")[0]
                                          + f" at THETA 2 = {d.at[frame]:.0f} deg")


def _joints(d: LinkageData, k: int) -> dict[str, tuple[float, float]]:
    return {n: (x[k], y[k]) for n, (x, y) in d.joints.items()}


#: The moving links: (from joint, to joint, colour, legend label).
_LINKS = (("O2", "A", "tab:red", "link 2 (crank)"), ("A", "B", "tab:green", "link 3 (coupler)"),
          ("O4", "B", "tab:purple", "link 4 (rocker)"))


def _links(ax, d: LinkageData, k: int, alpha: float, labelled: bool) -> list:
    """The three moving links and the centres of mass at angle ``k``: their artists
    (the links in :data:`_LINKS` order, then the centres of mass)."""
    j = _joints(d, k)
    out = [ax.plot([j[a][0], j[b][0]], [j[a][1], j[b][1]], color=color, lw=4,
                   solid_capstyle="round", alpha=alpha, label=label if labelled else None)[0]
           for a, b, color, label in _LINKS]
    out += ax.plot([j[n][0] for n in ("G2", "G3", "G4")], [j[n][1] for n in ("G2", "G3", "G4")],
                   "D", color="tab:orange", ms=6, alpha=alpha,
                   label="centres of mass" if labelled else None)
    return out


def _frame_and_toggles(ax, d: LinkageData) -> list:
    """The frame (link 1) and the toggle limits of link 2: their artists."""
    out = ax.plot([0.0, d.joints["O4"][0][0]], [0.0, 0.0], "s:", color="0.3", ms=9, lw=1.5,
                  label="frame (link 1)")
    reach = 0.25 * d.joints["O4"][0][0]
    for n, t in enumerate(d.toggles):
        out += ax.plot([0, reach * math.cos(math.radians(t))],
                       [0, reach * math.sin(math.radians(t))], color="0.5", lw=0.8,
                       label="toggle limits of link 2" if n == 0 else None)
    return out


def _names(ax, d: LinkageData, k: int) -> list:
    """Each joint's name beside it at angle ``k``: the annotations, in ``d.joints`` order."""
    return [ax.annotate(name, xy, xytext=(7, 7), textcoords="offset points", fontsize=9)
            for name, xy in _joints(d, k).items()]


def write_linkage(deck: Deck, directory: str, at=(40.0,), points=(), branch: str = "open",
                  animate: bool = False) -> list[str]:
    """``linkage.png`` (and ``linkage.gif``, one cycle, with ``animate``), all or none."""
    plt = _pyplot()
    d = linkage_data(deck, at, points, branch)
    images = {}
    fig = _draw_linkage(plt, d)
    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png")
    finally:
        plt.close(fig)
    images[os.path.join(directory, "linkage.png")] = buf.getvalue()
    if animate:
        images[os.path.join(directory, "linkage.gif")] = _animation(plt, deck, points, branch)
    write_files(images)
    return list(images)


def _animation(plt, deck: Deck, points, branch: str, frames: int = 36) -> bytes:
    """One cycle (the angles the linkage reaches) as a GIF, ``frames`` pictures at 12 a
    second.

    The figure is laid out and drawn once without the parts that move (the paths, the
    frame, the toggles, the axes and their labels); each frame then puts back that
    picture and draws over it only the links, the centres of mass, the joints' names, the
    title, and the frame and toggles that lie over the links (blitting, as matplotlib's
    animations do), so a frame costs a few artists, not a whole figure.  The frames share
    one palette (:func:`_gif`): the drawing is a few flat colours and their anti-aliased
    edges, and one palette keeps them from flickering between frames.
    """
    from sielaff.engine import reachable

    cycle = reachable(deck.mechanism, frames)
    if not np.size(cycle):
        raise ValueError(f"{deck.path}: --animate: the linkage cannot be put together at any "
                         "crank angle (link 3 never reaches link 4): there is no cycle to show")
    d = linkage_data(deck, cycle, points, branch)
    fig, ax = plt.subplots(figsize=(7, 5), dpi=80, layout="constrained")
    try:
        xs = np.concatenate([np.ravel(x) for x, _ in (*d.joints.values(), *d.curves.values())])
        ys = np.concatenate([np.ravel(y) for _, y in (*d.joints.values(), *d.curves.values())])
        pad = 0.08 * (np.nanmax(xs) - np.nanmin(xs))
        ax.set_aspect("equal")
        for name, (x, y) in d.curves.items():
            ax.plot(x, y, lw=1.0, ls="--", label=f"path of {name}")
        moving = _links(ax, d, 0, 1.0, labelled=True)
        fixed = _frame_and_toggles(ax, d)  # drawn over the links, as in a still drawing
        names = _names(ax, d, 0)
        ax.set_xlabel(f"x ({d.units}), O2 to O4")
        ax.set_ylabel(f"y ({d.units})")
        # the layout is made for the longest title, then frozen: every frame the same
        title = ax.set_title(max((_title(d, k) for k in range(len(d.at))), key=len),
                             fontsize=10)
        ax.grid(True, color="0.9")
        ax.set_xlim(np.nanmin(xs) - pad, np.nanmax(xs) + pad)
        ax.set_ylim(np.nanmin(ys) - pad, np.nanmax(ys) + pad)
        fig.get_layout_engine().execute(fig)  # the layout, without drawing
        fig.set_layout_engine("none")
        animated = [*moving, *fixed, *names, title]
        for a in animated:
            a.set_animated(True)
        fig.canvas.draw()
        background = fig.canvas.copy_from_bbox(fig.bbox)
        pictures = []
        for k in range(len(d.at)):
            j = _joints(d, k)
            for line, (a, b, _, _) in zip(moving, _LINKS):
                line.set_data([j[a][0], j[b][0]], [j[a][1], j[b][1]])
            moving[-1].set_data([j[n][0] for n in ("G2", "G3", "G4")],
                                [j[n][1] for n in ("G2", "G3", "G4")])
            for note, xy in zip(names, j.values()):
                note.xy = xy
            title.set_text(_title(d, k))
            fig.canvas.restore_region(background)
            for a in animated:
                fig.draw_artist(a)
            pictures.append(np.asarray(fig.canvas.buffer_rgba())[..., :3].copy())
    finally:
        plt.close(fig)
    return _gif(pictures, fps=12)


#: Colours in the GIF's one palette.
GIF_COLOURS = 64


def _gif(pictures: list[np.ndarray], fps: int) -> bytes:
    """RGB pictures (uint8, (h, w, 3)) as a looping GIF with one palette: Pillow's median
    cut of the first picture, each pixel of every picture given its nearest colour
    there (exactly, over the picture's distinct colours; Pillow's own mapping onto a given
    palette is approximate and turns white into grey)."""
    from PIL import Image

    first = Image.fromarray(pictures[0]).quantize(colors=GIF_COLOURS,
                                                  method=Image.Quantize.MEDIANCUT,
                                                  dither=Image.Dither.NONE)
    palette = first.getpalette()[:3 * GIF_COLOURS]
    rgb = np.asarray(palette, dtype=np.int32).reshape(-1, 3)
    frames = []
    for p in pictures:
        packed = (p[..., 0].astype(np.int32) << 16) | (p[..., 1].astype(np.int32) << 8) \
            | p[..., 2]
        colours, where = np.unique(packed, return_inverse=True)
        c = np.stack([colours >> 16, (colours >> 8) & 255, colours & 255], axis=1)
        nearest = np.argmin(((c[:, None, :] - rgb[None, :, :]) ** 2).sum(axis=-1), axis=1)
        im = Image.fromarray(nearest.astype(np.uint8)[where].reshape(p.shape[:2]), mode="P")
        im.putpalette(palette)
        frames.append(im)
    buf = io.BytesIO()
    frames[0].save(buf, format="GIF", save_all=True, append_images=frames[1:],
                   duration=1000 // fps, loop=0)
    return buf.getvalue()
