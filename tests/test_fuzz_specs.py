"""Fuzzing the TOML specs: mutated specs through ``punch``, ``table``, ``check`` and
``sweep`` (issue 21).

A mutated spec (a number swapped for an edge case: past a decimal's reach, 1E99, NaN,
a string, an array; lines dropped, duplicated, cut; characters flipped; tables inserted)
must give exit 0, or exit 2 (3: not a crank-rocker) and exactly one error line, within
:data:`SECONDS_PER_RUN`, never a traceback, never a Python or numpy warning; an existing
``-o`` file survives every failure.  A sweep whose grid is past :data:`RUN_DESIGNS` is
checked up to its refusal or its grid (``sweep_of``), not run: 10**8 designs are a legal
request that takes hours.

The CI profile draws 150 specs (``derandomize``: the same ones each run); with
``SIELAFF_NIGHTLY=1`` the "nightly" profile draws 3000 at random.  Each example runs
``sielaff.cli.main`` in-process; the process's peak memory is checked at the end.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import resource
import tempfile
import time

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from hypothesis.control import currently_in_test_context

from conftest import DECKS
from sielaff.cli import main

NIGHTLY = os.environ.get("SIELAFF_NIGHTLY") == "1"
settings.register_profile("specs-ci", max_examples=150, deadline=None, derandomize=True,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("specs-nightly", max_examples=3000, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
PROFILE = settings.get_profile("specs-nightly" if NIGHTLY else "specs-ci")

DIAGNOSTIC = ("sielaff: warning: ", "sielaff: 1966 quirk: ")
API_WORDS = ("Traceback", "encountered", "RuntimeWarning", "ASSEMBLED", "All-NaN")
SECONDS_PER_RUN = 60.0  # generous on a shared machine: most runs take well under a second
RUN_DESIGNS = 64
PEAK_RSS_KB = 3 << 20

EXAMPLE = (DECKS / "example.toml").read_text()
SCENE = (DECKS / "scene.toml").read_text()
SWEEP = (DECKS / "sweep.toml").read_text().split("[sweep.vary]")[0].replace(
    "angles = 360 ", "angles = 36  ") + (
    "[sweep.vary]\nR4 = { from = 10.0, to = 14.0, n = 3 }\nBALANCE = [0, 1]\n")

#: What a number may become: the edges of spec_number's bound and beyond, other types.
EDGES = ["0", "-0.0", "3", "-4.0", "0.5", "360.0", "9.9e98", "1e99", "-1e99", "1e-99",
         "1e-100", "1e999999999", "1e-999999999", "12.00000000000000000000000000001",
         "1" + "0" * 40, "inf", "-inf", "nan", "true", '"12"', "[1.0]", "{ a = 1 }",
         "0.3333333333", "123456.78", "1e300"]
NUMBER = re.compile(r"(?<=[=\[,] )-?[0-9][0-9.eE+-]*|(?<=\[)-?[0-9][0-9.eE+-]*")
INSERTS = ["[sweep]", "[[range]]\nstart = 0.0\nstep = 0.5\nstop = 1.0", "x = 1",
           '[scene]\ngravity = "down"', "[scene]\nunits = \"SI\"",
           '[[scene.load]]\nlink = "coupler"\nforce = [1e98, 0.0]', "[deck]\nsequence = 5",
           "[sweep.vary]\nTEX = [1e98]", "[sweep.vary]\nR1 = { from = 1, to = 2, n = 0 }",
           "a = [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]]]]]]"
           "]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]"]
ALPHABET = "0123456789 .-+eE=[]{}\",#\t\x00\xe9x"

number = st.tuples(st.just("number"), st.integers(0, 200), st.sampled_from(EDGES))
drop = st.tuples(st.just("drop"), st.integers(0, 200))
dup = st.tuples(st.just("dup"), st.integers(0, 200), st.integers(0, 200))
cut = st.tuples(st.just("cut"), st.integers(0, 200), st.integers(0, 60))
flip = st.tuples(st.just("flip"), st.integers(0, 200), st.integers(0, 60),
                 st.sampled_from(list(ALPHABET)))
insert = st.tuples(st.just("insert"), st.integers(0, 200), st.sampled_from(INSERTS))
mutation = st.one_of(number, number, number, drop, dup, cut, flip, insert)


def mutate(text: str, mutations) -> str:
    lines = text.split("\n")
    for op, *args in mutations:
        n = len(lines)
        if op == "number":
            joined = "\n".join(lines)
            found = list(NUMBER.finditer(joined))
            if found:
                m = found[args[0] % len(found)]
                joined = joined[:m.start()] + args[1] + joined[m.end():]
            lines = joined.split("\n")
        elif op == "insert":
            lines[args[0] % (n + 1):args[0] % (n + 1)] = args[1].split("\n")
        elif not lines:
            continue
        elif op == "drop":
            del lines[args[0] % n]
        elif op == "dup":
            lines.insert(args[1] % (n + 1), lines[args[0] % n])
        elif op == "cut":
            i = args[0] % n
            lines[i] = lines[i][:args[1]]
        elif op == "flip":
            i = args[0] % n
            line = lines[i].ljust(args[1] + 1)
            lines[i] = line[:args[1]] + args[2] + line[args[1] + 1:]
    return "\n".join(lines)


def _sweep_too_large(path: str) -> bool:
    """True if the spec's sweep is valid but too large to run here (see the module doc)."""
    from sielaff.tools.spec import PunchError, read_spec, sweep_of

    try:
        grid = sweep_of(read_spec(path), path)
    except PunchError:
        return False
    size = 1
    for values in grid["axes"].values():
        size *= len(values)
    return size > RUN_DESIGNS


