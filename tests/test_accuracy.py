"""Accuracy of the number models: Figures 10 and 11 field by field, ARCCOS termination,
convergence of the 1410 model to float64 as K grows, and the accuracy study itself."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from sielaff.emulator import program as program_module
from sielaff.emulator.arithmetic import get_arithmetic
from sielaff.emulator.arithmetic.ibm1410 import IBM1410
from sielaff.emulator.program import Program, ProgramError
from sielaff.mechanism import EXAMPLE, crank_rocker_failure
from sielaff.tools.bench import study as bench

#: Every test here compares printed digits (tests/test_ulp_immunity.py re-runs them).
pytestmark = pytest.mark.pinned

# ----- Figures 10 and 11: what each model prints, field by field -------------------------
#: model -> (the fields it certainly prints differently from the figures,
#:           the fields within reach of a printed-digit boundary: THETA 2 and name).
#: A field is certain when every value within NEARBY_ULPS of the computed one prints the
#: same text (bench.FigureField); a boundary field's true value is a round number, and
#: which neighbour prints depends on the CPU's libm, so only that is asserted.
ROUND = ["40 VG2", "40 VA", "40 DVG2", "40 DVA", "40 AG2", "40 AA", "40 DAG2", "40 DAA",
         "50 VG2", "50 VA", "50 DVG2", "50 DVA", "50 AG2", "50 AA", "50 DAG2", "50 DAA"]
FIGURE_FIELDS = {
    # the port's own short PI and RAD move the directions of link 2 off their round values
    "float64": (["40 DVG2 130.0", "40 DAG2 220.0", "40 DAA 220.0", "50 DAG2 230.0",
                 "50 DAA 230.0"],
                ["40 VG2", "40 VA", "40 AG2", "40 AA", "50 VG2", "50 VA", "50 AG2", "50 AA"]),
    "float32": ([], ROUND),
    "engine": ([], ROUND),  # exact mechanics: every round value lands on its boundary
    "ibm1410:8": ([], []),  # every one of the 82 fields, on every machine
    "ibm1410:12": (["40 DVG2 130.0", "40 AG2 .4999E 04", "40 DAG2 220.0", "40 DAA 220.0",
                    "50 DAG2 230.0", "50 DAA 230.0"], []),
    "ibm1410:16": (["40 VG2 .9999E 02", "40 DVG2 130.0", "40 AG2 .4999E 04", "40 AA .9999E 04",
                    "40 DAG2 220.0", "40 DAA 220.0", "50 VA .2000E 03", "50 DAG2 230.0",
                    "50 DAA 230.0"], []),
}
CERTAIN_MATCHES = {"float64": 69, "float32": 66, "engine": 66, "ibm1410:8": 82,
                   "ibm1410:12": 76, "ibm1410:16": 73}

#: every library variant tried at K = 8 (docs/accuracy.md): fields matched, fields differing
VARIANT_COUNTS = {
    "sine": (82, []),
    "taylor": (79, ["40 DVA 129.9", "40 AG2 .4999E 04", "50 AG2 .4999E 04"]),
    "quadrant": (78, ["40 DVA 129.9", "40 AG2 .4999E 04", "50 DVG2 139.9", "50 DVA 139.9"]),
    "hastings": (77, ["40 VA .2000E 03", "40 DVA 129.9", "50 VA .2000E 03", "50 DVG2 139.9",
                      "50 DVA 139.9"]),
    "taylor,cos=shift": (79, ["40 DVA 129.9", "40 AG2 .4999E 04", "50 AG2 .4999E 04"]),
    "taylor,final=round2": (77, ["40 VG2 .9999E 02", "40 DVG2 130.0", "40 AG2 .4999E 04",
                                 "40 AA .9999E 04", "50 AG2 .4999E 04"]),
    "taylor,atan=pi3": (79, ["40 DVA 129.9", "40 AG2 .4999E 04", "50 AG2 .4999E 04"]),
    "taylor,reduce=exact": (79, ["40 DVA 129.9", "40 AG2 .4999E 04", "50 AG2 .4999E 04"]),
    "sine,reduce=model,atan=pi6": (80, ["40 DVA 129.9", "50 VA .2000E 03"]),
    "sine,reduce=model": (81, ["50 VA .2000E 03"]),
    "sine,atan=pi6": (81, ["40 DVA 129.9"]),
    "sine,atan=pi4": (81, ["40 DVA 129.9"]),
    "sine,atan=hastings": (80, ["50 DVG2 139.9", "50 DVA 139.9"]),
    "sine,trig=hastings": (77, ["40 VA .2000E 03", "40 DVA 129.9", "50 VA .2000E 03",
                                "50 DVG2 139.9", "50 DVA 139.9"]),
    "sine,final=round2": (77, ["40 VG2 .9999E 02", "40 DVG2 130.0", "40 AG2 .4999E 04",
                               "40 AA .9999E 04", "50 AG2 .4999E 04"]),
    "sine,sqrt=one": (82, []),
    "sine,sqrt=fixed": (82, []),
}


def short(diffs):
    return [bench._short(d) for d in diffs]


@pytest.mark.parametrize("model", sorted(FIGURE_FIELDS))
def test_figure_fields_per_model(model):
    fields = bench.figure_fields(model)
    assert len(fields) == 82
    diffs, boundary = FIGURE_FIELDS[model]
    assert [f.short for f in fields if f.certain and f.got != f.golden] == diffs
    assert [f"{f.theta} {f.name}" for f in fields if not f.certain] == boundary
    assert sum(f.certain and f.got == f.golden for f in fields) == CERTAIN_MATCHES[model]
    for f in fields:
        assert f.got in f.nearby and len(f.nearby) <= 2
        if not f.certain:  # the 1410 printed one of the two neighbours
            assert f.golden in f.nearby, f


def test_figure_diffs_agree_with_figure_fields():
    """The listing the emulator prints differs from the figures in the certain fields, and
    in no more than the boundary fields besides (whichever way this CPU rounds them)."""
    for model in ("float64", "float32"):
        fields = bench.figure_fields(model)
        got = set(short(bench.figure_diffs(model)))
        certain = {f.short for f in fields if f.certain and f.got != f.golden}
        either = {f"{f.theta} {f.name} {t.strip()}" for f in fields if not f.certain
                  for t in f.nearby if t != f.golden}
        assert certain <= got <= certain | either


def test_ibm1410_default_matches_all_82_fields_exactly():
    """The moonshot: with --arith ibm1410 the figures' sheets come out digit for digit."""
    import io

    from conftest import GOLDEN, split_sheets
    from sielaff.emulator.cards import read_deck
    from sielaff.emulator.program import SheetLimit
    from sielaff.emulator.run import run

    out = io.StringIO()
    with pytest.raises(SheetLimit):
        run(read_deck(bench.EXAMPLE_DECK), out, arithmetic="ibm1410", max_sheets=5)
    sheets = split_sheets(out.getvalue())
    for index, name in ((3, "figure10.asa"), (4, "figure11.asa")):
        assert "\n".join(sheets[index]) + "\n" == (GOLDEN / name).read_text()
    assert "129.9" in "\n".join(sheets[3]) and ".1999E 03" in "\n".join(sheets[4])


