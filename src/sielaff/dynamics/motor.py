"""Motors: a drive torque as a function of the crank speed.

A motor is any callable ``torque(TH2D)`` [in-lb or N m, CCW +] of the crank speed TH2D
[rad/sec]; it must accept a float and a numpy array.  :class:`Motor` gives the common
curves:

* ``Motor.constant(torque)``: the same torque at every speed.
* ``Motor.linear(stall_torque, no_load_speed)``: a DC shunt (or permanent-magnet)
  motor's straight speed-torque line, ``T = stall_torque (1 - w / no_load_speed)``.
* ``Motor.induction(rated_torque, rated_speed, breakdown_torque, synchronous_speed)``:
  an induction motor's slip curve by Kloss's formula
  ``T = 2 Tb / (s / sb + sb / s)``, slip ``s = (ws - w) / ws``, as written (with the
  overload ratio K = Tb / Tr) in "Motor-Mechanical Features" (franker, cnblogs, 2013,
  https://www.cnblogs.com/franker/articles/3416229.html).  The breakdown slip ``sb``
  follows from the rated point by solving Kloss's formula at ``(sr, Tr)``:
  ``sb = sr (K + sqrt(K^2 - 1))`` (the root on the stable side, sb > sr).  That page
  prints ``sqrt(K^2 + 1)``, which does not put the rated point on its own curve; the
  tests check ours does (``T(rated_speed) = rated_torque``, the peak at ``sb``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Motor"]


def _positive(name: str, v: Any) -> float:
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise ValueError(f"Motor {name} = {v!r}: not a number") from None
    if not (math.isfinite(x) and x > 0.0):
        raise ValueError(f"Motor {name} = {v!r}: a finite number above 0")
    return x


@dataclass(frozen=True)
class Motor:
    """A speed-torque curve (``kind`` and its parameters); call it with TH2D [rad/sec].

    Build one with :meth:`constant`, :meth:`linear` or :meth:`induction`.
    """

    kind: str
    parameters: tuple[tuple[str, float], ...]

    def __call__(self, th2d: Any) -> Any:
        p = dict(self.parameters)
        w = np.asarray(th2d, dtype=float)
        if self.kind == "constant":
            out = np.full_like(w, p["torque"])
        elif self.kind == "linear":
            out = p["stall_torque"] * (1.0 - w / p["no_load_speed"])
        else:
            ws, sb, tb = p["synchronous_speed"], p["breakdown_slip"], p["breakdown_torque"]
            s = (ws - w) / ws
            with np.errstate(divide="ignore", invalid="ignore"):
                out = np.where(s == 0.0, 0.0, 2.0 * tb / (s / sb + sb / np.where(s == 0, 1, s)))
        return float(out) if np.ndim(out) == 0 else out

    @property
    def stiffness(self) -> float:
        """-dT/dw at the working point's side [torque per rad/sec]: how hard the motor
        holds its speed (0 for a constant torque; the steepest, at synchronous speed,
        for an induction motor)."""
        p = dict(self.parameters)
        if self.kind == "constant":
            return 0.0
        if self.kind == "linear":
            return p["stall_torque"] / p["no_load_speed"]
        return 2.0 * p["breakdown_torque"] / (p["breakdown_slip"] * p["synchronous_speed"])

    @property
    def speed_scale(self) -> float:
        """A speed typical of the motor [rad/sec] (0 when it has none)."""
        p = dict(self.parameters)
        return p.get("no_load_speed", p.get("synchronous_speed", 0.0))

    def describe(self, units: str = "in-lb-sec") -> str:
        """One line: the kind and its parameters, each with its unit in the unit system
        ``units`` (``"in-lb-sec"`` or ``"SI"``)."""
        from sielaff.quantities import fmt

        kinds = {"torque": "torque", "stall_torque": "torque", "rated_torque": "torque",
                 "breakdown_torque": "torque", "no_load_speed": "rate",
                 "synchronous_speed": "rate", "rated_speed": "rate",
                 "breakdown_slip": "number"}
        return f"{self.kind} motor: " + ", ".join(
            f"{k} = {fmt(v, kinds[k], units, '.6g')}" for k, v in self.parameters)

    @classmethod
    def constant(cls, torque: float) -> Motor:
        """The same ``torque`` [in-lb or N m] at every speed (it may be 0 or negative)."""
        try:
            t = float(torque)
        except (TypeError, ValueError):
            raise ValueError(f"Motor torque = {torque!r}: not a number") from None
        if not math.isfinite(t):
            raise ValueError(f"Motor torque = {torque!r}: not finite")
        return cls("constant", (("torque", t),))

    @classmethod
    def linear(cls, stall_torque: float, no_load_speed: float) -> Motor:
        """A straight speed-torque line: ``stall_torque`` [in-lb or N m] at rest, none at
        ``no_load_speed`` [rad/sec] (a DC shunt motor)."""
        return cls("linear", (("stall_torque", _positive("stall_torque", stall_torque)),
                              ("no_load_speed", _positive("no_load_speed", no_load_speed))))

    @classmethod
    def induction(cls, rated_torque: float, rated_speed: float, breakdown_torque: float,
                  synchronous_speed: float) -> Motor:
        """Kloss's slip curve through the rated point (``rated_torque`` [in-lb or N m] at
        ``rated_speed`` [rad/sec]) with the peak ``breakdown_torque`` [in-lb or N m];
        no torque at ``synchronous_speed`` [rad/sec]."""
        tr = _positive("rated_torque", rated_torque)
        wr = _positive("rated_speed", rated_speed)
        tb = _positive("breakdown_torque", breakdown_torque)
        ws = _positive("synchronous_speed", synchronous_speed)
        if not wr < ws:
            raise ValueError(f"Motor rated_speed = {wr:g} rad/sec: must be below the "
                             f"synchronous speed {ws:g} rad/sec (an induction motor slips)")
        if not tb > tr:
            raise ValueError(f"Motor breakdown_torque = {tb:g}: must be above the rated "
                             f"torque {tr:g}")
        k = tb / tr
        sr = (ws - wr) / ws
        sb = sr * (k + math.sqrt(k * k - 1.0))
        return cls("induction", (("rated_torque", tr), ("rated_speed", wr),
                                 ("breakdown_torque", tb), ("synchronous_speed", ws),
                                 ("breakdown_slip", sb)))
