"""The :func:`acroplan.plan` keywords a sweep knows, read from plan()'s own signature (so the list
cannot drift from it), and the names of the special ``plan.*`` fields."""

from __future__ import annotations

import inspect
import re

from ..planning import plan as _plan

__all__ = ["PLAN_KEYWORDS", "PLAN_DEFAULTS", "PLAN_SPECIALS", "ALIASES", "INDEXED", "limit_keys", "option_keys"]

_SIGNATURE = inspect.signature(_plan)
#: plan()'s keywords a base problem or an ``options.*`` field may give (``progress`` is the sweep's).
PLAN_KEYWORDS = tuple(k for k in _SIGNATURE.parameters if k not in ("system", "progress", "waypoints"))
#: plan()'s defaults: left out of a definition, so that stating one hashes as leaving it out.
PLAN_DEFAULTS = {k: p.default for k, p in _SIGNATURE.parameters.items()
                 if p.default is not inspect.Parameter.empty and p.default is not None}
#: ``plan.*`` fields that are not a waypoint: the flight time, somersaults, the relative reach, conditions.
PLAN_SPECIALS = ("T", "somersaults", "reach", "conditions")
#: Two names of one body parameter: either is accepted for the other (``P0`` is the angular momentum).
ALIASES = {"angular_momentum": "P0", "P0": "angular_momentum"}
#: ``NAME[k]``: waypoint ``k`` of ``NAME``.
INDEXED = re.compile(r"^([A-Za-z_]\w*)\[(-?\d+)\]$")


def limit_keys(system) -> set[str]:
    """The ``limits.*`` fields of a system: ``u_max`` and ``NAME_min``/``NAME_max`` of each state whose
    rate is an input."""
    return {"u_max"} | {f"{s}_{e}" for s in system.rate_inputs.values() for e in ("min", "max")}


def option_keys(system) -> set[str]:
    """The ``options.*`` fields: plan()'s other keywords."""
    lim = limit_keys(system)
    return {k for k in PLAN_KEYWORDS if k not in ("times", "conditions", "limits", "state_bounds") and k not in lim}
