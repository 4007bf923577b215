"""Synthesis: from what a linkage must do to linkages that do it (docs/synthesis.md).

* :func:`crank_rocker`  crank-rockers for a rocker swing and a time ratio (the family,
  and the member with the best transmission angle)
* :func:`function`      Freudenstein's function generator (three precision points, or
  least squares over more), with its structural error
* :func:`motion`        two or three coupler poses, exactly, with branch and order checks
* :func:`path`          a coupler curve through N points by optimisation (scipy, an
  optional extra)
* :func:`masses`        the default mass model (uniform steel bars)
* :func:`rank`          candidates ranked by dynamics under a Scene, with a Pareto front

This layer imports ``design``, the engine, ``quantities`` and ``mechanism``
(docs/architecture.md).  Each method lives in its own module; this file only gathers
their names (add a module and its names here).
"""

from sielaff.synthesis.common import CouplerPoint, Placement, masses
from sielaff.synthesis.crank_rocker import CrankRocker, CrankRockerFamily, crank_rocker
from sielaff.synthesis.function import FunctionGenerator, function
from sielaff.synthesis.motion import CouplerLinkage, motion
from sielaff.synthesis.path import curve_distance, path
from sielaff.synthesis.rank import Ranking, pareto_front, rank

__all__ = ["CouplerLinkage", "CouplerPoint", "CrankRocker", "CrankRockerFamily",
           "FunctionGenerator", "Placement", "Ranking", "crank_rocker", "curve_distance",
           "function", "masses", "motion", "pareto_front", "path", "rank"]
