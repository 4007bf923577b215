"""The full accuracy/cost study: regenerates docs/accuracy.md and docs/accuracy.png.

    python benchmarks/accuracy.py            # full (about a minute)
    python benchmarks/accuracy.py --quick    # what `sielaff bench --quick` runs
"""

import sys

from sielaff.tools.bench import main

if __name__ == "__main__":
    sys.exit(main())
