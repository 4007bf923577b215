"""The compiled backend's steps: each numpy step the kernel covers, written for one
position as (provides, needs, zero groups, code), and the plan over them (the numpy
engine's plan, with the kernel's shortcuts).  :mod:`sielaff.engine.compiled` generates
one kernel from the steps a request needs."""

from __future__ import annotations

from typing import Any

# --- the steps, as the numpy engine declares them, each written for one position ------
# (provides, needs, zero groups, code).  ``code`` is a string, or a function of the set of
# names known to be the plain 0.0 of a skipped step (for ``statics.plus``).  A step whose
# zero group is all zero is skipped, its results the literal 0.0, as in registry._plan.


def _plus(a: str, b: str, zero: set[str]) -> str:
    """``statics.plus``: the other operand itself when one is a skipped step's 0.0."""
    if b in zero:
        return a
    if a in zero:
        return b
    return f"({a}) + ({b})"


def _pins_code(p: str, f2: tuple, f3: tuple, f4: tuple) -> str:
    """statics.pins for per-link loads (F2X, F2Y, M2), ...; results named p + suffix."""
    (F2X, F2Y, M2), (F3X, F3Y, M3), (F4X, F4Y, M4) = f2, f3, f4
    return f"""
ux_{p} = R3 * c3
uy_{p} = R3 * s3
vx_{p} = R4 * c4
vy_{p} = R4 * s4
d_{p} = s34 * (R3 * R4)
f34x_{p} = (-({M4}) * ux_{p} - vx_{p} * ({M3})) / d_{p}
f34y_{p} = (-vy_{p} * ({M3}) - uy_{p} * ({M4})) / d_{p}
f32x_{p} = ({F3X}) - f34x_{p}
f32y_{p} = ({F3Y}) - f34y_{p}
fa32x_{p} = f32x_{p}
fa32y_{p} = f32y_{p}
fb34x_{p} = f34x_{p}
fb34y_{p} = f34y_{p}
foax_{p} = f32x_{p} + ({F2X})
foay_{p} = f32y_{p} + ({F2Y})
fobx_{p} = f34x_{p} + ({F4X})
foby_{p} = f34y_{p} + ({F4Y})
torq_{p} = -(R2 * (c2 * f32y_{p} - s2 * f32x_{p})) - ({M2})
"""


_PARTS = ("fa32x", "fa32y", "fb34x", "fb34y", "foax", "foay", "fobx", "foby")


def _gravity_code(zero):
    lines = [f"gfx{k} = W{k} / GW * GX\ngfy{k} = W{k} / GW * GY\n"
             f"gm{k} = RG{k} * (cd{k} * gfy{k} - sd{k} * gfx{k})" for k in (2, 3, 4)]
    return ("\n".join(lines) + _pins_code("g", ("gfx2", "gfy2", "gm2"), ("gfx3", "gfy3", "gm3"),
                                          ("gfx4", "gfy4", "gm4")) + "TORQ_GRAVITY = torq_g\n")


def _loads_code(zero, loads):
    """The loads step: ``loads`` a tuple of (link, {field: expression})."""
    lines = []
    per = {2: ["0.0", "0.0", "0.0"], 3: ["0.0", "0.0", "0.0"], 4: ["0.0", "0.0", "0.0"]}
    for j, (link, f) in enumerate(loads):
        c, s = {2: ("c2", "s2"), 3: ("c3", "s3"), 4: ("c4", "s4")}[link]
        lines.append(f"lpx{j} = {f['r']} * ({c} * {f['ca']} - {s} * {f['sa']})\n"
                     f"lpy{j} = {f['r']} * ({s} * {f['ca']} + {c} * {f['sa']})")
        fs = per[link]
        lines.append(f"lf{j}x = ({fs[0]}) + {f['fx']}\nlf{j}y = ({fs[1]}) + {f['fy']}\n"
                     f"lf{j}m = ({fs[2]}) + ((lpx{j} * {f['fy']} - lpy{j} * {f['fx']}) "
                     f"+ {f['torque']})")
        per[link] = [f"lf{j}x", f"lf{j}y", f"lf{j}m"]
    return "\n".join(lines) + _pins_code("l", tuple(per[2]), tuple(per[3]),
                                         tuple(per[4])) + "TORQ_LOADS = torq_l\n"


