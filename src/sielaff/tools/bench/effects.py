"""``sielaff bench --effects``: what accuracy costs in time for the new solves.

Three questions, each answered by measurement (``effects_study``), each error read from a
quantity the solve does not control:

* **the friction fixed point** (``PinFriction.tol`` 1e-3 to 1e-13): ``analyze`` on the 1966
  example with mu r = 0.1 in each pin; the error is the largest residual of friction's
  power identity ``TORQ_FRICTION TH2D = sum of mu r |F| |relative rotation|`` (F the
  reported pin forces) over the largest loss;
* **simulate's integration** (rtol 1e-3 to 1e-12, and the method) on decks/friction.toml's
  scene (pin friction and a return spring) with its linear motor and flywheel, 2
  revolutions from 50 rad/sec; the error is the energy balance over the run, |motor work
  - change of kinetic energy - friction losses - change of the spring's energy| over
  the motor work, every term from the engine's outputs at 2000 samples per revolution
  (velocities and masses, PLOSS_*, SPRING1_L), none from the reduced inertia the
  equation of motion uses;
* **the hard cases**: friction near a toggle, a motor too weak for the dead point, a
  start from rest: what each does, and what it costs.

Each configuration runs ``rounds`` times: CPU time (user + sys of this process) beside
wall time, median and range; the 1966 scene (no friction) is timed beside the friction
solve in every round.  ``--quick`` (the default grid of ``sielaff bench --effects``) is a
small grid, one round: seconds, not minutes.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable

import numpy as np

TOLS = (1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-13)
RTOLS = (1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
METHODS = ("DOP853", "RK45", "LSODA", "Radau")
PLOSS = ("PLOSS_O2", "PLOSS_A", "PLOSS_B", "PLOSS_O4")
G = 386.088  # in/sec^2: W / G is a mass in the report's units


def _timed(fn: Callable[[], object]) -> tuple[float, float, object]:
    c0, w0 = time.process_time(), time.perf_counter()
    out = fn()
    return time.process_time() - c0, time.perf_counter() - w0, out


def spread(xs: list[float], fmt: str = "{:.3g}") -> str:
    """median (min-max)."""
    return (f"{fmt.format(statistics.median(xs))} "
            f"({fmt.format(min(xs))}-{fmt.format(max(xs))})")


def friction_rows(tols, n: int, rounds: int) -> list[dict]:
    """The friction fixed point's tolerance against CPU time and the power-identity error."""
    from sielaff.engine.analysis import analyze
    from sielaff.engine.friction import PinFriction
    from sielaff.engine.scene import Scene
    from sielaff.mechanism import EXAMPLE

    th = np.linspace(0.0, 360.0, n, endpoint=False)
    out = ["TORQ", "TORQ_FRICTION", "FRICTION_ITERATIONS", *PLOSS]
    analyze(EXAMPLE, th, ["TORQ"])  # warm up
    rows = []
    for tol in tols:
        sc = Scene(friction=PinFriction(0.1, 1.0, tol=tol))
        cpu, wall, ref = [], [], []
        for _ in range(rounds):
            rc, _, _ = _timed(lambda: analyze(EXAMPLE, th, ["TORQ"]))
            c, w, r = _timed(lambda sc=sc: analyze(EXAMPLE, th, out, scene=sc))
            cpu.append(c * 1e3)
            wall.append(w * 1e3)
            ref.append(rc * 1e3)
        loss = sum(r[p] for p in PLOSS)
        err = float(np.nanmax(np.abs(r["TORQ_FRICTION"] * EXAMPLE.TH2D - loss))
                    / np.nanmax(loss))
        rows.append({"tol": tol, "iterations": float(np.max(r["FRICTION_ITERATIONS"])),
                     "cpu_ms": cpu, "wall_ms": wall, "ref_ms": ref, "error": err})
    return rows


def friction_scene():
    """decks/friction.toml's scene, motor and flywheel."""
    from sielaff.dynamics.motor import Motor
    from sielaff.engine.elements import Spring
    from sielaff.engine.friction import PinFriction
    from sielaff.engine.scene import Scene

    return (Scene(friction=PinFriction(0.1, 0.25),
                  elements=[Spring((1, 18.0, 0.0), (4, 6.0, 0.0), 20.0, 8.0)]),
            Motor.linear(2000.0, 55.0), 7.41)


