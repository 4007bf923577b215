"""The package version (one place: the command's --version and sielaff.__version__)."""

__version__ = "0.1.0"
