"""Inertia: D'Alembert's inertia forces ``-m aG`` of links 2-4 (at each G; m = W / GW, GW
being g = 386.088 in/sec^2 for the report's weights in lb, 1 for masses in kg in SI) and
inertia torques ``-ZI TH DD`` of links 3 and 4 (ZI about each G)."""

from __future__ import annotations

from sielaff.engine.registry import step


@step(provides=("FG2X", "FG2Y"), needs=("W2", "GW", "AG2X", "AG2Y"),
      zero_when=[("W2",), ("AG2X", "AG2Y")])
def _inertia_force2(W2, GW, AG2X, AG2Y):
    k = -W2 / GW
    return AG2X * k, AG2Y * k


@step(provides=("FG3X", "FG3Y"), needs=("W3", "GW", "AG3X", "AG3Y"),
      zero_when=[("W3",), ("AG3X", "AG3Y")])
def _inertia_force3(W3, GW, AG3X, AG3Y):
    k = -W3 / GW
    return AG3X * k, AG3Y * k


@step(provides=("TI3",), needs=("ZI3", "TH3DD"), zero_when=[("ZI3",), ("TH3DD",)])
def _inertia_torque3(ZI3, TH3DD):
    return TH3DD * -ZI3


@step(provides=("FG4X", "FG4Y"), needs=("W4", "GW", "AG4X", "AG4Y"),
      zero_when=[("W4",), ("AG4X", "AG4Y")])
def _inertia_force4(W4, GW, AG4X, AG4Y):
    k = -W4 / GW
    return AG4X * k, AG4Y * k


@step(provides=("TI4",), needs=("ZI4", "TH4DD"), zero_when=[("ZI4",), ("TH4DD",)])
def _inertia_torque4(ZI4, TH4DD):
    return TH4DD * -ZI4