def check_spec(text: str, command: str) -> None:
    with tempfile.TemporaryDirectory() as directory:
        path = os.path.join(directory, "spec.toml")
        with open(path, "w", encoding="utf-8", errors="surrogateescape") as f:
            f.write(text)
        out = os.path.join(directory, "old.out")
        with open(out, "w") as f:
            f.write("precious\n")
        argv = {"punch": ["punch", path, "-o", out],
                "table": ["table", path, "--only", "kinematics", "-o", out],
                "check": ["check", path],
                "sweep": ["sweep", path, "--workers", "1", "-o", out]}[command]
        if command == "sweep" and _sweep_too_large(path):
            if currently_in_test_context():
                event("sweep: valid, too large to run here")
            return
        stdout, stderr = io.StringIO(), io.StringIO()
        start = time.perf_counter()
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            status = main(argv)
        elapsed = time.perf_counter() - start
        with open(out) as f:
            kept = f.read() == "precious\n"
        left = [n for n in os.listdir(directory) if ".tmp" in n]
        with open(path, encoding="utf-8", errors="surrogateescape") as f:
            assert f.read() == text  # the input is never touched
    err = stderr.getvalue()
    assert elapsed < SECONDS_PER_RUN, (elapsed, text)
    assert not any(w in err for w in API_WORDS), err
    assert status in (0, 2, 3), (status, err)
    errors = [x for x in err.splitlines() if not x.startswith(DIAGNOSTIC)
              and not x.startswith("sielaff sweep: ")]
    assert len(errors) == (status != 0), err
    assert not left, left
    if status != 0 and command != "check":
        assert kept, err
    if currently_in_test_context():
        event(f"{command} exit {status}")


@settings(PROFILE)
@given(st.sampled_from([("example", EXAMPLE), ("scene", SCENE), ("sweep", SWEEP)]),
       st.sampled_from(["punch", "table", "check", "sweep"]),
       st.lists(mutation, min_size=1, max_size=4))
def test_mutated_specs_run_or_fail_in_one_line(base, command, mutations):
    name, text = base
    if command == "sweep" and name != "sweep":
        text = SWEEP
    check_spec(mutate(text, mutations), command)


@pytest.mark.parametrize("command", ["punch", "table", "check", "sweep"])
def test_unmutated_specs_run(command):
    base = SWEEP if command == "sweep" else EXAMPLE
    check_spec(base, command)


def test_mutations_reach_every_number():
    """The "number" mutation can reach each number of each base spec (so the fuzz draws
    the edges in every table: weights to sweep axes)."""
    for text in (EXAMPLE, SCENE, SWEEP):
        found = NUMBER.findall(text)
        assert len(found) >= 20
        for k in range(len(found)):
            assert mutate(text, [("number", k, "@")]).count("@") == 1
    reached = {mutate(SWEEP, [("number", k, "@")]).split("@")[0].rsplit("\n", 1)[-1]
               for k in range(len(NUMBER.findall(SWEEP)))}
    for where in ("frame = ", "R4 = { from = 10.0, to = 14.0, n = ", "BALANCE = [0, ",
                  "cf = ", "angles = ", "crank = { distance = 2.0, angle = "):
        assert where in reached, sorted(reached)


def test_memory_stayed_bounded():
    """After the fuzz above (same process), the peak resident set is bounded."""
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss < PEAK_RSS_KB


@pytest.mark.nightly
@pytest.mark.skipif(not NIGHTLY, reason="nightly budget: SIELAFF_NIGHTLY=1")
@settings(PROFILE)
@given(st.sampled_from(["punch", "table", "check", "sweep"]),
       st.lists(mutation, min_size=3, max_size=10))
def test_nightly_heavily_mutated_specs(command, mutations):
    check_spec(mutate(SWEEP if command == "sweep" else SCENE, mutations), command)
