"""Small control-affine systems that show the core is general: :class:`Unicycle` (driftless, two
inputs) and :class:`ChainedForm` (the canonical nonholonomic normal form)."""

from .chained import ChainedForm
from .unicycle import Unicycle

__all__ = ["ChainedForm", "Unicycle"]