_EFFECT_PARTS = tuple(f"{n}_g" for n in _PARTS) + ("TORQ_GRAVITY",) + tuple(
    f"{n}_l" for n in _PARTS) + ("TORQ_LOADS", "torq_c")


def _effects_code(zero):
    """forces._effects: each part plus(gravity's, the loads'), the torque plus torq_c."""
    out = [f"{n}_e = {_plus(n + '_g', n + '_l', zero)}" for n in _PARTS]
    if "TORQ_GRAVITY" in zero and "TORQ_LOADS" in zero:  # plus(0.0, 0.0) is the 0.0
        t = "TORQ_GRAVITY"
        out.append("torq_e = " + ("torq_c" if "torq_c" not in zero else t))
    else:
        out.append(f"torq_e = {_plus(_plus('TORQ_GRAVITY', 'TORQ_LOADS', zero), 'torq_c', zero)}")
    return "\n".join(out)


def _sum_zero(names, zero):
    """Python floats 0.0 + 0.0 stay the plain 0.0 (so ``plus`` sees them as zero)."""
    return all(n in zero for n in names)


def _totals(zero, terms, e, out):
    """out = plus(sum of terms, e)."""
    s = " + ".join(terms)
    if _sum_zero(terms, zero):
        return f"{out} = {e if e not in zero else s}"
    return f"{out} = {_plus(s, e, zero)}"


