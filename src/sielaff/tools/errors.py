"""The exit statuses every command shares, and the one-line failure that carries one
(``sielaff help exit`` lists them)."""

from __future__ import annotations

EXIT_DIFFERENT, EXIT_DECK, EXIT_NOT_CRANK_ROCKER, EXIT_INTERRUPTED = 1, 2, 3, 130


class CommandError(Exception):
    """A one-line failure with its exit status."""

    def __init__(self, message: str, status: int = EXIT_DECK) -> None:
        super().__init__(message)
        self.status = status