def energy_error(r, scene, fw: float) -> float:
    """|motor work - dKE - losses - dPE| / motor work over a run, from engine outputs."""
    from scipy.integrate import simpson

    from sielaff.engine.analysis import analyze
    from sielaff.mechanism import EXAMPLE

    m = EXAMPLE
    w = r["TH2D"]
    k = analyze(m.replace(TH2D=w), r["ATH2"], ["VG2", "VG3", "VG4", "TH3D", "TH4D",
                                                  "SPRING1_L", *PLOSS],
                scene=scene.replace(th2dd=r["TH2DD"]))
    ke = (0.5 * (m.W2 * k["VG2"] ** 2 + m.W3 * k["VG3"] ** 2 + m.W4 * k["VG4"] ** 2) / G
          + 0.5 * (m.ZI2 * w ** 2 + m.ZI3 * k["TH3D"] ** 2 + m.ZI4 * k["TH4D"] ** 2)
          + 0.5 * fw * w ** 2)
    spring = scene.elements[0]
    pe = 0.5 * spring.k * (k["SPRING1_L"] - spring.length) ** 2
    work = simpson(r["MOTOR"], x=np.radians(r["ATH2"]))
    losses = simpson(sum(k[p] for p in PLOSS), x=r["t"])
    return float(abs(work - (ke[-1] - ke[0]) - losses - (pe[-1] - pe[0])) / abs(work))


def simulate_rows(rtols, methods, rounds: int, revolutions: float = 2.0) -> list[dict]:
    """simulate's rtol and method against CPU time, the energy error and the end error."""
    from sielaff.dynamics import simulate
    from sielaff.mechanism import EXAMPLE

    scene, motor, fw = friction_scene()
    kw = dict(flywheel=fw, scene=scene, speed0=50.0, revolutions=revolutions,
              per_revolution=2000)
    end = simulate(EXAMPLE, motor, method="DOP853", rtol=1e-13, **kw)["TH2D"][-1]
    rows = []
    for method in methods:
        for rtol in rtols:
            cpu, wall = [], []
            for _ in range(rounds):
                c, w, r = _timed(lambda method=method, rtol=rtol: simulate(
                    EXAMPLE, motor, method=method, rtol=rtol, **kw))
                cpu.append(c)
                wall.append(w)
            rows.append({"method": method, "rtol": rtol, "evaluations": r.evaluations,
                         "cpu_s": cpu, "wall_s": wall, "mode": r.mode,
                         "energy": energy_error(r, scene, fw),
                         "end": float(abs(r["TH2D"][-1] - end) / abs(end))})
    return rows


def energy_floor(revolutions: float) -> list[tuple[int, float]]:
    """The energy error of one tight run (LSODA, rtol 1e-12) read with 2000 and with 8000
    samples per revolution: where it falls with the samples, the floor in the table is
    the quadrature's (the Coulomb losses jump where a relative rotation changes sign),
    not the integration's."""
    from sielaff.dynamics import simulate
    from sielaff.mechanism import EXAMPLE

    scene, motor, fw = friction_scene()
    out = []
    for n in (2000, 8000):
        r = simulate(EXAMPLE, motor, flywheel=fw, scene=scene, speed0=50.0,
                     revolutions=revolutions, per_revolution=n, rtol=1e-12)
        out.append((n, energy_error(r, scene, fw)))
    return out


