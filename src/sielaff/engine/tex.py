"""TEX, the external torque on link 4 (in-lb or N m, CCW +): the 1966 program's one load.

The rocker's force step takes TEX directly (as statement 74 of the listing), so this
effect adds no part to the superposed sums; it gives TEX itself when the scene holds a
function of ATH4 (the report's own edit of statement 74), and TORQ_TEX, the share of TORQ
that TEX alone takes (for the breakdown; TORQ_INERTIA excludes it).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sielaff.engine.declare import Fact, SpecForm, number_param
from sielaff.engine.registry import Effect, step, step_of
from sielaff.engine.statics import pins
from sielaff.engine.values import call_checked


@step(provides=("TEX",), needs=("tex_fn", "ATH4"))
def _external_torque(tex_fn, ATH4):
    """TEX = f(ATH4 in degrees), the report's statement 74 option."""
    return call_checked("Scene.tex", tex_fn, ATH4)


@step(provides=("TORQ_TEX",), needs=("TEX", "R2", "R3", "R4", "c2", "s2", "c3", "s3", "c4",
                                     "s4", "s34"), zero_when=("TEX",))
def _torque_for_tex(TEX, R2, R3, R4, c2, s2, c3, s3, c4, s4, s34):
    """The drive torque TEX alone takes (part of TORQ, for the breakdown)."""
    return pins(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, TEX, R2, R3, R4, c2, s2, c3, s3, c4,
                s4, s34)[8]


def _seed(scene: Any, mechanism: Any) -> dict[str, Any]:
    v = scene.tex
    return {"tex_fn": v} if callable(v) else {"TEX": v}


def _on(scene: Any) -> bool:
    return callable(scene.tex) or bool(np.any(np.asarray(scene.tex) != 0.0))


def _summary(scene: Any, units: str) -> str:
    from sielaff.quantities import unit

    v = scene.tex
    if callable(v):
        return "TEX a function of THETA 4"
    if np.ndim(v):
        return "TEX varying with THETA 2"
    return f"TEX = {v:g} {unit('TEX', units)}"


def _describe(scene: Any, units: str) -> list[Fact]:
    v = scene.tex
    if callable(v) or np.ndim(v):
        return [Fact("", "TEX", _summary(scene, units).removeprefix("TEX "))]
    return [Fact("", "TEX, torque on link 4 (CCW +)", float(v), "torque")]


def _read(table: Any, path: str, reader: Any) -> dict[str, Any]:
    return {"tex": reader.number(f"{path}: [scene] tex", table["tex"])} if "tex" in table else {}


def _write(scene: Any) -> dict[str, Any]:
    v = scene.tex
    return {"tex": float(v)} if not callable(v) and not np.ndim(v) and v else {}


EFFECT = Effect("TEX", (step_of(_external_torque), step_of(_torque_for_tex)), _seed,
                torque="TORQ_TEX",
                params=(number_param("tex", "float, array or callable\n"
                                     "    External torque on link 4 [in-lb or N m], CCW +; a "
                                     "constant, an array broadcasting\n    against the crank "
                                     "angles, or a function of ATH4 [deg]."),),
                outputs={"TEX": ("torque", "external torque on link 4, CCW + (0 in the 1966 "
                                           "program)"),
                         "TORQ_TEX": ("torque", "the part of TORQ the torque TEX on link 4 "
                                                "takes")},
                on=_on, summary=_summary, describe=_describe, columns=lambda s: ("TORQ_TEX",),
                spec=SpecForm(("tex",), _read, _write,
                              "tex = 0.0                     # torque on the rocker, CCW +"),
                compiled=True, in_1966=True)
