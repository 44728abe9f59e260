"""Spatial bodies' registration as a family (:mod:`acroplan.core.family`): their ``[body]`` table
(``angular_momentum = [Lx, Ly, Lz]``), attitude waypoints, the bundled cat, drawings."""

from __future__ import annotations

from ...core.family import Example, Family, hook

__all__ = ["FAMILY", "BODY_KEYS", "ATTITUDE_KEYS", "QUATERNION_STATES"]

#: the keys of [body] a spatial body reads
BODY_KEYS = ("urdf", "link", "angular_momentum")
#: the attitude keys in [plan] (one attitude per waypoint) and [simulate] (the initial one), and
#: the form of :func:`~acroplan.families.spatial.rotations.as_quaternion` each names
#: (``attitude``: a quaternion [w, x, y, z] or an inline table of any form); ``attitude_seq``
#: names another Euler sequence than Yeadon's
ATTITUDE_KEYS = {"attitude": None, "attitude_euler_deg": "euler_deg", "attitude_euler": "euler",
                 "attitude_rotvec_deg": "rotvec_deg", "attitude_rotvec": "rotvec"}
#: the states the attitude keys give
QUATERNION_STATES = ("qw", "qx", "qy", "qz")
_PROBLEM = f"{__package__}.problem"


def _draw(folder, solution, gif, strobe_path, mp4, *, speed, fps, load):
    """A spatial body's animation and strobe (the links as shaded equivalent boxes, the root's axes,
    the angular momentum vector), from the exact result ``solution.json`` records."""
    from ...core.animation import samples_from_csv
    from .drawing import animate, save_strobe

    result = load()
    # drawn from the folder's samples: no integrator to compile (seconds for a body in 3-D)
    samples = samples_from_csv(folder / "trajectory.csv", result.system.state_names)
    n = animate(result, gif, speed=speed, fps=fps, mp4_path=mp4, samples=samples)
    save_strobe(result, strobe_path, poses=6, samples=samples)
    return n


def _compile_seconds(body, n):
    """What a spatial plan compiles: its topology's momentum maps (Gauss collocation, issue #22),
    none when both were compiled before (in this process or on this machine)."""
    from ...core import backend
    from ..tree.compile_cost import compile_seconds
    from .collocation import map_key

    if all(backend.compiled_before(map_key(body, light)) for light in (False, True)):
        return None
    return compile_seconds("spatial-map", body, n)


def _check_request(req):
    from .requests import check_request

    check_request(req)


def _animate(result, path, **kw):
    from .drawing import animate

    return animate(result, path, **kw)


def _view(result, path, **kw):
    from .view import figure, write_view

    return figure(result, **kw) if path is None else write_view(result, path, **kw)


FAMILY = Family(
    name="spatial",
    system_types=(f"{__package__}.model:SpatialBody",),
    setup=(f"{__package__}.registry",),  # the torque model
    priority=10,
    tables=("body",),
    reads=hook(f"{_PROBLEM}:reads"),
    limits_in_body=True,
    read=hook(f"{_PROBLEM}:read"),
    table_keys=BODY_KEYS,
    waypoints=hook(f"{_PROBLEM}:waypoints"),
    waypoint_keys=tuple(ATTITUDE_KEYS) + ("attitude_seq",),
    waypoint_states=QUATERNION_STATES,
    examples={
        "falling-cat": Example(__package__, "data/falling-cat.toml", "spatial body (link tables): Kane and Scher's "
                               "cat turns over, 180 deg about its long axis at zero angular momentum in 0.5 s, from a "
                               "shape back to the same shape, within its joint ranges"),
    },
    draw=_draw,
    animate=_animate,
    view=_view,
    describe=lambda body: f"a spatial body of {body.n_links} links",
    check_request=_check_request,
    compile_seconds=_compile_seconds,
    twist_potential=hook(f"{__package__}.potential:twist_potential"),
    twist_potential_figure=hook(f"{__package__}.potential:twist_potential_figure"),
    attitude_angles=hook(f"{__package__}.potential:attitude_angles"),
)
