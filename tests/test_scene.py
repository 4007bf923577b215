"""The Scene as one object, the model you extend by adding a module, one path in.

Each of the five defects a review reproduced (issue 20) is a test here that failed on the
engine before the redesign: the transmission angle on the crossed branch, the direction
of a zero vector, a loop that cannot close reported as assembled, ``out=`` with an array
load longer than a block, and a NaN crank angle that changed the other elements.
"""

from __future__ import annotations

import dataclasses
import math
import types
import warnings
from collections import Counter

import numpy as np
import pytest
from hypothesis import assume, event, given, settings
from hypothesis import strategies as st

from sielaff import EXAMPLE, Load, Scene, analyze, linkage_class
from sielaff.engine import FOURBAR, OUTPUTS, RESULTS, AssemblyWarning, Effect, Model, plan
from sielaff.engine.registry import step, step_of
from sielaff.engine.statics import pins

ANGLES = np.arange(0.0, 360.0, 7.5)


# ----- the five defects -----------------------------------------------------------------

@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_gamma_is_within_0_and_180_on_both_branches(branch):
    r = analyze(EXAMPLE, ANGLES, ["GAMMA"], branch=branch)
    assert np.all((r["GAMMA"] >= 0.0) & (r["GAMMA"] <= 180.0)), r["GAMMA"].min()
    # the two branches are mirror images about A-O4: the same angle at B
    other = analyze(EXAMPLE, ANGLES, ["GAMMA"], branch="open")["GAMMA"]
    np.testing.assert_allclose(r["GAMMA"], other, atol=1e-12)


def test_gamma_min_of_the_crossed_branch_is_an_angle():
    from sielaff.design.figures import figures

    f = figures(EXAMPLE, scene=Scene(branch="crossed"))
    assert 0.0 <= f["GAMMA_MIN"] <= 90.0


def test_a_zero_vector_points_at_0_as_the_port_vector_does():
    """RG2 = 0 puts G2 on O2: its velocity and acceleration are zero vectors at every
    angle, and arctan2 of signed zeros said 180 at some of them."""
    r = analyze(EXAMPLE.replace(RG2=0.0), ANGLES, ["DAG2", "DVG2", "AG2", "VG2"])
    assert not np.any(r["AG2"]) and not np.any(r["VG2"])
    np.testing.assert_array_equal(r["DAG2"], 0.0)
    np.testing.assert_array_equal(r["DVG2"], 0.0)
    # a crank at rest with gravity: every acceleration of link 2 is zero too
    r = analyze(EXAMPLE.replace(TH2D=0.0), ANGLES, ["DAA", "DAG2", "DVA"], gravity="down")
    for name in r:
        np.testing.assert_array_equal(r[name], 0.0, err_msg=name)


def test_a_loop_that_cannot_close_is_not_assembled():
    m = EXAMPLE.replace(R1=1000.0, R2=999.0, R3=1.0, R4=1.0)
    with pytest.warns(AssemblyWarning, match="^1 of 1 positions"):
        r = analyze(m, [0.099487], ["ASSEMBLED", "GAMMA", "TH3D"])
    assert r.not_assembled == 1 and not r["ASSEMBLED"][0]
    assert np.isnan(r["GAMMA"][0]) and np.isnan(r["TH3D"][0])
    # and linkage_class's reachable arc ends before that angle
    (a, b), = linkage_class(m).arcs
    assert (0.099487 - a) % 360.0 > (b - a) % 360.0


