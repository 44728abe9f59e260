"""What planar bodies register in the core's registries: the optimal strategies' starts
(:func:`~acroplan.families.planar.effort.optimal_starts`). Imported by
:func:`acroplan.core.family.prepare` before a planar body is planned (the family's ``setup``), and by
the package on first use of its names."""

from ...core.optimal import register_starts
from .effort import optimal_starts
from .model import PlanarBody

register_starts(PlanarBody, optimal_starts)
