"""``sielaff simulate SPEC.toml [-o FILE.csv] [--plot FILE.png]``: the crank driven by a
motor (:func:`sielaff.dynamics.simulate`).

The spec's mechanism and [scene] are the linkage and what acts on it; its ``[motor]``
(:func:`motor_of`, read here: spec_fields.py only lets the table through) is the motor, the
flywheel, how many revolutions, or
``steady = true`` for one revolution of the periodic steady state.  The time history is
CSV, the header naming each column with its unit (``t[s]``, ``ATH2[deg]`` unwrapped,
``TH2D[rad/sec]``, ``TH2DD[rad/sec^2]``, ``MOTOR[in-lb]``, ``TORQ[in-lb]``; in SI
``rad/s`` and ``N m``, as ``table`` writes them), on stdout or in ``-o``; ``--plot``
draws the speed, the torques and the motor's power against time.  On stderr, one line
says what happened (the revolutions made, the steady speed, or a stall), then the motor
sizing (:mod:`sielaff.dynamics.sizing`: torque peak and RMS, power, speed range,
fluctuation, slip) and a warning where the motor runs as a generator.  Files are written
whole or not at all.  Needs scipy (``pip install -e ".[dynamics]"``).
"""

from __future__ import annotations

import sys

from sielaff.tools.spec_tables import MOTOR_KINDS, motor_keys

COLUMNS = ("t", "ATH2", "TH2D", "TH2DD", "MOTOR", "TORQ")



def motor_of(spec: dict, path: str = "<spec>", units: str = "in-lb-sec") -> dict:
    """The spec's ``[motor]`` for ``sielaff simulate``: ``{"motor": Motor, "flywheel",
    "revolutions", "steady", "speed", "method", "rtol"}``::

        [motor]
        kind = "linear"           # constant (torque), linear (stall_torque, no_load_speed)
        stall_torque = 2000.0     # or induction (rated_torque, rated_speed,
        no_load_speed = 55.0      #   breakdown_torque, synchronous_speed); torques in the
        flywheel = 2.0            #   spec's units, speeds rad/sec; flywheel inertia
        revolutions = 20          #   (in-lb-sec^2 or kg m^2); speed: the crank speed at
        steady = false            #   the start (default TH2D), 0 from rest; method and
        method = "LSODA"          #   rtol: solve_ivp's (LSODA, RK45, RK23, DOP853,
        rtol = 1e-8               #   Radau, BDF), 1e-14 to 0.1

    A missing, unknown or bad key is one line naming it.
    """
    from sielaff.dynamics.motor import Motor
    from sielaff.dynamics.simulate import MAX_SPEED, METHODS, RTOL, max_revolutions
    from sielaff.quantities import unit_of
    from sielaff.tools.spec_fields import PunchError, _float, _name, _table, _unknown

    where = f"{path}: [motor]"
    ru = unit_of("rate", units)
    if "motor" not in spec:
        raise PunchError(f"{path}: no [motor] table (kind = \"constant\", \"linear\" or "
                         "\"induction\" and its parameters)")
    table = _table(where, spec["motor"])
    kind = _name(f"{where} kind", table.get("kind"), tuple(MOTOR_KINDS))
    # the declared keys: kind, this kind's own, and the run's
    run_keys = [k.name for k in motor_keys() if not any(k.name in v for v in
                                                         MOTOR_KINDS.values())]
    _unknown(where, table, (*MOTOR_KINDS[kind], *run_keys))
    params = []
    for key in MOTOR_KINDS[kind]:
        if key not in table:
            raise PunchError(f"{where} has no {key} (a {kind} motor needs "
                             f"{', '.join(MOTOR_KINDS[kind])})")
        params.append(_float(f"{where} {key}", table[key]))
        if key.endswith("speed") and abs(params[-1]) > MAX_SPEED:
            raise PunchError(f"{where} {key} = {params[-1]:g}: past {MAX_SPEED:g} {ru} "
                             "(the largest speed simulate takes: docs/robustness.md)")
    try:
        motor = getattr(Motor, kind)(*params)
    except ValueError as exc:
        raise PunchError(f"{where}: {str(exc).replace('rad/sec', ru)}") from None
    out = {"motor": motor, "flywheel": _float(f"{where} flywheel", table.get("flywheel", 0)),
           "revolutions": _float(f"{where} revolutions", table.get("revolutions", 20)),
           "speed": (None if "speed" not in table
                     else _float(f"{where} speed", table["speed"]))}
    steady = table.get("steady", False)
    if not isinstance(steady, bool):
        raise PunchError(f"{where} steady = {steady!r}: true or false")
    out["steady"] = steady
    out["method"] = _name(f"{where} method", table.get("method", METHODS[0]), METHODS)
    out["rtol"] = _float(f"{where} rtol", table["rtol"]) if "rtol" in table else 1e-8
    if not RTOL[0] <= out["rtol"] <= RTOL[1]:
        raise PunchError(f"{where} rtol = {out['rtol']:g}: in [{RTOL[0]:g}, {RTOL[1]:g}]")
    if out["flywheel"] < 0:
        raise PunchError(f"{where} flywheel = {out['flywheel']:g}: an inertia cannot be "
                         "negative")
    most = max_revolutions()
    if not 0 < out["revolutions"] <= most:
        raise PunchError(f"{where} revolutions = {out['revolutions']:g}: in (0, {most:g}] "
                         "(360 samples a revolution, at most 1,048,576 in the CSV); "
                         "steady = true gives the periodic state in one revolution")
    if out["speed"] is not None and abs(out["speed"]) > MAX_SPEED:
        raise PunchError(f"{where} speed = {out['speed']:g}: past {MAX_SPEED:g} {ru} "
                         "(the largest speed simulate takes: docs/robustness.md)")
    return out