def hard_cases() -> list[dict]:
    """Friction near a toggle, a stall at the dead point, a start from rest: the outcome
    (one line, as the user reads it) and its CPU time."""
    import warnings

    from sielaff.dynamics import SimulationError, simulate
    from sielaff.dynamics.motor import Motor
    from sielaff.engine.analysis import analyze
    from sielaff.engine.friction import FrictionWarning, PinFriction
    from sielaff.engine.scene import Scene
    from sielaff.mechanism import EXAMPLE

    scene, motor, fw = friction_scene()
    rows = []

    def toggle():  # a double-rocker (R = 12, 4, 16, 12 with the crank 9): near its toggles
        m = EXAMPLE.replace(R2=9.0)
        from sielaff.engine.positions import reachable

        th = reachable(m, 3600)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", FrictionWarning)
            r = analyze(m, th, ["FRICTION_STATUS", "FRICTION_SOLUTIONS"],
                        scene=Scene(friction=PinFriction(0.3, 1.0)))
        bad = int(np.count_nonzero(r["FRICTION_STATUS"] == 2))
        several = int(np.count_nonzero(r["FRICTION_SOLUTIONS"] >= 2))
        return (f"a double-rocker over 3600 reachable angles, mu r = 0.3: {bad} positions "
                "next to its toggles have no solution of the friction law (self-locking: "
                f"NaN, FRICTION_STATUS 2, one FrictionWarning); {several} have two, the one "
                "continuous from mu = 0 taken")

    def no_solution():
        try:
            simulate(EXAMPLE, motor, flywheel=fw, scene=Scene(friction=PinFriction(1.0, 6.0)),
                     speed0=50.0, revolutions=0.5)
        except SimulationError as exc:
            return f"simulate, mu r = 6 in (of the links' size): {exc}"
        return "simulate, mu r = 6 in: converged"

    def stall():
        heavy = EXAMPLE.replace(W3=40.0)
        r = simulate(heavy, Motor.constant(5.0), scene=Scene(gravity="down"), speed0=1.0,
                     revolutions=2)
        return f"a 5 in-lb motor, a 40 lb coupler under gravity: {r.message}"

    def from_rest():
        r = simulate(EXAMPLE, motor, flywheel=fw, scene=scene, speed0=0.0, revolutions=5)
        w = r["TH2D"]
        t90 = float(r["t"][np.argmax(w >= 0.9 * w[-1])])
        return (f"decks/friction.toml from rest: {r.message}; 90% of that speed after "
                f"{t90:.3g} s")

    for name, fn in (("friction near a toggle", toggle),
                     ("friction with no solution", no_solution),
                     ("a motor too weak for the dead point", stall),
                     ("a start from rest", from_rest)):
        c, w, text = _timed(fn)
        rows.append({"case": name, "outcome": text, "cpu_s": c, "wall_s": w})
    return rows


def effects_study(quick: bool = True, progress: Callable[[str], None] = print) -> dict:
    """Everything ``--effects`` reports (quick: a small grid, one round)."""
    from sielaff.tools.bench.study import machine

    res = {"machine": machine(), "quick": quick}
    rounds = 1 if quick else 3
    progress("the friction fixed point's tolerance")
    res["friction"] = friction_rows(TOLS[::2] + (TOLS[-1],) if quick else TOLS,
                                    2000 if quick else 10_000, rounds)
    progress("simulate's rtol and method (friction and a spring on)")
    res["simulate"] = simulate_rows((1e-3, 1e-6, 1e-9) if quick else RTOLS,
                                    ("DOP853", "LSODA") if quick else METHODS, rounds,
                                    revolutions=0.5 if quick else 2.0)
    res["revolutions"] = 0.5 if quick else 2.0
    progress("the energy measure's own floor (more samples, same run)")
    res["floor"] = energy_floor(res["revolutions"])
    progress("the hard cases")
    res["hard"] = hard_cases()
    return res


def headline(res: dict) -> str:
    """The tables as plain text (stdout)."""
    lines = [f"Machine: {res['machine']}",
             "Pin friction, the 1966 example, mu r = 0.1 in every pin: tolerance against "
             "time (CPU ms median (range); the 1966 scene beside it)",
             f"  {'tol':>7} {'iter':>5} {'CPU ms':>22} {'1966 CPU ms':>22} {'power error':>12}"]
    for r in res["friction"]:
        lines.append(f"  {r['tol']:7.0e} {r['iterations']:5.0f} {spread(r['cpu_ms']):>22} "
                     f"{spread(r['ref_ms']):>22} {r['error']:12.1e}")
    lines += [f"simulate, decks/friction.toml's scene and motor, {res['revolutions']:g} "
              "revolutions from 50 rad/sec: rtol and method against time",
              f"  {'method':7} {'rtol':>7} {'evals':>6} {'CPU s':>22} {'energy err':>11} "
              f"{'end err':>9}"]
    for r in res["simulate"]:
        lines.append(f"  {r['method']:7} {r['rtol']:7.0e} {r['evaluations']:6d} "
                     f"{spread(r['cpu_s']):>22} {r['energy']:11.1e} {r['end']:9.1e}")
    lines.append("Hard cases")
    for r in res["hard"]:
        lines.append(f"  {r['case']} ({r['cpu_s']:.3g} s CPU): {r['outcome']}")
    return "\n".join(lines)


