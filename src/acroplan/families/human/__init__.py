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

from .body import Part, SagittalBody, combine
from .deleva import de_leva_table, from_height_mass
from .examples import PlatformDive, flight_time, platform_dive, platform_dive_pike
from .limits import (POSITIONS, Position, hip_rate_literature, hip_torque_literature, human_data, human_limits,
                     position)
from .momentum import LeastMomentumTable, least_momentum_table
from .spatial_body import spatial_from_height_mass, spatial_from_yeadon, spatial_joint_limits
from .yeadon_body import from_yeadon, load_human, sample_measurements

__all__ = ["Part", "SagittalBody", "combine", "from_yeadon", "load_human", "sample_measurements", "from_height_mass",
           "de_leva_table", "human_limits", "human_data", "hip_rate_literature", "hip_torque_literature", "Position",
           "POSITIONS", "position",
           "flight_time", "PlatformDive", "platform_dive", "platform_dive_pike", "LeastMomentumTable",
           "least_momentum_table", "spatial_from_yeadon", "spatial_from_height_mass", "spatial_joint_limits"]
