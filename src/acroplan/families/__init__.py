"""Body families on the generic core: each a folder, each registering its own strategies and its
exact feasibility test.

* :mod:`acroplan.families.acrobot`: the free-flying two-link body of the dissertation;
* :mod:`acroplan.families.small`: small systems that show the core is general (unicycle,
  chained form).
"""
