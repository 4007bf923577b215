"""``python -m sielaff``: the same as the ``sielaff`` command."""

from sielaff.cli import entry

entry()
