"""The slider-crank model against what does not trust it: the closed form differentiated
by sympy, an independent Newton-Euler solve of its three bodies with every effect it
takes, the power balance, zero cycle work where nothing dissipates, pylinkage's RRP dyad
for the positions, and its one-line refusals of geometry that cannot close."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import slider_reference as ref
from sielaff import AssemblyWarning, Load, SliderCrank, SliderCrankScene, Spring, analyze
from sielaff.engine.slider_crank import SLIDER_CRANK, SLIDER_RESULTS
from sielaff.quantities import G, unit
from sielaff.slider_crank import SLIDER_EXAMPLE, full_turn_failure

TH = np.arange(0.0, 360.0, 15.0) + 7.0  # 24 angles, none on an axis

#: (offset, ADEL2, ADEL3): centred, offset (a desaxé engine), masses off their lines
GEOMETRIES = [(0.0, 0.0, 0.0), (0.6, 10.0, -5.0), (-1.1, -20.0, 12.0)]


def _m(offset, adel2, adel3):
    return SLIDER_EXAMPLE.replace(offset=offset, ADEL2=adel2, ADEL3=adel3, TH2D=90.0)


def _scale(*values):
    return max(float(np.max(np.abs(v))) for v in values)


@pytest.mark.parametrize("branch", ["open", "crossed"])
@pytest.mark.parametrize("th2dd", [0.0, 400.0])
@pytest.mark.parametrize("geo", GEOMETRIES)
def test_motion_is_the_closed_form_differentiated(geo, th2dd, branch):
    m = _m(*geo)
    r = analyze(m, TH, ["ATH3", "TH3D", "TH3DD", "XB", "VXB", "AXB", "AG3X", "AG3Y", "VG3X",
                        "AG2Y"], scene=SliderCrankScene(th2dd=th2dd, branch=branch))
    refs = [ref.motion(m, float(t), th2dd, branch) for t in TH]
    for name, key, order in (("XB", "XB", 0), ("VXB", "XB", 1), ("AXB", "XB", 2),
                             ("TH3D", "th3", 1), ("TH3DD", "th3", 2), ("VG3X", "G3x", 1),
                             ("AG3X", "G3x", 2), ("AG3Y", "G3y", 2), ("AG2Y", "G2y", 2)):
        want = np.array([k[key][order] for k in refs])
        np.testing.assert_allclose(r[name], want, rtol=0, atol=1e-12 * _scale(want), err_msg=name)
    th3 = np.degrees(np.array([k["th3"][0] for k in refs]))
    th3 = np.where(th3 <= -90.0, th3 + 360.0, th3)  # the listing's range (-90, 270]
    np.testing.assert_allclose(r["ATH3"], th3, rtol=0, atol=1e-11)
    # the branch is the side of B: right of A (open) or left
    ax = m.R2 * np.cos(np.radians(TH))
    assert np.all((r["XB"] > ax) == (branch == "open"))


def test_centred_slider_velocity_is_the_textbook_product():
    """For offset 0 the piston speed is -R2 w (sin th + R2 sin 2th / (2 sqrt(R3^2 - R2^2
    sin^2 th))), the derivative of XB = R2 cos th + sqrt(R3^2 - R2^2 sin^2 th)."""
    m = SLIDER_EXAMPLE
    r = analyze(m, TH, ["XB", "VXB"])
    th = np.radians(TH)
    root = np.sqrt(m.R3 ** 2 - (m.R2 * np.sin(th)) ** 2)
    np.testing.assert_allclose(r["XB"], m.R2 * np.cos(th) + root, rtol=1e-14)
    want = -m.R2 * m.TH2D * (np.sin(th) + m.R2 * np.sin(2 * th) / (2 * root))
    np.testing.assert_allclose(r["VXB"], want, rtol=0, atol=1e-12 * _scale(want))


def _full_scene(m, branch, th2dd, fex):
    rod_load = (3.0, 15.0, 40.0, -25.0, 30.0)  # r, angle, fx, fy, torque on the rod
    spring = (m.R2 + m.R3 + 4.0, m.offset + 3.0, 50.0, 2.0)  # frame point, k, free length
    scene = SliderCrankScene(
        branch=branch, th2dd=th2dd, gravity="down", fex=fex,
        loads=(Load(3, *rod_load),),
        elements=(Spring((1, math.hypot(spring[0], spring[1]),
                          math.degrees(math.atan2(spring[1], spring[0]))),
                         (4, 0.0, 0.0), spring[2], spring[3]),))
    return scene, rod_load, spring


@pytest.mark.parametrize("branch", ["open", "crossed"])
@pytest.mark.parametrize("geo", GEOMETRIES)
def test_forces_are_newton_eulers_with_every_effect(geo, branch):
    m = _m(*geo)
    th2dd, fex = -250.0, -180.0
    scene, rod_load, spring = _full_scene(m, branch, th2dd, fex)
    names = ("FOAX", "FOAY", "FA32X", "FA32Y", "FB34X", "FB34Y", "FN", "MN", "TORQ")
    r = analyze(m, TH, names + ("SHAKX", "SHAKY", "SHAKM", "XB"), scene=scene)
    refs = [ref.newton_euler(m, float(t), th2dd=th2dd, branch=branch, gravity=(0.0, -G),
                             fex=fex, rod_load=rod_load, spring=spring) for t in TH]
    scale = _scale(*(r[n] for n in names))
    for name in names:
        want = np.array([x[name] for x in refs])
        np.testing.assert_allclose(r[name], want, rtol=0, atol=1e-11 * scale, err_msg=name)
    # the frame's share: FOA at O2 and the slider's -FN on the guide
    np.testing.assert_allclose(r["SHAKY"], r["FOAY"] - r["FN"], rtol=0, atol=1e-12 * scale)
    np.testing.assert_array_equal(r["SHAKX"], r["FOAX"])


def test_a_slider_force_may_be_a_function_of_the_slider_position():
    m = _m(*GEOMETRIES[1])

    def gas(xb):
        return -2000.0 / (xb - 4.0)  # a pressure rising as the slider nears x = 4

    r = analyze(m, TH, ["FEX", "XB", "TORQ", "TORQ_FEX"], scene=SliderCrankScene(fex=gas))
    np.testing.assert_array_equal(r["FEX"], gas(r["XB"]))
    refs = [ref.newton_euler(m, float(t), fex=float(gas(x))) for t, x in zip(TH, r["XB"])]
    want = np.array([x["TORQ"] for x in refs])
    np.testing.assert_allclose(r["TORQ"], want, rtol=0, atol=1e-11 * _scale(want))


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_power_balance(branch):
    """Drive power + the applied forces' power = d(kinetic energy)/dt, at every position:
    the engine's TORQ against the reference's energy rate (gravity, FEX, the spring and
    the rod's load each doing work)."""
    m = _m(*GEOMETRIES[2])
    th2dd, fex = 300.0, 250.0
    scene, rod_load, spring = _full_scene(m, branch, th2dd, fex)
    r = analyze(m, TH, ["TORQ", "VXB", "XB", "VG2Y", "VG3Y", "TH3D", "SPRING1_F",
                        "SPRING1_LD", "ATH3", "VAX", "VAY"], scene=scene)
    radius, ang, lfx, lfy, lt = rod_load
    th3 = np.radians(r["ATH3"]) + math.radians(ang)
    vpx = r["VAX"] - r["TH3D"] * radius * np.sin(th3)  # the load's point on the rod
    vpy = r["VAY"] + r["TH3D"] * radius * np.cos(th3)
    power = (r["TORQ"] * m.TH2D + fex * r["VXB"]
             - G * (m.W2 / G * r["VG2Y"] + m.W3 / G * r["VG3Y"])  # weights along -y
             - r["SPRING1_F"] * r["SPRING1_LD"]  # the spring's tension does -T dL/dt
             + lfx * vpx + lfy * vpy + lt * r["TH3D"])
    want = np.array([ref.kinetic_energy_rate(m, float(t), th2dd, branch) for t in TH])
    np.testing.assert_allclose(power, want, rtol=0, atol=1e-10 * _scale(want))


def test_no_cycle_work_where_nothing_dissipates():
    """At constant speed under gravity and a spring the drive does no net work over a
    revolution (all of it conservative); 256 equal steps integrate a periodic smooth
    integrand to roundoff."""
    m = _m(*GEOMETRIES[1])
    scene, _, _ = _full_scene(m, "open", 0.0, 0.0)
    scene = scene.replace(loads=())
    th = np.arange(256) * (360.0 / 256)
    r = analyze(m, th, ["TORQ", "TORQ_INERTIA", "TORQ_GRAVITY", "TORQ_ELEMENTS"], scene=scene)
    for name in ("TORQ", "TORQ_INERTIA", "TORQ_GRAVITY", "TORQ_ELEMENTS"):
        work = float(np.mean(r[name])) * 2 * math.pi
        assert abs(work) < 1e-11 * _scale(r[name]) * 2 * math.pi, name
    parts = r["TORQ_INERTIA"] + r["TORQ_GRAVITY"] + r["TORQ_ELEMENTS"]
    np.testing.assert_allclose(parts, r["TORQ"], rtol=0, atol=1e-12 * _scale(r["TORQ"]))


def test_results_have_the_listing_names_and_units():
    r = analyze(SLIDER_EXAMPLE, TH)
    assert tuple(r) == SLIDER_RESULTS
    assert {"ATH3", "TH3D", "TH3DD", "FA32", "FOA", "TORQ", "SHAK", "SHAKX", "SHAKY", "XB",
            "VXB", "AXB", "FN", "FB34"} <= set(r)
    for name, u in (("XB", "in"), ("VXB", "in/sec"), ("AXB", "in/sec^2"), ("FN", "lb"),
                    ("MN", "in-lb"), ("FEX", "lb"), ("TORQ_FEX", "in-lb")):
        assert unit(name) == u
    assert unit("FN", "SI") == "N" and unit("XB", "SI") == "m"


def test_si_is_the_same_linkage_in_other_units():
    """The example in metres and kilograms (each report mass W / g converted exactly,
    1 lb-sec^2/in = 4.4482216152605 / 0.0254 kg): lengths scale by in -> m, forces by
    lb -> N and torques by in-lb -> N m."""
    inch, newton = 0.0254, 4.4482216152605
    kg = newton / inch  # per lb-sec^2/in
    m = SLIDER_EXAMPLE
    si = m.replace(units="SI", R2=m.R2 * inch, R3=m.R3 * inch, offset=m.offset * inch,
                   RG2=m.RG2 * inch, RG3=m.RG3 * inch, W2=m.W2 / G * kg, W3=m.W3 / G * kg,
                   W4=m.W4 / G * kg, ZI2=m.ZI2 * newton * inch, ZI3=m.ZI3 * newton * inch)
    names = ["XB", "AXB", "FN", "FOAX", "TORQ"]
    a, b = analyze(m, TH, names), analyze(si, TH, names)
    for name, k in (("XB", inch), ("AXB", inch), ("FN", newton), ("FOAX", newton),
                    ("TORQ", newton * inch)):
        np.testing.assert_allclose(b[name], a[name] * k, rtol=0,
                                   atol=1e-12 * _scale(a[name] * k), err_msg=name)


def test_where_the_rod_cannot_reach_the_results_are_nan_and_counted():
    m = SLIDER_EXAMPLE.replace(R3=2.5, offset=1.0)  # R3 < R2 + |offset|: the crank rocks
    assert "cannot turn a full revolution" in full_turn_failure(m)
    th = np.arange(0.0, 360.0, 1.0)
    reach = np.abs(m.offset - m.R2 * np.sin(np.radians(th))) <= m.R3  # counted here
    with pytest.warns(AssemblyWarning, match=f"{int(np.sum(~reach))} of 360 positions"):
        r = analyze(m, th, ["XB", "TORQ", "ASSEMBLED", "FN"])
    assert r.not_assembled == int(np.sum(~reach)) > 0
    np.testing.assert_array_equal(r["ASSEMBLED"], reach)
    for name in ("XB", "TORQ", "FN"):
        assert np.all(np.isnan(r[name][~reach])) and np.all(np.isfinite(r[name][reach]))
    assert full_turn_failure(SLIDER_EXAMPLE) is None


@pytest.mark.parametrize("fields, words", [
    ({"offset": 10.5}, "offset = 10.5: |offset| > R2 + R3 = 10"),
    ({"R3": 0.0}, "SliderCrank.R3 = 0 in: the crank and the rod must have a length > 0"),
    ({"W4": -1.0}, "SliderCrank.W4 = -1 lb: weights"),
    ({"offset": np.array([0.0, -12.0])}, "offset = -12"),
    ({"TH2D": float("nan")}, "SliderCrank.TH2D = nan is not finite"),
])
def test_geometry_that_cannot_be_is_one_line(fields, words):
    with pytest.raises(ValueError) as info:
        analyze(SLIDER_EXAMPLE.replace(**fields), TH)
    message = str(info.value)
    assert words in message and "\n" not in message


def test_a_scene_of_the_other_linkage_is_refused_in_one_line():
    from sielaff import Scene

    with pytest.raises(ValueError, match="tex is not part of a slider-crank's scene"):
        analyze(SLIDER_EXAMPLE, TH, tex=5.0)
    with pytest.raises(ValueError, match="scene has no field fex"):
        analyze(SLIDER_EXAMPLE, TH, scene=Scene())


def test_only_the_steps_an_answer_needs_run():
    SLIDER_CRANK.calls.clear()
    analyze(SLIDER_EXAMPLE, TH, ["XB", "VXB"])
    ran = set(SLIDER_CRANK.calls)
    assert {"_positions", "_coordinates", "_velocities", "_slider_velocity"} <= ran
    assert not ran & {"_accelerations", "_inertia_loads", "_inertia_forces", "_totals"}
    SLIDER_CRANK.calls.clear()
    analyze(SLIDER_EXAMPLE, TH, ["TORQ"])
    assert "_inertia_forces" in SLIDER_CRANK.calls
    # effects that are off cost nothing
    assert not set(SLIDER_CRANK.calls) & {"_gravity", "_loads", "_slider_loads", "_elements"}


def test_a_sweep_broadcasts_over_designs():
    m = SLIDER_EXAMPLE.replace(R3=np.array([[6.0], [8.0], [10.0]]))
    r = analyze(m, TH, ["XB", "TORQ"])
    assert r["XB"].shape == (3, TH.size)
    for i, r3 in enumerate((6.0, 8.0, 10.0)):
        one = analyze(SLIDER_EXAMPLE.replace(R3=r3), TH, ["XB", "TORQ"])
        np.testing.assert_array_equal(r["XB"][i], one["XB"])
        np.testing.assert_allclose(r["TORQ"][i], one["TORQ"], rtol=1e-15, atol=1e-12)


def test_slider_positions_where_pylinkage_puts_them():
    """pylinkage's RRP dyad (a circle about A meets the slider's line), stepped from the
    engine's B at the first angle: every later B is pylinkage's own."""
    pl = pytest.importorskip("pylinkage")
    m = SLIDER_EXAMPLE.replace(offset=0.75)
    n = 120
    th = np.arange(n) * (360.0 / n)
    ours = analyze(m, th, ["XB"])["XB"]
    o2 = pl.Ground(0.0, 0.0)
    l1, l2 = pl.Ground(-5.0, m.offset), pl.Ground(20.0, m.offset)
    crank = pl.Crank(anchor=o2, radius=m.R2, angular_velocity=math.radians(360.0 / n),
                     initial_angle=0.0)
    slider = pl.RRPDyad(crank.output, l1, l2, distance=m.R3, x=float(ours[0]), y=m.offset)
    linkage = pl.Linkage([o2, l1, l2, crank, slider])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        theirs = np.array([p[-1] for p in linkage.step(iterations=n - 1)], dtype=float)
    np.testing.assert_allclose(theirs[:, 0], ours[1:], rtol=0, atol=1e-9)
    np.testing.assert_allclose(theirs[:, 1], m.offset, rtol=0, atol=1e-9)


def test_a_slider_crank_is_its_own_type():
    assert isinstance(SLIDER_EXAMPLE, SliderCrank)
    with pytest.raises(TypeError, match="SliderCrank has no field R4"):
        SLIDER_EXAMPLE.replace(R4=3.0)
