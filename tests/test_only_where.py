"""A step's ``only_where`` promise (engine/registry.py's Step): where the need it names
is 0.0 the step's outputs are the needs it names, bit for bit.

The compiled kernel calls a serial step (array code) that promises it only where the
flag holds and copies those needs elsewhere (engine/kernel.py), so the promise is what
makes the kernel's answer the numpy engine's there.  Checked here:

* every step of every model that promises it keeps the promise on drawn scenes (each
  call's outputs against the named needs where the flag is 0.0), and the draw holds
  positions on both sides of the flag (counted);
* the checker catches a broken promise, and ``step`` refuses one that names no need or
  the wrong number of them;
* the kernel's source calls the step under the flag (numba only, no compiling).

That the kernel with the call so guarded gives the numpy engine's answers at every kind
of position (contracting, solved by Newton, self-locking) is test_compiled_friction.py's.
"""

from __future__ import annotations

import warnings
from collections import Counter

import numpy as np
import pytest

from sielaff import EXAMPLE, PinFriction, Scene, analyze
from sielaff.engine import FOURBAR
from sielaff.engine.analysis import MODELS
from sielaff.engine.positions import reachable
from sielaff.engine.registry import step
from test_elements import draw


def _promising(model):
    """The steps of ``model`` (its own and its effects') that promise ``only_where``."""
    return [st for st in [*model.steps, *(s for e in model.effects for s in e.steps)]
            if st.only_where is not None]


def _broken(st, args, result):
    """The outputs of ``st`` (``result`` of a call with ``args``) that are not, where the
    flag is 0.0, the needs it names; and how many positions the flag is 0.0 and not."""
    values = dict(zip(st.needs, args, strict=True))
    flag, through = st.only_where
    result = result if len(st.provides) > 1 else (result,)
    shape = np.broadcast_shapes(*(np.shape(x) for x in (*args, *result)))
    off = np.broadcast_to(np.asarray(values[flag]) == 0.0, shape)
    finite = np.ones(shape, dtype=bool)
    for x in args:
        finite &= np.broadcast_to(np.isfinite(np.asarray(x, dtype=float)), shape)
    bad = []
    for name, got, need in zip(st.provides, result, through, strict=True):
        a = np.broadcast_to(np.asarray(got, dtype=float), shape)[off]
        b = np.broadcast_to(np.asarray(values[need], dtype=float), shape)[off]
        if not np.array_equal(a.view(np.int64), b.view(np.int64)):
            bad.append(name)
    return bad, int(np.count_nonzero(off)), int(off.size - np.count_nonzero(off)), int(
        np.count_nonzero(off & ~finite))


def _checked(model, tally, spoil=None):
    """``model`` with each promising step's calls checked (``tally``: the positions on
    each side of the flag, those off it where a need is not finite, and the outputs that
    broke the promise); ``spoil`` changes a result first (to see the check fail)."""
    def wrap(st):
        if st.only_where is None:
            return st.fn

        def check(*args):
            result = st.fn(*args)
            if spoil is not None:
                result = spoil(result)
            bad, off, on, stopped = _broken(st, args, result)
            tally["off"] += off
            tally["on"] += on
            tally["stopped"] += stopped
            tally.update(f"{st.name}: {n}" for n in bad)
            return result
        return check

    return model.mapping(wrap)


def _broken_promises(tally):
    """The outputs ``tally`` counted as breaking a promise (not its position counts)."""
    return {k: v for k, v in tally.items() if k not in ("off", "on", "stopped")}


def _draws():
    """Four-bars of several kinds with each pin's friction drawn large enough that the
    law need not contract near their toggles (as test_compiled_friction.py's)."""
    for i, (m, _) in enumerate(draw(6, 31)):
        rng = np.random.default_rng(700 + i)
        fr = {p: PinFriction(float(rng.uniform(0, 0.5)), float(rng.uniform(0, 1.0)))
              for p in ("O2", "A", "B", "O4")}
        for branch in ("open", "crossed"):
            yield m, Scene(friction=fr, tex=float(rng.uniform(-50, 50)), branch=branch)


def test_the_promises_are_the_ones_known():
    """A step that starts to promise must be drawn here: the list is the test's to extend."""
    found = {(model.name, st.name) for model in MODELS for st in _promising(model)}
    assert {st for _, st in found} == {"_friction_solve"}, found


def test_every_promise_holds_on_drawn_scenes():
    tally: Counter[str] = Counter()
    model = _checked(FOURBAR, tally)
    for m, sc in _draws():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            # a crank angle not finite: the fixed point does not run there (friction_go)
            th = np.append(reachable(m, 181), [np.nan, np.inf])
            analyze(m, th, ["TORQ", "FRICTION_STATUS"], scene=sc, model=model)
    broken = _broken_promises(tally)
    assert not broken, broken
    # both sides of the flag drawn: the fixed point's answers, and the solve's positions;
    # and positions where it did not run
    assert tally["off"] > 1000 and tally["on"] > 20 and tally["stopped"] >= 24, tally