_STEPS: list[tuple[tuple[str, ...], tuple[str, ...], tuple[tuple[str, ...], ...], Any]] = [
    (("c2", "s2"), ("ATH2",), (), "s2, c2 = _crank(ATH2)"),
    (("c3", "s3", "c4", "s4", "s34", "c34"), ("c2", "s2"), (), """
dx = R1s - R2s * c2
dy = s2 * -R2s
zl2 = dx * dx
zl2 = zl2 + dy * dy
zl = math.sqrt(zl2)
t = zl + R3s
f1 = t + R4s
f2 = t - R4s
t = zl - R3s
f3 = R4s - t
f4 = t + R4s
assembled = (f2 >= -TOL) & (f3 >= -TOL) & (f4 >= -TOL)
bad += _select(assembled, 0, 1)
f2 = _select(f2 > 0.0, f2, 0.0)
f3 = _select(f3 > 0.0, f3, 0.0)
f4 = _select(f4 > 0.0, f4, 0.0)
hh = (f1 * f2) * (f3 * f4)
h = _select(assembled, math.sqrt(hh), math.nan)
h = h * BRANCH_SIGN
p = zl2 + R3R4M
c3 = dx * p
c3 = c3 - dy * h
s3 = dy * p
s3 = s3 + dx * h
p = HALF_R3 / zl2
c3 = c3 * p
s3 = s3 * p
c4 = R3s * c3
c4 = (c4 - dx) / R4s
s4 = R3s * s3
s4 = (s4 - dy) / R4s
s34 = h * KK
c34 = (zl2 - R3R4P) * KK
"""),
    (("ATH3", "ATH4"), ("c3", "s3", "c4", "s4"), (),
     "ATH3 = _link_angle(s3, c3)\nATH4 = _link_angle(s4, c4)"),
    (("GAMMA",), ("s34", "c34"), (), "GAMMA = _gamma(s34, c34)"),
    (("TH3D", "TH4D"), ("TH2D", "c2", "s2", "c3", "s3", "c4", "s4", "s34"), (("TH2D",),), """
k = (R2 * TH2D) / s34
TH3D = (s4 * c2 - c4 * s2) * k / R3
TH4D = (s3 * c2 - c3 * s2) * k / R4
"""),
    (("cd2", "sd2"), ("c2", "s2"), (), "cd2, sd2 = ROT2"),
    (("cd3", "sd3"), ("c3", "s3"), (), "cd3, sd3 = ROT3"),
    (("cd4", "sd4"), ("c4", "s4"), (), "cd4, sd4 = ROT4"),
    (("VAX", "VAY"), ("TH2D", "c2", "s2"), (), "VAX = s2 * -(R2 * TH2D)\nVAY = c2 * (R2 * TH2D)"),
    (("VG2X", "VG2Y"), ("TH2D", "cd2", "sd2"), (),
     "VG2X = sd2 * -(RG2 * TH2D)\nVG2Y = cd2 * (RG2 * TH2D)"),
    (("VBX", "VBY"), ("TH4D", "c4", "s4"), (), "VBX = s4 * -(R4 * TH4D)\nVBY = c4 * (R4 * TH4D)"),
    (("VG4X", "VG4Y"), ("TH4D", "cd4", "sd4"), (),
     "VG4X = sd4 * -(RG4 * TH4D)\nVG4Y = cd4 * (RG4 * TH4D)"),
    (("VG3X", "VG3Y"), ("VAX", "VAY", "TH3D", "cd3", "sd3"), (),
     "VG3X = sd3 * -(RG3 * TH3D) + VAX\nVG3Y = cd3 * (RG3 * TH3D) + VAY"),
    (("th3dd_w", "th4dd_w"), ("TH2D", "TH3D", "TH4D", "c2", "s2", "c3", "s3", "c4", "s4",
                              "s34", "c34"), (("TH2D",),), """
a2 = R2 * TH2D * TH2D
a3 = TH3D * TH3D * R3
a4 = TH4D * TH4D * R4
th3dd_w = ((((c4 * c2) + s4 * s2) * a2 + a3 * c34) - a4) / (s34 * -R3)
th4dd_w = ((((c3 * c2) + s3 * s2) * -a2 + a4 * c34) - a3) / (s34 * R4)
"""),
    (("aax_w", "aay_w"), ("TH2D", "c2", "s2"), (("TH2D",),),
     "aax_w = c2 * (-R2 * TH2D * TH2D)\naay_w = s2 * (-R2 * TH2D * TH2D)"),
    (("ag2x_w", "ag2y_w"), ("TH2D", "cd2", "sd2"), (("TH2D",),),
     "ag2x_w = cd2 * (-RG2 * TH2D * TH2D)\nag2y_w = sd2 * (-RG2 * TH2D * TH2D)"),
    (("ABX", "ABY"), ("TH4D", "TH4DD", "c4", "s4"), (("TH4D", "TH4DD"),), """
rw2 = TH4D * TH4D * R4
ra = TH4DD * R4
ABX = -(rw2 * c4 + ra * s4)
ABY = ra * c4 - rw2 * s4
"""),
    (("AG4X", "AG4Y"), ("TH4D", "TH4DD", "cd4", "sd4"), (("TH4D", "TH4DD"),), """
rw2 = TH4D * TH4D * RG4
ra = TH4DD * RG4
AG4X = -(rw2 * cd4 + ra * sd4)
AG4Y = ra * cd4 - rw2 * sd4
"""),
    (("AG3X", "AG3Y"), ("AAX", "AAY", "TH3D", "TH3DD", "cd3", "sd3"),
     (("AAX", "AAY", "TH3D", "TH3DD"),), """
rw2 = TH3D * TH3D * RG3
ra = TH3DD * RG3
AG3X = -(rw2 * cd3 + ra * sd3) + AAX
AG3Y = (ra * cd3 - rw2 * sd3) + AAY
"""),
    (("TH3DD", "TH4DD"), ("th3dd_w", "th4dd_w", "th3dd_a", "th4dd_a"),
     (("th3dd_w", "th4dd_w", "th3dd_a", "th4dd_a"),),
     lambda z: (f"TH3DD = {_plus('th3dd_w', 'th3dd_a', z)}\n"
                f"TH4DD = {_plus('th4dd_w', 'th4dd_a', z)}")),
    (("AAX", "AAY"), ("aax_w", "aay_w", "aax_a", "aay_a"), (("aax_w", "aay_w", "aax_a", "aay_a"),),
     lambda z: f"AAX = {_plus('aax_w', 'aax_a', z)}\nAAY = {_plus('aay_w', 'aay_a', z)}"),
    (("AG2X", "AG2Y"), ("ag2x_w", "ag2y_w", "ag2x_a", "ag2y_a"),
     (("ag2x_w", "ag2y_w", "ag2x_a", "ag2y_a"),),
     lambda z: f"AG2X = {_plus('ag2x_w', 'ag2x_a', z)}\nAG2Y = {_plus('ag2y_w', 'ag2y_a', z)}"),
    # crank.py: the crank's angular acceleration
    (("th3dd_a", "th4dd_a"), ("TH2DD", "c2", "s2", "c3", "s3", "c4", "s4", "s34"),
     (("TH2DD",),), """
k = (R2 * 1.0) / s34
th3dd_a = (s4 * c2 - c4 * s2) * k / R3 * TH2DD
th4dd_a = (s3 * c2 - c3 * s2) * k / R4 * TH2DD
"""),
    (("aax_a", "aay_a"), ("TH2DD", "c2", "s2"), (("TH2DD",),),
     "aax_a = -s2 * (R2 * TH2DD)\naay_a = c2 * (R2 * TH2DD)"),
    (("ag2x_a", "ag2y_a"), ("TH2DD", "cd2", "sd2"), (("TH2DD",),),
     "ag2x_a = -sd2 * (RG2 * TH2DD)\nag2y_a = cd2 * (RG2 * TH2DD)"),
    (("torq_c",), ("TH2DD", "cd2", "sd2", "FG2X", "FG2Y"), (("TH2DD",),),
     "torq_c = ZI2 * TH2DD - RG2 * (cd2 * FG2Y - sd2 * FG2X)"),
    # inertia.py
    (("FG2X", "FG2Y"), ("W2", "AG2X", "AG2Y"), (("W2",), ("AG2X", "AG2Y")),
     "FG2X = AG2X * (-W2 / GW)\nFG2Y = AG2Y * (-W2 / GW)"),
    (("FG3X", "FG3Y"), ("W3", "AG3X", "AG3Y"), (("W3",), ("AG3X", "AG3Y")),
     "FG3X = AG3X * (-W3 / GW)\nFG3Y = AG3Y * (-W3 / GW)"),
    (("TI3",), ("ZI3", "TH3DD"), (("ZI3",), ("TH3DD",)), "TI3 = TH3DD * -ZI3"),
    (("FG4X", "FG4Y"), ("W4", "AG4X", "AG4Y"), (("W4",), ("AG4X", "AG4Y")),
     "FG4X = AG4X * (-W4 / GW)\nFG4Y = AG4Y * (-W4 / GW)"),
    (("TI4",), ("ZI4", "TH4DD"), (("ZI4",), ("TH4DD",)), "TI4 = TH4DD * -ZI4"),
    # forces.py
    (("FP34X", "FP34Y", "FP32X", "FP32Y", "FP21X", "FP21Y", "FP41X", "FP41Y", "TP2"),
     ("FG4X", "FG4Y", "TI4", "TEX", "cd4", "sd4", "c2", "s2", "c3", "s3", "s34"),
     (("FG4X", "FG4Y", "TI4", "TEX"),), """
f = ((((sd4 * FG4X - cd4 * FG4Y) * RG4) - TI4) - TEX) / (s34 * R4)
FP34X = f * c3
FP34Y = f * s3
FP32X = -FP34X
FP32Y = -FP34Y
FP21X = FP32X
FP21Y = FP32Y
FP41X = FG4X + FP34X
FP41Y = FG4Y + FP34Y
TP2 = (s3 * c2 - c3 * s2) * f * R2
"""),
    (("FPP34X", "FPP34Y", "FPP32X", "FPP32Y", "FPP21X", "FPP21Y", "FPP41X", "FPP41Y", "TPP2"),
     ("FG3X", "FG3Y", "TI3", "cd3", "sd3", "c2", "s2", "c4", "s4", "s34"),
     (("FG3X", "FG3Y", "TI3"),), """
g = (((sd3 * FG3X - cd3 * FG3Y) * RG3) - TI3) / (s34 * -R3)
fpp43x = g * c4
fpp43y = g * s4
FPP34X = -fpp43x
FPP34Y = -fpp43y
FPP32X = fpp43x + FG3X
FPP32Y = fpp43y + FG3Y
FPP21X = FPP32X
FPP21Y = FPP32Y
FPP41X = FPP34X
FPP41Y = FPP34Y
TPP2 = (s2 * FPP32X - c2 * FPP32Y) * R2
"""),
    (("F3P21X", "F3P21Y"), ("FG2X", "FG2Y"), (("FG2X", "FG2Y"),),
     "F3P21X = FG2X\nF3P21Y = FG2Y"),
    (tuple(f"{n}_g" for n in _PARTS) + ("TORQ_GRAVITY",),
     ("GX", "GY", "W2", "W3", "W4", "cd2", "sd2", "cd3", "sd3", "cd4", "sd4", "c2", "s2",
      "c3", "s3", "c4", "s4", "s34"), (("GX", "GY"),),
     _gravity_code),
    (tuple(f"{n}_l" for n in _PARTS) + ("TORQ_LOADS",),
     ("NLOADS", "c2", "s2", "c3", "s3", "c4", "s4", "s34"), (("NLOADS",),), "LOADS"),
    (tuple(f"{n}_e" for n in _PARTS) + ("torq_e",), _EFFECT_PARTS, (_EFFECT_PARTS,),
     _effects_code),
    (("FA32X", "FA32Y"), ("FP32X", "FP32Y", "FPP32X", "FPP32Y", "fa32x_e", "fa32y_e"), (),
     lambda z: _totals(z, ["FP32X", "FPP32X"], "fa32x_e", "FA32X") + "\n"
     + _totals(z, ["FP32Y", "FPP32Y"], "fa32y_e", "FA32Y")),
    (("FB34X", "FB34Y"), ("FP34X", "FP34Y", "FPP34X", "FPP34Y", "fb34x_e", "fb34y_e"), (),
     lambda z: _totals(z, ["FP34X", "FPP34X"], "fb34x_e", "FB34X") + "\n"
     + _totals(z, ["FP34Y", "FPP34Y"], "fb34y_e", "FB34Y")),
    (("TORQ",), ("TP2", "TPP2", "torq_e"), (),
     lambda z: _totals(z, ["TP2", "TPP2"], "torq_e", "TORQ")),
    (("FOAX", "FOAY"), ("FP21X", "FP21Y", "FPP21X", "FPP21Y", "F3P21X", "F3P21Y", "foax_e",
                        "foay_e"), (),
     lambda z: _totals(z, ["FP21X", "FPP21X", "F3P21X"], "foax_e", "FOAX") + "\n"
     + _totals(z, ["FP21Y", "FPP21Y", "F3P21Y"], "foay_e", "FOAY")),
    (("FOBX", "FOBY"), ("FP41X", "FP41Y", "FPP41X", "FPP41Y", "fobx_e", "foby_e"), (),
     lambda z: _totals(z, ["FP41X", "FPP41X"], "fobx_e", "FOBX") + "\n"
     + _totals(z, ["FP41Y", "FPP41Y"], "foby_e", "FOBY")),
    (("TORQ_TEX",), ("TEX", "c2", "s2", "c3", "s3", "c4", "s4", "s34"), (("TEX",),),
     _pins_code("t", ("0.0", "0.0", "0.0"), ("0.0", "0.0", "0.0"), ("0.0", "0.0", "TEX"))
     + "TORQ_TEX = torq_t\n"),
    (("TORQ_INERTIA",), ("TORQ", "TORQ_GRAVITY", "TORQ_LOADS", "TORQ_TEX"), (),
     "TORQ_INERTIA = TORQ - TORQ_GRAVITY - TORQ_LOADS - TORQ_TEX"),
    (("SHAKX", "SHAKY"), ("FOAX", "FOAY", "FOBX", "FOBY"), (),
     "SHAKX = FOAX + FOBX\nSHAKY = FOAY + FOBY"),
    (("SHAKM",), ("FOBY", "TORQ"), (), "SHAKM = FOBY * R1 - TORQ"),
]

