"""``sielaff sweep SPEC.toml [-o FILE.csv] [--plot FILE.png]``: a grid of designs.

The spec's mechanism and [scene] are the base design; its ``[sweep]`` names the fields to
vary and how (``sielaff.tools.spec.sweep_of``).  Each design's figures
(:data:`sielaff.design.figures.FIGURES`) are one CSV row: ``DESIGN``, the varied values,
then the figures, the header naming each with its unit (``TORQ_PEAK[in-lb]``); ``KIND``
is written as its name.  Blocks of designs are computed and written one after another,
so memory stays flat; the CSV (and the Pareto plot) are written whole or not at all.

Where it runs: ``--workers 1``, or a small sweep (:data:`SMALL` designs), in this
process; otherwise through dask when it is installed (``pip install -e ".[sweep]"``):
local threads on all cores by default, or the dask.distributed cluster at
``--scheduler``. The results do not depend on where they ran (the same blocks, the same
function).
"""

from __future__ import annotations

import os
import sys

#: A sweep of at most this many designs runs in process unless --workers says otherwise.
SMALL = 1024
#: ``--scheduler``: seconds to open the connection, and for the scheduler's first words
#: (a dask scheduler speaks at once; a server that accepts and stays silent is not one).
CONNECT_SECONDS = 10.0
HANDSHAKE_SECONDS = 10.0


def _probe_scheduler(address: str) -> None:
    """Refuse, in one line and within :data:`CONNECT_SECONDS` + :data:`HANDSHAKE_SECONDS`,
    an address where no dask scheduler answers: nothing listening, a server that never
    speaks, or one that speaks another protocol (HTTP: the dashboard's port, say).

    A dask scheduler greets each connection first, with a frame header: an 8-byte
    little-endian length, then the frames (``distributed.comm.tcp``).  Only ``tcp://``
    addresses are probed; another scheme (``tls://``) goes straight to the client, whose
    own timeout is :data:`CONNECT_SECONDS`.
    """
    import socket

    from sielaff.tools.common import CommandError

    if not address.strip():
        raise CommandError("--scheduler '': an empty address (give tcp://HOST:PORT, or leave "
                           "--scheduler out to run on this machine)")
    from distributed.comm import parse_address, parse_host_port

    try:
        scheme, location = parse_address(address)
        if scheme != "tcp":
            return
        host, port = parse_host_port(location, 8786)
    except (ValueError, TypeError) as exc:
        raise CommandError(f"--scheduler {address}: not an address ({exc}; give "
                           "tcp://HOST:PORT)") from None
    where = f"--scheduler {address}"
    try:
        conn = socket.create_connection((host, int(port)), timeout=CONNECT_SECONDS)
    except TimeoutError:
        raise CommandError(f"{where}: cannot reach it (no answer within "
                           f"{CONNECT_SECONDS:g} s)") from None
    except OSError as exc:
        raise CommandError(f"{where}: cannot reach it ({exc.strerror or exc})") from None
    with conn:
        conn.settimeout(HANDSHAKE_SECONDS)
        head = b""
        try:
            while len(head) < 8:
                more = conn.recv(8 - len(head))
                if not more:
                    break
                head += more
        except TimeoutError:
            raise CommandError(f"{where}: it accepts connections but says nothing within "
                               f"{HANDSHAKE_SECONDS:g} s: not a dask scheduler (the "
                               "scheduler's usual port is 8786; 8787 is its dashboard)") \
                from None
        except OSError as exc:
            raise CommandError(f"{where}: the connection failed ({exc.strerror or exc})") \
                from None
    length = int.from_bytes(head.ljust(8, b"\0"), "little")
    if len(head) < 8 or not 0 < length < 1 << 20:
        what = "it speaks HTTP" if head.startswith(b"HTTP") else "its first bytes are not"
        raise CommandError(f"{where}: it answers, but not as a dask scheduler ({what} a "
                           "dask handshake)")


