"""Where the compiled kernels are kept between processes (``backend="numba"``).

The first call of a request compiles its kernel (seconds to tens of seconds).  To keep the
machine code for later processes the kernel's source is written, once, as a module named
by its hash (a temporary file renamed: whole or not at all) into ``$SIELAFF_KERNEL_DIR``,
else ``$XDG_CACHE_HOME/sielaff/kernels``, else ``~/.cache/sielaff/kernels``, and imported
from there, numba's own cache beside it (``__pycache__``).  The hash covers the kernel's
source, the text of every module of the engine (the steps it compiles) and the versions
of numba and numpy, so a changed step is a new module.  Nothing is written anywhere else
(not in the package, not in the working directory).  ``SIELAFF_KERNEL_DIR=off`` turns
the cache off; a folder that cannot be made or written (a read-only home) is no cache:
the kernel is then compiled in memory for this process alone, silently.  The folder only
grows by one small module per request shape; deleting it is always safe.
"""

from __future__ import annotations

import functools
import hashlib
import os
import sys
import threading
from collections.abc import Mapping
from pathlib import Path
from typing import Any

__all__ = ["KERNEL_DIR_ENV", "engine_hash", "kernel_dir"]

#: The environment variable naming where kernels are cached ("off": no cache).
KERNEL_DIR_ENV = "SIELAFF_KERNEL_DIR"


def kernel_dir() -> Path | None:
    """Where generated kernels are cached, or None for no cache (see the module's doc)."""
    root = os.environ.get(KERNEL_DIR_ENV, "")
    if root.strip().lower() == "off":
        return None
    if root:
        d = Path(root).expanduser()
    else:
        d = Path(os.environ.get("XDG_CACHE_HOME") or "~/.cache").expanduser() / "sielaff"
        d = d / "kernels"
    try:
        d.mkdir(parents=True, exist_ok=True)
    except (OSError, RuntimeError):  # RuntimeError: ~ with no home to expand
        return None
    return d if os.access(d, os.W_OK | os.X_OK) else None


@functools.cache
def engine_hash() -> str:
    """A hash of the engine's modules' text and of numba's and numpy's versions."""
    import numba
    import numpy

    h = hashlib.sha256(f"{numba.__version__} {numpy.__version__}".encode())
    for path in sorted(Path(__file__).parent.glob("*.py")):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def _cached_module(d: Path, name: str, text: str, inject: Mapping[str, Any] | None = None
                   ) -> Any:
    """The module ``text``, written to ``d / name.py`` once (atomically: a temporary file
    renamed) and imported from there with ``inject`` in its namespace first, so that
    numba's cache (``d/__pycache__``) keeps its machine code; OSError if ``d`` cannot be
    written or read."""
    import importlib.util

    path = d / f"{name}.py"
    if not path.exists():
        tmp = d / f".{name}.{os.getpid()}.{threading.get_ident()}.tmp"
        try:
            tmp.write_text(text)
            os.replace(tmp, path)
        finally:
            tmp.unlink(missing_ok=True)
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise OSError(f"cannot import {path}")
    module = importlib.util.module_from_spec(spec)
    module.__dict__.update(inject or {})
    sys.modules[name] = module  # numba's cache finds the kernel's globals by name
    try:
        spec.loader.exec_module(module)
    except BaseException:
        sys.modules.pop(name, None)
        raise
    return module
