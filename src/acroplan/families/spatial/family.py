"""Spatial bodies' registration as a family (:mod:`acroplan.core.family`): their ``[body]`` table
(``angular_momentum = [Lx, Ly, Lz]``), attitude waypoints, the bundled cat, drawings."""

from __future__ import annotations

from ...core.family import Example, Family
from ..tree.compile_cost import compile_seconds
from . import problem
from .model import SpatialBody

__all__ = ["FAMILY"]


def _draw(folder, solution, gif, strobe_path, mp4, *, speed, fps, load):
    """A spatial body's animation and strobe (the links as shaded equivalent boxes, the root's axes,
    the angular momentum vector), from the exact result ``solution.json`` records."""
    from .drawing import animate, save_strobe

    result = load()
    n = animate(result, gif, speed=speed, fps=fps)
    save_strobe(result, strobe_path, poses=6)
    return n


def _check_request(req):
    from .requests import check_request

    check_request(req)


def _animate(result, path, **kw):
    from .drawing import animate

    return animate(result, path, **kw)


FAMILY = Family(
    name="spatial",
    system_types=(SpatialBody,),
    priority=10,
    tables=("body",),
    reads=problem.reads,
    limits_in_body=True,
    read=problem.read,
    table_keys=problem.BODY_KEYS,
    waypoints=problem.waypoints,
    waypoint_keys=tuple(problem.ATTITUDE_KEYS) + ("attitude_seq",),
    waypoint_states=problem.QUATERNION_STATES,
    examples={
        "falling-cat": Example(__package__, "data/falling-cat.toml", "spatial body (link tables): Kane and Scher's "
                               "cat turns over, 180 deg about its long axis at zero angular momentum in 0.5 s, from a "
                               "shape back to the same shape, within its joint ranges"),
    },
    draw=_draw,
    animate=_animate,
    describe=lambda body: f"a spatial body of {body.n_links} links",
    check_request=_check_request,
    compile_seconds=lambda body, n: compile_seconds("spatial", body, n),
)
