"""Each effect declares itself once, and every tool shows it (issue 31).

Two kinds of test: one parametrised over the model's registered effects checks each
declaration (units and descriptions of its outputs, its Scene field's default and check,
the spec round trip, the on rule, the plan skipping it bit for bit when it is off, the
compiled backend refusing it when it has no compiled form); and one adds an effect the
way docs/architecture.md says (a new module and one registration line, in a copy of the
package) and finds it in the Scene, the spec, the table, the torque parts, ``check``
(text and JSON), ``report`` and the compiled backend's refusal.  A place that kept its
own list of effects would miss it.
"""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import DECKS, ROOT
from sielaff import EXAMPLE, analyze
from sielaff.engine import RESULTS
from sielaff.engine.elements import Damper, Spring
from sielaff.engine.fourbar import FOURBAR
from sielaff.engine.friction import PinFriction
from sielaff.engine.loads import Load
from sielaff.engine.registry import Model
from sielaff.engine.scene import Scene
from sielaff.quantities import KINDS, describe, unit

ANGLES = np.arange(0.0, 360.0, 7.5)

#: A scene that turns each registered effect on (by the effect's name).
EXAMPLES = {
    "gravity": {"gravity": "down"},
    "loads": {"loads": (Load(3, 8.0, 10.0, 80.0, -20.0, 5.0),)},
    "TEX": {"tex": 150.0},
    "crank acceleration": {"th2dd": -40.0},
    "springs and dampers": {"elements": (Spring((1, 18.0, 0.0), (4, 6.0, 0.0), 20.0, 8.0),
                                         Damper((2, 2.0, 0.0), (4, 6.0, 0.0), 0.5))},
    "pin friction": {"friction": PinFriction(0.1, 0.25)},
}

NAMES = [e.name for e in FOURBAR.effects]


