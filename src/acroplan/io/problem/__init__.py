"""Problem files (TOML) and their validation.

A problem file describes a body and what to do with it. The body is a ``[robot]`` or a ``[body]``
table, read by the body family that claims it (:mod:`acroplan.core.family`: the two-link acrobot
of the text, planar and spatial bodies from a URDF file or link tables, human bodies from
anthropometric data); then a ``[plan]`` table (``acroplan plan``, ``acroplan reach``) and/or a
``[simulate]`` table (``acroplan simulate``). The modules: :mod:`~.model` (:class:`Problem`,
:class:`Simulation`), :mod:`~.reader` (the shared tables, the system table through the registry),
:mod:`~.options` (``[options]``), :mod:`~.files` (TOML on disk). The families' own tables are read
in their folders (``families/*/problem.py``).

The tables, as the bundled families read them::

    [robot]            # the acrobot: either the physical body ...
    torso_mass = 40.0          # M  (> 0)
    leg_mass = 20.0            # m  (> 0)
    torso_inertia = 2.5        # J  (> 0), about the torso's centre of mass
    leg_inertia = 1.2          # j  (> 0), about the leg's centre of mass
    torso_length = 0.35        # L  (>= 0), torso centre of mass to joint
    leg_length = 0.45          # l  (>= 0), leg centre of mass to joint
    angular_momentum = 10.0    # P0
    # ... or the lumped parameters M1, A1, M2, A2, P0 of text eq. (3)

    [plan]
    times = [0, 2]
    theta = ["-0.5*pi", "0.9*pi"]   # numbers, or strings of arithmetic with pi
    phi = ["-pi", "-2*pi"]
    conditions = "spline"           # or "free"

    [limits]           # optional
    phi_min = "-2*pi"               # joint limits on phi
    phi_max = "-pi"
    u_max = 20.0                    # |u| <= u_max (rad/s)

    [options]          # optional
    method = "auto"                 # or "deform" (the text's), "flat"
    basis = "legendre"              # or "monomial"
    n_coefficients = 6
    tol = 1e-10
    max_evaluations = 2000
    objective = "energy"            # or "torque": an optimal plan (least integral of u^2 or tau^2)
    tau_max = 50.0                  # |tau| <= 50 N m at every joint (needs the physical body) ...
    # [options.tau_max]             # ... or per joint (joints not named have no torque limit)
    # phi = 50.0                    # the acrobot's joint; a body's joints by name

With ``objective`` or ``tau_max`` and no ``plan.conditions``, the conditions are :func:`acroplan.plan`'s
default for optimal plans (``"free"``: the end inputs are left to the optimiser); otherwise
``"spline"`` as always. Torques (``objective = "torque"``, ``tau_max``) need a body with its masses
and inertias: the acrobot's physical keys, or any ``[body]``.

A planar body (:class:`~acroplan.families.planar.model.PlanarBody`; state :math:`(\\theta, q_1,
\\dots, q_{n-1})`, :math:`\\theta` the root link's angle, :math:`q_j` the joint angles named by
their joints; inputs :math:`u_j = \\dot q_j` named ``u_<joint>``; the angular momentum :math:`P_0`
about the axis normal to the plane is conserved)::

    [body]
    urdf = "diver.urdf"             # relative to the problem file (read by Pinocchio) ...
    angular_momentum = 36.0         # P0
    # ... or, instead of urdf, one [[body.link]] table per link:
    # [[body.link]]
    # name = "base"                 # the root: no parent
    # mass = 150.0
    # inertia = 25.0                # about the link's centre of mass
    # com = [0.0, 0.0]              # centre of mass in the link's own frame
    # [[body.link]]
    # name = "upper_arm"
    # parent = "base"
    # joint = [0.6, 0.0]            # its joint, in the parent's frame
    # joint_name = "shoulder"       # default: the link's name
    # mass = 12.0
    # inertia = 1.44
    # com = [0.6, 0.0]
    # lower = -2.6                  # optional joint limits (rad) and rate limit (rad/s)
    # upper = 2.6
    # velocity = 0.5

    [plan]
    times = [0.0, 1.5]
    theta = [0.0, 1.2]              # the root link's angle
    shoulder = [0.3, 0.3]           # one array per joint, named as in the URDF / link table
    conditions = "free"

    [limits]           # optional: overrides the URDF's / table's limits, joint by joint
    shoulder_min = -1.0             # joint limits; "none" drops the URDF's
    shoulder_max = 3.0
    u_shoulder = 5.0                # the joint's rate limit |u_shoulder| <= 5 rad/s
    u_max = 8.0                     # every joint's rate limit (a joint's own u_<joint> wins)

The file's ``[limits]`` are written into the body's link table, so the limits a plan honours are the
URDF's (or the table's) unless the file overrides them, and ``solution.json`` records them with the
body. The link table is always in radians; ``options.degrees = true`` applies to ``[plan]`` and
``[limits]``.

A human body (:mod:`acroplan.families.human`, docs/human.md) from Yeadon's measurements or from
height and mass, split at the hips (the two-link body: an :class:`Acrobot`, state ``theta``,
``phi``) or at the hips and shoulders (a :class:`PlanarBody`, joints ``hip`` and ``shoulder``)::

    [body]
    yeadon = "male1"                # a yeadon measurement file (relative to the problem file),
                                    # or a bundled sample by name; needs pip install "acroplan[human]"
    # height = 1.74                 # ... or, instead of yeadon, de Leva's (1996) tables:
    # mass = 70.0                   # stature (m) and mass (kg),
    # sex = "male"                  # "male" (default) or "female"
    split = "hips"                  # default; or "hips+shoulders"
    angular_momentum = 65.7         # P0 (kg m^2/s; > 0 for a forward somersault)
    position = "pike"               # optional: "pike", "tuck", "straight": the default [limits]
    # knee_flexion = 0.0            # rad; default the position's (a tuck's 125 degrees), else 0
    # shoulder_flexion = 0.0        # rad; split = "hips" only: the arms' fixed angle

``position`` gives the joint ranges and rates of :func:`~acroplan.families.human.limits.human_limits`
(``phi_min``, ``phi_max``, ``u_max`` for ``split = "hips"``; ``hip_min``, ..., ``u_shoulder`` in the
link table for ``"hips+shoulders"``); each key of the file's ``[limits]`` overrides one of them
(``"none"`` drops it). The body's angles are in radians whatever ``options.degrees`` says.

A simulation (``acroplan simulate``): the motion a given joint motion produces::

    [simulate]
    times = [0.0, 10.0, 20.0]
    theta = 0.0                     # the initial root angle
    shoulder = [0.0, 1.5, 0.0]      # a joint's angle at each time: a clamped cubic spline
                                    # through them (at rest at both ends, u continuous) ...
    elbow = 0.0                     # ... or its initial angle and
    u_elbow = [[0.0, 0.3], [0.0, -0.3]]   # its rate's Legendre coefficients per segment

Per joint either form; a joint given neither way is refused. The spline's rate is a quadratic per
segment, so its three Legendre coefficients are exact. For the acrobot the joint is ``phi`` and its
rate ``u``.

Files a problem file names (a URDF, a measurement file) are read from its folder only; a path that
leads out of it (``..``, an absolute path, a symbolic link) is refused unless a ``[files]`` table
allows its folder (or the command line's ``--allow-outside``, the readers' ``allowed=``)::

    [files]
    allow = ["../shared"]           # relative to the problem file's folder

Unknown tables and keys are rejected with the nearest known name, so a typo never passes silently;
every message names the file's field (``body.link[2].mass``, ``plan.shoulder``,
``limits.u_shoulder``, ``simulate.u_elbow[1]``) and the fix.
"""

from .files import load_problem, load_simulation, load_toml, with_options
from .model import Problem, Simulation
from .options import OBJECTIVES, OPTION_KEYS, OPTION_PARSERS, torque_joints
from .reader import TABLES, parse_body, parse_problem, parse_simulation, read_system

__all__ = ["Problem", "Simulation", "load_problem", "load_simulation", "parse_problem", "parse_simulation",
           "parse_body", "read_system", "system_to_dict", "with_options", "torque_joints", "load_toml",
           "OPTION_PARSERS", "OPTION_KEYS", "OBJECTIVES", "TABLES"]


def system_to_dict(system) -> dict:
    """The system's own record (:meth:`ControlAffineSystem.to_dict`)."""
    return system.to_dict()