@settings(max_examples=200, derandomize=True)
@given(st.lists(st.floats(0.05, 20.0), min_size=4, max_size=4), st.floats(0.0, 360.0))
def test_assembly_agrees_with_the_arcs_of_linkage_class(r, th2):
    """Inside an arc (away from its ends by more than roundoff) the loop closes; outside,
    it does not."""
    m = EXAMPLE.replace(R1=r[0], R2=r[1], R3=r[2], R4=r[3])
    c = linkage_class(m)
    assume(c.kind != "change-point")
    if c.turns_fully:
        inside, margin = True, 1.0
    else:
        spans = [((th2 - a) % 360.0, (b - a) % 360.0) for a, b in c.arcs]
        inside = any(x <= w for x, w in spans)
        margin = min((min(x, abs(w - x), 360.0 - x) for x, w in spans), default=1.0)
    assume(margin > 1e-6)
    event("inside an arc" if inside else "outside every arc")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AssemblyWarning)
        assembled = bool(analyze(m, [th2], ["ASSEMBLED"])["ASSEMBLED"][0])
    assert assembled == inside


def test_out_takes_array_loads_of_any_length():
    n = 20_000  # longer than a block (16,384)
    th = np.linspace(0.0, 720.0, n)
    fx = np.linspace(-50.0, 50.0, n)
    load = Load(3, r=4.0, angle=10.0, fx=fx, torque=np.cos(np.radians(th)))
    out = {"TORQ": np.empty(n), "FB34": np.empty(n)}
    analyze(EXAMPLE, th, out=out, loads=[load], th2dd=np.full(n, 3.0), block=5000)
    want = analyze(EXAMPLE, th, ["TORQ", "FB34"], loads=[load], th2dd=np.full(n, 3.0))
    for name in out:
        np.testing.assert_array_equal(out[name], want[name])
    with pytest.raises(ValueError, match=r"loads\[0\]\.fx .*ath2's shape"):
        analyze(EXAMPLE, th, out={"TORQ": np.empty(n)}, loads=[Load(3, fx=np.ones(7))])


def test_a_nan_angle_changes_no_other_element():
    base = analyze(EXAMPLE, ANGLES, RESULTS)
    with pytest.warns(AssemblyWarning, match="^1 of"):
        r = analyze(EXAMPLE, np.append(ANGLES + 360.0, np.nan), RESULTS)
    for name in RESULTS:
        if name == "ATH2":
            continue
        np.testing.assert_array_equal(r[name][:-1], base[name], err_msg=name)
    for name in ("ATH3", "GAMMA", "TH4D", "TORQ", "DVA", "SHAKM"):
        assert np.isnan(r[name][-1]), name


# ----- the Scene -----------------------------------------------------------------------

SCENE = Scene(tex=np.linspace(0.0, 50.0, ANGLES.size), th2dd=-40.0, gravity="down",
              loads=(Load(3, r=8.0, angle=5.0, fx=350.0),
                     Load(4, torque=lambda th: 20.0 * np.sin(np.radians(th)))),
              branch="crossed")


def test_keywords_and_the_scene_give_the_same_bits():
    a = analyze(EXAMPLE, ANGLES, OUTPUTS, scene=SCENE)
    b = analyze(EXAMPLE, ANGLES, OUTPUTS, SCENE.tex, th2dd=SCENE.th2dd,
                gravity=SCENE.gravity, loads=SCENE.loads, branch=SCENE.branch)
    for name in OUTPUTS:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)
    assert plan(OUTPUTS, scene=SCENE) == plan(OUTPUTS, None, SCENE.tex, th2dd=-40.0,
                                              gravity="down", loads=SCENE.loads,
                                              branch="crossed")


@pytest.mark.parametrize("keyword", ["tex", "th2dd", "gravity", "loads", "branch"])
def test_a_scene_and_a_keyword_is_an_error_naming_both(keyword):
    value = {"tex": 1.0, "th2dd": 1.0, "gravity": None, "loads": (), "branch": "open"}
    with pytest.raises(ValueError, match=f"scene= or {keyword}, not both"):
        analyze(EXAMPLE, ANGLES, ["TORQ"], scene=Scene(), **{keyword: value[keyword]})


