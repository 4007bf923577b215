"""The effects that load the links know no linkage: gravity, external loads and springs
and dampers run unchanged on a second model (the crank alone, a pendulum about O2 held
by the drive), whose links and statics are its own (engine/links.py), and give what the
statics of one body says, computed here from vectors.

Pin friction and TEX are written for the four-bar's pins and rocker (docs/architecture.md
says so); the slider-crank and six-bar models bring their own.
"""

from __future__ import annotations

import numpy as np
import pytest

from sielaff import EXAMPLE, Damper, Load, Spring, analyze
from sielaff.engine.links import FRAME, FRAME_RATE, Link, LinkRate
from sielaff.engine.registry import Model, step, step_of
from sielaff.engine.scene import scene_type
from sielaff.mechanism import MASS_DIVISOR

TH = np.arange(0.0, 360.0, 5.0)


@step(provides=("c2", "s2", "cd2", "sd2"), needs=("ATH2", "ADEL2"))
def _crank(ATH2, ADEL2):
    a, g = np.radians(ATH2), np.radians(ATH2 + ADEL2)
    return np.cos(a), np.sin(a), np.cos(g), np.sin(g)


@step(provides=("links",), needs=("c2", "s2", "W2", "RG2", "cd2", "sd2"))
def _links(c2, s2, W2, RG2, cd2, sd2):
    return (FRAME, Link(c2, s2, 0.0, 0.0, W2, RG2, cd2, sd2))


@step(provides=("link_rates",), needs=("TH2D",))
def _rates(TH2D):
    return (FRAME_RATE, LinkRate(TH2D, 0.0, 0.0))


@step(provides=("FOAX", "FOAY", "TORQ"), needs=("foax_e", "foay_e", "torq_e"))
def _totals(foax_e, foay_e, torq_e):
    return foax_e, foay_e, torq_e


def _statics(loads):
    """The crank alone: the load F2 passes to the frame at O2, the drive holds M2."""
    (fx, fy, m), = loads  # one (fx, fy, m) per moving link: the crank's
    return fx, fy, -m


def _model() -> tuple[Model, type]:
    def seed(m, ath2, scene):
        return {"ATH2": np.atleast_1d(np.asarray(ath2, dtype=float)), "W2": m.W2,
                "RG2": m.RG2, "ADEL2": m.ADEL2, "TH2D": m.TH2D, "GW": MASS_DIVISOR[m.units]}

    model = Model("crank alone", seed=seed, results=("FOAX", "FOAY", "TORQ"),
                  sums={"foax": "foax_e", "foay": "foay_e", "torq": "torq_e"},
                  statics=(_statics, ()))
    model.add(step_of(_crank), step_of(_links), step_of(_rates), step_of(_totals))
    model.link_names = {1: "frame", 2: "crank"}
    for name in ("gravity", "loads", "elements"):  # the four-bar's own modules
        model.add_effect(name)
    return model, scene_type(model)


def test_the_second_model_has_the_effects_fields_and_only_those():
    model, scene = _model()
    assert [p.name for p in model.params] == ["gravity", "loads", "elements"]
    assert model.torque_parts == ("TORQ_GRAVITY", "TORQ_LOADS", "TORQ_ELEMENTS")
    with pytest.raises(TypeError):
        scene(friction=None)  # the crank alone has no pin friction field


def test_gravity_on_the_crank_alone():
    model, scene = _model()
    r = analyze(EXAMPLE, TH, ["FOAX", "FOAY", "TORQ", "TORQ_GRAVITY"], model=model,
                scene=scene(gravity="down"))
    w, rg = EXAMPLE.W2, EXAMPLE.RG2  # W2 a weight in lb: m g = W2
    g = np.radians(TH + EXAMPLE.ADEL2)
    np.testing.assert_allclose(r["TORQ"], w * rg * np.cos(g), rtol=0, atol=1e-12 * w * rg)
    np.testing.assert_array_equal(r["TORQ"], r["TORQ_GRAVITY"])
    np.testing.assert_allclose(r["FOAY"], -w, rtol=1e-15)
    np.testing.assert_array_equal(r["FOAX"], 0.0 * r["FOAX"])


def test_a_load_on_the_crank_alone():
    model, scene = _model()
    load = Load(2, 3.0, 20.0, 10.0, -4.0, 2.0)
    r = analyze(EXAMPLE, TH, ["FOAX", "FOAY", "TORQ"], model=model, scene=scene(loads=[load]))
    p = 3.0 * np.stack([np.cos(np.radians(TH + 20.0)), np.sin(np.radians(TH + 20.0))])
    moment = p[0] * -4.0 - p[1] * 10.0 + 2.0
    np.testing.assert_allclose(r["TORQ"], -moment, rtol=0, atol=1e-12 * 50.0)
    np.testing.assert_allclose(r["FOAX"], 10.0, rtol=1e-15)
    np.testing.assert_allclose(r["FOAY"], -4.0, rtol=1e-15)


def test_a_spring_and_a_damper_on_the_crank_alone():
    """The spring from (18, 0) on the frame to 4 in along the crank: tension k (L - L0)
    pulls the crank's point toward the frame's; the damper's c dL/dt likewise."""
    model, scene = _model()
    spring, damper = Spring((1, 18.0, 0.0), (2, 4.0, 0.0), 20.0, 8.0), \
        Damper((1, 18.0, 0.0), (2, 4.0, 0.0), 0.5)
    r = analyze(EXAMPLE, TH, ["TORQ", "TORQ_ELEMENTS", "SPRING1_F", "DAMPER1_F"], model=model,
                scene=scene(elements=[spring, damper]))
    a = np.array([18.0, 0.0])[:, None]
    c, s = np.cos(np.radians(TH)), np.sin(np.radians(TH))
    b = 4.0 * np.stack([c, s])
    vb = EXAMPLE.TH2D * 4.0 * np.stack([-s, c])
    d = b - a
    length = np.hypot(*d)
    u = d / length
    tension = 20.0 * (length - 8.0) + 0.5 * np.sum(u * vb, axis=0)
    force = -tension * u  # on the crank, at b
    torq = -(b[0] * force[1] - b[1] * force[0])
    scale = np.max(np.abs(torq))
    np.testing.assert_allclose(r["TORQ"], torq, rtol=0, atol=1e-12 * scale)
    np.testing.assert_array_equal(r["TORQ"], r["TORQ_ELEMENTS"])
    np.testing.assert_allclose(r["SPRING1_F"], 20.0 * (length - 8.0), rtol=1e-13)


def test_an_effect_off_costs_the_second_model_nothing():
    model, scene = _model()
    model.calls.clear()
    r = analyze(EXAMPLE, TH, ["TORQ"], model=model, scene=scene())
    np.testing.assert_array_equal(r["TORQ"], 0.0 * r["TORQ"])
    assert not {"_gravity", "_loads", "_elements"} & set(model.calls)
