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
from sielaff.engine.outputs import RESULTS, VECTOR_STEPS
from sielaff.engine.registry import SLOTS, Model
from sielaff.mechanism import FIELD_NAMES, MASS_DIVISOR

__all__ = ["BRANCHES", "FOURBAR", "INPUTS", "KINEMATIC_OUTPUTS", "OUTPUTS"]

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


#: The report's model: positions, velocities, accelerations, inertia, forces, outputs.
FOURBAR = Model("four-bar", seed=_seed, results=RESULTS,
                sums={slot: slot + "_e" for slot in SLOTS},
                breakdown=("TORQ_INERTIA", "TORQ"), counts="s34",
                params=(Param("branch", "open", _branch,
                              '{"open", "crossed"}\n    Which assembly of the loop.'),))
FOURBAR.add(positions, velocities, accelerations, inertia, forces, VECTOR_STEPS)
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

#: Inputs seeded into the namespace by the model and its effects (for the 1966 scene):
#: what each effect's seed gives for its fields' defaults, less what a step provides.
_DEFAULTS = SimpleNamespace(**{p.name: p.default for p in FOURBAR.params})
INPUTS = ("ATH2",) + FIELD_NAMES + ("BRANCH", "GW") + tuple(
    n for e in FOURBAR.effects for n in e.seed(_DEFAULTS, None) if n not in FOURBAR.provider)
