"""Chapter 3: plan the pike dive with the text's scheme, check it independently, save the figures.

Run:  python examples/pike_dive.py [OUT_DIR]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402

import acroplan  # noqa: E402
from acroplan.core.verify import simulate_segment  # noqa: E402

out = Path(sys.argv[1] if len(sys.argv) > 1 else "pike-dive-example")
out.mkdir(parents=True, exist_ok=True)

problem = acroplan.examples.load("pike-dive")  # the text's waypoints, 6 coefficients, spline conditions
result = problem.solve()
print(result.message)
assert result.success

# re-simulate the exported power-basis inputs ourselves, segment after segment
x = result.waypoints[0]
for seg in result.segments:
    x = simulate_segment(result.system, x, seg.t0, seg.t1, seg.coefficients).y[:, -1]
print("final state", x, "target", result.waypoints[-1], "error", np.max(np.abs(x - result.waypoints[-1])))

for name, fig in result.plot().items():
    fig.savefig(out / f"{name}.png", dpi=100)
print("figures in", out)