def markdown(res: dict, figure: str | None, command: str) -> str:
    """The section for docs/effects.md: every number measured by ``command``."""
    out = [f"Measured by `{command}` on {res['machine']}; "
           f"{1 if res['quick'] else 3} round(s) each, median (range); CPU time (user + "
           "sys of the process) beside wall time.", "",
           "The friction fixed point on the 1966 example, mu r = 0.1 in every pin, "
           f"{'2,000' if res['quick'] else '10,000'} positions; the error is the largest "
           "residual of TORQ_FRICTION TH2D = sum of mu r |F| |relative rotation| over the "
           "largest loss:", "",
           "| tol | iterations, max | CPU ms | wall ms | 1966 scene, CPU ms | power error |",
           "|---|---:|---:|---:|---:|---:|"]
    for r in res["friction"]:
        out.append(f"| {r['tol']:.0e} | {r['iterations']:.0f} | {spread(r['cpu_ms'])} | "
                   f"{spread(r['wall_ms'])} | {spread(r['ref_ms'])} | {r['error']:.1e} |")
    out += ["", f"`simulate` on decks/friction.toml's scene (pin friction, a return spring), "
            f"motor and flywheel, {res['revolutions']:g} revolutions from 50 rad/sec "
            "(the friction tables, built once per run, are in the time).  Energy error: "
            "|motor work - change of kinetic energy - friction losses - change of the "
            "spring's energy| / motor work, each term from the engine's outputs at 2000 "
            "samples per revolution; end error: TH2D at the end against DOP853 at rtol "
            "1e-13:", "",
            "| method | rtol | evaluations | CPU s | wall s | energy error | end error |",
            "|---|---:|---:|---:|---:|---:|---:|"]
    for r in res["simulate"]:
        out.append(f"| {r['method']} | {r['rtol']:.0e} | {r['evaluations']} | "
                   f"{spread(r['cpu_s'])} | {spread(r['wall_s'])} | {r['energy']:.1e} | "
                   f"{r['end']:.1e} |")
    if "floor" in res:
        (n1, e1), (n2, e2) = res["floor"]
        out += ["", f"The energy error of the LSODA run at rtol 1e-12 is {e1:.1e} read with "
                f"{n1} samples per revolution and {e2:.1e} with {n2}: where the energy column "
                "stops falling while the end error still falls, the floor is the "
                "quadrature's (the Coulomb losses jump where a relative rotation changes "
                "sign), not the integration's."]
    if figure:
        out += ["", f"![error against CPU time]({figure})"]
    out += ["", "The hard cases, each run once:", "", "| case | CPU s | what happens |",
            "|---|---:|---|"]
    for r in res["hard"]:
        out.append(f"| {r['case']} | {r['cpu_s']:.3g} | {r['outcome']} |")
    return "\n".join(out) + "\n"


def plot(res: dict, path: str) -> None:
    """Error against CPU time: simulate's methods, and the friction tolerance."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    for method in dict.fromkeys(r["method"] for r in res["simulate"]):
        rows = [r for r in res["simulate"] if r["method"] == method]
        a1.loglog([statistics.median(r["cpu_s"]) for r in rows],
                  [max(r["energy"], 1e-17) for r in rows], "o-", label=method)
    a1.set_xlabel("CPU time per run [s]")
    a1.set_ylabel("energy balance error [-]")
    a1.set_title("simulate, friction and a spring on", fontsize=9)
    a1.legend(fontsize=8)
    f = res["friction"]
    a2.semilogy([statistics.median(r["cpu_ms"]) for r in f],
                [max(r["error"], 1e-17) for r in f], "s-", color="C3")
    for r in f:
        a2.annotate(f"tol {r['tol']:.0e}", (statistics.median(r["cpu_ms"]),
                                            max(r["error"], 1e-17)), fontsize=7)
    a2.set_xlabel("CPU time per analyze call [ms]")
    a2.set_ylabel("friction power identity error [-]")
    a2.set_title("the friction fixed point", fontsize=9)
    for ax in (a1, a2):
        ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(path, dpi=100, format="png")
    plt.close(fig)
