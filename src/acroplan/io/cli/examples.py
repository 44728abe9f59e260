"""``acroplan examples`` and ``acroplan init``: the bundled problems, a starter file."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from ...core.errors import InvalidInputError
from .. import examples as _examples
from .common import fail


@click.command("examples")
@click.option("--show", metavar="NAME", help="Print the example's problem file.")
def examples_cmd(show):
    """List the bundled example problems, or print one's problem file.

    \b
    Examples:
      acroplan examples
      acroplan examples --show pike-dive > my-dive.toml
    """
    if show is not None:
        try:
            click.echo(_examples.text(show), nl=False)
        except InvalidInputError as e:
            fail(str(e))
        return
    for line in example_rows(_examples.names(), sys.stdout.isatty()):
        click.echo(line)


def example_rows(names: dict[str, str], styled: bool = False, width: int | None = None) -> list[str]:
    """The rows of ``acroplan examples``: each name in a column as wide as the longest, its
    description wrapped to the terminal's width (at least 60 columns) and indented under itself."""
    import shutil
    import textwrap

    width = width or max(60, min(shutil.get_terminal_size((100, 24)).columns, 120))
    pad = max(map(len, names), default=0) + 2
    rows = []
    for name, desc in names.items():
        lines = textwrap.wrap(desc, max(20, width - pad)) or [""]
        head = click.style(name, bold=True) if styled else name
        rows.append(head + " " * (pad - len(name)) + lines[0])
        rows.extend(" " * pad + more for more in lines[1:])
    return rows


STARTER = '''# acroplan problem file: plan a motion of the free-flying acrobot through waypoints.
# Run it with:  acroplan plan {name}.toml --out {name}-out --animate
# Reference: docs/problem-files.md. For a planar body of any number of links (a [body] table:
# a URDF file or link tables) start from an example: acroplan init NAME --example three-rods-turn

[robot]                        # the body (SI units, or any consistent set) ...
torso_mass = 40.0              # M  (> 0)
leg_mass = 20.0                # m  (> 0)
torso_inertia = 1.8            # J  (> 0), about the torso's centre of mass
leg_inertia = 1.2              # j  (> 0), about the leg's centre of mass
torso_length = 0.35            # L  (>= 0), torso centre of mass to the joint
leg_length = 0.45              # l  (>= 0), leg centre of mass to the joint
angular_momentum = 10.0        # P0, constant in flight
# ... or instead the lumped parameters of the text's eq. (3): M1, A1, M2, A2, P0 (M1 > |A1|)

[plan]
times = [0, 1]                 # waypoint times, strictly increasing
theta = [0, 1.0]               # leg angle at each time (numbers or text like "0.5*pi")
phi = ["-pi", "-pi/2"]         # joint angle: -pi straight, 0 folded
conditions = "free"            # "free" (u continuous) or "spline" (the text's scheme)

# [limits]                     # optional
# phi_min = "-pi"              # joint limits; waypoints must lie inside
# phi_max = 0.0
# u_max = 20.0                 # |u| <= u_max (rad/s)

# [options]                    # optional
# method = "auto"              # "auto", "deform" (the text's path deformation), "flat"
# basis = "legendre"           # or "monomial"
# n_coefficients = 6           # per segment (auto raises it when needed if left out)
# objective = "energy"         # an optimal plan: least integral of u^2 ("torque": of tau^2)
# tau_max = 31.0               # joint torque limit |tau| <= 31 N m (an energy-optimal plan)
'''


@click.command("init")
@click.argument("name")
@click.option("--example", metavar="EXAMPLE", help="Start from a bundled example (acroplan examples lists them).")
@click.option("--force", is_flag=True, help="Overwrite an existing file.")
def init_cmd(name, example, force):
    """Write a commented starter problem file NAME.toml (or a copy of a bundled example, with the
    files it names: the diver's URDF beside it). NAME may name a folder that does not exist yet
    (robots/dive): it is made.

    \b
    Examples:
      acroplan init my-dive && acroplan plan my-dive.toml --out my-dive-out
      acroplan init my-diver --example diver-somersault     # also writes diver.urdf
      acroplan init my-ch4 --example chapter4 && acroplan nilpotent my-ch4.toml --out ch4
    """
    path = Path(name if name.endswith(".toml") else f"{name}.toml")
    if path.exists() and not force:
        fail(f"{path}: exists; choose another name or add --force")
    try:
        text = STARTER.format(name=path.stem) if example is None else _examples.text(example)
        extra = {} if example is None else _examples.files(example)
        cmd = "plan" if example is None else _examples.command(example)
    except InvalidInputError as e:
        fail(str(e))
    for fname in extra:
        if (path.parent / fname).exists() and not force:
            fail(f"{path.parent / fname}: exists (the example's {fname}, which {path.name} names); choose another "
                  "folder or add --force")
    try:  # a folder that does not exist yet is made (acroplan init robots/dive)
        path.parent.mkdir(parents=True, exist_ok=True)
        for fname, body in extra.items():
            (path.parent / fname).write_text(body, encoding="utf-8")
        path.write_text(text, encoding="utf-8")
    except OSError as e:
        fail(f"{path}: cannot be written ({e.strerror or type(e).__name__}); choose another name or folder")
    also = "".join(f" and {path.parent / f}" for f in extra)
    click.echo(f"wrote {path}{also}; run: acroplan {cmd} {path} --out {path.stem}-out")
