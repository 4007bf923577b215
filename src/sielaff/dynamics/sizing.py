"""Motor sizing: what a motor must give for a simulated run (issue 33).

``sizing(sim)`` reads a :class:`~sielaff.dynamics.simulate.Simulation` and answers "what
motor do I need?" with the figures a motor's data sheet is read against:

* the motor's torque over the running window: largest, smallest, mean and RMS (the RMS
  is what heats the motor: its continuous rating), and the largest over the whole run,
  start-up included (what its peak rating must cover);
* the shaft power ``P = MOTOR x TH2D``: mean and largest, and the smallest;
* the crank speed: smallest, largest, the time average ``angle turned / time`` and the
  coefficient of fluctuation ``(max - min) / mean``;
* for an induction motor, the slip at the mean speed, ``(ws - w) / ws``.

The running window is the periodic steady state for ``steady`` runs, the last whole
revolution of a run that made more than one, and else the whole run.  Averages are over
time (trapezoids on the samples' times), never over crank angle.

Warnings, each one sentence: the motor runs as a generator (its power is negative:
the linkage drives it) for a share of the window, or the crank runs above an induction
motor's synchronous speed (the same thing, said in the motor's terms).

Units: torques in the mechanism's torque unit (in-lb or N m), power in in-lb/sec or W,
speeds in rad/sec or rad/s (:func:`sielaff.quantities.unit_of`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from sielaff.quantities import unit_of

__all__ = ["sizing", "sizing_lines"]

#: The figures, in order: (key, words, kind of quantity for its unit).
FIGURES = (
    ("MOTOR_MAX", "largest torque", "torque"),
    ("MOTOR_MIN", "smallest torque", "torque"),
    ("MOTOR_MEAN", "mean torque", "torque"),
    ("MOTOR_RMS", "RMS torque (the continuous rating)", "torque"),
    ("START_PEAK", "largest |torque| over the whole run (start-up included)", "torque"),
    ("POWER_MEAN", "mean power", "power"),
    ("POWER_MAX", "largest power", "power"),
    ("POWER_MIN", "smallest power", "power"),
    ("SPEED_MIN", "slowest crank speed", "rate"),
    ("SPEED_MAX", "fastest crank speed", "rate"),
    ("SPEED_MEAN", "mean crank speed (time average)", "rate"),
    ("FLUCTUATION", "coefficient of speed fluctuation (max - min) / mean", "number"),
    ("SLIP", "slip at the mean speed (ws - w) / ws", "number"),
)


def _mean(t: np.ndarray, x: np.ndarray) -> float:
    span = float(t[-1] - t[0])
    if not span > 0.0:
        return float(x[-1])
    return float(np.sum((x[1:] + x[:-1]) * np.diff(t)) / (2.0 * span))


def _share(t: np.ndarray, mask: np.ndarray) -> float:
    """The share of the window's time where ``mask`` holds (samples' intervals)."""
    span = float(t[-1] - t[0])
    if not span > 0.0:
        return float(mask[-1])
    both = (mask[1:] & mask[:-1]).astype(float) + 0.5 * (mask[1:] ^ mask[:-1])
    return float(np.sum(both * np.diff(t)) / span)


def sizing(sim: Any) -> dict[str, Any]:
    """The motor sizing figures of a simulation.

    Parameters
    ----------
    sim : Simulation
        A run of :func:`sielaff.dynamics.simulate` [its own units].

    Returns
    -------
    dict
        ``window`` (words: which samples), ``units`` (a unit for each figure), each key
        of :data:`FIGURES` [its unit] (``SLIP`` only for an induction motor), and
        ``warnings`` (sentences).
    """
    units = getattr(sim, "mechanism_units", "in-lb-sec")
    t = np.asarray(sim["t"], dtype=float)
    ath2 = np.asarray(sim["ATH2"], dtype=float)
    w = np.asarray(sim["TH2D"], dtype=float)
    mt = np.asarray(sim["MOTOR"], dtype=float)
    made = (ath2[-1] - ath2[0]) / 360.0
    if sim.steady:
        window, sel = "the periodic steady state (one revolution)", slice(None)
    elif made > 1.0:
        first = int(np.searchsorted(ath2, ath2[-1] - 360.0, side="left"))
        sel = slice(max(first - 1, 0), None)
        window = f"the last revolution, t = {t[sel][0]:.4g} to {t[-1]:.4g} s"
    else:
        window, sel = "the whole run (less than a revolution)", slice(None)
    tw, ww, mw = t[sel], w[sel], mt[sel]
    pw = mw * ww
    span = float(tw[-1] - tw[0])
    turned = math.radians(float(ath2[sel][-1] - ath2[sel][0]))
    mean_speed = turned / span if span > 0.0 else float(ww[-1])
    out: dict[str, Any] = {
        "window": window,
        "MOTOR_MAX": float(np.max(mw)), "MOTOR_MIN": float(np.min(mw)),
        "MOTOR_MEAN": _mean(tw, mw), "MOTOR_RMS": math.sqrt(max(_mean(tw, mw * mw), 0.0)),
        "POWER_MEAN": _mean(tw, pw), "POWER_MAX": float(np.max(pw)),
        "POWER_MIN": float(np.min(pw)),
        "SPEED_MIN": float(np.min(ww)), "SPEED_MAX": float(np.max(ww)),
        "SPEED_MEAN": mean_speed,
        "FLUCTUATION": (float(np.max(ww) - np.min(ww)) / mean_speed if mean_speed > 0.0
                        else math.nan),
    }
    if not sim.steady:
        out["START_PEAK"] = float(np.max(np.abs(mt)))
    warnings: list[str] = []
    ru, pu = unit_of("rate", units), unit_of("power", units)
    params = dict(getattr(getattr(sim, "motor", None), "parameters", ()) or ())
    kind = getattr(getattr(sim, "motor", None), "kind", None)
    if kind == "induction":
        ws = params["synchronous_speed"]
        out["SLIP"] = (ws - mean_speed) / ws
        above = _share(tw, ww > ws)
        if above > 0.0:
            warnings.append(
                f"the crank runs above the synchronous speed {ws:.6g} {ru} for "
                f"{100.0 * above:.3g}% of {window}: the linkage drives the motor (a "
                f"generator) there")
    gen = _share(tw, pw < 0.0)
    if gen > 0.0 and not (kind == "induction" and warnings):
        warnings.append(
            f"the motor runs as a generator (its power negative, down to "
            f"{out['POWER_MIN']:.4g} {pu}: the linkage drives it) for {100.0 * gen:.3g}% "
            f"of {window}")
    out["warnings"] = warnings
    out["units"] = {key: unit_of(what, units) for key, _, what in FIGURES}
    return out


def sizing_lines(sim: Any) -> list[str]:
    """The sizing as lines of text, each figure with its unit, then the warnings."""
    s = sizing(sim)
    lines = [f"motor sizing over {s['window']}:"]
    for key, words, _ in FIGURES:
        if key not in s:
            continue
        u = s["units"][key]
        lines.append(f"  {words}: {s[key]:.6g}{'' if u == '-' else ' ' + u}")
    lines += [f"warning: {text}" for text in s["warnings"]]
    return lines