@pytest.mark.parametrize("make, field", [
    (lambda: Scene(tex=math.nan), "Scene.tex"),
    (lambda: Scene(tex=[1.0, math.inf]), "Scene.tex"),
    (lambda: Scene(th2dd=1e300), "Scene.th2dd"),
    (lambda: Scene(th2dd="fast"), "Scene.th2dd"),
    (lambda: Scene(gravity=(0.0, math.nan)), "Scene.gravity gy"),
    (lambda: Scene(gravity="up"), "Scene.gravity"),
    (lambda: Scene(gravity=(1.0, 2.0, 3.0)), "Scene.gravity"),
    (lambda: Scene(loads=Load(3)), "Scene.loads"),
    (lambda: Scene(loads=[3]), r"Scene.loads\[0\]"),
    (lambda: Scene(branch="upside-down"), "Scene.branch"),
    (lambda: Load(3, fx=math.nan), "Load.fx"),
    (lambda: Load(3, r=[1.0, -math.inf]), "Load.r"),
    (lambda: Load(1), "Load.link"),
    (lambda: Load(True), "Load.link"),
])
def test_every_scene_value_is_checked_once_naming_its_field(make, field):
    with pytest.raises(ValueError, match=f"^{field}"):
        make()


def test_a_function_in_the_scene_is_checked_where_it_is_called():
    with pytest.raises(ValueError, match=r"^Scene.tex: the function gave nan"):
        analyze(EXAMPLE, ANGLES, ["TORQ"], tex=lambda th4: th4 * math.nan)
    with pytest.raises(ValueError, match=r"^Scene.th2dd: the function gave inf"):
        analyze(EXAMPLE, ANGLES, ["TORQ"], th2dd=lambda th2: th2 * 0.0 + math.inf)
    with pytest.raises(ValueError, match=r"^Load.fx: the function gave"):
        analyze(EXAMPLE, ANGLES, ["TORQ"], loads=[Load(3, fx=lambda th: 1e300 * th)])


def test_a_scene_array_that_does_not_broadcast_is_named():
    with pytest.raises(ValueError, match=r"cannot broadcast loads\[0\]\.fy \(shape \(3,\)\)"):
        analyze(EXAMPLE, ANGLES, ["TORQ"], loads=[Load(3, fy=np.ones(3))])