def draw(fig, r) -> None:
    """The run on ``fig``: crank speed, torques and the motor's power against time."""
    import textwrap

    from sielaff.quantities import unit_of

    ax1, ax2, ax3 = fig.subplots(3, 1, sharex=True)
    t = r["t"]
    ax1.plot(t, r["TH2D"], color="C0")
    ax1.set_ylabel(f"crank speed TH2D [{r.units['TH2D']}]")
    ax1.set_title("\n".join(textwrap.wrap(r.message, 100)), fontsize=9)
    ax2.plot(t, r["MOTOR"], label="motor torque MOTOR")
    ax2.plot(t, r["TORQ"], label="linkage's drive torque TORQ")
    ax2.set_ylabel(f"torque [{r.units['MOTOR']}]")
    ax2.legend(fontsize=8)
    ax3.plot(t, r["MOTOR"] * r["TH2D"], color="C2")
    ax3.axhline(0.0, color="0.5", lw=0.8)
    ax3.set_ylabel(f"motor power [{unit_of('power', r.mechanism_units)}]")
    ax3.set_xlabel("time t [s]")
    for ax in (ax1, ax2, ax3):
        ax.grid(alpha=0.3)


def _plot(path: str, r) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(8, 8))
    draw(fig, r)
    fig.tight_layout()
    fig.savefig(path, dpi=100, format="png")
    plt.close(fig)


def cmd_simulate(args) -> int:
    from sielaff.tools.common import (
        CommandError,
        load_scene,
        read_spec,
        refuse_bad_output,
        refuse_stdout,
        spec_path,
    )
    from sielaff.tools.output import atomic_files
    from sielaff.tools.spec import PunchError

    path = args.spec
    if args.output == "-":
        args.output = None  # -o -: the time history on stdout, the status on stderr
    for target in (args.output, args.plot):
        refuse_bad_output(target, [path])
    refuse_stdout(args.plot, "--plot writes a PNG file", "--plot", "a file")
    try:
        import scipy.integrate  # noqa: F401
        import scipy.optimize  # noqa: F401
    except ImportError:
        raise CommandError('sielaff: simulate needs scipy: pip install -e ".[dynamics]"') \
            from None
    if args.plot:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            raise CommandError('sielaff: --plot needs matplotlib: pip install -e ".[plot]"') \
                from None
    if not spec_path(path):
        raise CommandError(f"{path}: simulate reads a TOML spec with a [motor] table")
    from sielaff.tools.kinds import other_kinds

    deck, scene = load_scene(path, kinds=other_kinds())
    try:
        run = motor_of(read_spec(path), path, deck.mechanism.units)
    except PunchError as exc:
        raise CommandError(str(exc), exc.status) from None
    from sielaff.dynamics import simulate

    m = deck.mechanism
    r = simulate(m, run["motor"], flywheel=run["flywheel"], scene=scene,
                 speed0=run["speed"], revolutions=run["revolutions"], steady=run["steady"],
                 outputs=["TORQ"], method=run["method"], rtol=run["rtol"])
    header = ",".join(f"{c}[{r.units[c]}]" for c in COLUMNS)
    table = [header] + [",".join(repr(float(v)) for v in row)
                        for row in zip(*(r[c] for c in COLUMNS))]
    text = "\n".join(table) + "\n"
    paths = [p for p in (args.output, args.plot) if p]
    with atomic_files(paths) as temps:
        if args.output:
            with open(temps[0], "w", newline="") as f:
                f.write(text)
        if args.plot:
            _plot(temps[-1], r)
    if not args.output:
        sys.stdout.write(text)
    print(f"sielaff: simulate: {r.message}", file=sys.stderr)
    from sielaff.dynamics.sizing import sizing_lines

    for line in sizing_lines(r):
        print(f"sielaff: {line}" if line.startswith("warning:") else line, file=sys.stderr)
    return 0