#: Vectors reported as magnitude NAME and direction DNAME (outputs.VECTORS).
_VECTORS = ("VG2", "VA", "VG3", "VB", "VG4", "AG2", "AA", "AG3", "AB", "AG4",
            "FA32", "FB34", "FOA", "FOB", "SHAK")
#: outputs.ROTATING: name -> (distance, line, its ADEL or None, angular velocity)
_ROTATING = {"VA": ("R2", "ATH2", None, "TH2D"), "VG2": ("RG2", "ATH2", "ADEL2", "TH2D"),
             "VB": ("R4", "ATH4", None, "TH4D"), "VG4": ("RG4", "ATH4", "ADEL4", "TH4D")}
for _v in _VECTORS:
    if _v in _ROTATING:
        _r, _line, _adel, _w = _ROTATING[_v]
        _STEPS.append(((_v,), (_w,), (), f"{_v} = abs({_r} * {_w})"))
        _STEPS.append((("D" + _v,), (_line, _w), (),
                       f"D{_v} = _rot_direction({_r} * {_w}, {_line} + {_adel or '0.0'})"))
    else:
        _STEPS.append(((_v,), (_v + "X", _v + "Y"), (), f"{_v} = _magnitude({_v}X, {_v}Y)"))
        _STEPS.append((("D" + _v,), (_v + "X", _v + "Y"), (),
                       f"D{_v} = _direction({_v}X, {_v}Y)"))

