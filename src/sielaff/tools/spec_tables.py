"""The declared keys of the spec's tables that commands read (``[motor]`` for simulate,
``[synthesis]`` for synth, ``[tolerance]`` for tolerance; ``[sweep]``'s are in
:mod:`sielaff.tools.spec_sweep`, ``[scene]``'s in each effect's declaration).

Each reader refuses a key not declared here and takes its defaults as declared
(tests/test_spec_reference.py); ``sielaff help spec`` and docs/spec.md are made from
these.  Commands import this module; it imports no command.
"""

from __future__ import annotations

from sielaff.tools.spec_fields import Key

__all__ = ["MOTOR_KINDS", "PROBLEMS", "PROBLEM_KINDS", "motor_keys", "problem_unit",
           "synthesis_keys", "tolerance_keys"]

#: A [motor] table's keys for each kind (besides kind and the run's keys).
MOTOR_KINDS = {"constant": ("torque",), "linear": ("stall_torque", "no_load_speed"),
               "induction": ("rated_torque", "rated_speed", "breakdown_torque",
                             "synchronous_speed")}
#: Each synthesis problem's own keys ([synthesis.PROBLEM]).
PROBLEMS = {
    "crank_rocker": ("swing", "time_ratio", "rocker", "k_max", "members"),
    "function": ("f", "x_range", "input_range", "output_range", "points", "frame", "samples"),
    "motion": ("poses", "moving", "fixed", "direction"),
    "path": ("points", "crank_angles", "starts", "seed"),
}
#: The kind of quantity (quantities.KINDS) of each problem's keys that have one unit; the
#: others are "-" (ratios, counts, names); a pose is x, y and an angle.
PROBLEM_KINDS = {
    "crank_rocker": {"swing": "angle", "rocker": "length"},
    "function": {"input_range": "angle", "output_range": "angle"},
    "motion": {"poses": "length;length;angle", "moving": "length", "fixed": "length"},
    "path": {"points": "length", "crank_angles": "angle"},
}
#: Problems a spec may make (the product of [synthesis.vary]).
MAX_PROBLEMS = 1000


def problem_unit(problem: str, key: str, units: str) -> str:
    """The unit of a synthesis problem's key in ``units`` ("-" where it has none)."""
    from sielaff.quantities import unit_of

    kinds = PROBLEM_KINDS[problem].get(key, "number")
    return ";".join(unit_of(k, units) for k in kinds.split(";"))


def motor_keys() -> tuple:
    """The ``[motor]`` table's keys, declared (:class:`~sielaff.tools.spec_fields.Key`):
    what ``sielaff help spec`` and docs/spec.md say, and all :func:`motor_of` takes."""
    from sielaff.dynamics.simulate import MAX_SPEED, METHODS, RTOL, max_revolutions

    speed = f"0 to {MAX_SPEED:g}"
    return (
        Key("kind", "name", "", ", ".join(MOTOR_KINDS), "the speed-torque curve"),
        Key("torque", "torque", "", "any finite", "constant: the torque at every speed"),
        Key("stall_torque", "torque", "", "> 0", "linear: the torque at rest"),
        Key("no_load_speed", "rate", "", f"> 0, to {MAX_SPEED:g}",
            "linear: the speed of no torque"),
        Key("rated_torque", "torque", "", "> 0", "induction: the torque at the rated speed"),
        Key("rated_speed", "rate", "", "> 0, below synchronous_speed",
            "induction: the rated speed"),
        Key("breakdown_torque", "torque", "", "> rated_torque",
            "induction: the peak of the slip curve (Kloss)"),
        Key("synchronous_speed", "rate", "", f"> 0, to {MAX_SPEED:g}",
            "induction: the speed of no slip, no torque"),
        Key("flywheel", "inertia", "0", ">= 0", "inertia added to the crank"),
        Key("revolutions", "number", "20", f"(0, {max_revolutions():g}]",
            "how many revolutions to integrate (360 samples each)"),
        Key("steady", "bool", "false", "true, false",
            "true: one revolution of the periodic steady state instead"),
        Key("speed", "rate", "[drive] speed", speed.replace("0 to", "-/+ up to"),
            "the crank speed at the start (0: from rest)"),
        Key("method", "name", f'"{METHODS[0]}"', ", ".join(METHODS), "solve_ivp's method"),
        Key("rtol", "number", "1e-8", f"{RTOL[0]:g} to {RTOL[1]:g}",
            "solve_ivp's relative tolerance"),
    )


def tolerance_keys() -> tuple:
    """The ``[tolerance]`` table's keys, declared (:class:`~sielaff.tools.spec_fields.Key`)."""
    from sielaff.design.sweep import MAX_ANGLES
    from sielaff.design.tolerance import DISTRIBUTIONS, MAX_SAMPLES

    return (
        Key("n", "integer", "1000", f"2 to {MAX_SAMPLES:,}", "samples (Monte Carlo)"),
        Key("seed", "integer", "0", "0 to 2^63 - 1", "the random generator's seed"),
        Key("distribution", "name", '"normal"', ", ".join(DISTRIBUTIONS),
            "each deviation: one standard deviation (normal) or the half width (uniform)"),
        Key("angles", "integer", "360", f"even, 8 to {MAX_ANGLES}",
            "crank angles per revolution"),
        Key("cf", "number", "0.05", "(0, 2)", "coefficient of speed fluctuation (flywheel)"),
        Key("deviations", "table", "", "FIELD = deviation >= 0, in the field's unit",
            "[tolerance.deviations]: the fields that vary and by how much"),
    )


def synthesis_keys() -> tuple:
    """The ``[synthesis]`` table's keys, declared (:class:`~sielaff.tools.spec_fields.Key`);
    each problem's own table takes the keys of :data:`PROBLEMS` (docs/synthesis.md)."""
    from sielaff.design.sweep import MAX_ANGLES
    from sielaff.synthesis.rank import RANKABLE

    figures = " ".join(RANKABLE)
    return (
        Key("problem", "name", "", ", ".join(PROBLEMS), "what is synthesised"),
        Key("by", "list", '["TORQ_PEAK"]', figures, "the figures the ranking sorts by"),
        Key("pareto", "list", "", f"two of {figures}", "the two figures of the Pareto front"),
        Key("speed", "rate", "1", "non-zero, |x| < 1e6", "the crank speed the ranking uses"),
        Key("angles", "integer", "360", f"even, 8 to {MAX_ANGLES}",
            "crank angles per revolution"),
        Key("cf", "number", "0.05", "(0, 2)", "coefficient of speed fluctuation (flywheel)"),
        Key("best", "integer", "1", "0 to 1000", "candidates written by --write-best"),
        Key("density", "density", "", "> 0", "the links' material (with area): their "
            "weights (in SI masses) W = density x area x length"),
        Key("area", "area", "", "> 0", "the links' cross-section (with density)"),
        Key("vary", "table", "", f"{MAX_PROBLEMS} problems in all",
            "[synthesis.vary]: a problem's key = [alternatives]"),
        Key("constraints", "table", "", f"NAME = {{min = x, max = y}}, NAME one of {figures} "
            "LONGEST SHORTEST or a link ratio such as \"R3/R2\", in its unit",
            "[synthesis.constraints]: bounds a candidate must meet to rank first"),
        Key("tie", "number", "1e-9", "0 to below 0.1", "values of a figure closer than this "
            "times its largest magnitude are tied (the next figure decides)"),
        *(Key(name, "table", "", ", ".join(keys), f"[synthesis.{name}]: its parameters")
          for name, keys in PROBLEMS.items()),
    )
