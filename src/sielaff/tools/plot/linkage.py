"""``sielaff plot --linkage``: the linkage itself to scale (the report's Figure 9), and
``--animate``: one cycle as a GIF through matplotlib's Pillow writer."""

from __future__ import annotations

import io
import math
import os
import tempfile
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
        j = {n: (x[k], y[k]) for n, (x, y) in d.joints.items()}
        for a, b, color, label in (("O2", "A", "tab:red", "link 2 (crank)"),
                                   ("A", "B", "tab:green", "link 3 (coupler)"),
                                   ("O4", "B", "tab:purple", "link 4 (rocker)")):
            ax.plot([j[a][0], j[b][0]], [j[a][1], j[b][1]], color=color, lw=4,
                    solid_capstyle="round", alpha=alpha, label=label if k == 0 else None)
        ax.plot([j[n][0] for n in ("G2", "G3", "G4")], [j[n][1] for n in ("G2", "G3", "G4")],
                "D", color="tab:orange", ms=6, alpha=alpha,
                label="centres of mass" if k == 0 else None)
    ax.plot([0.0, d.joints["O4"][0][0]], [0.0, 0.0], "s:", color="0.3", ms=9, lw=1.5,
            label="frame (link 1)")
    k = 0 if frame is None else frame
    for name, (x, y) in d.joints.items():
        ax.annotate(name, (x[k], y[k]), xytext=(7, 7), textcoords="offset points", fontsize=9)
    reach = 0.25 * d.joints["O4"][0][0]
    for n, t in enumerate(d.toggles):
        ax.plot([0, reach * math.cos(math.radians(t))], [0, reach * math.sin(math.radians(t))],
                color="0.5", lw=0.8, label="toggle limits of link 2" if n == 0 else None)
    ax.set_xlabel(f"x ({d.units}), O2 to O4")
    ax.set_ylabel(f"y ({d.units})")
    title = d.title if frame is None else (d.title.split(" at THETA 2")[0]
                                           + f" at THETA 2 = {d.at[frame]:.0f} deg")
    ax.set_title(title, fontsize=10)
    ax.grid(True, color="0.9")


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
    """One cycle (the angles the linkage reaches) as a GIF: matplotlib's Pillow writer
    redraws one figure's axes for each frame, at fixed limits."""
    from matplotlib.animation import PillowWriter

    from sielaff.engine import reachable

    cycle = reachable(deck.mechanism, frames)
    if not np.size(cycle):
        raise ValueError(f"{deck.path}: --animate: the linkage cannot be put together at any "
                         "crank angle (link 3 never reaches link 4): there is no cycle to show")
    d = linkage_data(deck, cycle, points, branch)
    fig, ax = plt.subplots(figsize=(7, 5), dpi=80, layout="constrained")
    xs = np.concatenate([np.ravel(x) for x, _ in (*d.joints.values(), *d.curves.values())])
    ys = np.concatenate([np.ravel(y) for _, y in (*d.joints.values(), *d.curves.values())])
    pad = 0.08 * (np.nanmax(xs) - np.nanmin(xs))
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "cycle.gif")
        writer = PillowWriter(fps=12)
        try:
            with writer.saving(fig, path, dpi=80):
                for k in range(len(d.at)):
                    ax.clear()
                    _linkage_axes(ax, d, k)
                    ax.set_xlim(np.nanmin(xs) - pad, np.nanmax(xs) + pad)
                    ax.set_ylim(np.nanmin(ys) - pad, np.nanmax(ys) + pad)
                    writer.grab_frame()
        finally:
            plt.close(fig)
        with open(path, "rb") as f:
            return f.read()
