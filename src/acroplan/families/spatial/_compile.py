"""heyoka's compact mode for spatial bodies, until the core's back end has a switch for it.

The fields of a spatial body are a deep expression (products of rotations, an adjugate): heyoka's
default (full) mode unrolls every Taylor coefficient and had not compiled an early form of a 3-link
body's fields with their variational equations (4,889 nodes) after 15 minutes; compact mode takes
seconds. The core's :func:`acroplan.core.backend.compile_for` builds
under its build lock; this module wraps the back end's builder so that, for a system whose
``compact_mode`` attribute is true, ``taylor_adaptive`` gets ``compact_mode=True`` (a keyword the
core passes itself takes precedence). Other systems are built exactly as before.

Proposed core change (then this module is a no-op): in ``core/backend.py``'s ``_build``, pass
``compact_mode=bool(getattr(system, "compact_mode", False))`` to ``hy.taylor_adaptive``.
"""

from __future__ import annotations

import heyoka as hy

from ...core import backend

__all__ = ["install"]


class _CompactHeyoka:
    """heyoka's namespace, with ``taylor_adaptive`` defaulting to compact mode."""

    def __getattr__(self, name):
        return getattr(hy, name)

    @staticmethod
    def taylor_adaptive(*args, **kwargs):
        kwargs.setdefault("compact_mode", True)
        return hy.taylor_adaptive(*args, **kwargs)


def install() -> None:
    """Wrap :func:`acroplan.core.backend._build` once (idempotent)."""
    if getattr(backend._build, "_spatial_compact", False):
        return
    original = backend._build

    def _build(system, basis_cls, n):
        if not getattr(system, "compact_mode", False):
            return original(system, basis_cls, n)
        # compile_for holds the build lock: no other build sees the swapped namespace
        saved = backend.hy
        backend.hy = _CompactHeyoka()
        try:
            return original(system, basis_cls, n)
        finally:
            backend.hy = saved

    _build._spatial_compact = True
    backend._build = _build
