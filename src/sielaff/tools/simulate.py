"""``sielaff simulate SPEC.toml [-o FILE.csv] [--plot FILE.png]``: the crank driven by a
motor (:func:`sielaff.dynamics.simulate`).

The spec's mechanism and [scene] are the linkage and what acts on it; its ``[motor]``
(``sielaff.tools.spec.motor_of``) is the motor, the flywheel, how many revolutions, or
``steady = true`` for one revolution of the periodic steady state.  The time history is
CSV, the header naming each column with its unit (``t[s]``, ``ATH2[deg]`` unwrapped,
``TH2D[rad/sec]``, ``TH2DD[rad/sec^2]``, ``MOTOR[in-lb]``, ``TORQ[in-lb]``), on stdout
or in ``-o``; ``--plot`` draws the speed and the torques against THETA 2.  One line on
stderr says what happened (the revolutions made, the steady speed, or a stall).  Files
are written whole or not at all.  Needs scipy (``pip install -e ".[dynamics]"``).
"""

from __future__ import annotations

import os
import sys

COLUMNS = ("t", "ATH2", "TH2D", "TH2DD", "MOTOR", "TORQ")


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
    from sielaff.tools.common import CommandError, load_scene, refuse_overwriting_inputs
    from sielaff.tools.output import atomic_files
    from sielaff.tools.spec import PunchError, motor_of, read_spec

    path = args.spec
    for target in (args.output, args.plot):
        refuse_overwriting_inputs(target, [path])
        if target and os.path.isdir(target):
            raise CommandError(f"sielaff: {target} is a folder: name the file to write")
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
    if not path.endswith(".toml"):
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
