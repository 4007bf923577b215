"""The flywheel a driving torque calls for.

In:  the driving torque TORQ (in-lb or N m) over one revolution at the mean crank speed
     TH2D (rad/sec), and the coefficient of speed fluctuation ``cf`` (dimensionless).
Out: the energy fluctuation (in-lb or J), the flywheel inertia about O2 (in-lb-sec^2 or
     kg m^2), the motor's mean torque and power, and the speed with the flywheel on.

With a motor that gives the mean torque ``Tm`` (the cycle's mean of TORQ), the
flywheel gives or takes the rest, and its kinetic energy falls by

    E(th2) = integral from 0 to th2 of (TORQ - Tm) d(th2)          (th2 in radians)

The energy fluctuation is ``energy = max E - min E``.  The speed is largest where E is
least, and ``I (wmax^2 - wmin^2) / 2 = energy``.  With ``w_avg = (wmax + wmin) / 2``
and ``cf = (wmax - wmin) / w_avg`` this is exactly

    inertia = energy / (cf * w_avg^2)

with w_avg = TH2D.  As in the textbooks, TORQ is the torque at constant speed: the
fluctuation it allows must be small (cf of a few per cent) for that to hold.

E is integrated spectrally: TORQ is smooth and periodic, so the Fourier series of its
samples integrates to machine precision, and the extremes of E (where TORQ = Tm) are
found by Newton's method on that series, not taken from the grid.  ``n`` samples.

Every kind of linkage the engine analyses has a flywheel answer: the four-bar's crank is
asked whether it turns fully by its class, any other kind's by its model's ``full_turn``;
the torque is the engine's TORQ in the kind's own Scene.

The cycle need not be one crank revolution: ``cycle`` (degrees) is the crank angle over
which the torque repeats (720 for a four-stroke engine's), the samples span it, and E is
integrated over it (the series in the cycle's own angle, scaled by cycle / 360).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.design.kinds import is_four_bar, kind_name, scene_of_kind, turn_failures
from sielaff.engine.analysis import analyze
from sielaff.engine.classify import linkage_class
from sielaff.engine.scene import Scene, scene_from

__all__ = ["Flywheel", "flywheel", "flywheel_from_torque"]

#: Samples per revolution (a power of two is not needed; even is).
SAMPLES = 3600


@dataclass(frozen=True)
class Flywheel:
    """The flywheel answer (arrays over designs when the inputs are).

    ``energy``: the energy fluctuation (in-lb, or J in SI).  ``inertia``: the flywheel
    inertia about O2 for ``cf`` at the mean speed ``th2d`` (in-lb-sec^2 or kg m^2).
    ``mean_torque`` (in-lb or N m): what the motor gives with the flywheel on;
    ``mean_power`` = mean_torque * th2d (in-lb/sec or W).  ``peak_torque``: the largest
    |TORQ| without a flywheel.  ``theta2`` (degrees), ``torque`` (TORQ), ``energy_curve``
    (E), ``speed`` (rad/sec, with the flywheel) on the sample grid; ``flywheel_torque``
    = TORQ - mean_torque, what the flywheel gives.
    """

    cf: float
    th2d: Any
    energy: Any
    inertia: Any
    mean_torque: Any
    mean_power: Any
    peak_torque: Any
    theta2: np.ndarray
    torque: np.ndarray
    energy_curve: np.ndarray
    flywheel_torque: np.ndarray
    speed: np.ndarray


def _series(coef: np.ndarray, k: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Re(sum_k coef_k e^{i k theta}) over the last axis (theta broadcast against it)."""
    return np.real(np.sum(coef * np.exp(1j * k * theta[..., None]), axis=-1))


def _extreme(c_e, c_t, k, theta0, steps=4):
    """E's extreme near theta0: Newton on dE/dtheta = TORQ - Tm = 0 (series in c_t)."""
    theta = theta0
    for _ in range(steps):
        f = _series(c_t, k, theta)
        df = _series(1j * k * c_t, k, theta)
        with np.errstate(all="ignore"):
            step_ = np.where(df != 0.0, f / df, 0.0)
        theta = theta - np.clip(step_, -0.05, 0.05)
    return _series(c_e, k, theta)


def _cycle(cycle: Any) -> float:
    if isinstance(cycle, bool) or not isinstance(cycle, (int, float)) \
            or not 0.0 < cycle <= 36000.0:
        raise ValueError(f"cycle = {cycle!r}: the crank angle the torque repeats over, in "
                         "degrees (0, 36000]")
    return float(cycle)


