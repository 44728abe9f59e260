"""The acrobot's registration as a family (:mod:`acroplan.core.family`): its ``[robot]`` table,
reachable sets, bundled examples and drawings."""

from __future__ import annotations

from ...core.family import Example, Family, hook

__all__ = ["FAMILY", "PHYSICAL_KEYS", "LUMPED_KEYS", "ALIASES"]

#: the keys of [robot]: the physical body, or the lumped parameters of the text's eq. (3)
PHYSICAL_KEYS = ("torso_mass", "leg_mass", "torso_inertia", "leg_inertia", "torso_length", "leg_length",
                 "angular_momentum")
LUMPED_KEYS = ("M1", "A1", "M2", "A2", "P0")
#: the physical keys' clearer names (what they are: centre of mass to the joint)
ALIASES = {"torso_com_to_joint": "torso_length", "leg_com_to_joint": "leg_length"}
_PROBLEM = f"{__package__}.problem"


def _reach_figure(prob, rows):
    from .plots import plot_reach

    return plot_reach(prob)


def _draw(folder, solution, gif, strobe_path, mp4, *, speed, fps, load):
    """The animation and strobe of an acrobot's output folder, from its ``trajectory.csv`` (a plan's
    or a nilpotentization's: both write ``t, theta, phi, u``) and the body ``solution.json`` records."""
    import matplotlib.pyplot as plt
    import numpy as np

    from ...core.errors import InvalidInputError
    from .drawing import animate, geometry_of, strobe

    try:
        geom = geometry_of(solution["system"])
    except (KeyError, TypeError, ValueError) as e:
        raise InvalidInputError(str(folder / "solution.json"), f"is corrupt ({type(e).__name__}: {e})",
                                "plan again to rewrite it") from None
    try:
        data = np.loadtxt(folder / "trajectory.csv", delimiter=",", skiprows=1, ndmin=2)
        t, theta, phi, u = data[:, 0], data[:, 1], data[:, 2], data[:, 3]
    except (ValueError, IndexError) as e:
        raise InvalidInputError(str(folder / "trajectory.csv"), f"is corrupt ({e})", "plan again to rewrite it") \
            from None
    n = animate(t, theta, phi, u, geom, gif, speed=speed, fps=fps, mp4_path=mp4)
    fig = strobe(t, theta, phi, geom)
    try:
        fig.savefig(strobe_path, dpi=120)
    finally:
        plt.close(fig)
    return n


def _animate(result, path, **kw):
    from .drawing import animate_result

    return animate_result(result, path, **kw)


def _least_momentum(*args, **kwargs):
    from .momentum import least_momentum

    return least_momentum(*args, **kwargs)


def _somersault_table(*args, **kwargs):
    from .momentum import somersault_table

    return somersault_table(*args, **kwargs)


def _example(name, description, command="plan"):
    return Example(__package__, f"data/{name}.toml", description, command)


FAMILY = Family(
    name="acrobot",
    system_types=(f"{__package__}.model:Acrobot",),
    # the torque model and the optimal strategies' starts, the "flat" strategy, the sweep hooks
    setup=(f"{__package__}.effort", f"{__package__}.flat", f"{__package__}.sweeping"),
    tables=("robot",),
    reads=hook(f"{_PROBLEM}:reads"),
    read=hook(f"{_PROBLEM}:read"),
    table_keys=PHYSICAL_KEYS + LUMPED_KEYS + tuple(ALIASES),
    reach=hook(f"{_PROBLEM}:reach_report"),
    reach_figure=_reach_figure,
    two_link=hook(f"{_PROBLEM}:two_link"),
    least_momentum=_least_momentum,
    somersault_table=_somersault_table,
    examples={
        "pike-dive": _example("pike-dive", "Chapter 3: straight -> pike -> 3.5 somersaults -> straight, 5 segments, "
                                           "spline conditions"),
        "pike-dive-limited": _example("pike-dive-limited", "the pike dive with phi kept in [-2 pi, -pi] (never "
                                                           "folding past flat), free conditions"),
        "chapter4": _example("chapter4", "Chapter 4: nilpotentization from (pi/4, 0, 0) to (pi/4, 2, 1.4 pi), cubic "
                                         "v1, v2 (acroplan nilpotent)", "nilpotent"),
    },
    draw=_draw,
    animate=_animate,
    # the DOP853 re-simulation: 10 ms do not matter on the command line, and it is the check the
    # text's scheme is judged by
    cli_verify="ode",
    torque_hint=("needs the joint torque, and this [robot] is given by its lumped parameters M1, A1, M2, A2, P0, "
                 "which fix the motion but not the torque's scale", "give the physical body in [robot] (torso_mass, "
                 "leg_mass, torso_inertia, leg_inertia, torso_length, leg_length, angular_momentum)"),
    describe=lambda robot: "the two-link acrobot",
)
