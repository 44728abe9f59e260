"""The control-affine system interface.

A system is

.. math::  \\dot x = f(x; p) + \\sum_{j=1}^{m} g_j(x; p)\\, u_j ,

with state :math:`x \\in \\mathbb{R}^n`, inputs :math:`u \\in \\mathbb{R}^m` and constant
parameters :math:`p \\in \\mathbb{R}^{n_p}`. A concrete system writes its fields **once**, in
sympy (:meth:`ControlAffineSystem.symbolic_fields`); the compiled integrator (heyoka) and the
independent checking integrator (numpy through ``sympy.lambdify``) are both generated from that
one definition. Parameters are runtime values, so one compilation serves every instance of a
system class.

Contract for implementers
-------------------------
1. Subclass as a frozen dataclass whose fields are the parameters, in :attr:`param_names` order.
2. Set the class attributes :attr:`state_names`, :attr:`input_names`, :attr:`param_names`.
3. Implement :meth:`symbolic_fields`.
4. Optionally set :attr:`rate_inputs` (input name -> state name) for inputs that are the time
   derivative of a state, which enables spline-derived input conditions; and override
   :meth:`check_segment` with an exact feasibility test.
"""

from __future__ import annotations

import abc
import dataclasses
import functools
from typing import ClassVar

import numpy as np
import sympy as sp

__all__ = ["ControlAffineSystem", "Infeasibility"]


@dataclasses.dataclass(frozen=True)
class Infeasibility:
    """Proof that a segment cannot be done.

    Attributes
    ----------
    reason : str
        One sentence a user can read.
    field : str
        The state that cannot be reached (for example ``"theta"``).
    interval : tuple of float or None
        The reachable values of that state at the segment end (an open interval), or a single
        value ``(v, v)`` when only one value is reachable.
    """

    reason: str
    field: str
    interval: tuple[float, float] | None = None


class ControlAffineSystem(abc.ABC):
    """Abstract control-affine system :math:`\\dot x = f(x;p) + G(x;p)\\,u`.

    Shapes: ``f`` is ``(n,)``, ``G`` is ``(n, m)``.
    """

    state_names: ClassVar[tuple[str, ...]]
    input_names: ClassVar[tuple[str, ...]]
    param_names: ClassVar[tuple[str, ...]] = ()
    #: inputs that are the time derivative of a state: ``{"u": "phi"}`` means u = d(phi)/dt.
    rate_inputs: ClassVar[dict[str, str]] = {}

    # ------------------------------------------------------------------ symbolic definition
    @classmethod
    @abc.abstractmethod
    def symbolic_fields(cls, x: tuple[sp.Symbol, ...], p: tuple[sp.Symbol, ...]) -> tuple[sp.Matrix, sp.Matrix]:
        """Drift and input fields in sympy.

        Parameters
        ----------
        x : tuple of sympy.Symbol, length n
            State symbols, in :attr:`state_names` order.
        p : tuple of sympy.Symbol, length n_p
            Parameter symbols, in :attr:`param_names` order.

        Returns
        -------
        f : sympy.Matrix, shape (n, 1)
        G : sympy.Matrix, shape (n, m)
        """

    @classmethod
    def symbols(cls) -> tuple[tuple[sp.Symbol, ...], tuple[sp.Symbol, ...]]:
        """The state and parameter symbols used by :meth:`symbolic`."""
        x = tuple(sp.Symbol(name, real=True) for name in cls.state_names)
        p = tuple(sp.Symbol(name, real=True) for name in cls.param_names)
        return x, p

    @classmethod
    @functools.cache
    def symbolic(cls) -> tuple[sp.Matrix, sp.Matrix]:
        """``(f, G)`` in the symbols of :meth:`symbols`, cached per class."""
        x, p = cls.symbols()
        f, G = cls.symbolic_fields(x, p)
        f = sp.Matrix(f).reshape(len(cls.state_names), 1)
        G = sp.Matrix(G).reshape(len(cls.state_names), len(cls.input_names))
        return f, G

    @classmethod
    @functools.cache
    def _numeric(cls):
        x, p = cls.symbols()
        f, G = cls.symbolic()
        # lambdify the right-hand side x' = f + G u, with u as extra symbols
        u = tuple(sp.Symbol(f"_u{j}", real=True) for j in range(len(cls.input_names)))
        rhs = f + G * sp.Matrix(u)
        fn = sp.lambdify((x, u, p), list(rhs), modules="numpy")
        return fn

    # ------------------------------------------------------------------ numeric interface
    @property
    def n_states(self) -> int:
        return len(self.state_names)

    @property
    def n_inputs(self) -> int:
        return len(self.input_names)

    @property
    def params(self) -> np.ndarray:
        """Parameter values, shape ``(n_p,)``, in :attr:`param_names` order."""
        return np.array([float(getattr(self, name)) for name in self.param_names], dtype=float)

    def rhs(self, x, u) -> np.ndarray:
        """Right-hand side :math:`f(x) + G(x) u`.

        Parameters
        ----------
        x : array_like, shape (n,) or (n, N)
        u : array_like, shape (m,) or (m, N)

        Returns
        -------
        numpy.ndarray, shape (n,) or (n, N)
        """
        x = np.asarray(x, dtype=float)
        u = np.asarray(u, dtype=float)
        if x.ndim == 1:  # one state (the checking integrator's every call): plain floats, no broadcasting
            return np.array(self._numeric()(tuple(x.tolist()), tuple(u.reshape(-1).tolist()), self._param_tuple),
                            dtype=float)
        out = self._numeric()(tuple(x), tuple(u), self._param_tuple)
        shape = x.shape
        return np.array([np.broadcast_to(np.asarray(v, dtype=float), shape[1:]) for v in out])

    @functools.cached_property
    def _param_tuple(self) -> tuple:
        """:attr:`params` as a tuple of floats (the system is immutable: computed once)."""
        return tuple(float(getattr(self, name)) for name in self.param_names)

    def check_segment(self, x0: np.ndarray, x1: np.ndarray, duration: float, limits=None) -> Infeasibility | None:
        """Exact feasibility test of steering ``x0`` to ``x1`` in ``duration``.

        Returns ``None`` when the segment may be feasible (or no test is known), else an
        :class:`Infeasibility` that proves it is not. ``limits`` is an :class:`acroplan.Limits` or
        ``None``. The default knows no test.
        """
        return None

    def continuation_path(self, y0, x1, x0, duration):
        """The target path :math:`\\pi(\\tau)`, :math:`\\tau \\in [0, 1]`, from ``y0`` (the start input's
        endpoint) to ``x1``, for path deformation. Default: the straight segment.

        Returns
        -------
        callable
            ``pi(tau) -> numpy.ndarray, shape (n,)``.
        """
        y0 = np.asarray(y0, dtype=float)
        x1 = np.asarray(x1, dtype=float)
        return lambda tau: y0 + tau * (x1 - y0)

    def lumped(self) -> dict[str, float]:
        """Parameter values by name."""
        return {name: float(getattr(self, name)) for name in self.param_names}
