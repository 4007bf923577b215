"""sielaff: Sielaff's 1966 crank-rocker program, emulated exactly, and a modern engine."""

from sielaff.mechanism import EXAMPLE, Mechanism

__all__ = ["EXAMPLE", "Mechanism"]
__version__ = "0.1.0"
