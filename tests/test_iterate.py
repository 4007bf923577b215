"""An iterated step (engine/iterate.py) on a model of its own: Heron's square root, a
pass that converges in a different number of passes at each position, never at some
(a negative number: the limit is reached), and not at all where its start says so.

The numpy form is checked against a plain loop over the positions written here, one
position at a time; the compiled kernel (passes over a chunk, each position's results
captured at the pass that said done) against the numpy form, bit for bit (the pass is
+ - * / and abs only, each correctly rounded in both).  Pin friction's fixed point is
the package's iterated step: tests/test_compiled_friction.py checks it on drawn
linkages."""

from __future__ import annotations

import importlib.util
import itertools
import math
import re

import numpy as np
import pytest

from sielaff.engine import analyze
from sielaff.engine import kernel as K
from sielaff.engine.iterate import iterated, run
from sielaff.engine.registry import Model, step, step_of
from sielaff.mechanism import EXAMPLE

LIMIT, TOL = 40, 1e-15


@step(provides=("x_0", "go"), needs=("ATH2",))
def _start(ATH2):
    """Heron's start (a, or 1 below 1), and where to run (not at NaN)."""
    return np.where(ATH2 > 1.0, ATH2, 1.0), np.where(ATH2 == ATH2, 1.0, 0.0)


@iterated(provides=("ROOT", "HALF", "PASSES"), limit="LIMIT", go="go", start=("x_0",),
          consts=("ATH2", "TOL"))
def _heron(x, ATH2, TOL):
    new = 0.5 * (x + ATH2 / x)
    blown = ~np.isfinite(new)
    done = (np.abs(new - x) <= TOL * new) & ~blown
    return new, new, 0.5 * new, done, ~done & ~blown


def _model() -> Model:
    def seed(m, ath2, scene):
        return {"ATH2": np.atleast_1d(np.asarray(ath2, dtype=float)), "LIMIT": LIMIT,
                "TOL": TOL}

    model = Model("heron", seed=seed, results=("ROOT", "HALF", "PASSES"))
    model.add(step_of(_start), step_of(_heron))
    return model


def _one_by_one(a: np.ndarray) -> dict[str, np.ndarray]:
    """The iteration's definition at each position in turn, in Python's floats."""
    out = {n: np.zeros(a.size) for n in ("ROOT", "HALF", "PASSES")}
    for i, ai in enumerate(a.tolist()):
        if ai != ai:
            continue
        x = ai if ai > 1.0 else 1.0
        for k in range(1, LIMIT + 1):
            new = 0.5 * (x + ai / x)
            blown = not math.isfinite(new)
            done = abs(new - x) <= TOL * new and not blown
            if done:
                out["ROOT"][i], out["HALF"][i], out["PASSES"][i] = new, 0.5 * new, k
            if done or blown:
                break
            x = new
    return out


def _numbers(n: int) -> np.ndarray:
    rng = np.random.default_rng(n)
    a = 10.0 ** rng.uniform(-8.0, 12.0, n)
    a[::7] *= -1.0  # no root: the limit is reached
    a[3::11] = np.nan  # not run
    a[5::13] = 0.0
    return a


def _drawn(r: dict[str, np.ndarray], a: np.ndarray) -> None:
    """The cases the test claims, counted: several pass counts in one chunk, the limit
    reached, positions not run."""
    passes = r["PASSES"][:K.CHUNK]
    assert len(np.unique(passes[passes > 0])) >= 5
    assert np.count_nonzero((r["PASSES"] == 0) & (a < 0)) >= 10
    assert np.count_nonzero(np.isnan(a)) >= 10


def test_the_numpy_form_is_the_iteration_at_each_position():
    a = _numbers(3 * K.CHUNK + 5)
    r = analyze(EXAMPLE, a, ["ROOT", "HALF", "PASSES"], model=_model())
    _drawn(r, a)
    ref = _one_by_one(a)
    for name in ref:
        np.testing.assert_array_equal(r[name], ref[name], err_msg=name)
    ok = r["PASSES"] > 0
    np.testing.assert_allclose(r["ROOT"][ok] ** 2, a[ok], rtol=4e-16 * 4)


def test_the_numpy_form_broadcasts_its_values_and_keeps_a_number_one():
    a = _numbers(60).reshape(6, 10)
    got = run(_heron, 1, 2, LIMIT, np.where(a == a, 1.0, 0.0),
              (np.where(a > 1.0, a, 1.0), a, TOL))
    assert all(g.shape == (6, 10) for g in got)
    ref = _one_by_one(a.reshape(-1))
    np.testing.assert_array_equal(got[0].reshape(-1), ref["ROOT"])
    np.testing.assert_array_equal(got[2].reshape(-1), ref["PASSES"])


def test_the_declaration_is_checked_against_the_pass():
    with pytest.raises(TypeError, match="parameters"):
        iterated(provides=("Y", "N"), limit="L", go="g", start=("s",), consts=("b",))(
            lambda x, c: (x, x, True, False))


@pytest.mark.parametrize("n", [0, 1, K.CHUNK, 3 * K.CHUNK + 5])
def test_the_compiled_passes_give_the_numpy_forms_bits(n):
    pytest.importorskip("numba")
    a = _numbers(n)
    model = _model()
    got = analyze(EXAMPLE, a, ["ROOT", "HALF", "PASSES"], model=model, backend="numba")
    ref = analyze(EXAMPLE, a, ["ROOT", "HALF", "PASSES"], model=model)
    if n > K.CHUNK:
        _drawn(ref, a)
    for name in ref:
        np.testing.assert_array_equal(got[name], ref[name], err_msg=name)