def test_every_registered_effect_has_an_example_here():
    assert sorted(EXAMPLES) == sorted(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_outputs_have_a_unit_in_each_system_and_a_meaning(name):
    effect = FOURBAR.effect(name)
    assert effect.outputs
    for out, (kind, meaning) in effect.outputs.items():
        assert kind in KINDS
        assert unit(out) == KINDS[kind][0] and unit(out, "SI") == KINDS[kind][1]
        assert describe(out) == meaning and meaning
        assert out in FOURBAR.outputs
    assert effect.torque is None or effect.torque in FOURBAR.torque_parts


@pytest.mark.parametrize("name", NAMES)
def test_fields_default_off_and_the_on_rule(name):
    effect = FOURBAR.effect(name)
    assert effect.params, "every effect of the four-bar has a Scene field"
    for p in effect.params:
        assert p.check(p.default) == p.default or p.default is None
        assert p.name in {f for f in Scene.__dataclass_fields__}
    assert not effect.is_on(Scene())
    on = Scene(**EXAMPLES[name])
    assert effect.is_on(on)
    assert [e.name for e in on.effects] == [name]
    assert on.is_1966 == effect.in_1966


def _as_parsed(v):
    """A table as the spec's TOML parser gives it (numbers as Decimal, parse_float)."""
    from decimal import Decimal

    if isinstance(v, dict):
        return {k: _as_parsed(x) for k, x in v.items()}
    if isinstance(v, list | tuple):
        return [_as_parsed(x) for x in v]
    return Decimal(repr(v)) if isinstance(v, float) else v


@pytest.mark.parametrize("name", NAMES)
def test_the_spec_reads_back_what_the_effect_writes(name):
    from sielaff.tools.spec_scene import scene_help, scene_of, scene_spec

    scene = Scene(**EXAMPLES[name])
    table = scene_spec(scene, "in-lb-sec")
    assert set(table) - {"units", "branch"} <= set(FOURBAR.effect(name).spec.keys)
    units, back = scene_of({"scene": _as_parsed(table)})
    assert units == "in-lb-sec" and back == scene
    for key in FOURBAR.effect(name).spec.keys:  # and help spec says each key
        assert key in scene_help()


@pytest.mark.parametrize("name", NAMES)
def test_off_the_plan_is_the_model_without_it_bit_for_bit(name):
    """Off, none of its steps runs; and where the model can do without it at all (its
    outputs feed nothing else: not TEX, which statement 74 takes, nor TH2DD's terms of the
    accelerations) the results are the model's without it, bit for bit."""
    without = FOURBAR.mapping(lambda st: st.fn)
    without.effects = [e for e in without.effects if e.name != name]
    without._derive()
    removable = name not in ("TEX", "crank acceleration")
    if removable:
        a = analyze(EXAMPLE, ANGLES, list(RESULTS))
        b = analyze(EXAMPLE, ANGLES, list(RESULTS), model=without)
        for n in RESULTS:
            np.testing.assert_array_equal(a[n], b[n], err_msg=n)
    else:
        with pytest.raises(ValueError, match="neither an input nor provided"):
            analyze(EXAMPLE, ANGLES, list(RESULTS), model=without)
    FOURBAR.calls.clear()
    analyze(EXAMPLE, ANGLES, list(RESULTS) + list(FOURBAR.torque_parts))
    ran = {s.name for s in FOURBAR.effect(name).steps} & set(FOURBAR.calls)
    assert not ran, f"{name} is off but {sorted(ran)} ran"


@pytest.mark.parametrize("name", NAMES)
def test_on_its_steps_run_and_its_outputs_answer(name):
    scene = Scene(**EXAMPLES[name])
    FOURBAR.calls.clear()
    r = analyze(EXAMPLE, ANGLES, list(FOURBAR.effect(name).shown(scene)) + ["TORQ"],
                scene=scene)
    assert {s.name for s in FOURBAR.effect(name).steps} & set(FOURBAR.calls)
    assert any(np.any(r[n] != 0.0) for n in FOURBAR.effect(name).shown(scene))


@pytest.mark.parametrize("name", NAMES)
def test_the_compiled_backend_compiles_it_from_its_steps_or_refuses_it(name):
    """The compiled backend asks no declaration: it compiles the effect's own steps (and
    then agrees with the numpy engine) or refuses it in one line naming it.  Every effect
    compiles, pin friction's count of solutions (FRICTION_SOLUTIONS) too (a refusal is
    shown in tests/test_compiled.py, on an effect registered there)."""
    pytest.importorskip("numba")
    scene = Scene(**EXAMPLES[name])
    names = ["TORQ"] + (["FRICTION_SOLUTIONS"] if name == "pin friction" else [])
    got = analyze(EXAMPLE, ANGLES, names, scene=scene, backend="numba")
    ref = analyze(EXAMPLE, ANGLES, names, scene=scene)
    assert not np.array_equal(ref["TORQ"], analyze(EXAMPLE, ANGLES, ["TORQ"])["TORQ"])
    assert np.max(np.abs(got["TORQ"] - ref["TORQ"])) <= 1e-12 * np.max(np.abs(ref["TORQ"]))
    for n in names[1:]:
        np.testing.assert_array_equal(got[n], ref[n])


def test_the_torque_parts_sum_to_torq_with_every_effect_on():
    fields: dict = {}
    for example in EXAMPLES.values():
        fields.update(example)
    scene = Scene(**fields)
    assert len(scene.effects) == len(NAMES)
    r = analyze(EXAMPLE, ANGLES, ["TORQ", *FOURBAR.torque_parts], scene=scene)
    total = sum(r[p] for p in FOURBAR.torque_parts)
    scale = np.max(np.abs([r[p] for p in FOURBAR.torque_parts]))
    np.testing.assert_allclose(total, r["TORQ"], rtol=0, atol=1e-12 * scale)


# ----- the friction deck through the tools ------------------------------------------------

FRICTION = DECKS / "friction.toml"


def test_table_of_the_friction_deck_has_its_effects_and_parts_that_sum(capsys):
    import csv
    import io

    from sielaff.cli import main

    assert main(["table", str(FRICTION), "--torque-parts"]) == 0
    rows = list(csv.reader(io.StringIO(capsys.readouterr().out)))
    head = rows[0]
    values = np.array([[float(v) for v in r] for r in rows[1:]])
    names = [h.split("[")[0] for h in head]
    for col in ("TORQ_FRICTION[in-lb]", "PLOSS_O2[in-lb/sec]", "PLOSS_A[in-lb/sec]",
                "PLOSS_B[in-lb/sec]", "PLOSS_O4[in-lb/sec]", "TORQ_ELEMENTS[in-lb]",
                "SPRING1_L[in]", "SPRING1_F[lb]", "FRICTION_STATUS[-]"):
        assert col in head
    parts = [names.index(p) for p in FOURBAR.torque_parts]
    torq = values[:, names.index("TORQ")]
    scale = np.max(np.abs(values[:, parts]))
    np.testing.assert_allclose(values[:, parts].sum(axis=1), torq, rtol=0, atol=1e-12 * scale)
    assert np.any(values[:, names.index("TORQ_FRICTION")] != 0.0)


def _friction_deck():
    from sielaff.tools.common import read_spec_deck

    return read_spec_deck(str(FRICTION))


def test_check_states_the_friction_and_spring_parameters_and_the_loss_per_pin():
    from sielaff.tools.check import check_deck, report_json

    deck, scene = _friction_deck()
    rep = check_deck(deck, scene=scene)
    text = rep.text
    for pin in ("O2", "A", "B", "O4"):
        assert f"    {pin}: mu = 0.1, pin radius = 0.25 in" in text
        assert f"    loss at {pin}: mean = " in text
    assert "k = 20 lb/in, free length = 8 in" in text
    assert "loss in all: mean = " in text
    data = json.loads(report_json(deck, rep, scene))
    by_name = {e["name"]: e for e in data["effects"]}
    assert by_name["pin friction"]["parameters"]["A"]["pin radius"] == {"value": 0.25,
                                                                       "unit": "in"}
    assert by_name["springs and dampers"]["parameters"]["spring 1"]["k"]["unit"] == "lb/in"
    loss = by_name["pin friction"]["figures"]["loss in all"]["per revolution"]
    assert loss["unit"] == "in-lb"
    # the loss of a revolution is the drive's work over it (the spring's and the inertia's
    # are zero over a cycle): two paths, pin forces times slips and the drive torque
    from sielaff.engine.derived import cycle_work

    work, _ = cycle_work(deck.mechanism, scene=scene)
    assert loss["value"] == pytest.approx(work, rel=1e-9)


def test_check_figures_of_the_spring_match_its_geometry():
    """The spring runs from (18, 0) on the frame to 6 in along the rocker from O4 = (12, 0):
    its length from ATH4 alone, its tension 20 (L - 8)."""
    from sielaff.design.effects import effect_facts
    from sielaff.engine.derived import revolution

    deck, scene = _friction_deck()
    facts = {f.name: f for f in effect_facts(deck.mechanism, scene)}
    figs = {f.label: f.value for f in facts["springs and dampers"].figures}
    th4 = np.radians(analyze(deck.mechanism, revolution()[:-1], ["ATH4"], scene=scene)["ATH4"])
    length = np.hypot(12.0 + 6.0 * np.cos(th4) - 18.0, 6.0 * np.sin(th4))
    assert figs["shortest"] == pytest.approx(length.min(), rel=1e-12)
    assert figs["most tension"] == pytest.approx(20.0 * (length.max() - 8.0), rel=1e-12)


def test_report_has_the_scene_section():
    pytest.importorskip("matplotlib")
    from sielaff.tools.report import scene_section

    deck, scene = _friction_deck()
    page = "\n".join(scene_section(deck.mechanism, scene, True))
    assert "<h2>The scene</h2>" in page and "pin radius = 0.25 in" in page
    assert "k = 20 lb/in, free length = 8 in" in page and "loss at O4: mean = " in page


# ----- an effect added as docs/architecture.md says ---------------------------------------

#: The whole new effect: a viscous crank bearing, its torque c TH2D its own part of TORQ.
#: docs/architecture.md shows this text as the diff of adding an effect.
BEARING = '''\
"""A viscous crank bearing: the drive torque c TH2D its drag takes (TORQ_BEARING)."""

from __future__ import annotations

from typing import Any

import numpy as np

from sielaff.engine.declare import Fact, Param, SpecForm
from sielaff.engine.registry import Effect, step, step_of
from sielaff.engine.values import check_value


@step(provides=("TORQ_BEARING",), needs=("BEARING_C", "TH2D"), zero_when=("BEARING_C",))
def _bearing(BEARING_C, TH2D):
    return BEARING_C * TH2D


def _check(v: Any) -> float:
    x = check_value("Scene.bearing_damping", v)
    if np.ndim(x) or x < 0.0:
        raise ValueError(f"Scene.bearing_damping = {v!r}: a number >= 0")
    return float(x)


def _read(table: Any, path: str, reader: Any) -> dict[str, Any]:
    key = "bearing_damping"
    return {key: reader.number(f"{path}: [scene] {key}", table[key])} if key in table else {}


EFFECT = Effect(
    "crank bearing", (step_of(_bearing),), lambda scene, m: {"BEARING_C": scene.bearing_damping},
    parts={"torq": "TORQ_BEARING"}, torque="TORQ_BEARING",
    params=(Param("bearing_damping", 0.0, _check,
                  "float\\n    The crank bearing's viscous drag [in-lb-sec or N m s], >= 0."),),
    outputs={"TORQ_BEARING": ("torque", "the part of TORQ the crank bearing's drag takes")},
    on=lambda scene: scene.bearing_damping > 0.0,
    summary=lambda scene, units: "a viscous crank bearing",
    describe=lambda scene, units: [Fact("", "c", scene.bearing_damping, "rotary damping")],
    spec=SpecForm(("bearing_damping",), _read,
                  lambda s: {"bearing_damping": s.bearing_damping} if s.bearing_damping else {},
                  "bearing_damping = 0.5         # the crank bearing's drag, in-lb-sec"))
'''

#: The one registration line, added to engine/fourbar.py after the last effect's.
LINE = 'FOURBAR.add_effect("bearing")\n'

#: What the child does with the copy: every place the effect must reach.
CHILD = r'''
import contextlib, io, json, math, sys
import numpy as np
from sielaff import EXAMPLE, Scene, analyze
from sielaff.cli import main
from sielaff.quantities import unit

found = {}
spec = sys.argv[1]

def run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(argv)
    return status, out.getvalue(), err.getvalue()

s = Scene(bearing_damping=2.0)
found["scene"] = [e.name for e in s.effects]
try:
    Scene(bearing_damping=math.nan)
except ValueError as exc:
    found["check"] = str(exc)
found["units"] = [unit("TORQ_BEARING"), unit("TORQ_BEARING", "SI")]
status, out, err = run(["table", spec, "--torque-parts"])
head = out.splitlines()[0].split(",")
rows = np.array([[float(x) for x in line.split(",")] for line in out.splitlines()[1:]])
names = [h.split("[")[0] for h in head]
from sielaff.engine.fourbar import FOURBAR
parts = [names.index(p) for p in FOURBAR.torque_parts]
found["table"] = {"status": status, "bearing": "TORQ_BEARING[in-lb]" in head,
                  "parts": list(FOURBAR.torque_parts),
                  "sum": float(np.max(np.abs(rows[:, parts].sum(axis=1)
                                             - rows[:, names.index("TORQ")]))),
                  "scale": float(np.max(np.abs(rows[:, parts]))),
                  "value": rows[0, names.index("TORQ_BEARING")]}
status, out, err = run(["help", "spec"])
found["help"] = [status, out]
status, out, err = run(["check", spec])
found["check_text"] = [status, out]
status, out, err = run(["check", spec, "--format", "json"])
found["check_json"] = json.loads(out).get("effects")
status, out, err = run(["report", spec, "-o", sys.argv[2]])
found["report"] = [status, err]
r = analyze(EXAMPLE, [40.0], ["TORQ"], scene=s)
base = analyze(EXAMPLE, [40.0], ["TORQ"])
try:
    c = analyze(EXAMPLE, [40.0], ["TORQ"], scene=s, backend="numba")
    found["compiled"] = float(c["TORQ"][0] - base["TORQ"][0])
except (ValueError, ImportError) as exc:
    found["compiled_error"] = str(exc)
found["torq"] = float(r["TORQ"][0] - base["TORQ"][0])
print(json.dumps(found))
'''


@pytest.fixture(scope="module")
def added(tmp_path_factory):
    pytest.importorskip("matplotlib")
    tmp = tmp_path_factory.mktemp("added")
    pkg = tmp / "src" / "sielaff"
    shutil.copytree(ROOT / "src" / "sielaff", pkg,
                    ignore=shutil.ignore_patterns("__pycache__"))
    (pkg / "engine" / "bearing.py").write_text(BEARING)
    fourbar = pkg / "engine" / "fourbar.py"
    text = fourbar.read_text()
    anchor = 'FOURBAR.add_effect("friction")\n'
    assert text.count(anchor) == 1
    fourbar.write_text(text.replace(anchor, anchor + LINE))
    spec = tmp / "bearing.toml"
    spec.write_text(FRICTION.read_text().replace(
        '[scene]\nunits = "in-lb-sec"\n', '[scene]\nunits = "in-lb-sec"\nbearing_damping = 2.0\n'))
    changed = sorted(str(p.relative_to(pkg)) for p in pkg.rglob("*.py")
                     if not (ROOT / "src" / "sielaff" / p.relative_to(pkg)).exists()
                     or (ROOT / "src" / "sielaff" / p.relative_to(pkg)).read_text()
                     != p.read_text())
    assert changed == ["engine/bearing.py", "engine/fourbar.py"]  # one file, one line
    env = {"PYTHONPATH": str(tmp / "src"), "PATH": "/usr/bin:/bin", "HOME": str(tmp),
           "MPLBACKEND": "Agg", "SIELAFF_KERNEL_DIR": "off"}
    p = subprocess.run([sys.executable, "-c", CHILD, str(spec), str(tmp / "r.html")],
                       capture_output=True, text=True, timeout=600, env=env, cwd=tmp)
    assert p.returncode == 0, p.stderr[-3000:]
    found = json.loads(p.stdout.splitlines()[-1])
    found["html"] = (tmp / "r.html").read_text()
    return found


def test_added_effect_is_a_scene_field_with_its_check(added):
    assert "crank bearing" in added["scene"]
    assert added["check"].startswith("Scene.bearing_damping = nan")
    assert added["units"] == ["in-lb", "N m"]


def test_added_effect_is_in_the_spec_the_table_and_the_torque_parts(added):
    t = added["table"]
    assert t["status"] == 0 and t["bearing"] and t["parts"][-1] == "TORQ_BEARING"
    assert t["sum"] <= 1e-12 * t["scale"]
    assert t["value"] == pytest.approx(2.0 * 50.0, rel=1e-15)  # c TH2D
    assert added["torq"] == pytest.approx(100.0, rel=1e-12)


def test_added_effect_is_in_help_spec(added):
    status, out = added["help"]
    assert status == 0 and "bearing_damping = 0.5         # the crank bearing's drag" in out


def test_added_effect_is_in_check_and_its_json(added):
    status, out = added["check_text"]
    assert status == 0 and "crank bearing: a viscous crank bearing" in out
    assert "    c = 2 in-lb-sec" in out and "a viscous crank bearing, " not in out[:0]
    names = [e["name"] for e in added["check_json"]]
    assert "crank bearing" in names
    bearing = added["check_json"][names.index("crank bearing")]
    assert bearing["parameters"]["c"] == {"value": 2.0, "unit": "in-lb-sec"}


def test_added_effect_is_in_the_report(added):
    assert added["report"][0] == 0, added["report"][1]
    assert "<th>crank bearing</th>" in added["html"] and "c = 2 in-lb-sec" in added["html"]


def test_added_effect_is_compiled_from_its_own_step(added):
    """Nothing but its module and its line: the compiled backend runs the new effect's
    step as written (or, without numba, says what it needs)."""
    if "compiled_error" in added:
        assert "needs numba" in added["compiled_error"]
    else:
        assert added["compiled"] == pytest.approx(added["torq"], rel=1e-12, abs=1e-12)


def test_architecture_doc_shows_this_effect_as_the_diff():
    doc = (ROOT / "docs" / "architecture.md").read_text()
    for line in BEARING.splitlines():
        assert "+" + line in doc.splitlines() or (not line and "+" in doc), line
    assert "+" + LINE.strip() in doc


def test_a_model_may_not_take_an_undeclared_output():
    from sielaff.engine.registry import Effect, step, step_of

    @step(provides=("TORQ_X",), needs=("TH2D",))
    def _x(TH2D):
        return TH2D

    with pytest.raises(ValueError, match=r"outputs \['TORQ_X'\] have no declared"):
        Effect("x", (step_of(_x),), lambda s, m: {})
    assert isinstance(FOURBAR, Model) and math.isfinite(EXAMPLE.TH2D)


def test_the_architecture_doc_names_this_file():
    assert Path(__file__).name in (ROOT / "docs" / "architecture.md").read_text()
