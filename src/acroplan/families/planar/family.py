"""Planar bodies' registration as a family (:mod:`acroplan.core.family`): their ``[body]`` table
(link tables or a URDF), what ``acroplan reach`` proves, bundled examples, drawings."""

from __future__ import annotations

from ...core.family import Example, Family, hook

__all__ = ["FAMILY", "BODY_KEYS"]

#: the keys of [body] a planar body reads
BODY_KEYS = ("urdf", "link", "angular_momentum")
_PROBLEM = f"{__package__}.problem"


def _draw(folder, solution, gif, strobe_path, mp4, *, speed, fps, load):
    """A planar body's animation and strobe, from the exact result ``solution.json`` records."""
    from ...core.animation import samples_from_csv
    from .drawing import animate, strobe

    result = load()
    samples = samples_from_csv(folder / "trajectory.csv", result.system.state_names)  # (nothing to compile)
    n = animate(result, gif, speed=speed, fps=fps, mp4_path=mp4, samples=samples)
    fig = strobe(result, poses=9, samples=samples, title=f"{result.system.n_links} links: theta {result.waypoints[0][0]:.3g} -> "
                 f"{result.waypoints[-1][0]:.3g} rad in {result.times[-1] - result.times[0]:.3g} s")
    fig.savefig(strobe_path, dpi=120)
    return n


def _animate(result, path, **kw):
    from .drawing import animate

    return animate(result, path, **kw)


def _compile_seconds(body, n):
    from ..tree.compile_cost import compile_seconds

    return compile_seconds("planar", body, n)


def _example(name, description, command="plan", companions=()):
    return Example(__package__, f"data/{name}.toml", description, command, tuple(companions))


FAMILY = Family(
    name="planar",
    system_types=(f"{__package__}.model:PlanarBody",),
    setup=(f"{__package__}.registry",),  # the optimal strategies' starts
    priority=0,
    tables=("body",),
    reads=hook(f"{_PROBLEM}:reads"),
    limits_in_body=True,
    read=hook(f"{_PROBLEM}:read"),
    table_keys=BODY_KEYS,
    reach=hook(f"{_PROBLEM}:reach_report"),
    two_link=hook(f"{_PROBLEM}:two_link"),
    examples={
        "diver-somersault": _example("diver-somersault", "planar body (URDF): a diver with arms turns one somersault "
                                     "in pike with an arm sweep, P0 = 36, 4 segments, spline conditions",
                                     companions=("data/diver.urdf",)),
        "space-robot-turn": _example("space-robot-turn", "planar body (link tables): a space robot turns its base "
                                     "90 deg at zero momentum by arm loops, within its joint and rate limits"),
        "three-rods-turn": _example("three-rods-turn", "planar body (link tables): three equal rods at zero momentum "
                                    "turn 0.4 rad by one shape loop, |u| <= 2 rad/s"),
        "space-robot-arm-loop": _example("space-robot-arm-loop", "planar body: the turn of the space robot's base "
                                         "under a given arm loop (acroplan simulate)", "simulate"),
    },
    draw=_draw,
    animate=_animate,
    describe=lambda body: f"a planar body of {body.n_links} links",
    compile_seconds=_compile_seconds,
)
