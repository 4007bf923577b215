"""``sielaff simulate SPEC.toml [-o FILE.csv] [--plot FILE.png]``: the crank driven by a
motor (:func:`sielaff.dynamics.simulate`).

The spec's mechanism and [scene] are the linkage and what acts on it; its ``[motor]``
(:func:`motor_of`, read here: spec_fields.py only lets the table through) is the motor, the
flywheel, how many revolutions, or
``steady = true`` for one revolution of the periodic steady state.  The time history is
CSV, the header naming each column with its unit (``t[s]``, ``ATH2[deg]`` unwrapped,
``TH2D[rad/sec]``, ``TH2DD[rad/sec^2]``, ``MOTOR[in-lb]``, ``TORQ[in-lb]``), on stdout
or in ``-o``; ``--plot`` draws the speed and the torques against THETA 2.  One line on
stderr says what happened (the revolutions made, the steady speed, or a stall).  Files
are written whole or not at all.  Needs scipy (``pip install -e ".[dynamics]"``).
"""

from __future__ import annotations

import sys

COLUMNS = ("t", "ATH2", "TH2D", "TH2DD", "MOTOR", "TORQ")

#: A [motor] table's keys for each kind (besides kind and the run's keys).
MOTOR_KINDS = {"constant": ("torque",), "linear": ("stall_torque", "no_load_speed"),
               "induction": ("rated_torque", "rated_speed", "breakdown_torque",
                             "synchronous_speed")}
MOTOR_RUN = ("flywheel", "revolutions", "steady", "speed")


def motor_of(spec: dict, path: str = "<spec>") -> dict:
    """The spec's ``[motor]`` for ``sielaff simulate``: ``{"motor": Motor, "flywheel",
    "revolutions", "steady", "speed"}``::

        [motor]
        kind = "linear"           # constant (torque), linear (stall_torque, no_load_speed)
        stall_torque = 2000.0     # or induction (rated_torque, rated_speed,
        no_load_speed = 55.0      #   breakdown_torque, synchronous_speed); torques in the
        flywheel = 2.0            #   spec's units, speeds rad/sec; flywheel inertia
        revolutions = 20          #   (in-lb-sec^2 or kg m^2); speed: the crank speed at
        steady = false            #   the start (default TH2D), 0 from rest

    A missing, unknown or bad key is one line naming it.
    """
    from sielaff.dynamics.motor import Motor
    from sielaff.tools.spec_fields import PunchError, _float, _name, _table, _unknown

    where = f"{path}: [motor]"
    if "motor" not in spec:
        raise PunchError(f"{path}: no [motor] table (kind = \"constant\", \"linear\" or "
                         "\"induction\" and its parameters)")
    table = _table(where, spec["motor"])
    kind = _name(f"{where} kind", table.get("kind"), tuple(MOTOR_KINDS))
    _unknown(where, table, ("kind", *MOTOR_KINDS[kind], *MOTOR_RUN))
    params = []
    for key in MOTOR_KINDS[kind]:
        if key not in table:
            raise PunchError(f"{where} has no {key} (a {kind} motor needs "
                             f"{', '.join(MOTOR_KINDS[kind])})")
        params.append(_float(f"{where} {key}", table[key]))
    try:
        motor = getattr(Motor, kind)(*params)
    except ValueError as exc:
        raise PunchError(f"{where}: {exc}") from None
    out = {"motor": motor, "flywheel": _float(f"{where} flywheel", table.get("flywheel", 0)),
           "revolutions": _float(f"{where} revolutions", table.get("revolutions", 20)),
           "speed": (None if "speed" not in table
                     else _float(f"{where} speed", table["speed"]))}
    steady = table.get("steady", False)
    if not isinstance(steady, bool):
        raise PunchError(f"{where} steady = {steady!r}: true or false")
    out["steady"] = steady
    if out["flywheel"] < 0:
        raise PunchError(f"{where} flywheel = {out['flywheel']:g}: an inertia cannot be "
                         "negative")
    if not 0 < out["revolutions"] <= 1e5:
        raise PunchError(f"{where} revolutions = {out['revolutions']:g}: in (0, 100000]")
    return out


def _plot(path: str, r, units: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    ax1.plot(r["ATH2"], r["TH2D"], color="C0")
    ax1.set_ylabel("crank speed TH2D [rad/sec]")
    ax1.set_title(r.message, fontsize=9)
    ax2.plot(r["ATH2"], r["MOTOR"], label="motor torque MOTOR")
    ax2.plot(r["ATH2"], r["TORQ"], label="linkage's drive torque TORQ")
    ax2.set_ylabel(f"torque [{r.units['MOTOR']}]")
    ax2.set_xlabel("THETA 2 [deg] (unwrapped)")
    ax2.legend(fontsize=8)
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
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
    refuse_stdout(args.plot, "--plot writes a PNG file")
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
    deck, scene = load_scene(path)
    try:
        run = motor_of(read_spec(path), path)
    except PunchError as exc:
        raise CommandError(str(exc), exc.status) from None
    from sielaff.dynamics import simulate

    m = deck.mechanism
    r = simulate(m, run["motor"], flywheel=run["flywheel"], scene=scene,
                 speed0=run["speed"], revolutions=run["revolutions"], steady=run["steady"],
                 outputs=["TORQ"])
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
            _plot(temps[-1], r, m.units)
    if not args.output:
        sys.stdout.write(text)
    print(f"sielaff: simulate: {r.message}", file=sys.stderr)
    return 0
