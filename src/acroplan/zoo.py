"""The model zoo's random problems, shared by tests, examples and benchmarks: each family's
generators, gathered (today the acrobot's: :func:`random_body`, :func:`random_segment`)."""

from .families.acrobot.zoo import SegmentProblem, random_body, random_segment

__all__ = ["SegmentProblem", "random_body", "random_segment"]
