"""Output files that are written whole or not at all."""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
from collections.abc import Iterator
from typing import TextIO


@contextlib.contextmanager
def atomic_output(path: str | None, newline: str | None = None) -> Iterator[TextIO]:
    """Yield a stream for ``path`` (stdout if None or "-").

    A file is written to a temporary file in the same directory and renamed
    over ``path`` only when the block ends without an exception, so an
    existing file survives any failure, Ctrl-C included.
    """
    if path in (None, "-"):
        yield sys.stdout
        sys.stdout.flush()
        return
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(path)}.", suffix=".tmp", dir=directory)
    try:
        with os.fdopen(fd, "w", newline=newline, buffering=1 << 16) as stream:
            yield stream
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
