"""Render the public API's numpydoc docstrings into docs/api.md.

Run:  python docs/make_api.py          (tests/test_docs.py checks that docs/api.md is current)
"""

from __future__ import annotations

import importlib
import inspect
import sys
from pathlib import Path

import acroplan
from acroplan.core import lie, strategies
from acroplan.families.acrobot import nilpotent

SECTIONS = [
    ("Planning", acroplan, ["plan", "plan_many", "simulate", "warm_up", "PlanResult", "SegmentResult", "Samples",
                            "Status"]),
    ("Strategies", acroplan, ["Strategy", "register_strategy"]),
    ("Strategies", strategies, ["Interval", "IntervalOutcome", "Deform", "deform_attempt", "run_stages"]),
    ("Models", acroplan, ["ControlAffineSystem", "Acrobot", "PhysicalParameters", "Unicycle", "ChainedForm",
                          "Infeasibility"]),
    ("Planar bodies", acroplan, ["PlanarBody", "Link"]),
    ("Spatial bodies", importlib.import_module("acroplan.families.spatial"), ["SpatialBody", "SpatialLink",
                                                                           "attitude_states", "read_urdf",
                                                                           "read_biomod", "to_urdf",
                                                                           "SpatialTorque"]),
    ("Human bodies", importlib.import_module("acroplan.families.human"), ["SagittalBody", "from_yeadon",
                                                                       "from_height_mass", "human_limits",
                                                                       "position", "platform_dive_pike",
                                                                       "flight_time", "least_momentum_table",
                                                                       "spatial_from_yeadon",
                                                                       "spatial_from_height_mass",
                                                                       "spatial_joint_limits"]),
    ("Feasibility and limits", acroplan, ["Limits", "reachable_interval", "reachable_set", "Reach"]),
    ("Input bases", acroplan, ["InputBasis", "Legendre", "Monomial"]),
    ("Problems", acroplan, ["Problem", "load_problem", "load_result", "examples", "zoo"]),
    ("Chapter 4: nilpotentization", nilpotent, ["NilpotentProblem", "NilpotentResult", "SeriesResult", "FlatYResult",
                                                 "construction",
                                                 "endpoint_equations", "format_equations", "iterated_integrals",
                                                 "solve_nilpotent", "counterexample", "solve_flat_y",
                                                 "resimulate"]),
    ("Lie algebra tools", lie, ["bracket", "hall_basis", "hall_count", "evaluate", "derived_distributions",
                                "growth_vector", "larc", "is_nilpotent", "is_exact", "frobenius"]),
    ("Effort and optimal plans", acroplan, ["EnergyOptimal", "TorqueOptimal", "JointEffort",
                                            "register_torque_model"]),
    ("Least angular momentum", importlib.import_module("acroplan.families.acrobot.momentum"),
     ["least_momentum", "MomentumBound", "somersault_table", "SomersaultTable"]),
    ("Sweeps", importlib.import_module("acroplan.sweeps"), ["sweep", "Sweep", "SweepPoint", "PointStatus",
                                                          "register_factory", "register_derived", "from_definition"]),
    ("Sweeps", importlib.import_module("acroplan.families.acrobot.sweeping"), ["least_momentum"]),
    ("Sweeps", acroplan, ["run_sweep", "open_sweep", "load_sweep", "draw_map", "SweepSummary"]),
    ("Errors", acroplan, ["InvalidInputError"]),
]


def render() -> str:
    out = ["# API reference", "",
           "Generated from the docstrings by `python docs/make_api.py`; the mathematics is in each entry.", ""]
    last = None
    for title, module, names in SECTIONS:
        if title != last:
            out += [f"## {title}", ""]
            last = title
        for name in names:
            obj = getattr(module, name)
            qual = f"{module.__name__}.{name}"
            try:
                sig = str(inspect.signature(obj)) if callable(obj) and not inspect.ismodule(obj) else ""
            except (TypeError, ValueError):
                sig = ""
            out += [f"### `{qual}{sig}`", "", "```text", inspect.cleandoc(obj.__doc__ or "(no docstring)"), "```", ""]
    return "\n".join(out)


if __name__ == "__main__":
    path = Path(__file__).with_name("api.md")
    path.write_text(render(), encoding="utf-8")
    print(f"wrote {path}", file=sys.stderr)
