"""Problem-file texts shared by the tests (one copy of the standard physical body)."""

#: the physical acrobot of the tests' problem files (M = 40, m = 20, J = 1.8, j = 1.2, L = 0.35,
#: l = 0.45, P0 = 10): it has torques
ROBOT = """
[robot]
torso_mass = 40.0
leg_mass = 20.0
torso_inertia = 1.8
leg_inertia = 1.2
torso_length = 0.35
leg_length = 0.45
angular_momentum = 10.0
"""


def problem(theta="1.0", phi='"-pi/2"', conditions=None) -> str:
    """``ROBOT`` and a one-segment ``[plan]`` over [0, 1] from (0, -pi) to (theta, phi)."""
    text = ROBOT + f'\n[plan]\ntimes = [0, 1]\ntheta = [0, {theta}]\nphi = ["-pi", {phi}]\n'
    return text + (f'conditions = "{conditions}"\n' if conditions else "")
