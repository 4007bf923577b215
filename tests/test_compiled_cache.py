"""The compiled backend's edges that need no kernel: the package without numba, and the
kernel cache's folder (engine/kernel_cache.py).

These run whether or not numba is installed: numba is hidden from a child process
(``sys.modules["numba"] = None``) to check that nothing but ``backend="numba"`` needs it,
and the cache's folder is only resolved, never compiled into.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from sielaff.engine import compiled
from sielaff.engine import kernel_cache as C

ROOT = Path(__file__).resolve().parent.parent

WITHOUT_NUMBA = r"""
import sys
sys.modules["numba"] = None  # as if not installed: `import numba` raises ImportError
import numpy as np
from sielaff import EXAMPLE, PinFriction, Scene, analyze
from sielaff.engine import compiled
assert not compiled.available()
r = analyze(EXAMPLE, np.linspace(0.0, 360.0, 7), ["TORQ"])  # the numpy engine
assert np.isfinite(r["TORQ"]).all()
try:
    analyze(EXAMPLE, [10.0], ["TORQ"], backend="numba")
except ImportError as e:
    print("IMPORT:", e)
try:
    analyze(EXAMPLE, [10.0], ["TORQ"], scene=Scene(friction=PinFriction(0.1, 0.2)),
            backend="numba")
except (ImportError, ValueError) as e:
    print(type(e).__name__ + ":", e)
print("numba imported:", "numba" in sys.modules and sys.modules["numba"] is not None)
"""


def _child(code: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    e = dict(os.environ)
    e["PYTHONPATH"] = str(ROOT / "src") + os.pathsep + e.get("PYTHONPATH", "")
    e.update(env or {})
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=e, timeout=300, cwd=ROOT)


def test_without_numba_the_backend_says_so_in_one_line():
    p = _child(WITHOUT_NUMBA)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert lines[0].startswith("IMPORT: backend='numba' needs numba") and "[fast]" in lines[0]
    # whether an effect compiles is numba's to say (it compiles the effect's own steps):
    # without numba every request says what it needs, and nothing else
    assert lines[1].startswith("ImportError: backend='numba' needs numba")
    assert lines[2] == "numba imported: False" and len(lines) == 3
    assert p.stderr == ""


def test_kernel_dir_by_environment(tmp_path, monkeypatch):
    monkeypatch.setenv(C.KERNEL_DIR_ENV, str(tmp_path / "k"))
    assert C.kernel_dir() == tmp_path / "k" and (tmp_path / "k").is_dir()
    monkeypatch.setenv(C.KERNEL_DIR_ENV, "off")
    assert C.kernel_dir() is None
    monkeypatch.delenv(C.KERNEL_DIR_ENV)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert C.kernel_dir() == tmp_path / "xdg" / "sielaff" / "kernels"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert C.kernel_dir() == tmp_path / "home" / ".cache" / "sielaff" / "kernels"


def test_a_cache_that_cannot_be_written_is_no_cache(tmp_path, monkeypatch):
    """A HOME (or folder) the process cannot write: no cache, and no error.  A path under
    a plain file cannot be made even by root, whom file modes do not stop."""
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    monkeypatch.delenv(C.KERNEL_DIR_ENV, raising=False)
    monkeypatch.delenv("XDG_CACHE_HOME", raising=False)
    monkeypatch.setenv("HOME", str(blocker / "home"))
    assert C.kernel_dir() is None
    monkeypatch.setenv(C.KERNEL_DIR_ENV, str(blocker / "kernels"))
    assert C.kernel_dir() is None
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a-file"]


def test_cached_module_written_whole_or_not_at_all(tmp_path):
    """The kernel's module is written to a temporary file and renamed: an unwritable
    folder raises OSError (the caller then compiles in memory) and leaves nothing."""
    d = tmp_path / "gone"
    with pytest.raises(OSError):
        C._cached_module(d, "sielaff_kernel_test", "kernel = 1\n")
    assert not d.exists()
    d.mkdir()
    m = C._cached_module(d, "sielaff_kernel_test_ok", "kernel = 2\n")
    # the module, whole, and no temporary file; Python's bytecode of it (where it writes
    # bytecode) goes to __pycache__, where numba's cache goes too
    assert m.kernel == 2 and sorted(p.name for p in d.iterdir() if p.name != "__pycache__") == [
        "sielaff_kernel_test_ok.py"]
    sys.modules.pop("sielaff_kernel_test_ok", None)


@pytest.mark.slow  # compiles a kernel in a fresh process (the default tier checks the
# same choice in process: test_a_cache_that_cannot_be_written_is_no_cache)
@pytest.mark.skipif(not compiled.available(), reason="numba is not installed (the fast extra)")
def test_the_backend_runs_with_a_home_it_cannot_write(tmp_path):
    """A read-only home (here: under a plain file) does not fail the backend: the kernel
    is compiled in memory, nothing is written, nothing is said on stderr."""
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    code = ("import numpy as np\nfrom sielaff import EXAMPLE, analyze\n"
            "r = analyze(EXAMPLE, np.linspace(0.0, 360.0, 9), ['ATH3'], backend='numba')\n"
            "ref = analyze(EXAMPLE, np.linspace(0.0, 360.0, 9), ['ATH3'])\n"
            "assert np.max(np.abs(r['ATH3'] - ref['ATH3'])) < 1e-10\nprint('ok')\n")
    env = {"HOME": str(blocker / "home"), "XDG_CACHE_HOME": "", C.KERNEL_DIR_ENV: "",
           "NUMBA_CACHE_DIR": ""}
    p = _child(code, env)
    assert p.returncode == 0 and p.stdout == "ok\n", p.stderr
    assert p.stderr == ""
    assert sorted(x.name for x in tmp_path.iterdir()) == ["a-file"]
