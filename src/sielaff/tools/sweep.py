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
    from sielaff.design.figures import FIGURES
    from sielaff.quantities import unit

    def one(n: str) -> str:
        if n in ("DESIGN", "BALANCE", "KIND"):
            return n
        base = FIGURES[n][0] if n in FIGURES else {"CW_R2": "R2", "CW_R4": "R4"}.get(n, n)
        return f"{n}[{unit(base, system)}]"

    return ",".join(one(n) for n in names)


def _pareto(x, y):
    """Indices of the designs no other design beats in both x and y (both minimised)."""
    import numpy as np

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
    import numpy as np

    from sielaff.design.sweep import Grid, columns, iter_blocks
    from sielaff.tools.common import CommandError, read_spec_deck, refuse_overwriting_inputs
    from sielaff.tools.output import atomic_files, check_targets
    from sielaff.tools.spec import PunchError, read_spec, sweep_of

    path = args.spec
    for target in (args.output, args.plot):
        refuse_overwriting_inputs(target, [path])
        if target and os.path.isdir(target):
            raise CommandError(f"sielaff: {target} is a folder: name the file to write")
    check_targets([p for p in (args.output, args.plot) if p])  # before any work
    if args.plot:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            raise CommandError("sielaff: --plot needs matplotlib: pip install -e "
                               "\".[plot]\"") from None
    if not path.endswith(".toml"):
        raise CommandError(f"{path}: sweep reads a TOML spec with a [sweep] table")
    deck, scene = read_spec_deck(path)
    try:
        sweep = sweep_of(read_spec(path), path)
    except PunchError as exc:
        raise CommandError(str(exc), exc.status) from None
    m = deck.mechanism
    grid = Grid(m, sweep["axes"])
    backend, client = "process", None
    workers = args.workers or os.cpu_count() or 1
    if args.workers is None and grid.size <= SMALL and not args.scheduler:
        workers = 1  # a small sweep: starting dask would cost more than it saves
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
    if backend == "dask" and args.scheduler:
        from distributed import Client

        try:
            client = Client(args.scheduler, timeout=30)
        except OSError as exc:
            raise CommandError(f"--scheduler {args.scheduler}: cannot reach it ({exc})") \
                from None
    names = columns(grid)
    header = _header(names, m.units)
    px, py = (names.index(p) for p in sweep["pareto"])
    xs, ys = [], []
    paths = [p for p in (args.output, args.plot) if p]
    try:
        with atomic_files(paths) as temps:
            out = open(temps[0], "w", newline="") if args.output else sys.stdout  # noqa: SIM115
            try:
                out.write(header + "\n")
                for block in iter_blocks(grid, sweep["angles"], sweep["cf"], scene, backend,
                                         client, workers=workers):
                    out.write("\n".join(_rows(block, names)) + "\n")
                    xs.append(block[:, px])
                    ys.append(block[:, py])
            finally:
                if args.output:
                    out.close()
            if args.plot:
                _plot(temps[-1], np.concatenate(xs), np.concatenate(ys), sweep["pareto"],
                      m.units, grid.size)
    finally:
        if client is not None:
            client.close()
    ok = np.isfinite(np.concatenate(xs))
    print(f"sielaff sweep: {grid.size} designs ({int(ok.sum())} with a full cycle), "
          f"{sweep['angles']} angles each, on {backend if backend == 'process' else 'dask'}"
          + (f" -> {args.output}" if args.output else ""), file=sys.stderr)
    return 0


def _plot(path: str, x, y, pair, system: str, size: int) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from sielaff.design.figures import FIGURES
    from sielaff.quantities import unit

    front = _pareto(x, y)
    fig, ax = plt.subplots(figsize=(7, 5), dpi=120)
    ok = (x == x) & (y == y)
    ax.scatter(x[ok], y[ok], s=4, color="0.7", label=f"designs ({int(ok.sum())} of {size})")
    ax.plot(x[front], y[front], "o-", ms=3, color="C3", label=f"Pareto front ({len(front)})")
    ax.set_xlabel(f"{pair[0]} ({FIGURES[pair[0]][1]}) [{unit(FIGURES[pair[0]][0], system)}]")
    ax.set_ylabel(f"{pair[1]} ({FIGURES[pair[1]][1]}) [{unit(FIGURES[pair[1]][0], system)}]")
    ax.legend(loc="upper right")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, format="png")
    plt.close(fig)
