"""``python -m sielaff``: the same as the ``sielaff`` command."""

import sys

from sielaff.cli import main

sys.exit(main())