def _rows(block, names: list[str]):
    """CSV lines: DESIGN and BALANCE as integers, KIND by name, the rest in full."""
    from sielaff.engine.classify import KINDS

    fmt = [(lambda v: KINDS[int(v)]) if n == "KIND" else
           (lambda v: str(int(v))) if n in ("DESIGN", "BALANCE") else
           (lambda v: repr(float(v))) for n in names]
    for row in block:
        yield ",".join(f(v) for f, v in zip(fmt, row))


def _header(names: list[str], system: str) -> str:
    """NAME[unit] for each column (none for DESIGN, BALANCE and KIND)."""
    from sielaff.design.sweep import column_units

    units = column_units(names, system)
    return ",".join(n if units[n] == "-" else f"{n}[{units[n]}]" for n in names)


def _pareto(x, y, senses=("min", "min")):
    """Indices of the designs no other design beats in both x and y, each minimised or
    maximised as ``senses`` says, sorted from the best in x."""
    import numpy as np

    x, y = ((-v if sense == "max" else v) for v, sense in zip((x, y), senses))
    # roundoff (a balanced design's shaking force, ~1E-13) is zero: ties never depend
    # on a CPU's last bits
    finite = np.isfinite(x) & np.isfinite(y)
    if not finite.any():  # no design turns fully: no front (and no all-NaN reduction)
        return np.array([], dtype=int)
    x, y = (np.where(np.abs(v) <= 1e-9 * np.max(np.abs(v[finite])), 0.0, v) for v in (x, y))
    ok = np.flatnonzero(finite)
    order = ok[np.lexsort((y[ok], x[ok]))]
    front, best = [], np.inf
    for i in order:
        if y[i] < best:
            front.append(i)
            best = y[i]
    return np.array(front, dtype=int)