def test_every_variant_tried_is_pinned():
    assert {v for v, _ in bench.VARIANTS_TRIED} == set(VARIANT_COUNTS)
    for variant, (count, diffs) in VARIANT_COUNTS.items():
        got = short(bench.figure_diffs(IBM1410(8, variant=variant)))
        assert (82 - len(got), got) == (count, diffs), variant
    assert max(c for c, _ in VARIANT_COUNTS.values()) == 82
    assert IBM1410(8).variant == "sine"


def test_link2_trace_shows_why():
    """The digits docs/accuracy.md explains: the default's STH2/CTH2 and ATAN steps."""
    t40 = bench.link2_trace("sine", 40)
    assert (t40["STH2"], t40["CTH2"]) == ("0.64278765E+00", "0.76604444E+00")
    assert t40["VG2 |Y|/|X|"] == "0.11917535E+01" and t40["VA |Y|/|X|"] == "0.11917534E+01"
    assert t40["VG2 ATAN"] >= "0.87266460E+00" > t40["VA ATAN"]
    assert t40["VA X*X+Y*Y"] < "0.40000000E+05" <= t40["VA X*X+Y*Y"].replace("39", "40")
    assert t40["AG2 X*X+Y*Y"] == "0.25000000E+08"
    t50 = bench.link2_trace("sine", 50)
    assert t50["CTH2"] == "0.64278763E+00"  # sine(pi/2 - .87266463) = sine(.69813167)
    old = bench.link2_trace("taylor", 40)
    assert old["VG2 |Y|/|X|"] == old["VA |Y|/|X|"] == "0.11917536E+01"
    assert old["AG2 X*X+Y*Y"] == "0.24999999E+08"


