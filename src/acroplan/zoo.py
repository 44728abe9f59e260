"""The model zoo's random problems and bodies, shared by tests, examples and benchmarks: each family's
generators, gathered (the acrobot's :func:`random_body`, :func:`random_segment`; planar bodies:
:func:`three_rods`, :func:`diver_with_arms`, :func:`planar_space_robot`, :func:`random_planar_body`)."""

from .families.acrobot.zoo import SegmentProblem, random_body, random_segment
from .families.planar.zoo import diver_with_arms, planar_space_robot, three_rods
from .families.planar.zoo import random_body as random_planar_body

__all__ = ["SegmentProblem", "diver_with_arms", "planar_space_robot", "random_body", "random_planar_body",
           "random_segment", "three_rods"]