def cmd_sweep(args) -> int:
    import warnings

    import numpy as np

    from sielaff.design.sweep import Grid, columns, iter_blocks
    from sielaff.engine import AssemblyWarning
    from sielaff.mechanism import Mechanism
    from sielaff.tools.common import (
        CommandError,
        read_spec,
        read_spec_deck,
        refuse_bad_output,
        refuse_stdout,
        spec_path,
    )
    from sielaff.tools.output import atomic_files, check_targets
    from sielaff.tools.spec import PunchError, sweep_of

    path = args.spec
    if args.output == "-":
        args.output = None  # -o -: the table on stdout, the status on stderr
    for target in (args.output, args.plot):
        refuse_bad_output(target, [path])
    refuse_stdout(args.plot, "--plot writes a PNG file", "--plot", "a file")
    check_targets([p for p in (args.output, args.plot) if p])  # before any work
    if getattr(args, "pareto", None) and not args.plot:
        raise CommandError("sielaff: --pareto chooses the Pareto plot's figures: add --plot "
                           "FILE.png")
    if args.plot:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            raise CommandError("sielaff: --plot needs matplotlib: pip install -e "
                               "\".[plot]\"") from None
    if not spec_path(path):
        raise CommandError(f"{path}: sweep reads a TOML spec with a [sweep] table")
    from sielaff.tools.kinds import other_kinds

    deck, scene = read_spec_deck(path, other_kinds())
    if getattr(args, "branch", None):
        import dataclasses

        scene = dataclasses.replace(scene, branch=args.branch)
    if not isinstance(deck.mechanism, Mechanism):  # a branch on which it closes nowhere
        from sielaff.tools.kinds import full_turn_failure

        try:
            full_turn_failure(deck.mechanism, scene.branch)
        except CommandError as exc:
            raise CommandError(f"{path}: {exc}") from None
    try:
        sweep = sweep_of(read_spec(path), path, deck.mechanism)
    except PunchError as exc:
        raise CommandError(str(exc), exc.status) from None
    m = deck.mechanism
    grid = Grid(m, sweep["axes"])
    backend, client = "process", None
    workers = args.workers or os.cpu_count() or 1
    if args.workers is None and grid.size <= SMALL and not args.scheduler:
        workers = 1  # a small sweep: starting dask would cost more than it saves
    if args.scheduler == "":
        _probe_scheduler("")  # refused: an empty address is not "run locally"
    if args.scheduler or workers > 1:
        try:
            import dask  # noqa: F401
        except ImportError:
            if args.scheduler:
                raise CommandError("--scheduler needs dask: pip install -e \".[sweep]\"") \
                    from None
            workers = 1
        else:
            backend = "dask"
    if backend == "dask" and args.scheduler is not None:
        client = _connect(args.scheduler)
    names = columns(grid)
    figs = names[1 + len(grid.names):]  # the kind's figures, after DESIGN and the axes
    header = _header(names, m.units)
    pair = list(zip(sweep["pareto"], sweep["senses"]))
    if getattr(args, "pareto", None):
        from sielaff.design.sweep import pareto_pair

        try:
            from sielaff.design.figures import figure_table

            pair = list(pareto_pair(args.pareto, figure_table(m)))
        except ValueError as exc:
            raise CommandError(f"sielaff: --pareto {args.pareto}: "
                               f"{str(exc).removeprefix('pareto: ')}") from None
    px, py = (names.index(p) for p, _ in pair)
    xs, ys, ds = [], [], []
    dropped: dict[int, int] = {}  # KIND index -> designs left out
    paths = [p for p in (args.output, args.plot) if p]
    # a design that does not assemble somewhere is left out and counted below (its NaN
    # figures), not warned about position by position
    quiet = warnings.catch_warnings()
    quiet.__enter__()
    warnings.simplefilter("ignore", AssemblyWarning)
    try:
        with atomic_files(paths) as temps:
            out = open(temps[0], "w", newline="") if args.output else sys.stdout  # noqa: SIM115
            try:
                out.write(header + "\n")
                blocks = iter_blocks(grid, sweep["angles"], sweep["cf"], scene, backend,
                                     client, workers=workers)
                for block in _on_cluster(blocks, args.scheduler, client):
                    kept = _full_cycle(block, names, figs)
                    kinds = block[~kept, names.index("KIND")] if "KIND" in names else \
                        np.full(int(np.sum(~kept)), -1.0)  # another kind: no KIND column
                    for k in kinds:
                        dropped[int(k)] = dropped.get(int(k), 0) + 1
                    block = block[kept]
                    if block.size:
                        out.write("\n".join(_rows(block, names)) + "\n")
                    xs.append(block[:, px])
                    ys.append(block[:, py])
                    ds.append(block[:, names.index("DESIGN")])
            finally:
                if args.output:
                    out.close()
            if args.plot:
                _plot(temps[-1], np.concatenate(xs), np.concatenate(ys),
                      tuple(p for p, _ in pair), m.units, grid.size,
                      tuple(s for _, s in pair), designs=np.concatenate(ds), mechanism=m)
    finally:
        quiet.__exit__(None, None, None)
        if client is not None:
            _close(client)
    left_out = sum(dropped.values())
    print(f"sielaff sweep: {grid.size} designs ({grid.size - left_out} with a full cycle), "
          f"{sweep['angles']} angles each, "
          f"{'in this process' if backend == 'process' else 'through dask'}"
          + (f" -> {args.output}" if args.output else ""), file=sys.stderr)
    if left_out:
        from sielaff.engine.classify import KINDS

        if -1 in dropped:  # another kind: its crank cannot make a revolution
            print(f"sielaff sweep: {left_out} of {grid.size} designs left out (no row), the "
                  "figures being those of a whole revolution: their crank cannot make one "
                  "(a dyad cannot close somewhere on the way)", file=sys.stderr)
        else:
            kinds = ", ".join(f"{n} {KINDS[k]}" for k, n in sorted(dropped.items()))
            print(f"sielaff sweep: {left_out} of {grid.size} designs left out (no row), the "
                  "figures being those of a whole revolution: their crank cannot make one, "
                  f"or the linkage folds flat on the way at a change point ({kinds})",
                  file=sys.stderr)
    return 0


def _full_cycle(block, names: list[str], figs: list[str]):
    """The rows of designs whose figures (``figs``, the kind's) are a whole revolution's:
    every figure finite but FLYWHEEL_I, which is NaN at TH2D = 0 (no speed to size a
    flywheel for).  A design whose crank cannot turn fully, or that folds flat at a
    change point, has NaN figures (design.figures)."""
    import numpy as np

    cols = [names.index(f) for f in figs if f not in ("KIND", "FLYWHEEL_I")]
    return np.isfinite(block[:, cols]).all(axis=1)