def flywheel_from_torque(torque: Any, th2d: Any, cf: float = 0.05,
                         cycle: float = 360.0) -> Flywheel:
    """The flywheel for ``torque`` [in-lb or N m] sampled at THETA 2 = cycle j / n degrees,
    j = 0..n-1 (last axis; leading axes are designs), at mean speed ``th2d`` [rad/sec];
    ``cycle`` [deg] is the crank angle over which the torque repeats (360 by default)."""
    if not (isinstance(cf, (int, float)) and 0.0 < cf < 2.0):
        raise ValueError(f"cf = {cf!r}: the coefficient of speed fluctuation is in (0, 2)")
    span = _cycle(cycle) / 360.0       # crank radians per radian of the cycle's angle
    t = np.asarray(torque, dtype=float)
    n = t.shape[-1]
    if n < 8 or n % 2:
        raise ValueError(f"{n} torque samples: give an even number, at least 8")
    if not np.all(np.isfinite(t)):
        raise ValueError("the torque is not finite over the revolution (a toggle, or a "
                         "position that does not assemble): no flywheel answer")
    w = np.asarray(th2d, dtype=float)
    spectrum = np.fft.rfft(t, axis=-1)
    mean = spectrum[..., 0].real / n
    k = np.arange(spectrum.shape[-1], dtype=float)
    c_t = 2.0 * spectrum / n           # TORQ - Tm = Re sum_{k>=1} c_t e^{ik th}
    c_t[..., 0] = 0.0
    c_t[..., -1] = 0.0                 # the Nyquist term: no antiderivative on the grid
    c_e = np.zeros_like(c_t)
    c_e[..., 1:] = c_t[..., 1:] / (1j * k[1:])
    theta = 2.0 * np.pi * np.arange(n) / n
    g = np.fft.irfft(c_e * (n / 2.0), n, axis=-1) * span
    curve = g - g[..., :1]             # E(0) = 0
    i_max = np.argmax(curve, axis=-1)
    i_min = np.argmin(curve, axis=-1)
    e_max = _extreme(c_e, c_t, k, theta[i_max]) * span
    e_min = _extreme(c_e, c_t, k, theta[i_min]) * span
    energy = np.maximum(e_max - e_min, np.max(curve, axis=-1) - np.min(curve, axis=-1))
    with np.errstate(all="ignore"):  # TH2D = 0: the crank does not turn, no flywheel (NaN)
        inertia = np.where(w != 0.0, energy / (cf * w * w), np.nan)
    inertia = inertia[()] if np.ndim(inertia) == 0 else inertia
    # the speed with the flywheel on: 1/2 I w^2 = 1/2 I wmax^2 - (E - min E)
    w_max = w * (1.0 + cf / 2.0)
    with np.errstate(all="ignore"):
        speed = np.sqrt(np.maximum(
            (w_max * w_max)[..., None] - 2.0 * (curve - curve.min(axis=-1, keepdims=True))
            / np.asarray(inertia)[..., None], 0.0))
    return Flywheel(cf=float(cf), th2d=w, energy=energy, inertia=inertia,
                    mean_torque=mean, mean_power=mean * w,
                    peak_torque=np.max(np.abs(t), axis=-1),
                    theta2=np.degrees(theta) * span, torque=t, energy_curve=curve,
                    flywheel_torque=t - mean[..., None], speed=speed)


def flywheel(mechanism: Any, cf: float = 0.05, n: int = SAMPLES, *,
             scene: Scene | None = None, cycle: float = 360.0,
             **keywords: Any) -> Flywheel:
    """The flywheel on the crank shaft of ``mechanism`` for coefficient ``cf``.

    Parameters
    ----------
    mechanism : Mechanism, SliderCrank, InvertedSliderCrank, WattII, StephensonIII or Linkage
        The linkage [its unit system]; its fields may be arrays (designs).
    cf : float
        The coefficient of speed fluctuation (wmax - wmin) / w_avg [-], in (0, 2).
    n : int
        Crank angles sampled over ``cycle`` [-], even.
    scene : Scene, optional
        What acts on it, of its kind's Scene type (``sielaff.scene_for``) [-]; or
        ``analyze``'s keywords.  The crank speed is the steady TH2D, so ``th2dd`` must be 0.
    cycle : float
        The crank angle the torque repeats over [deg] (a whole number of revolutions for
        a linkage alone; a scene whose TEX or loads depend on more than the position,
        e.g. an engine's 720-degree cycle, needs more).

    Raises ValueError for a linkage whose crank cannot turn fully: a four-bar by its
    class (``linkage_class``), any other kind by its model's ``full_turn``, one design
    at a time (the first that cannot is named).
    """
    four_bar = is_four_bar(mechanism)
    sc = scene_from(scene, keywords, "flywheel") if four_bar \
        else scene_of_kind(mechanism, scene, keywords, "flywheel")
    if callable(sc.th2dd) or np.any(np.asarray(sc.th2dd) != 0.0):
        raise ValueError("a flywheel is sized at a steady mean speed: th2dd must be 0")
    if four_bar:
        if not np.all(linkage_class(mechanism).turns_fully):
            raise ValueError("the crank cannot make a whole revolution: no flywheel cycle")
        values = mechanism.as_tuple()
    else:
        why = [w for w in turn_failures(mechanism).reshape(-1) if w is not None]
        if why:
            raise ValueError(f"the crank of the {kind_name(mechanism)} cannot make a whole "
                             f"revolution ({why[0]}): no flywheel cycle")
        values = tuple(mechanism.as_dict().values())
    theta = np.arange(n) * (_cycle(cycle) / n)
    fields = np.broadcast(*(np.asarray(v) for v in values))
    ath2 = theta.reshape((1,) * fields.nd + (n,))
    m = mechanism.replace(**{name: np.asarray(v)[..., None]
                             for name, v in mechanism.as_dict().items()})
    torq = analyze(m, ath2, ["TORQ"], scene=sc)["TORQ"]
    return flywheel_from_torque(torq, np.asarray(mechanism.TH2D, dtype=float), cf, cycle)