def test_a_grid_of_designs_keeps_the_promise_row_by_row():
    """Designs in a column against angles in a row (design/figures.py asks so): each row
    is the one design's answer alone, bit for bit, and the promise holds on the grid."""
    tally: Counter[str] = Counter()
    model = _checked(FOURBAR, tally)
    r2 = np.array([3.5, 4.0, 4.5])
    th = np.linspace(0.0, 355.0, 72)
    sc = Scene(friction=PinFriction(0.3, 0.8), tex=20.0)
    wanted = ["TORQ", "FRICTION_STATUS", "FRICTION_ITERATIONS"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        grid = analyze(EXAMPLE.replace(R2=r2[:, None]), th, wanted, scene=sc, model=model)
        for i, v in enumerate(r2):
            one = analyze(EXAMPLE.replace(R2=float(v)), th, wanted, scene=sc)
            for name in wanted:
                assert np.shape(grid[name]) == (3, 72), name
                assert np.array_equal(np.asarray(grid[name][i]).view(np.int64),
                                      np.asarray(one[name]).view(np.int64)), (name, v)
    broken = _broken_promises(tally)
    assert not broken and tally["off"] + tally["on"] == 3 * 72, tally


def test_a_broken_promise_is_caught():
    tally: Counter[str] = Counter()
    model = _checked(FOURBAR, tally, spoil=lambda r: (r[0] + 1.0,) + tuple(r[1:]))
    analyze(EXAMPLE, np.linspace(0.0, 350.0, 36), ["TORQ"],
            scene=Scene(friction=PinFriction(0.1, 0.2)), model=model)
    assert tally["_friction_solve: fa32x_h"] == 1 and tally["off"] == 36, tally


@pytest.mark.parametrize("only_where, words", [
    (("nope", ("a", "b")), "the flag must be a need"),
    (("flag", "ab"), "a tuple of them"),
    (("flag", ("a",)), "one need per output"),
    (("flag", ("a", "c")), "one need per output")])
def test_step_refuses_a_promise_of_what_it_does_not_need(only_where, words):
    with pytest.raises(TypeError, match=words):
        @step(provides=("x", "y"), needs=("flag", "a", "b"), only_where=only_where)
        def _bad(flag, a, b):
            return a, b


def test_a_promise_is_a_tuple_and_only_its_own_functions_keep_it():
    @step(provides=("x", "y"), needs=("flag", "a", "b"), only_where=("flag", ["a", "b"]))
    def _fine(flag, a, b):
        return a, b

    from sielaff.engine.registry import step_of

    assert step_of(_fine).only_where == ("flag", ("a", "b"))
    hash(step_of(_fine))  # a Step is part of a compiled kernel's key
    # a model whose solve runs another function makes no promise for it
    assert _promising(FOURBAR.mapping(lambda st: st.fn))
    other = FOURBAR.replacing(_friction_solve=lambda *a: a)
    assert not _promising(other)


def test_the_kernel_calls_the_serial_step_only_where_its_flag_holds(monkeypatch):
    pytest.importorskip("numba")
    from sielaff.engine import kernel

    seen = []
    real = kernel.kernel_source

    class Seen(Exception):
        pass

    def spy(*args, **kw):
        seen.append(real(*args, **kw))
        raise Seen

    monkeypatch.setattr(kernel, "_KERNELS", {})
    monkeypatch.setattr(kernel, "kernel_source", spy)
    with pytest.raises(Seen):
        analyze(EXAMPLE, np.linspace(0.0, 350.0, 36), ["TORQ"],
                scene=Scene(friction=PinFriction(0.1, 0.2)), backend="numba")
    src, called = seen[0]
    k = [st.name for st in called].index("_friction_solve")
    lines = src.splitlines()
    at = [j for j, line in enumerate(lines) if f"= _s{k}(" in line]
    assert len(at) == 1
    guard, other = lines[at[0] - 1].strip(), lines[at[0] + 1].strip()
    assert guard.startswith("if ") and guard.endswith(" != 0.0:") and other == "else:"
    flag = guard[3:-len(" != 0.0:")]
    # elsewhere the outputs are the needs promised, in order
    st = called[k]
    targets, through = (x.strip() for x in lines[at[0] + 2].split(" = "))
    assert targets == lines[at[0]].split(" = ")[0].strip()
    assert through == ", ".join(st.only_where[1])
    # the flag is the step's friction_hard, read back from its row in the serial loop
    assert any(line.strip().startswith(f"{flag} = _x") for line in lines[:at[0]])
