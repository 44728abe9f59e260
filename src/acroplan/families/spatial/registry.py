"""What spatial bodies register in the core's registries: the torque model
(:class:`~acroplan.families.spatial.effort.SpatialTorque`). Imported by
:func:`acroplan.core.family.prepare` before a spatial body is planned (the family's ``setup``), and by
the package on first use of its names."""

from .effort import register

register()