def test_the_kernel_runs_the_passes_without_a_branch_and_stops_when_none_is_left():
    model = _model()
    ns = model.seed(EXAMPLE, np.zeros(4), None)
    order = model.plan(("ROOT", "PASSES"), frozenset(ns), model.zero_seeds(ns))
    src, called = K.kernel_source(model, order, ("ROOT", "PASSES"), ("LIMIT", "TOL"),
                                  ("ATH2",))
    assert [st.name for st in called] == ["_start", "_heron"]
    lines = src.splitlines()
    at = next(k for k, x in enumerate(lines) if "for _it in range(1, int(LIMIT) + 1)" in x)
    indent = len(lines[at]) - len(lines[at].lstrip())
    passes = list(itertools.takewhile(lambda x: len(x) - len(x.lstrip()) > indent,
                                      lines[at + 1:]))
    assert any("= _s1(_y0, ATH2, TOL)" in x for x in passes)
    inner = passes[passes.index(next(x for x in passes if "for _j" in x)) + 1:]
    inner = inner[:inner.index(next(x for x in inner if x.strip() == "if _left == 0:"))]
    assert not any(x.strip().startswith(("if ", "while ", "for ")) for x in inner)
    # the state stored as computed, the two results and the count captured at the pass
    # that says done (no select of a row's own value: a masked store), go selected
    assert sum("_capture(" in x for x in inner) == 3
    assert sum("_select(" in x for x in inner) == 1
    assert any(x.strip().startswith("_x") and x.strip().endswith("= _yn0") for x in inner)
    assert passes[-2].strip() == "if _left == 0:" and passes[-1].strip() == "break"
    with pytest.raises(K.Uncompilable, match="LIMIT"):  # a limit per position: refused
        K.kernel_source(model, order, ("ROOT",), ("TOL",), ("ATH2", "LIMIT"))


def test_capture_gives_the_bits_of_the_pass_that_said_done():
    """kernel_math._capture compiled: where c, q's bits exactly (-0.0, NaN, inf and a
    subnormal among them), else the row's value, as its Python form says."""
    numba = pytest.importorskip("numba")
    from sielaff.engine import kernel_math

    capture = kernel_math._capture_intrinsic()

    @numba.njit
    def rows(c, q, old, out):
        for j in range(q.size):
            out[j] = capture(c[j], q[j], old[j])

    q = np.array([-0.0, np.nan, -np.inf, 5e-324, -1.5, 3.0, 0.0, np.inf])
    c = np.array([True, True, True, True, True, False, False, False])
    old = np.where(c, 0.0, np.array([7.0] * 8))
    out = np.empty(q.size)
    rows(c, q, old, out)
    want = np.array([kernel_math._capture(ci, qi, oi) for ci, qi, oi in zip(c, q, old)])
    assert out.view(np.int64).tolist() == want.view(np.int64).tolist()
    assert np.signbit(out[0]) and out[1] != out[1] and out[2] == -np.inf


def test_the_passes_store_no_row_by_a_mask(monkeypatch):
    """No select of a row's own value in the passes, so no masked store in the kernel's
    assembly (x86-64: VMASKMOVPD, or a store under an AVX-512 mask), which costs an AVX2
    AMD CPU some ten cycles a store (engine/kernel.py's _passes)."""
    pytest.importorskip("numba")
    from sielaff.engine.kernel_math import X86

    if not X86:
        pytest.skip("the assembly is x86-64's")
    monkeypatch.setenv("SIELAFF_KERNEL_DIR", "off")
    monkeypatch.setattr(K, "_KERNELS", {})
    analyze(EXAMPLE, _numbers(K.CHUNK), ["ROOT", "HALF", "PASSES"], model=_model(),
            backend="numba")
    kernels = list(K._KERNELS.values())
    assert len(kernels) == 1  # counted: the kernel of the passes
    asm = kernels[0].inspect_asm(kernels[0].signatures[0])
    assert "vmaskmov" not in asm and not re.search(r"vmovup[sd]\s+%[xyz]mm\d+, [^\n]*\{%k", asm)
    assert re.search(r"\bvsqrtp|\bvdivp", asm)  # the pass vectorised (its division packed)


@iterated(provides=("ROOT", "HALF", "PASSES"), limit="LIMIT", go="go", start=("x_0",),
          consts=("ATH2", "TOL"))
def _heron_kept_on(x, ATH2, TOL):
    """Heron's pass saying keep where it says done: the position stops at its first done
    all the same."""
    new = 0.5 * (x + ATH2 / x)
    blown = ~np.isfinite(new)
    done = (np.abs(new - x) <= TOL * new) & ~blown
    return new, new, 0.5 * new, done, ~blown


def test_a_position_stops_at_its_first_done_whatever_keep_says():
    """Both engines keep the first done pass's results and number (a pass that went on
    would give the next pass's, an or of two captures in the kernel garbage)."""
    model = Model("heron-kept-on", seed=_model().seed, results=("ROOT", "HALF", "PASSES"))
    model.add(step_of(_start), step_of(_heron_kept_on))
    a = _numbers(3 * K.CHUNK + 5)
    ref = _one_by_one(a)
    got = {"numpy": analyze(EXAMPLE, a, ["ROOT", "HALF", "PASSES"], model=model)}
    if importlib.util.find_spec("numba"):
        got["numba"] = analyze(EXAMPLE, a, ["ROOT", "HALF", "PASSES"], model=model,
                               backend="numba")
    _drawn(got["numpy"], a)
    for engine_name, r in got.items():
        for name in ref:
            np.testing.assert_array_equal(r[name], ref[name], err_msg=f"{engine_name} {name}")
