"""The house: every import points down, no circles, no command imports another.

The package's modules and the imports they make (at any depth, in functions too) are
read with ``ast``; nothing is imported.  docs/architecture.md draws the same layers:

    cli                     parser and dispatch; imported by __main__ alone
    tools/                  commands (run, check, plot, punch, table, bench, helptext)
                            and what they share (common, errors, output, progress, spec)
    synthesis/              linkages from requirements (on design/ and the engine)
    dynamics/               the crank driven by a motor (on design/ and the engine)
    design/                 design answers on the engine
    engine/   emulator/     the modern engine; the 1966 machine (neither imports the other)
    quantities              names, units, meanings
    slider_crank, inverted_slider_crank, sixbar
                            the other kinds' fields and topologies (on linkage)
    linkage                 a crank and dyads: the topology and values of any linkage
    mechanism               the mechanism a deck describes
    version

The package root ``sielaff`` is the public facade: it may import anything below it, and
nothing inside the package imports it.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from conftest import ROOT

SRC = ROOT / "src"
SHARED_TOOLS = {"sielaff.tools.common", "sielaff.tools.output", "sielaff.tools.progress",
                "sielaff.tools.errors", "sielaff.tools.spec", "sielaff.tools.spec_fields",
                "sielaff.tools.spec_scene", "sielaff.tools.spec_sweep",
                "sielaff.tools.spec_tables", "sielaff.tools.kinds", "sielaff.tools.problems"}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


MODULES = {module_name(p): p for p in (SRC / "sielaff").rglob("*.py")}


def imports(name: str) -> set[str]:
    """The package modules ``name`` imports (a ``from pkg import mod`` counts the module)."""
    tree = ast.parse(MODULES[name].read_text())
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            targets = [f"{node.module}.{a.name}" if f"{node.module}.{a.name}" in MODULES
                       else node.module for a in node.names]
        else:
            continue
        found.update(t for t in targets if t == "sielaff" or t.startswith("sielaff."))
    return {t for t in found if t in MODULES and t != name}


GRAPH = {name: imports(name) for name in MODULES}


def layer(name: str) -> float:
    if name == "sielaff.__main__":
        return 7
    if name == "sielaff.cli":
        return 6
    if name == "sielaff.tools.report" or name.startswith("sielaff.tools.report."):
        return 5.5  # composes other commands' pages (check, plot, balance); none imports it
    if name.startswith("sielaff.tools."):
        return 5 if name not in SHARED_TOOLS else 4
    if name == "sielaff.tools":
        return 4
    if name == "sielaff.synthesis" or name.startswith("sielaff.synthesis."):
        return 3.75  # above design (it ranks on design's figures), below the tools
    if name == "sielaff.dynamics" or name.startswith("sielaff.dynamics."):
        return 3.6  # on design (the flywheel) and the engine, below synthesis and tools
    if name == "sielaff.design" or name.startswith("sielaff.design."):
        return 3.5  # above the engine, below the tools
    if name.startswith(("sielaff.engine", "sielaff.emulator")):
        return 3
    return {"sielaff.quantities": 2, "sielaff.slider_crank": 1.5,
            "sielaff.inverted_slider_crank": 1.5, "sielaff.sixbar": 1.5,
            "sielaff.linkage": 1.25, "sielaff.mechanism": 1, "sielaff.version": 0}[name]


def group(name: str) -> str:
    for g in ("sielaff.tools", "sielaff.engine", "sielaff.emulator", "sielaff.design",
              "sielaff.synthesis", "sielaff.dynamics"):
        if name == g or name.startswith(g + "."):
            return g
    return name


def command(name: str) -> str:
    """The command a tools module belongs to: sielaff.tools.bench.study -> bench."""
    return name.split(".")[2]


def test_the_walk_sees_the_package():
    assert {"sielaff.cli", "sielaff.engine.analysis", "sielaff.emulator.run",
            "sielaff.tools.common", "sielaff.emulator.arithmetic.ibm1410.number"} <= set(MODULES)
    assert "sielaff.engine.registry" in GRAPH["sielaff.engine.positions"]
    assert "sielaff.tools.bench.study" in GRAPH["sielaff.tools.bench"]
    assert "sielaff.synthesis.common" in GRAPH["sielaff.synthesis.motion"]


@pytest.mark.parametrize("name", sorted(n for n in MODULES if n != "sielaff"))
def test_imports_point_down(name):
    for target in GRAPH[name]:
        assert target != "sielaff", f"{name} imports the package root (the public facade)"
        if target == "sielaff.cli":
            assert name == "sielaff.__main__", f"{name} imports cli"
            continue
        if group(name) == group(target):
            if group(name) == "sielaff.tools" and layer(name) == layer(target) == 5:
                # commands never import each other (a command package imports its parts)
                assert command(name) == command(target), \
                    f"command {name} imports command {target}"
            else:
                assert layer(target) <= layer(name), f"{name} imports {target}"
            continue  # within one package: the circle test below
        assert layer(target) < layer(name), f"{name} (layer {layer(name)}) imports " \
                                            f"{target} (layer {layer(target)})"


def test_no_circles():
    state: dict[str, int] = {}

    def visit(node: str, path: list[str]) -> None:
        state[node] = 1
        for nxt in sorted(GRAPH[node]):
            if state.get(nxt) == 1:
                pytest.fail("import circle: " + " -> ".join(path[path.index(nxt):] + [nxt]))
            if nxt not in state:
                visit(nxt, path + [nxt])
        state[node] = 2

    for name in sorted(GRAPH):
        if name not in state:
            visit(name, [name])


def test_the_test_catches_a_command_importing_another(monkeypatch):
    monkeypatch.setitem(GRAPH, "sielaff.tools.plot",
                        GRAPH["sielaff.tools.plot"] | {"sielaff.tools.check"})
    with pytest.raises(AssertionError, match="command sielaff.tools.plot imports command"):
        test_imports_point_down("sielaff.tools.plot")
    monkeypatch.setitem(GRAPH, "sielaff.engine.derived",
                        GRAPH["sielaff.engine.derived"] | {"sielaff.emulator.cards"})
    with pytest.raises(AssertionError, match="imports sielaff.emulator.cards"):
        test_imports_point_down("sielaff.engine.derived")


def test_the_test_catches_a_circle_and_an_upward_import(monkeypatch):
    monkeypatch.setitem(GRAPH, "sielaff.mechanism", GRAPH["sielaff.mechanism"] | {"sielaff.cli"})
    with pytest.raises(AssertionError, match="imports cli"):
        test_imports_point_down("sielaff.mechanism")
    monkeypatch.setitem(GRAPH, "sielaff.mechanism", {"sielaff.quantities"})
    with pytest.raises(pytest.fail.Exception, match="import circle"):
        test_no_circles()


def test_modules_are_short_enough_to_hold():
    """No module over 700 lines: past that a module is split by what it does."""
    long = {name: n for name, path in MODULES.items()
            if (n := len(path.read_text().splitlines())) > 700}
    assert not long, long


def test_the_length_rule_catches_a_long_module(monkeypatch, tmp_path):
    long = tmp_path / "long.py"
    long.write_text('"""This module reads better whole."""\n' + "x = 1\n" * 700)
    monkeypatch.setitem(MODULES, "sielaff.long", long)
    with pytest.raises(AssertionError, match="sielaff.long"):
        test_modules_are_short_enough_to_hold()
