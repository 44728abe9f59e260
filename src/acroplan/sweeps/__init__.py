"""Sweeps: one problem varied over a grid or a random sample of its fields, planned point by point.

A sweep is a definition (:class:`Sweep`, immutable, built by :func:`sweep`, ``acroplan.sweep``, or
read from a TOML file by :func:`acroplan.load_sweep`) and a store it is computed into
(:func:`acroplan.run_sweep`, a zarr store read back with xarray: :mod:`acroplan.io.sweeps`). This
package is the front door: it knows the definition, its points, what is computed at a point and
how a chunk of points is computed by a task on any executor; it writes no file and names no body
family (what a family offers sweeps is registered in :mod:`acroplan.core.sweep_hooks`).

One job per module:

* :mod:`~.vocabulary`: statuses (:class:`PointStatus`, :class:`SweepPoint`), message codes,
  the canonical JSON;
* :mod:`~.keywords`: the :func:`acroplan.plan` keywords, from its signature;
* :mod:`~.fields`: the fields (``robot.NAME``, ``plan.T``, ``theta[-1]``, ...) and their
  resolution;
* :mod:`~.axes`: grid axes and samples, described and generated on demand; the size limits;
* :mod:`~.base`: the base problem in canonical form;
* :mod:`~.definition`: :class:`Sweep` (layout, points, the problem of a point);
* :mod:`~.compute`, :mod:`~.metrics`: what a point records, a chunk's task;
* :mod:`~.front`: :func:`sweep`.

What a point records
--------------------
``status`` (:class:`PointStatus`: 0 success, 1 infeasible, 2 not converged or crashed, 3 invalid;
-1 not computed), ``message`` (a code: the CRC-32 of the message with its numbers replaced by
``#``; the store keeps the table), ``effort``, ``peak_rate``, ``peak_torque``, ``final_error``,
``verified_error``, ``evaluations``, ``segments``, ``seconds`` and each derived quantity asked
for. With ``plan=False`` only the derived quantities are computed, and ``status`` is theirs. Every
value but ``seconds`` depends only on the point: a sweep gives the same numbers, bit for bit, on
any executor, in any chunking of the work, and when resumed.
"""

from ..core.family import prepare_all
from ..core.sweep_hooks import DERIVED, register_derived, register_factory
from .axes import DEFAULT_CHUNK, MAX_CHUNK_SIZE, MAX_CHUNKS, MAX_POINTS
from .compute import run_chunk, warm_worker
from .definition import Sweep, from_definition
from .front import resolve_field, sweep
from .metrics import TORQUE_SAMPLES
from .vocabulary import (FORMAT, MISSING, STATUS_CODES, PointStatus, SweepPoint, canonical_json, message_code,
                         message_template)

__all__ = ["sweep", "Sweep", "SweepPoint", "PointStatus", "STATUS_CODES", "MISSING", "FORMAT", "DERIVED",
           "register_derived", "register_factory", "message_code", "message_template", "canonical_json",
           "resolve_field", "from_definition", "run_chunk", "warm_worker", "TORQUE_SAMPLES", "DEFAULT_CHUNK",
           "MAX_POINTS", "MAX_CHUNKS", "MAX_CHUNK_SIZE"]

prepare_all()  # what the families offer sweeps (derived quantities, factories) is registered