_PROVIDER = {name: st for st in _STEPS for name in st[0]}

#: With TH2DD a constant, the crank's accelerations turn with it: AA = R2 e^{i ATH2}
#: (-TH2D^2 + i TH2DD), and AG2 the same from RG2 and ATH2 + ADEL2, so their magnitudes
#: are R2 K and |RG2| K (K = |TH2D^2 - i TH2DD|, per call) and their directions ATH2 plus a
#: constant PHI (issue 25's rotating-vector shortcut: no atan2 or sqrt per position).
#: NaN where ATH2 is not finite, as the components would be, but where the steps are
#: skipped (K = 0: the plain 0.0).
_ACC2_SHORTCUT = {
    "AA": (("AA",), ("ATH2",), (), "AA = R2 * K_ACC2 + _select(K_ACC2 == 0.0, 0.0, ATH2 - ATH2)"),
    "AG2": (("AG2",), ("ATH2",), (),
            "AG2 = abs(RG2) * K_ACC2 + _select(K_ACC2 == 0.0, 0.0, ATH2 - ATH2)"),
    "DAA": (("DAA",), ("ATH2",), (),
            "DAA = _turned(R2 * K_ACC2, K_ACC2, ATH2, PHI_AA)"),
    "DAG2": (("DAG2",), ("ATH2",), (),
             "DAG2 = _turned(abs(RG2) * K_ACC2, K_ACC2, ATH2, PHI_AG2)"),
}

