"""Human bodies from anthropometric data, and what they can do (docs/human.md).

* :mod:`~.body`: :class:`SagittalBody`, a body in the sagittal plane in three rigid parts (trunk
  with head, arms, legs), its angle conventions, and the two- and three-part models
  (:meth:`SagittalBody.two_link`: an :class:`~acroplan.Acrobot`; :meth:`SagittalBody.three_part`:
  a :class:`~acroplan.PlanarBody`);
* :mod:`~.yeadon_body`: :func:`from_yeadon`, from Yeadon's 95 measurements through the optional
  ``yeadon`` package (``pip install acroplan[human]``; a measurement file of one man is bundled);
* :mod:`~.deleva`: :func:`from_height_mass`, from stature and mass by de Leva's (1996) tables;
* :mod:`~.limits`: joint ranges and rates with their sources, the diving positions,
  :func:`human_limits`;
* :mod:`~.examples`: :func:`platform_dive_pike`, the 10 m platform dive in pike;
* :mod:`~.momentum`: :func:`least_momentum_table`, the least angular momentum for n somersaults in
  pike, tuck or straight position in a given flight time (exact for the two-link body);
* :mod:`~.spatial_body`: the 3-D human, Yeadon's 11 segments as a
  :class:`~acroplan.families.spatial.model.SpatialBody` (:func:`spatial_from_yeadon`,
  :func:`spatial_from_height_mass`), its joint presets, held postures, and 3-D joint ranges and
  rates as data (:func:`spatial_joint_limits`, ``data/limits_3d.toml``).
"""

from __future__ import annotations

from ...core.family import lazy_package

#: The public names and their modules, loaded on first use (PEP 562): the family's descriptor
#: (``family.py``) is imported without the numerics; the first name used also imports what the
#: family registers (its ``setup``: strategies, torque models, ...).
_NAMES = {"Part": "body", "SagittalBody": "body", "combine": "body", "from_yeadon": "yeadon_body",
          "load_human": "yeadon_body", "sample_measurements": "yeadon_body", "from_height_mass": "deleva",
          "de_leva_table": "deleva", "human_limits": "limits", "human_data": "limits",
          "hip_rate_literature": "limits", "hip_torque_literature": "limits", "Position": "limits",
          "POSITIONS": "limits", "position": "limits", "flight_time": "examples", "PlatformDive": "examples",
          "platform_dive": "examples", "platform_dive_pike": "examples", "LeastMomentumTable": "momentum",
          "least_momentum_table": "momentum", "spatial_from_yeadon": "spatial_body",
          "spatial_from_height_mass": "spatial_body", "spatial_joint_limits": "spatial_body"}

__all__ = list(_NAMES)
__getattr__, __dir__ = lazy_package(__name__, _NAMES)
