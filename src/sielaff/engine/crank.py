"""Crank angular acceleration TH2DD (rad/sec^2, CCW +): the terms it adds.

The 1966 program turns the crank at constant speed.  With TH2DD the angular
accelerations of links 3 and 4 gain ``K3 TH2DD`` and ``K4 TH2DD`` (K3 = TH3D/TH2D,
K4 = TH4D/TH2D, the velocity ratios, from the velocity equations at TH2D = 1), A and
G2 gain their tangential accelerations, and the crank its inertia torque -ZI2 TH2DD.
Every step here is skipped when TH2DD is zero (``zero_when``), and the totals then keep
the constant-speed results bit for bit (``statics.plus``).  ``Scene(th2dd=...)`` turns it
on; its part of TORQ (the crank's own inertia) stays in ``TORQ_INERTIA``.
"""

from __future__ import annotations

from sielaff.engine.declare import number_effect, number_param
from sielaff.engine.registry import Effect, step, step_of
from sielaff.engine.values import call_checked
from sielaff.engine.velocities import _angular_velocities


@step(provides=("TH2DD",), needs=("th2dd_fn", "ATH2"))
def _crank_acceleration(th2dd_fn, ATH2):
    """TH2DD = f(ATH2 in degrees), when the caller gives a function."""
    return call_checked("Scene.th2dd", th2dd_fn, ATH2)


@step(provides=("th3dd_a", "th4dd_a"),
      needs=("TH2DD", "R2", "R3", "R4", "c2", "s2", "c3", "s3", "c4", "s4", "s34"),
      zero_when=("TH2DD",))
def _angular_acc_crank(TH2DD, R2, R3, R4, c2, s2, c3, s3, c4, s4, s34):
    k3, k4 = _angular_velocities(R2, R3, R4, 1.0, c2, s2, c3, s3, c4, s4, s34)
    return k3 * TH2DD, k4 * TH2DD


@step(provides=("aax_a", "aay_a"), needs=("R2", "TH2DD", "c2", "s2"), zero_when=("TH2DD",))
def _acc_A_crank(R2, TH2DD, c2, s2):
    k = R2 * TH2DD
    return -s2 * k, c2 * k


@step(provides=("ag2x_a", "ag2y_a"), needs=("RG2", "TH2DD", "cd2", "sd2"),
      zero_when=("TH2DD",))
def _acc_G2_crank(RG2, TH2DD, cd2, sd2):
    k = RG2 * TH2DD
    return -sd2 * k, cd2 * k


@step(provides=("torq_c",), needs=("ZI2", "TH2DD", "RG2", "cd2", "sd2", "FG2X", "FG2Y"),
      zero_when=[("TH2DD",)])
def _crank_inertia_torque(ZI2, TH2DD, RG2, cd2, sd2, FG2X, FG2Y):
    """The drive's share for the crank's own inertia: -(rG2 x FG2) + ZI2 TH2DD (at constant
    speed FG2 is radial and this is zero, as the 1966 program assumes)."""
    return ZI2 * TH2DD - RG2 * (cd2 * FG2Y - sd2 * FG2X)


EFFECT = Effect("crank acceleration",
                tuple(step_of(f) for f in (_crank_acceleration, _angular_acc_crank, _acc_A_crank,
                                           _acc_G2_crank, _crank_inertia_torque)),
                parts={"torq": "torq_c"},
                params=(number_param("th2dd", "float, array or callable\n"
                                     "    The crank's angular acceleration [rad/sec^2], CCW +; "
                                     "TH2D is then the crank\n    speed at each position.  A "
                                     "constant, an array or a function of ATH2 [deg]."),),
                outputs={"TH2DD": ("angular acceleration",
                                   "angular acceleration of the crank, CCW + (0 in 1966)")},
                **number_effect("th2dd", "TH2DD", "THETA 2",
                                "TH2DD, the crank's angular acceleration (CCW +)",
                                "angular acceleration", "crank_acceleration",
                                "crank_acceleration = -40.0    # TH2DD, rad/sec^2"))
