"""Reachability and limits: the exact reachable interval, a rate-limited plan, and a refusal with proof.

Run:  python examples/limits_and_reach.py
"""

import numpy as np

import acroplan

robot = acroplan.Acrobot.from_physical(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2,
                                       torso_length=0.35, leg_length=0.45, angular_momentum=10.0)
segment = dict(theta0=0.0, phi0=-2.0, phiT=-0.5, T=1.5)
free = acroplan.reachable_set(robot, **segment).interval
limited = acroplan.reachable_set(robot, **segment, u_max=4.0).interval
print(f"reachable theta(T): {free} (open), with |u| <= 4: {limited} (closed)")

target = limited[0] + 0.7 * (limited[1] - limited[0])
r = acroplan.plan(robot, times=[0, 1.5], theta=[0.0, target], phi=[-2.0, -0.5], conditions="free", u_max=4.0)
print(r.message, "| max |u| =", max(s.max_abs_u for s in r.segments))
assert r.success and max(s.max_abs_u for s in r.segments) <= 4.0 + 1e-9

impossible = 0.5 * (limited[1] + free[1])  # reachable without the limit, not with it
r = acroplan.plan(robot, times=[0, 1.5], theta=[0.0, impossible], phi=[-2.0, -0.5], u_max=4.0)
print(r.status, "-", r.message)
assert r.status == "infeasible" and np.allclose(r.infeasible[0]["interval"], limited)