# ----- ARCCOS terminates under the 1410 alignment rule, on the real port -------------------
def test_port_arccos_terminates_on_a_grid(monkeypatch):
    """Program(IBM1410(8)).ARCCOS ends within 25 terms for every X in [-1, 1] on a grid.

    The stopping test ABS(SUM-SAVE) < 1E-8 is below one unit in SUM's last place, so the
    loop ends only when SUM stops changing; lowering the port's own guard to 25 terms
    turns any longer run into a ProgramError."""
    monkeypatch.setattr(program_module, "ARCCOS_MAX_TERMS", 25)
    for K in (8, 12):
        P = Program(IBM1410(K))
        for i in range(-2000, 2001):
            x = P.ar.num(i / 2000)
            v = P.ARCCOS(x)
            assert abs(float(v) - math.acos(float(x))) < 2e-6 + math.sqrt(2e-7)
    for special in ("0.7", "-0.7", "0.70000001", "-0.69999999", "0.99999999", "-0.99999999"):
        Program(IBM1410(8)).ARCCOS(IBM1410(8).num(special))


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.floats(min_value=-1.0, max_value=1.0))
def test_port_arccos_terminates_hypothesis(x):
    old = program_module.ARCCOS_MAX_TERMS
    program_module.ARCCOS_MAX_TERMS = 25
    try:
        for name in ("ibm1410:8", "float64", "float32"):
            ar = get_arithmetic(name)
            Program(ar).ARCCOS(ar.num(x))
    finally:
        program_module.ARCCOS_MAX_TERMS = old


def test_port_arccos_guard_raises(monkeypatch):
    monkeypatch.setattr(program_module, "ARCCOS_MAX_TERMS", 2)
    A = IBM1410(8)
    with pytest.raises(ProgramError, match="did not converge"):
        Program(A).ARCCOS(A.num(0.5))


def test_bench_arccos_guard_raises():
    with pytest.raises(ProgramError, match="did not converge"):
        bench.arccos_listing(0.5, 0.0)  # a tolerance no difference is below


# ----- more digits: the 1410 model approaches float64 ----------------------------------------
def bound(K: int) -> float:
    """Scaled error bound of ibm1410:K against float64: 1E4 units of the K-digit and of
    the float64 roundoff (the force analysis amplifies input errors by up to ~2000)."""
    return 1e4 * (10.0**-K + 2.0**-53)


@settings(max_examples=12, deadline=None, derandomize=True)
@given(st.floats(2.0, 6.0), st.floats(2.0, 6.0), st.floats(2.0, 6.0), st.floats(5.0, 80.0))
def test_ibm1410_approaches_float64_as_K_grows(R1, R3, R4, TH2D):
    m = dataclasses.replace(EXAMPLE, R1=round(R1, 3), R2=1.0, R3=round(R3, 3), R4=round(R4, 3),
                            RG3=round(R3, 3) / 2, RG4=round(R4, 3) / 2, TH2D=round(TH2D, 2))
    assume(crank_rocker_failure(m) is None)
    from sielaff.engine import analyze

    gamma = analyze(m, np.arange(0.0, 360.0, 5.0), outputs=["GAMMA"])["GAMMA"]
    assume(np.min(np.abs(np.sin(np.radians(gamma)))) > 0.3)  # away from the toggle
    deck = bench.example_deck(7.0, 45.0, 300.0, mechanism=m)
    ref = bench.port_values(Program(get_arithmetic("float64")), deck)
    errs = []
    for K in (8, 12, 16):
        vals = bench.port_values(Program(get_arithmetic(f"ibm1410:{K}")), deck)
        err = float(np.max(bench.scaled_errors(vals, ref)))
        assert err <= bound(K), (K, err)
        errs.append(err)
    assert errs[0] > errs[1] > errs[2]


