"""The coach's question: how much angular momentum must a diver take off with to turn :math:`n`
somersaults in pike, tuck or straight position in a given flight time?

For the two-link body (split at the hips) the answer is exact, with no planning:
:func:`acroplan.families.acrobot.momentum.least_momentum` finds the least :math:`P_0` whose exact
reachable set (:mod:`acroplan.families.acrobot.reach`) reaches the turn, under the joint range and
rate limits. :func:`least_momentum_table` does it for each position, number of somersaults and
flight time:

* **The turn**: :math:`n` forward somersaults, :math:`\\Delta\\theta = 2\\pi n` (the human body's
  convention: :math:`\\theta` grows as the head goes forward), from take-off to entry.
* **Take-off and entry**: hip flexion 0 at both (straight at the hips), the hip rates free.
* **A position** (:func:`~acroplan.families.human.limits.position`) is the hip's range and rate
  limit and the knee angle the legs are held at:

  - *pike*: straight knees, hip flexion -30 to 150 degrees;
  - *tuck*: the legs one rigid part with the knees held at 125 degrees for the **whole flight**,
    hip flexion -30 to 140 degrees. This is how the two-link body approximates a tuck: a diver
    takes off and enters with straight knees and bends them in the air, and the two-link body
    cannot move its knees; here they are bent from take-off to entry, so the body is a little more
    compact at take-off and entry than a diver's (its moment of inertia straight at the hips with
    bent knees is smaller than with straight legs), and the least momentum is a little lower
    than a diver's. "Tuck-like", as the issue says;
  - *straight*: straight knees, hip flexion within 15 degrees of straight;

  all with the arms along the trunk (:math:`\\sigma = 0`) and the hip rate at most 12 rad/s.
* **The least momentum is attained** (rate limits make the reachable set closed) and only by the
  extremal motion: piking at the full rate, holding the deepest position, opening at the full
  rate. With the same hip angle at take-off and entry the far end of the reachable set is
  :math:`P_0 J_+(T)` with :math:`J_+ = \\sup \\int_0^T dt/h(\\varphi)`, so the least :math:`P_0` is
  :math:`2\\pi n / J_+(T)`: proportional to :math:`n`, and falling with :math:`T`.

Regenerate the table and figure of docs/human.md with::

    python -c "from acroplan.families.human.momentum import least_momentum_table as t; x = t(); print(x.to_markdown()); x.plot().savefig('docs/images/human-least-momentum.png', dpi=130)"
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Mapping

import numpy as np

from ...core.errors import InvalidInputError
from ..acrobot.model import Acrobot
from ..acrobot.momentum import SomersaultTable, somersault_table
from .body import SagittalBody
from .examples import THETA0, flight_time
from .limits import human_limits, position

__all__ = ["LeastMomentumTable", "least_momentum_table", "FLIGHT_TIMES", "SOMERSAULTS", "BOARDS"]

#: The default flight times (s): around a 3 m springboard's and a 10 m platform's (:data:`BOARDS`).
FLIGHT_TIMES = (1.2, 1.3, 1.4, 1.5, 1.6, 1.7, 1.8)

#: The default somersault counts.
SOMERSAULTS = (1.5, 2.5, 3.5, 4.5)

#: Flight times marked on the figure, by :func:`~acroplan.families.human.examples.flight_time`
#: with an assumed rise of the centre of mass: 3 m springboard, 1 m rise; 10 m platform, 0.2 m.
BOARDS = {"3 m board (1 m rise)": flight_time(3.0, 1.0), "10 m platform (0.2 m rise)": flight_time(10.0, 0.2)}


@dataclasses.dataclass(frozen=True)
class LeastMomentumTable:
    """The least angular momentum for each position, somersault count and flight time
    (:func:`least_momentum_table`).

    Attributes
    ----------
    positions : tuple of str
    somersaults : numpy.ndarray, shape (S,)
    flight_times : numpy.ndarray, shape (F,)
    P0 : numpy.ndarray, shape (len(positions), S, F)
        The least :math:`P_0` (kg m²/s; NaN where none works).
    bodies : dict of str to SagittalBody
        The body used for each position (its legs built with the position's knee angle).
    limits : dict of str to acroplan.Limits
        Each position's limits of the two-link body (``phi``, ``u_max``).
    messages : tuple
        ``least_momentum``'s message per entry, shape (positions, S, F).
    """

    positions: tuple
    somersaults: np.ndarray
    flight_times: np.ndarray
    P0: np.ndarray
    bodies: dict
    limits: dict
    messages: tuple

    def _index(self, name: str) -> int:
        if name not in self.positions:
            raise InvalidInputError("position", f"must be one of {list(self.positions)}, got {name!r}",
                                    "give a position the table was made for")
        return self.positions.index(name)

    def table(self, name: str) -> SomersaultTable:
        """One position's table, an :class:`acroplan.families.acrobot.momentum.SomersaultTable`."""
        i = self._index(name)
        return SomersaultTable(self.somersaults, self.flight_times, self.P0[i], self.messages[i])

    def least(self, name: str, somersaults: float, flight_time: float) -> float:
        """The entry for ``somersaults`` in ``flight_time`` (both must be in the table)."""
        i = self._index(name)
        js = np.flatnonzero(self.somersaults == somersaults)
        ks = np.flatnonzero(self.flight_times == flight_time)
        if js.size == 0 or ks.size == 0:
            raise InvalidInputError("somersaults", f"({somersaults!r}, {flight_time!r}) is not in the table",
                                    f"give one of {self.somersaults.tolist()} and one of {self.flight_times.tolist()}")
        return float(self.P0[i, js[0], ks[0]])

    def problem(self, name: str, somersaults: float, flight_time: float, factor: float = 1.0
                ) -> tuple[Acrobot, dict]:
        """The planning problem of one entry at ``factor`` times its least momentum:
        ``(robot, plan keywords)`` for :func:`acroplan.plan` (two waypoints, hip flexion 0 at
        take-off and entry, the hip rates free, the position's limits). Below ``factor = 1`` the
        planner refuses it as infeasible, with the exact reachable interval as the proof."""
        P = self.least(name, somersaults, flight_time)
        body = self.bodies[name]
        phi0 = float(body.phi(0.0))
        kw = dict(times=[0.0, float(flight_time)], theta=[THETA0, THETA0 + 2.0 * math.pi * float(somersaults)],
                  phi=[phi0, phi0], limits=self.limits[name], conditions="free")
        return body.two_link(angular_momentum=float(factor) * P), kw

    def to_markdown(self, digits: int = 1) -> str:
        """One table: a row per position and somersault count, a column per flight time."""
        head = "| position | somersaults | " + " | ".join(f"T = {t:g} s" for t in self.flight_times) + " |"
        rule = "|---|---|" + "---|" * len(self.flight_times)
        rows = [head, rule]
        for i, name in enumerate(self.positions):
            for n, row in zip(self.somersaults, self.P0[i]):
                rows.append(f"| {name} | {n:g} | " + " | ".join(
                    "impossible" if not math.isfinite(p) else f"{p:.{digits}f}" for p in row) + " |")
        return "\n".join(rows)

    def plot(self, *, boards: bool = True):
        """The figure: least :math:`P_0` against flight time, one line per somersault count, one panel
        per position (a common vertical scale), with the flights of :data:`BOARDS` marked."""
        return plot_least_momentum(self, boards=boards)


def _bodies(body, names) -> dict:
    out = {}
    for name in names:
        kappa = position(name).knee_flexion
        if body is None:
            from .yeadon_body import from_yeadon

            b = from_yeadon(knee_flexion=kappa)
        elif isinstance(body, SagittalBody):
            b = body
        elif isinstance(body, Mapping):
            if name not in body:
                raise InvalidInputError("body", f"has no body for the position {name!r}",
                                        "give a body per position, or a function of the knee flexion")
            b = body[name]
        elif callable(body) and not isinstance(body, (str, os.PathLike)):
            b = body(kappa)
        else:  # a yeadon.Human or a measurement file
            from .yeadon_body import from_yeadon

            b = from_yeadon(body, knee_flexion=kappa)
        if not isinstance(b, SagittalBody):
            raise InvalidInputError("body", f"gave a {type(b).__name__} for {name!r}, not a SagittalBody",
                                    "build bodies with from_yeadon() or from_height_mass()")
        out[name] = b
    return out


def least_momentum_table(body=None, positions=("pike", "tuck", "straight"), somersaults=SOMERSAULTS,
                         flight_times=FLIGHT_TIMES) -> LeastMomentumTable:
    """The least angular momentum for ``somersaults`` forward somersaults in each position and flight
    time, exact for the two-link body (module docstring).

    Parameters
    ----------
    body : optional
        ``None`` (default): Yeadon's model of the bundled ``male1``, built for each position with its
        knee angle (needs yeadon). A function of the knee flexion returning a
        :class:`~acroplan.families.human.body.SagittalBody` (``lambda k: from_height_mass(1.8, 75,
        knee_flexion=k)``); a dict of bodies by position; a ``yeadon.Human`` or a measurement file;
        or one ``SagittalBody`` (then every position must hold its knees at the body's angle: a
        straight-legged body serves pike and straight, not tuck).
    positions : sequence of {"pike", "tuck", "straight"}
    somersaults : sequence of float
        Positive.
    flight_times : sequence of float
        Seconds, positive.

    Returns
    -------
    LeastMomentumTable

    Examples
    --------
    >>> from acroplan.families.human import from_height_mass
    >>> t = least_momentum_table(lambda k: from_height_mass(1.75, 70.0, knee_flexion=k), somersaults=[2.5, 3.5],
    ...                          flight_times=[1.5, 1.7])
    >>> bool((t.P0[2] > t.P0[0]).all() and (t.P0[0] > t.P0[1]).all())   # straight > pike > tuck
    True
    """
    if isinstance(positions, str):
        positions = (positions,)
    names = tuple(position(p).name for p in positions)
    if not names or len(set(names)) != len(names):
        raise InvalidInputError("positions", f"must name distinct positions, got {positions!r}",
                                "give for example ('pike', 'tuck', 'straight')")
    S = np.atleast_1d(np.asarray(somersaults, dtype=float))
    F = np.atleast_1d(np.asarray(flight_times, dtype=float))
    if S.ndim != 1 or S.size == 0 or not (np.all(np.isfinite(S)) and np.all(S > 0)):
        raise InvalidInputError("somersaults", f"must be a list of positive numbers, got {somersaults!r}",
                                "give for example [1.5, 2.5, 3.5, 4.5]")
    if F.ndim != 1 or F.size == 0 or not (np.all(np.isfinite(F)) and np.all(F > 0)):
        raise InvalidInputError("flight_times", f"must be a list of positive times (s), got {flight_times!r}",
                                "give for example [1.3, 1.5, 1.7]")
    bodies = _bodies(body, names)
    limits = {name: human_limits(bodies[name], name, links=2) for name in names}
    # forward somersaults turn theta up in this family's convention: the table's "backward" sign
    tables = [somersault_table(bodies[name].two_link(angular_momentum=1.0), somersaults=S, flight_times=F,
                               phi0=float(bodies[name].phi(0.0)), phiT=float(bodies[name].phi(0.0)),
                               limits=limits[name], backward=True) for name in names]
    return LeastMomentumTable(names, S, F, np.stack([t.P0 for t in tables]), bodies, limits,
                              tuple(t.messages for t in tables))


def plot_least_momentum(table: LeastMomentumTable, *, boards: bool = True):
    """Least :math:`P_0` against flight time, one line per somersault count, one panel per position."""
    import matplotlib.pyplot as plt  # plotting apart from the numerics: imported here

    k = len(table.positions)
    fig, axes = plt.subplots(1, k, figsize=(3.4 * k + 0.6, 4.2), sharey=True, constrained_layout=True, squeeze=False)
    axes = axes[0]
    for ax, name in zip(axes, table.positions):
        i = table.positions.index(name)
        for j, n in enumerate(table.somersaults):
            ax.plot(table.flight_times, table.P0[i, j], marker="o", ms=3, color=f"C{j}", label=f"{n:g} somersaults")
        if boards:
            for m, (label, T) in enumerate(BOARDS.items()):
                if table.flight_times.min() <= T <= table.flight_times.max():
                    ax.axvline(T, color="0.5", ls=("--", ":")[m % 2], lw=1, label=f"{label}: {T:.2f} s")
        pos = position(name)
        lo, hi = (math.degrees(v) for v in pos.hip)
        knees = "straight knees" if pos.knee_flexion == 0 else f"knees held at {math.degrees(pos.knee_flexion):.0f}°"
        ax.set_title(f"{name}: hip flexion {lo:.0f}° to {hi:.0f}°, {knees}", fontsize=9)
        ax.set_xlabel("flight time T [s]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("least angular momentum P0 [kg m²/s]")
    axes[0].legend(fontsize=7)
    b = next(iter(table.bodies.values()))
    fig.suptitle(f"Least take-off angular momentum for n forward somersaults, two-link body of {b.mass:.1f} kg "
                 f"(exact), hip rate ≤ {table.limits[table.positions[0]].input_bound('u'):g} rad/s", fontsize=9)
    return fig
