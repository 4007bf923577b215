"""What each named quantity means, and its unit: one catalogue for every tool.

The names are the listing's (``ATH3``, ``VG2``, ``FA32``, ``TORQ``, ...) and the
engine's additions (``GAMMA``, ``SHAKM``, the X and Y components).  The sign
conventions behind every description are stated once, in
``docs/conventions.md``; :data:`CONVENTIONS` is their short form, for
``sielaff --help`` and the README.

Units are the report's in-lb-sec system: lengths in inches, forces and weights
in pounds, time in seconds, angles printed in degrees, rates in radians.
"""

from __future__ import annotations

from sielaff.inverted_slider_crank import InvertedSliderCrank
from sielaff.mechanism import SI as MECHANISM_SI
from sielaff.mechanism import UNITS as FOURBAR_UNITS
from sielaff.sixbar import WattII
from sielaff.slider_crank import UNITS as SLIDER_UNITS

#: Every mechanism field's unit (the kinds share their names where they mean the same).
MECHANISM_UNITS = {**FOURBAR_UNITS, **SLIDER_UNITS, **InvertedSliderCrank.UNITS,
                   **WattII.UNITS}

__all__ = ["CONVENTIONS", "G", "KINDS", "declare", "describe", "fmt", "unit", "unit_of"]

#: Standard gravity in the report's unit system, in/sec^2 (the listing's G=386.0880):
#: W / G turns a weight in lb into a mass in lb-sec^2/in.
G = 386.088

#: The sign conventions in brief (docs/conventions.md has them in full, with a drawing).
CONVENTIONS = """\
conventions (docs/conventions.md):
  frame: O2 at the origin, O4 at (R1, 0); x along O2->O4, y 90 degrees CCW from it
  angles: THETA 2, 3, 4 and every direction in degrees, CCW from +x; THETA 3 is the
    line A->B, THETA 4 the line O4->B; ADEL is CCW from the link's line to its G
  rates: TH2D, TH3D, TH4D and the torques are CCW-positive (TH2D > 0: the crank
    turns CCW)
  forces: FA32 is the force of link 3 on link 2 (at A), FB34 of 3 on 4 (at B),
    FOA and FOB what the moving links put on the frame at O2 and O4, SHAKE their
    sum (the shaking force on the frame)
  TORQ: the torque the drive puts on the crank; TEX: an external torque on link 4
  units: in, lb, sec (or SI: m, kg, N); W is a weight, mass = W / g with
    g = 386.088 in/sec^2 (in SI W is the mass itself)
  scene: the 1966 program's by default (constant crank speed, no gravity, TEX the
    only load); gravity, crank acceleration and loads are modelled when a spec's
    [scene] or the API's Scene turns them on (docs/effects.md)"""

_POINTS = {"G2": "the centre of mass G2 of link 2", "A": "pin A (links 2 and 3)",
           "G3": "the centre of mass G3 of link 3", "B": "pin B (links 3 and 4)",
           "G4": "the centre of mass G4 of link 4"}
_FORCES = {"FA32": "force of link 3 on link 2 at A", "FB34": "force of link 3 on link 4 at B",
           "FOA": "force of link 2 on the frame at O2 (F 2 ON 1)",
           "FOB": "force of link 4 on the frame at O4 (F 4 ON 1)",
           "SHAK": "shaking force on the frame, FOA + FOB"}

