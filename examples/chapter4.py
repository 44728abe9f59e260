"""Chapter 4: nilpotentization with time moving forward, and the text's failure mode.

Run:  python examples/chapter4.py
"""

import math

import acroplan
from acroplan.families.acrobot import nilpotent as nil

robot = acroplan.examples.robot("pike-dive")
problem = nil.NilpotentProblem(robot, P=(math.pi / 4, 0.0, 0.0), Q=(math.pi / 4, 2.0, 1.4 * math.pi), degree=3)
print(nil.format_equations(problem))

result = nil.solve_nilpotent(problem)
print(result.message)
assert result.success and result.margin > 0 and result.verified_error <= 1e-8

bad = nil.counterexample(problem, result.m)
print("same equations, but:", bad.message)
assert bad.margin < 0

flat = nil.solve_flat_y(problem)
print("flat output as the clock:", flat.message)
