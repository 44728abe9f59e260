"""The model zoo's random problems and bodies, shared by tests, examples and benchmarks: each family's
generators, gathered (the acrobot's :func:`random_body`, :func:`random_segment`; planar bodies:
:func:`three_rods`, :func:`diver_with_arms`, :func:`planar_space_robot`, :func:`random_planar_body`;
spatial bodies: :func:`falling_cat`, :func:`astronaut`, :func:`twisting_diver`,
:func:`random_spatial_body`, :func:`random_spatial_segment`)."""

from .families.acrobot.zoo import SegmentProblem, random_body, random_segment
from .families.planar.zoo import diver_with_arms, planar_space_robot, three_rods
from .families.planar.zoo import random_body as random_planar_body
from .families.spatial.zoo import astronaut, falling_cat, twisting_diver
from .families.spatial.zoo import random_body as random_spatial_body
from .families.spatial.zoo import random_segment as random_spatial_segment

__all__ = ["SegmentProblem", "astronaut", "diver_with_arms", "falling_cat", "planar_space_robot", "random_body",
           "random_planar_body", "random_segment", "random_spatial_body", "random_spatial_segment", "three_rods",
           "twisting_diver"]