_FIXED: dict[str, tuple[str, str]] = {
    "ATH2": ("deg", "THETA 2, the crank angle O2->A, CCW from O2->O4"),
    "ATH3": ("deg", "THETA 3, the coupler angle A->B, CCW from O2->O4, in (-90, 270]"),
    "ATH4": ("deg", "THETA 4, the rocker angle O4->B, CCW from O2->O4, in (-90, 270]"),
    "GAMMA": ("deg", "transmission angle, between B->A and B->O4, 0 to 180"),
    "TH3D": ("rad/sec", "angular velocity of link 3, CCW +"),
    "TH4D": ("rad/sec", "angular velocity of link 4, CCW +"),
    "TH3DD": ("rad/sec^2", "angular acceleration of link 3, CCW +"),
    "TH4DD": ("rad/sec^2", "angular acceleration of link 4, CCW +"),
    "TEX": ("in-lb", "external torque on link 4, CCW + (0 in the 1966 program)"),
    "TORQ_INERTIA": ("in-lb", "the part of TORQ the links' inertia takes"),
    "TORQ": ("in-lb", "driving torque the drive puts on the crank, CCW +"),
    "SHAKM": ("in-lb", "shaking moment on the frame about O2, CCW +"),
    "ASSEMBLED": ("-", "True where the loop closes at this crank angle (the position exists)"),
    "TI3": ("in-lb", "inertia torque of link 3, -ZI3 TH3DD"),
    "TI4": ("in-lb", "inertia torque of link 4, -ZI4 TH4DD"),
    "TP2": ("in-lb", "driving torque for link 3's inertia alone (superposition)"),
    "TPP2": ("in-lb", "driving torque for link 4's inertia alone (superposition)"),
}


#: The outputs the model's effects declare (``Model.add_effect``): name -> (kind, meaning).
_DECLARED: dict[str, tuple[str, str]] = {}


def declare(name: str, kind: str, description: str) -> None:
    """Enter an effect's output in the catalogue: its kind of quantity (a key of
    :data:`KINDS`, which gives its unit in each system) and its meaning.  The effect's
    declaration is the one place that says it; declaring a name again with another kind
    is a ValueError."""
    if kind not in KINDS:
        raise ValueError(f"output {name}: kind {kind!r} is not one of {', '.join(KINDS)}")
    known = _DECLARED.get(name)
    if known is not None and known[0] != kind:
        raise ValueError(f"output {name} declared as {known[0]} and as {kind}")
    if name in _FIXED:  # a listing name an effect also provides (TEX): the same unit
        if _FIXED[name][0] != KINDS[kind][0]:
            raise ValueError(f"output {name}: the listing's unit is {_FIXED[name][0]}, "
                             f"not {KINDS[kind][0]}")
        return
    _DECLARED[name] = (kind, description)


def _vector(name: str) -> tuple[str, str] | None:
    """Unit and meaning of a vector quantity's magnitude, direction or component."""
    for prefix, kind, u in (("V", "velocity", "in/sec"), ("A", "acceleration", "in/sec^2")):
        for pt, where in _POINTS.items():
            base = prefix + pt if pt != "A" else prefix + "A"
            if name == base:
                return u, f"magnitude of the {kind} of {where}"
            if name == "D" + base:
                return "deg", f"direction of the {kind} of {where}, CCW from +x"
            if name in (base + "X", base + "Y"):
                return u, f"{name[-1].lower()} component of the {kind} of {where}"
    for base, meaning in _FORCES.items():
        if name == base:
            return "lb", f"magnitude of the {meaning}"
        if name == "D" + base:
            return "deg", f"direction of the {meaning}, CCW from +x"
        if name in (base + "X", base + "Y"):
            return "lb", f"{name[-1].lower()} component of the {meaning}"
    if name[:2] == "FG" and name[-1] in "XY":  # FG2X: D'Alembert inertia force
        return "lb", f"{name[-1].lower()} component of the inertia force -m aG of link {name[2]}"
    if name.startswith(("FP", "F3P")) and name[-1] in "XY":  # superposition partials
        return "lb", (f"{name[-1].lower()} component of a partial pin force "
                      "(one link's inertia alone, superposition as in the listing)")
    return None


#: The report's units and their SI counterparts (mechanism.SI, the one table).
SI = MECHANISM_SI