#: Where the plan computes ATH3 and ATH4 anyway: GAMMA is the angle between them (the
#: numpy engine takes atan2(|s34|, c34); the two differ by the angles' roundoff, some
#: 1e-13 degrees at most, against a bound of ERROR_BOUND 360 degrees).
_GAMMA_SHORTCUT = {"GAMMA": (("GAMMA",), ("ATH3", "ATH4"), (), "GAMMA = _between(ATH3, ATH4)")}

#: Where the plan computes ATH4 anyway and wants both DAB and DAG4: AB = R4 e^{i ATH4}
#: (-TH4D^2 + i TH4DD) and AG4 the same from RG4 and ATH4 + ADEL4, so both directions are
#: ATH4 plus one angle PHI4 per position, the direction of (-TH4D^2, TH4DD): one atan2
#: for the two (issue 25's "three directions from ATH2 or ATH4"), and their magnitudes
#: R4 K4 and |RG4| K4, K4 = |-TH4D^2 + i TH4DD|: one sqrt for the two.  The zero
#: vector's direction is 0 (NaN where an ingredient is not finite), as the numpy
#: engine's.
_ACC4_SHORTCUT = {
    "phi4": (("phi4", "w4", "nz4", "k4"), ("TH4D", "TH4DD", "c4"), (), """
w4 = TH4D * TH4D
phi4 = _direction(-w4, TH4DD)
nz4 = (w4 + TH4DD + c4) * 0.0
k4 = _magnitude(w4, TH4DD)
"""),
    "AB": (("AB",), ("phi4", "TH4D", "TH4DD"), (("TH4D", "TH4DD"),), "AB = R4 * k4"),
    "AG4": (("AG4",), ("phi4", "TH4D", "TH4DD"), (("TH4D", "TH4DD"),), "AG4 = abs(RG4) * k4"),
    "DAB": (("DAB",), ("ATH4", "phi4", "TH4D", "TH4DD"), (("TH4D", "TH4DD"),),
            "DAB = _acc_direction(ATH4, TURN_B, phi4, R4, w4, TH4DD, nz4)"),
    "DAG4": (("DAG4",), ("ATH4", "phi4", "TH4D", "TH4DD"), (("TH4D", "TH4DD"),),
             "DAG4 = _acc_direction(ATH4, TURN_G4, phi4, RG4, w4, TH4DD, nz4)"),
}

