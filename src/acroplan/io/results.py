"""Reading a result back: :func:`load_result` turns a ``solution.json`` into a
:class:`~acroplan.core.result.PlanResult` (evaluate, plot, to_pandas work on it as on a fresh one)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..core.basis import make_basis
from ..core.errors import InvalidInputError
from ..core.limits import Limits
from ..core.result import PlanResult, SegmentResult, Status
from ..core.system import ControlAffineSystem

__all__ = ["load_result", "result_from_dict"]


def load_result(path) -> PlanResult:
    """The :class:`PlanResult` a ``solution.json`` (written by ``acroplan plan`` or
    ``PlanResult.to_json``) records.

    The input of every segment is rebuilt from its ``basis_coefficients`` (exact); the continuation
    history is not stored and comes back empty. Files written before segments recorded their end
    states get them by integrating the chain from the first waypoint.

    Raises
    ------
    InvalidInputError
        When the file cannot be read or is not a plan result (naming the field).
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InvalidInputError(str(path), "no such file", "give the path of a solution.json") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise InvalidInputError(str(path), f"cannot be read as JSON ({type(e).__name__})",
                                "give a solution.json written by acroplan") from None
    return result_from_dict(data)


def result_from_dict(data: dict) -> PlanResult:
    """The inverse of :meth:`PlanResult.to_dict`."""
    try:
        system = ControlAffineSystem.from_dict(data["system"])
        names = system.state_names
        wp = data["waypoints"]
        times = np.asarray(wp["times"], dtype=float)
        X = np.stack([np.asarray(wp[n], dtype=float) for n in names], axis=1)
        family = data["basis"]["family"]
        lim = data.get("limits")
        limits = None if not lim else Limits({k: tuple(v) for k, v in lim.get("state_bounds", {}).items()},
                                             lim.get("input_bounds") or {}, u_max=lim.get("u_max"))
        segments = []
        x = X[0]
        for d in data["segments"]:
            c = np.array([d["basis_coefficients"][n] for n in system.input_names], dtype=float)
            basis = make_basis(family, c.shape[1])
            T = float(d["t1"]) - float(d["t0"])
            start = np.array([d["start"][n] for n in names]) if "start" in d else x
            if "target" in d:
                target = np.array([d["target"][n] for n in names])
            else:  # older files: the end state by the compiled integrator
                from ..core import backend

                target = backend.endpoint(system, basis, start, T, c)[0]
            num = lambda v: float("nan") if v is None else float(v)  # noqa: E731
            segments.append(SegmentResult(
                index=int(d["index"]), interval=int(d.get("interval", 0)), method=d.get("method", "deform"),
                t0=float(d["t0"]), t1=float(d["t1"]), coefficients=basis.to_power(c, T), basis_coefficients=c,
                start=start, target=target, final_error=num(d.get("final_error")),
                verified_error=None if d.get("verified_error") is None else float(d["verified_error"]),
                iterations=int(d.get("iterations", 0)), evaluations=int(d.get("evaluations", 0)),
                restarts=int(d.get("restarts", 0)), sigma_min=num(d.get("sigma_min")),
                success=bool(d.get("success", True)), message=str(d.get("message", "")), basis=basis,
                extremes=None if d.get("max_abs_u") is None else {
                    "max_abs_u": float(d["max_abs_u"]),
                    "state_ranges": {k: tuple(v) for k, v in (d.get("state_ranges") or {}).items()}},
                optimality=_optimality(d.get("optimality"), len(segments))))
            x = target
        return PlanResult(status=Status(data["status"]), message=data["message"], system=system, times=times,
                          waypoints=X, conditions=data.get("conditions", "free"),
                          basis=make_basis(family, int(data["basis"]["n_coefficients"])),
                          segments=tuple(segments), infeasible=tuple(data.get("infeasible", ())),
                          verified=bool(data.get("verified", False)), limits=limits,
                          verification=data.get("verification"), objective=_objective(data.get("objective")),
                          torque_limits=_torque_limits(data.get("torque_limits")),
                          warnings=_warnings(data.get("warnings")))
    except InvalidInputError:
        raise
    except (KeyError, TypeError, ValueError, IndexError) as e:
        raise InvalidInputError("solution.json", f"is not a plan result ({type(e).__name__}: {e})",
                                "give a solution.json written by acroplan plan") from None


def _warnings(value) -> tuple[str, ...]:
    """``warnings`` of a solution.json: a list of strings (absent in files written before them)."""
    if value is None:
        return ()
    if not isinstance(value, list) or not all(isinstance(w, str) for w in value):
        raise InvalidInputError("solution.json: warnings", f"must be a list of strings, got {type(value).__name__}",
                                "give a solution.json written by acroplan plan (or drop the key)")
    return tuple(value)


def _objective(value):
    """``objective``: ``None`` (a feasible plan), ``"energy"`` or ``"torque"``."""
    if value is None or value in ("energy", "torque"):
        return value
    raise InvalidInputError("solution.json: objective", f"must be null, \"energy\" or \"torque\", got {value!r}",
                            "give a solution.json written by acroplan plan")


def _torque_limits(value):
    """``torque_limits``: ``{joint: tau_max}`` or ``None``."""
    if value is None:
        return None
    if not isinstance(value, dict):
        raise InvalidInputError("solution.json: torque_limits", f"must be a table by joint, got {type(value).__name__}",
                                "give a solution.json written by acroplan plan")
    return {str(k): float(v) for k, v in value.items()}


def _optimality(value, index: int):
    """A segment's ``optimality`` diagnostics (plain JSON types, kept as they are) or ``None``."""
    if value is None or isinstance(value, dict):
        return None if value is None else dict(value)
    raise InvalidInputError(f"solution.json: segments[{index}].optimality",
                            f"must be a table, got {type(value).__name__}",
                            "give a solution.json written by acroplan plan")
