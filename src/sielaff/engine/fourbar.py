"""The 1966 four-bar as a model: its steps, its effects, one registration line each.

To add an effect: write its module (its ``@step`` s, a ``_seed(scene, mechanism)`` and
an ``EFFECT = Effect(...)`` declaring the parts it adds to the pin forces and TORQ, its
Scene fields, its outputs' units, its spec form and its words), then add one line below
naming the module.  The order of the effects is the order their parts are added in, and
the order the tools show them in.
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np

from sielaff.engine import (
    accelerations,
    forces,
    inertia,
    positions,
    velocities,
)
from sielaff.engine.declare import Param
from sielaff.engine.links import FRAME, FRAME_RATE, Link, LinkRate
from sielaff.engine.outputs import RESULTS, VECTOR_STEPS
from sielaff.engine.registry import Model, step, step_of
from sielaff.engine.statics import pins
from sielaff.mechanism import FIELD_NAMES, MASS_DIVISOR, Mechanism, validate

__all__ = ["BRANCHES", "FOURBAR", "INPUTS", "KINEMATIC_OUTPUTS", "OUTPUTS", "SLOTS"]

#: The superposed quantities an effect may add to: the pin forces and the drive torque.
SLOTS = ("fa32x", "fa32y", "fb34x", "fb34y", "foax", "foay", "fobx", "foby", "torq")

#: The two assemblies of a four-bar: ``open`` (the 1966 program's: B above the line A-O4
#: for the report's example) and ``crossed`` (B mirrored about that line).
BRANCHES = ("open", "crossed")


def _branch(v: Any) -> str:
    if not isinstance(v, str) or v not in BRANCHES:
        raise ValueError(f"Scene.branch = {v!r}: 'open' (the 1966 program's) or 'crossed'")
    return v


def _seed(mechanism: Any, ath2: Any, scene: Any) -> dict[str, Any]:
    """The mechanism's fields, the crank angles, the branch, the mass divisor."""
    ns: dict[str, Any] = {"BRANCH": 1.0 if scene.branch == "open" else -1.0}
    for name in FIELD_NAMES:
        v = np.asarray(getattr(mechanism, name), dtype=float)
        ns[name] = float(v) if v.ndim == 0 else v
    ns["ATH2"] = np.atleast_1d(np.asarray(ath2, dtype=float))  # ufuncs keep arrays
    ns["GW"] = MASS_DIVISOR[mechanism.units]
    return ns


@step(provides=("links",), needs=("R1", "R2", "c2", "s2", "c3", "s3", "c4", "s4", "W2", "W3",
                                  "W4", "RG2", "RG3", "RG4", "cd2", "sd2", "cd3", "sd3", "cd4",
                                  "sd4"))
def _links(R1, R2, c2, s2, c3, s3, c4, s4, W2, W3, W4, RG2, RG3, RG4, cd2, sd2, cd3, sd3, cd4,
           sd4):
    """The links as the effects see them (engine/links.py): 2 from O2, 3 from A, 4 from O4."""
    return (FRAME, Link(c2, s2, 0.0, 0.0, W2, RG2, cd2, sd2),
            Link(c3, s3, R2 * c2, R2 * s2, W3, RG3, cd3, sd3),
            Link(c4, s4, R1, 0.0, W4, RG4, cd4, sd4))


@step(provides=("link_rates",), needs=("R2", "c2", "s2", "TH2D", "TH3D", "TH4D"))
def _link_rates(R2, c2, s2, TH2D, TH3D, TH4D):
    """Each link's angular velocity and its base point's velocity (A's for link 3)."""
    return (FRAME_RATE, LinkRate(TH2D, 0.0, 0.0),
            LinkRate(TH3D, -R2 * s2 * TH2D, R2 * c2 * TH2D), LinkRate(TH4D, 0.0, 0.0))


def _full_turn(mechanism: Any) -> str | None:
    """Why the crank cannot make a whole revolution (its class), or None."""
    from sielaff.engine.classify import linkage_class

    c = linkage_class(mechanism)
    if bool(np.all(c.turns_fully)):
        return None
    return f"the crank cannot make a whole revolution (a {c.kind})"


_GEOMETRY = ("R2", "R3", "R4", "c2", "s2", "c3", "s3", "c4", "s4", "s34")


def _statics(loads, R2, R3, R4, c2, s2, c3, s3, c4, s4, s34):
    """The slots for loads ``(fx, fy, m about its base pin)`` on links 2, 3 and 4."""
    f2, f3, f4 = loads
    return pins(f2[0], f2[1], f2[2], f3[0], f3[1], f3[2], f4[0], f4[1], f4[2],
                R2, R3, R4, c2, s2, c3, s3, c4, s4, s34)


#: The report's model: positions, velocities, accelerations, inertia, forces, outputs.
FOURBAR = Model("four-bar", seed=_seed, results=RESULTS,
                sums={slot: slot + "_e" for slot in SLOTS},
                breakdown=("TORQ_INERTIA", "TORQ"), counts="s34",
                params=(Param("branch", "open", _branch,
                              '{"open", "crossed"}\n    Which assembly of the loop.'),),
                statics=(_statics, _GEOMETRY), mechanism=Mechanism, validate=validate,
                full_turn=_full_turn)
FOURBAR.add(positions, velocities, accelerations, inertia, forces, VECTOR_STEPS,
            step_of(_links), step_of(_link_rates))
FOURBAR.add_effect("gravity")
FOURBAR.add_effect("loads")
FOURBAR.add_effect("tex")
FOURBAR.add_effect("crank")
FOURBAR.add_effect("elements")
FOURBAR.add_effect("friction")

#: Every name ``analyze`` accepts (of the default model): RESULTS plus the listing's
#: intermediate quantities (inertia loads FG2X.., TI3, TI4, superposition parts FP34X..,
#: FPP32X.., F3P21X, TP2, TPP2) and the effects' outputs.
OUTPUTS = FOURBAR.outputs

#: The results that need no masses, inertias or TEX: no force analysis.
KINEMATIC_OUTPUTS = tuple(
    n for n in RESULTS
    if n != "TEX" and not FOURBAR.depends_on(n, frozenset(
        ("W2", "W3", "W4", "ZI2", "ZI3", "ZI4", "TEX", "tex_fn")))
)
FOURBAR.kinematics = KINEMATIC_OUTPUTS

#: Inputs seeded into the namespace by the model and its effects (for the 1966 scene):
#: what each effect's seed gives for its fields' defaults, less what a step provides.
_DEFAULTS = SimpleNamespace(**{p.name: p.default for p in FOURBAR.params})
INPUTS = ("ATH2",) + FIELD_NAMES + ("BRANCH", "GW") + tuple(
    n for e in FOURBAR.effects for n in e.seed(_DEFAULTS, None) if n not in FOURBAR.provider)
