"""What the random single-segment problems of tree bodies share (the families'
``zoo.random_body`` and ``zoo.random_segment``): the check of a random body's size, a segment's
random duration and joint rates, and the problem (:class:`TreeSegment`)."""

from __future__ import annotations

import dataclasses

import numpy as np

from ...core.errors import InvalidInputError

__all__ = ["link_count", "random_rates", "TreeSegment"]


def link_count(n_links) -> int:
    """``n_links`` of a random body, checked: a whole number >= 2."""
    if isinstance(n_links, bool) or not isinstance(n_links, (int, np.integer)) or n_links < 2:
        raise InvalidInputError("n_links", f"must be a whole number >= 2, got {n_links!r}", "give for example 3")
    return int(n_links)


def random_rates(rng, m: int) -> tuple[float, np.ndarray]:
    """A random segment's duration :math:`T \\in [1, 3]` s and joint rates: 6 Legendre coefficients
    per joint (shape (m, 6)), standard deviations 1, 1, 0.6, 0.3 rad/s for the first four, 0 after."""
    T = float(rng.uniform(1.0, 3.0))
    c = np.zeros((m, 6))
    c[:, :4] = rng.normal(scale=[1.0, 1.0, 0.6, 0.3], size=(m, 4))
    return T, c


@dataclasses.dataclass(frozen=True)
class TreeSegment:
    """One random single-segment problem of a tree body: the base of the families' problems.

    Attributes
    ----------
    body : ControlAffineSystem
        The family's body.
    T : float
    x0, x1 : numpy.ndarray, shape (n,)
        Start and target; ``x1`` is where ``coefficients`` take ``x0`` in time ``T``.
    coefficients : numpy.ndarray, shape (m, 6)
        The joint rates that reach ``x1`` (Legendre basis on ``s = t / T``): the proof of
        reachability.
    limits : Limits or None
        Joint and rate limits that motion keeps (``None``: unlimited).
    """

    body: object
    T: float
    x0: np.ndarray
    x1: np.ndarray
    coefficients: np.ndarray
    limits: object = None

    def plan_kwargs(self) -> dict:
        """Keywords of :func:`acroplan.plan` for this problem (``limits=Limits()`` when unlimited)."""
        from ...core.limits import Limits

        names = self.body.state_names
        kw = {name: [float(a), float(b)] for name, a, b in zip(names, self.x0, self.x1)}
        return dict(times=[0.0, self.T], limits=self.limits if self.limits is not None else Limits(), **kw)