def test_the_scene_is_frozen_and_replace_validates():
    s = Scene(th2dd=2.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.th2dd = 3.0  # type: ignore[misc]
    assert s.replace(branch="crossed").branch == "crossed" and s.branch == "open"
    with pytest.raises(ValueError, match="Scene.th2dd"):
        s.replace(th2dd=math.nan)
    with pytest.raises(TypeError, match="no field speed"):
        s.replace(speed=1.0)


# ----- the model: extended by adding a module ----------------------------------------------

def _extra_torque_module():
    """A whole effect as a new module would write it: a constant torque on the coupler,
    seeded from an attribute the test's scene object carries."""
    mod = types.ModuleType("couple")

    @step(provides=("fa32x_c", "fa32y_c", "fb34x_c", "fb34y_c", "foax_c", "foay_c",
                    "fobx_c", "foby_c", "TORQ_COUPLE"),
          needs=("COUPLE", "R2", "R3", "R4", "c2", "s2", "c3", "s3", "c4", "s4", "s34"),
          zero_when=("COUPLE",))
    def _couple(COUPLE, R2, R3, R4, c2, s2, c3, s3, c4, s4, s34):
        return pins(0.0, 0.0, 0.0, 0.0, 0.0, COUPLE, 0.0, 0.0, 0.0, R2, R3, R4, c2, s2, c3,
                    s3, c4, s4, s34)

    mod.EFFECT = Effect("couple", (step_of(_couple),),
                        lambda scene, m: {"COUPLE": getattr(scene, "couple", 0.0)},
                        parts={"fa32x": "fa32x_c", "fa32y": "fa32y_c", "fb34x": "fb34x_c",
                               "fb34y": "fb34y_c", "foax": "foax_c", "foay": "foay_c",
                               "fobx": "fobx_c", "foby": "foby_c", "torq": "TORQ_COUPLE"},
                        torque="TORQ_COUPLE",
                        outputs={"TORQ_COUPLE": ("torque", "the part of TORQ the couple takes")})
    return mod


def _copy_of_the_fourbar():
    m = FOURBAR.mapping(lambda st: st.fn)
    assert m is not FOURBAR and m.outputs == FOURBAR.outputs
    return m


def test_an_effect_registered_later_can_be_asked_for():
    model = _copy_of_the_fourbar()
    assert "TORQ_COUPLE" not in model.outputs
    model.add_effect(_extra_torque_module().EFFECT)  # the one registration line
    assert "TORQ_COUPLE" in model.outputs and "TORQ_COUPLE" not in FOURBAR.outputs

    class CoupledScene(Scene):
        couple = 75.0

    names = ["TORQ", "TORQ_COUPLE", "TORQ_INERTIA", "FB34X", "FA32Y"]
    r = analyze(EXAMPLE, ANGLES, names, scene=CoupledScene(), model=model)
    base = analyze(EXAMPLE, ANGLES, names[:1] + names[2:])
    # superposed: the totals grow by the couple's own solution, the inertia part does not
    np.testing.assert_allclose(r["TORQ_INERTIA"], base["TORQ_INERTIA"], rtol=1e-12)
    np.testing.assert_allclose(r["TORQ"], base["TORQ"] + r["TORQ_COUPLE"], rtol=1e-12)
    # virtual work: the couple on link 3 takes TORQ_COUPLE TH2D = -75 TH3D of the drive
    th3d = analyze(EXAMPLE, ANGLES, ["TH3D"])["TH3D"]
    np.testing.assert_allclose(r["TORQ_COUPLE"] * EXAMPLE.TH2D, -75.0 * th3d, rtol=1e-9,
                               atol=1e-9)
    # off, it costs nothing: not a step of the plan runs
    model.calls.clear()
    r0 = analyze(EXAMPLE, ANGLES, names[:1], model=model)
    assert model.calls["_couple"] == 0
    np.testing.assert_array_equal(r0["TORQ"], base["TORQ"])


def test_a_second_model_has_its_own_steps():
    """Another closure providing c3 (the slider-crank's, say) is a second model, not
    'c3 provided twice'."""

    @step(provides=("c3", "s3"), needs=("ATH2",))
    def _other_closure(ATH2):
        return np.cos(np.radians(ATH2)), np.sin(np.radians(ATH2))

    other = Model("other", seed=lambda m, th, sc: {"ATH2": np.atleast_1d(th)},
                  results=("c3",))
    other.add(step_of(_other_closure))
    assert other.provider["c3"].name == "_other_closure"
    assert FOURBAR.provider["c3"].name == "_loop_closure"
    with pytest.raises(ValueError, match="c3 provided twice"):
        FOURBAR.mapping(lambda s: s.fn).add(step_of(_other_closure))


def test_steps_are_pure_on_read_only_inputs():
    """Every array a step is given is made read-only: a step that wrote into its inputs
    would raise.  The answers are the same bits."""
    def frozen(st):
        def run(*args):
            for a in args:
                if isinstance(a, np.ndarray):
                    a.flags.writeable = False
            return st.fn(*args)
        return run

    model = FOURBAR.mapping(frozen)
    m = EXAMPLE.replace(R4=np.array([11.0, 12.0, 13.0])[:, None])
    ath2 = np.arange(0.0, 360.0, 10.0)
    ath2.flags.writeable = False
    a = analyze(m, ath2, OUTPUTS, scene=SCENE.replace(tex=5.0), model=model)
    b = analyze(m, ath2, OUTPUTS, scene=SCENE.replace(tex=5.0))
    for name in OUTPUTS:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)