#: Inputs seeded per call (a scalar parameter, or a per-position array).
_SEEDS = ("ATH2", "TH2D", "W2", "W3", "W4", "ZI3", "ZI4", "TEX", "TH2DD", "GX", "GY", "NLOADS")

#: The outputs a kernel can write (the numpy engine's OUTPUTS but ASSEMBLED).
SUPPORTED = tuple(sorted({n for st in _STEPS for n in st[0] if n[0].isupper()}
                        | {"ATH2", "TEX", "TH2DD"}))


def _plan(wanted: tuple[str, ...], zero_seeds: frozenset[str], shortcut: bool = False):
    """The steps ``wanted`` needs, in order, each with whether it is skipped (as
    registry._plan: skipped when one of its zero groups is all known zero); with
    ``shortcut`` (TH2DD a constant), AA, AG2 and their directions by ``_ACC2_SHORTCUT``;
    where ATH3 and ATH4 are computed anyway, GAMMA by ``_GAMMA_SHORTCUT`` and, when
    both are wanted, DAB and DAG4 by ``_ACC4_SHORTCUT``."""
    first = _plan_with(wanted, zero_seeds, dict(_PROVIDER, **_ACC2_SHORTCUT) if shortcut
                       else _PROVIDER)
    done = {n for st, skipped in first if not skipped for n in st[0]}
    if "ATH4" not in done:
        return first
    provider = dict(_PROVIDER, **_ACC2_SHORTCUT) if shortcut else dict(_PROVIDER)
    provider.update(_GAMMA_SHORTCUT)
    if "DAB" in done and "DAG4" in done:
        provider.update(_ACC4_SHORTCUT)
    return _plan_with(wanted, zero_seeds, provider)


def _plan_with(wanted: tuple[str, ...], zero_seeds: frozenset[str], provider: dict):
    """_plan with the steps ``provider`` names."""
    known: dict[str, bool] = {n: n in zero_seeds for n in _SEEDS}
    order: list[tuple[Any, bool]] = []

    def visit(name: str) -> None:
        if name in known:
            return
        st = provider[name]
        skipped = any(all(known_zero(n) for n in g) for g in st[2])
        if not skipped:
            for need in st[1]:
                visit(need)
        order.append((st, skipped))
        for n in st[0]:
            known[n] = skipped

    def known_zero(name: str) -> bool:
        if name not in known:
            st = provider[name]
            return any(all(known_zero(n) for n in g) for g in st[2])
        return known[name]

    for name in wanted:
        visit(name)
    return order


_PARAMS = ("R1", "R2", "R3", "R4", "RG2", "RG3", "RG4", "W2", "W3", "W4", "ZI2", "ZI3", "ZI4",
           "ADEL2", "ADEL4", "TH2D", "GW", "GX", "GY", "R1s", "R2s", "R3s", "R4s", "TOL",
           "R3R4M", "R3R4P", "HALF_R3", "KK", "BRANCH_SIGN", "CA2", "SA2", "CA3", "SA3",
           "CA4", "SA4", "STREAM", "TURN_B", "TURN_G4")