def unit(name: str, units: str = "in-lb-sec") -> str:
    """The unit of a listing or engine name (``"in-lb"``, ``"deg"``, ...) in the unit
    system ``units`` (``"in-lb-sec"``, the report's, or ``"SI"``)."""
    if name in MECHANISM_UNITS:
        found = MECHANISM_UNITS[name]
        if units == "SI" and name[0] == "W" and name[1:].isdigit():
            return "kg"  # SI takes masses, not weights
    elif name == "CARD":
        found = "-"
    elif name in _DECLARED:
        return unit_of(_DECLARED[name][0], units)
    else:
        entry = _FIXED.get(name) or _vector(name)
        if entry is None:
            raise KeyError(f"no unit is known for {name!r} (an effect's outputs are known "
                           "once sielaff.engine is imported)")
        found = entry[0]
    if units == "SI":
        return SI[found]
    if units != "in-lb-sec":
        raise ValueError(f"units = {units!r}: in-lb-sec or SI")
    return found


#: The unit of each kind of quantity, (in-lb-sec, SI): every tool and figure labels a
#: number through :func:`unit_of` or :func:`fmt`, so a spec in SI never reads as inches.
#: In SI a link's W field is a mass (kg) and gravity makes it a weight in N.
KINDS: dict[str, tuple[str, str]] = {
    "length": ("in", "m"),
    "weight": ("lb", "kg"),  # the W fields: a weight in the report, a mass in SI
    "force": ("lb", "N"),
    "inertia": ("in-lb-sec^2", "kg m^2"),
    "torque": ("in-lb", "N m"),
    "work": ("in-lb", "J"),
    "power": ("in-lb/sec", "W"),
    "speed": ("in/sec", "m/s"),
    "acceleration": ("in/sec^2", "m/s^2"),
    "angle": ("deg", "deg"),
    "rate": ("rad/sec", "rad/s"),
    "angular acceleration": ("rad/sec^2", "rad/s^2"),
    "stiffness": ("lb/in", "N/m"),
    "damping": ("lb sec/in", "N s/m"),
    "rotary damping": ("in-lb-sec", "N m s"),  # a torque per rad/sec
    "number": ("-", "-"),
    "area": ("in^2", "m^2"),
    "density": ("lb/in^3", "kg/m^3"),  # a weight per volume, or in SI a mass per volume
}


def unit_of(name_or_kind: str, units: str = "in-lb-sec") -> str:
    """The unit of a kind of quantity (a key of :data:`KINDS`: ``"length"``,
    ``"force"``, ``"torque"``, ``"work"``, ...) or of a listing or engine name
    (``"R1"``, ``"TORQ"``, see :func:`unit`) in the unit system ``units``
    (``"in-lb-sec"`` or ``"SI"``)."""
    if units not in ("in-lb-sec", "SI"):
        raise ValueError(f"units = {units!r}: in-lb-sec or SI")
    if name_or_kind in KINDS:
        return KINDS[name_or_kind][units == "SI"]
    return unit(name_or_kind, units)


def fmt(value: float, name_or_kind: str, units: str = "in-lb-sec", spec: str = ".4g") -> str:
    """``value`` with its unit: ``fmt(12.0, "length", "SI") == "12 m"``.

    Parameters
    ----------
    value : float
        The number [the unit of ``name_or_kind`` in ``units``].
    name_or_kind : str
        A kind of :data:`KINDS` or a listing or engine name [-].
    units : str
        ``"in-lb-sec"`` (the report's) or ``"SI"`` [-].
    spec : str
        A format spec for the number (``".4g"``, ``"9.1f"``) [-].
    """
    u = unit_of(name_or_kind, units)
    text = format(float(value), spec)
    return text if u == "-" else f"{text} {u}"


def describe(name: str) -> str:
    """One line saying what a listing or engine name is."""
    if name == "CARD":
        return "the deck line of the range card this position comes from"
    found = _FIXED.get(name) or _DECLARED.get(name) or _vector(name)
    if found is None:
        raise KeyError(f"no description is known for {name!r}")
    return found[1]