def test_replacing_a_step_injects_through_the_model():
    calls = Counter()

    def spy(*args):
        calls["link4"] += 1
        return FOURBAR.provider["FP34X"].fn(*args)

    model = FOURBAR.replacing(_force_link4=spy)
    analyze(EXAMPLE, ANGLES, ["TORQ"], model=model)
    analyze(EXAMPLE, ANGLES, ["ATH3"], model=model)
    assert calls["link4"] == 1
    with pytest.raises(ValueError, match="no step _force_link9"):
        FOURBAR.replacing(_force_link9=spy)


# ----- zero_when: the declarations are true --------------------------------------------

zero_cases = st.fixed_dictionaries({
    "W2": st.sampled_from([0.0, 3.0]), "W3": st.sampled_from([0.0, 8.0]),
    "ZI3": st.sampled_from([0.0, 0.5]), "W4": st.sampled_from([0.0, 6.0]),
    "ZI4": st.sampled_from([0.0, 0.4]), "TH2D": st.sampled_from([0.0, 50.0, -20.0]),
    "tex": st.sampled_from([0.0, 150.0]), "th2dd": st.sampled_from([0.0, -40.0]),
    "gravity": st.sampled_from([None, "down"]),
    "loads": st.sampled_from([(), (Load(3, r=2.0, fy=-30.0),)]),
    "branch": st.sampled_from(["open", "crossed"]),
})


@settings(max_examples=60, derandomize=True)
@given(zero_cases, st.lists(st.floats(2.0, 20.0), min_size=4, max_size=4))
def test_skipping_zero_steps_changes_nothing(case, r):
    """The plan skips a step whose zero_when inputs are all zero; a model that never
    skips must give the same answers (directions of zero vectors included)."""
    m = EXAMPLE.replace(W2=case["W2"], W3=case["W3"], ZI3=case["ZI3"], W4=case["W4"],
                        ZI4=case["ZI4"], TH2D=case["TH2D"], R1=r[0], R2=r[1], R3=r[2],
                        R4=r[3])
    sc = Scene(tex=case["tex"], th2dd=case["th2dd"], gravity=case["gravity"],
               loads=case["loads"], branch=case["branch"])
    never = FOURBAR.mapping(lambda st: st.fn, skip_zeros=False)
    skipped = [s for s in plan(OUTPUTS, m, scene=sc) if s.endswith("=0")]
    event(f"{min(len(skipped), 10) // 3 * 3}+ steps skipped")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AssemblyWarning)
        a = analyze(m, ANGLES, OUTPUTS, scene=sc)
        b = analyze(m, ANGLES, OUTPUTS, scene=sc, model=never)
    assert not any(s.endswith("=0") for s in plan(OUTPUTS, m, scene=sc, model=never))
    # at a toggle the computed rates are 0/0; a skipped step says 0 there (at rest, say)
    away = ~(np.abs(np.sin(np.radians(a["GAMMA"]))) < 1e-9)
    event("a toggle drawn" if not away.all() else "no toggle")
    for name in OUTPUTS:
        # a step computed where it is known zero gives zero up to roundoff of its scale
        x, y = a[name][away], b[name][away]
        scale = max(np.nanmax(np.abs(y), initial=0.0), 1.0) if y.dtype != bool else 0.0
        np.testing.assert_allclose(x, y, rtol=1e-12, atol=1e-12 * scale, err_msg=name)


def test_the_zero_cases_skip_what_they_claim():
    """The drawn cases above do reach the skipping: a massless coupler, no TEX, no effect."""
    m = EXAMPLE.replace(W3=0.0, ZI3=0.0)
    steps = plan(OUTPUTS, m)
    for name in ("_force_link3=0", "_statics_gravity_loads=0", "_statics_external_loads=0",
                 "_effects=0", "_angular_acc_crank=0"):
        assert name in steps, name
