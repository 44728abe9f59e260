"""Body families on the generic core: each a folder, each registering its own strategies and its
exact feasibility test.

* :mod:`acroplan.families.acrobot`: the free-flying two-link body of the dissertation;
* :mod:`acroplan.families.planar`: free-flying planar bodies with any number of links (a tree of
  links and revolute joints), from a link table or a URDF, checked against Pinocchio;
* :mod:`acroplan.families.spatial`: free-floating bodies in 3-D (a tree of links and revolute
  joints of any axes), the attitude a unit quaternion, the angular momentum a vector, checked
  against Pinocchio;
* :mod:`acroplan.families.small`: small systems that show the core is general (unicycle,
  chained form).
"""
