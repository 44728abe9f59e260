"""What a first compilation of a tree body's integrator costs, known in advance (issue #25): a lower
bound from measurements, so that a plan whose time limit cannot cover it is refused up front
(:attr:`Family.compile_seconds <acroplan.core.family.Family.compile_seconds>`,
:func:`acroplan.core.backend.compile_estimate`).

The measurements (``benchmarks/compile_time.py``, the table in ``benchmarks/RESULTS.md``): the
seconds of a first compilation (heyoka's on-disk cache off: the symbolic fields, heyoka's
decomposition and LLVM) with 6 coefficients per input, of chains and of stars (every link on the
root) of 2 to 10 planar links and 2 to 7 spatial links, on a 2-core machine shared with other work.
A planar body of ``n`` links costs about what the chain and the star of ``n`` links cost (the link
count drives it); a spatial chain costs more than the star (its symbolic fields grow with the
depth), so the star is the bound of any tree; more coefficients cost more.

The bound (:func:`lower_bound`): a quarter (:data:`SAFETY`) of the least time measured for ``n``
links or more, over the runs and the topologies (the measurements' lower monotone envelope), and
beyond the last measured count that time grown by :data:`GROWTH` per link, less than every
measured average growth. Below 6 coefficients nothing is claimed. A bound that errs is low, so a
refusal is sure; what it misses, the time limit catches while the compilation runs
(:func:`acroplan.core.budget.wait`).

Spatial bodies (since issue #22) are planned by Gauss collocation of the attitude
(``families/spatial/collocation.py``): what a spatial plan compiles is its topology's momentum maps
(two ``heyoka.cfunc``, whatever the number of coefficients), not a Taylor integrator, so their bound
is the ``"spatial-map"`` table (``benchmarks/compile_time.py --spatial-map``), counted in processor
seconds, which a busy machine does not inflate (the same compilation took 6 to 9 times its
processor seconds of wall time at a load average of 10-19 on 2 cores). The Taylor integrator of a
spatial body (the ``"spatial"`` tables) is compiled only for the joint torques' attitude at a
non-zero angular momentum (the effort summary, torque objectives and limits), within the time
limit but not claimed up front.
"""

from __future__ import annotations

__all__ = ["lower_bound", "compile_seconds", "MEASURED", "SAFETY", "GROWTH", "MEASURED_SIZE", "SIZE_FREE"]

#: The least first compilation measured (seconds, 6 coefficients per input), by body kind and
#: number of links, over the runs and topologies of benchmarks/RESULTS.md ("spatial": the symbolic
#: fields and heyoka; "spatial-heyoka": heyoka alone, when the fields are already built).
MEASURED = {
    "planar": {2: 1.06, 3: 2.69, 4: 5.23, 5: 12.5, 6: 17.6, 7: 55.5, 8: 106.8, 9: 93.2, 10: 637.0},
    "spatial": {2: 1.74, 3: 2.76, 4: 4.93, 5: 10.6, 6: 18.3, 7: 24.9},
    "spatial-heyoka": {2: 1.5, 3: 2.2, 4: 3.3, 5: 4.1, 6: 7.3, 7: 19.3},
    # processor seconds of compiling a topology's two momentum maps (the collocation's; symbolic map
    # excluded), the least of chains and stars (the stars': a chain costs more, x2.0-2.8 per link)
    "spatial-map": {2: 0.22, 3: 0.42, 4: 0.75, 5: 1.32, 6: 2.05, 7: 2.84, 8: 4.17, 9: 6.08, 10: 8.34},
}
#: Kinds whose compilation does not depend on the number of coefficients.
SIZE_FREE = frozenset({"spatial-map"})
#: The basis size the measurements were made at; fewer coefficients compile faster, more slower.
MEASURED_SIZE = 6
#: The share of a measured time the bound claims: the measurements were made with the machine's load
#: average from 1.6 to 12 on 2 cores, and the same compilation took from 65 s to 156 s (a 7-link
#: planar chain), so a quarter: an idle machine, or one four times as fast (of the spatial maps'
#: processor seconds: a machine whose compilation runs on four cores at once, or as fast).
SAFETY = 0.25
#: The growth per link beyond the last measured count, below every measured average growth per link
#: (planar chains 2.2 and stars 2.0; spatial chains 2.2 and stars 1.34). ``None``: in proportion
#: to the links (the spatial maps of stars grew x1.83 to x1.37 per link, falling: the maps' outputs
#: grow in proportion to the joints, so no faster growth is claimed).
GROWTH = {"planar": 1.5, "spatial": 1.25, "spatial-heyoka": 1.25, "spatial-map": None}


def lower_bound(kind: str, links: int, size: int) -> float | None:
    """A lower bound of the seconds a first compilation of a ``kind`` body (``"planar"``,
    ``"spatial"``, ``"spatial-heyoka"``: the Taylor integrator; ``"spatial-map"``: the momentum maps)
    of ``links`` links with ``size`` coefficients takes; ``None`` below :data:`MEASURED_SIZE`
    coefficients (but for the :data:`SIZE_FREE` kinds) or for a kind not measured."""
    table = MEASURED.get(kind)
    if table is None or (size < MEASURED_SIZE and kind not in SIZE_FREE) or links < min(table):
        return None
    last = max(table)
    if links <= last:
        return SAFETY * min(t for n, t in table.items() if n >= links)
    if GROWTH[kind] is None:
        return SAFETY * table[last] * links / last
    return SAFETY * table[last] * GROWTH[kind] ** (links - last)


def _growth_words(kind: str) -> str:
    table = MEASURED[kind]
    lo, hi = min(table), max(table)
    per_link = (table[hi] / table[lo]) ** (1.0 / (hi - lo))
    words = (f"measured from {table[lo]:.3g} s for {lo} links to {table[hi]:.3g} s for {hi} links, about "
             f"x{per_link:.2g} per link")
    if kind == "spatial-map":
        return ("its topology's compiled momentum maps, whatever the number of coefficients: processor time "
                + words)
    return words


def compile_seconds(kind: str, system, n: int):
    """``(lower bound in seconds, the measured growth in words)`` for ``system`` (a tree body of
    ``kind``) with ``n`` coefficients, or ``None`` (:func:`lower_bound`)."""
    if kind == "spatial" and system.symbolic_ready:
        kind = "spatial-heyoka"
    seconds = lower_bound(kind, system.n_links, n)
    if seconds is None:
        return None
    return seconds, _growth_words(kind)