# ----- the study -------------------------------------------------------------------------------
def test_references_separate_arithmetic_from_algorithm():
    deck = bench.example_deck(0.0, 30.0)
    ref = bench.MPMath(50)
    with ref.precision():
        same = bench.port_values(Program(ref), deck)
        exact = bench.port_values(bench.exact_program(ref), deck)
    f64 = bench.port_values(Program(get_arithmetic("float64")), deck)
    arithmetic = np.max(bench.scaled_errors(f64, same))
    algorithm = np.max(bench.scaled_errors(same, exact))
    assert arithmetic < 1e-8 < algorithm < 1e-6  # the 1966 algorithm, not float64, limits
    eng = bench.engine_values(EXAMPLE, np.arange(12) * 30.0)
    assert np.max(bench.scaled_errors(eng, exact)) < 1e-13  # the engine is exact mechanics


def test_cycle_work_vanishes_and_coarsest_step():
    rows = bench.step_study((30.0, 10.0, 5.0), port_min_step=10.0)
    by = {r["delta"]: r for r in rows}
    assert by[10.0]["engine_rel"] < 1e-11 and by[30.0]["engine_rel"] > 1e-4
    assert 1e-9 < by[10.0]["port_rel"] < 1e-7  # the ARCCOS floor
    assert bench.coarsest_step(rows, 1e-2)["delta"] == 30.0
    assert bench.coarsest_step(rows, 1e-8)["delta"] == 10.0
    assert bench.coarsest_step(rows, 1e-30) is None
    assert bench.coarsest_step(rows, 1e-8, "port_rel") is None  # the port never gets there


@pytest.mark.slow
def test_bench_command_writes_report_and_figure(tmp_path, monkeypatch, capsys):
    from sielaff.cli import main

    monkeypatch.setattr(bench, "STEPS", (30.0, 10.0, 1.0))
    out = tmp_path / "new" / "folder" / "acc.md"  # folders that do not exist yet
    assert main(["bench", "--quick", "-o", str(out)]) == 0
    text = out.read_text()
    png = tmp_path / "new" / "folder" / "acc.png"
    assert png.stat().st_size > 10_000 and png.read_bytes()[:4] == b"\x89PNG"
    assert "| ibm1410:8 | 82 |" in text and "cores, Python" in text
    assert "x float64" in text and "ARCCOS" in text and "Choosing a step" in text
    assert "What the digits depend on" in text
    assert sorted(p.name for p in out.parent.iterdir()) == ["acc.md", "acc.png"]  # no temps
    table = capsys.readouterr().out
    assert table.splitlines()[0].split()[:2] == ["model", "us/position"]
    assert any(line.startswith("ibm1410:8") and "82 certain" in line
               for line in table.splitlines())


def test_bench_writes_nothing_without_o(tmp_path, monkeypatch, capsys):
    """From an empty folder (a user's, not the checkout): a table on stdout, no file."""
    from sielaff.cli import main

    monkeypatch.setattr(bench, "STEPS", (30.0, 10.0))
    monkeypatch.setattr(bench, "MODELS", ("float64",))  # where it writes, not what: one model
    monkeypatch.chdir(tmp_path)
    assert main(["bench", "--quick"]) == 0
    assert list(tmp_path.iterdir()) == []
    assert "engine" in capsys.readouterr().out


def test_bench_refuses_before_work(tmp_path, monkeypatch, capsys):
    import sys

    from sielaff.cli import main

    monkeypatch.setattr(bench, "study", lambda *a, **k: pytest.fail("computed first"))
    assert main(["bench", "-o", str(tmp_path)]) == 2
    assert "is a folder" in capsys.readouterr().err
    (tmp_path / "file").write_text("x")
    assert main(["bench", "-o", str(tmp_path / "file" / "acc.md")]) == 2
    assert "cannot create its folder" in capsys.readouterr().err
    monkeypatch.setitem(sys.modules, "mpmath", None)  # as if not installed
    assert main(["bench", "--quick"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "needs mpmath" in err and '.[bench]"' in err