def _connect(address: str):
    """A dask.distributed client for ``address``, or one line saying why not (the probe
    first: :func:`_probe_scheduler`).  distributed's log lines are silenced while the
    client lives: what goes wrong is said once, by sielaff."""
    import logging

    from sielaff.tools.common import CommandError

    _probe_scheduler(address)
    logging.disable(logging.CRITICAL)  # undone by _close
    from distributed import Client

    try:
        return Client(address, timeout=CONNECT_SECONDS)
    except Exception as exc:  # noqa: BLE001 (any failure of the handshake is one line)
        logging.disable(logging.NOTSET)
        raise CommandError(f"--scheduler {address}: cannot connect "
                           f"({_why(exc)})") from None


def _why(exc: BaseException) -> str:
    text = str(exc).splitlines()[0] if str(exc) else ""
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _on_cluster(blocks, address: str | None, client):
    """``blocks``, with a distributed cluster's failures (the scheduler gone, no worker
    left: :data:`sielaff.design.sweep.NO_WORKER_SECONDS`) as one line."""
    if client is None:
        yield from blocks
        return
    from sielaff.tools.common import CommandError

    while True:
        try:
            block = next(blocks)
        except StopIteration:
            return
        except Exception as exc:  # noqa: BLE001 (any failure on the cluster is one line)
            from sielaff.design.sweep import ClusterLost

            if isinstance(exc, ClusterLost):
                what = f"{exc}: the sweep stopped"
            elif ("Cancelled" in type(exc).__name__ or "CommClosed" in type(exc).__name__
                  or "connection-lost" in str(exc)):
                what = "the work was cancelled: the scheduler was lost or stopped mid-sweep"
            else:
                what = f"the sweep failed on the cluster ({_why(exc)})"
            raise CommandError(f"--scheduler {address}: {what}") from None
        yield block


def _close(client) -> None:
    """Close the client without waiting long for a scheduler that is gone."""
    import contextlib
    import logging

    with contextlib.suppress(Exception):
        client.close(timeout=2)
    logging.disable(logging.NOTSET)


#: A Pareto front of at most this many designs has each one labelled.
FRONT_LABELS = 30


def _plot(path: str, x, y, pair, system: str, size: int, senses=("min", "min"), *,
          designs, mechanism=None) -> None:
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from sielaff.design.figures import FIGURES, figure_table
    from sielaff.design.sweep import column_units

    table = FIGURES if mechanism is None else figure_table(mechanism)
    units = column_units(list(pair), system)
    front = _pareto(x, y, senses)
    fig, ax = plt.subplots(figsize=(7, 5), dpi=120)
    ok = np.isfinite(x) & np.isfinite(y)
    ax.scatter(x[ok], y[ok], s=4, color="0.7", label=f"designs ({int(ok.sum())} of {size})")
    # markers only: a line between front points would suggest designs between them
    ax.plot(x[front], y[front], "o", ms=4, color="C3", label=f"Pareto front ({len(front)})")
    if len(front) <= FRONT_LABELS:  # each front design by its DESIGN, the CSV's column
        for i in front:
            ax.annotate(f"{int(designs[i])}", (x[i], y[i]),
                        xytext=(4, 4), textcoords="offset points", fontsize=7, color="C3")
    word = {"min": "minimised", "max": "maximised"}
    ax.set_xlabel(f"{pair[0]} ({table[pair[0]][1]}, {word[senses[0]]}) [{units[pair[0]]}]")
    ax.set_ylabel(f"{pair[1]} ({table[pair[1]][1]}, {word[senses[1]]}) [{units[pair[1]]}]")
    ax.legend(loc="upper right")
    ax.grid(True, alpha=0.3)
    ax.set_title(f"Pareto front of {pair[0]} and {pair[1]}: {size:,} designs"
                 + (" (each front design labelled with its DESIGN)"
                    if len(front) <= FRONT_LABELS else ""), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, format="png")
    plt.close(fig)
