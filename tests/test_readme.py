"""The README's Python examples run as written, and say what they return.

Each ```python block runs in order in one namespace.  A line ``EXPR  # VALUE ...``
whose comment starts with a literal (``(5, 3, 360)``, ``0``, ``898.11...``) is
checked: ``str(EXPR)`` equals the literal, or starts with it where it ends in
``...``.
"""

from __future__ import annotations

import importlib.util
import re
import warnings

from conftest import ROOT

LITERAL = re.compile(r"^(\([^)]*\)|-?\d[\d.]*)")

#: What a block calls that needs an optional extra: (the call, the module it needs).  Such a
#: block is left out where the module is missing (the README's test command installs only
#: ``[test]``); CI installs the extras and runs it.
NEEDS = (("simulate(", "scipy"),)


def _missing(block: str) -> str | None:
    for call, module in NEEDS:
        if call in block and importlib.util.find_spec(module) is None:
            return module
    return None


def blocks() -> list[str]:
    text = (ROOT / "README.md").read_text()
    return re.findall(r"```python\n(.*?)```", text, re.S)


def test_readme_python_examples_run_and_say_true():
    assert len(blocks()) >= 2
    ns: dict = {}
    checked = 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the examples are clean: no warning either
        for block in blocks():
            if _missing(block):
                continue
            exec(compile(block, "README.md", "exec"), ns)
            for line in block.splitlines():
                code, sep, comment = line.partition("  # ")
                match = LITERAL.match(comment.strip())
                if not sep or not match or "=" in code.replace("==", ""):
                    continue
                value, claim = str(eval(code.strip(), ns)), match.group(1)
                if claim.endswith("..."):
                    assert value.startswith(claim[:-3]), (code, value, claim)
                else:
                    assert value == claim, (code, value, claim)
                checked += 1
    assert checked >= 3
