"""Draw docs/images/body-parameters.png: what the acrobot's parameters and angles mean.

Run:  python docs/make_body_figure.py
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # a script, not library code: it may choose its backend
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Arc, Circle  # noqa: E402


def main(path: Path) -> None:
    theta, phi = math.radians(-20), math.radians(-130)
    L, l = 0.35, 0.45
    joint = (0.0, 0.0)
    leg_dir = (math.cos(theta), math.sin(theta))
    torso_dir = (math.cos(theta + phi), math.sin(theta + phi))
    fig, ax = plt.subplots(figsize=(7.2, 4.6), constrained_layout=True)
    for d, length, c, lw, name in ((leg_dir, l, "C1", 6, "leg (mass m, inertia j)"),
                                   (torso_dir, L, "C0", 9, "torso (mass M, inertia J)")):
        end = (2 * length * d[0], 2 * length * d[1])
        ax.plot([0, end[0]], [0, end[1]], color=c, lw=lw, solid_capstyle="round", label=name)
        cm = (length * d[0], length * d[1])
        ax.plot(*cm, "o", ms=9, mfc="white", mec="k", zorder=5)
        ax.annotate("", xy=cm, xytext=joint, arrowprops=dict(arrowstyle="<->", color="k", lw=1.2,
                                                               shrinkA=0, shrinkB=5))
    ax.add_patch(Circle((2 * L * torso_dir[0] + 0.06 * torso_dir[0], 2 * L * torso_dir[1] + 0.06 * torso_dir[1]),
                        0.06, color="C0"))
    ax.plot(0, 0, "o", color="k", ms=8, zorder=6)
    ax.text(0.28, 0.1, "l = leg_com_to_joint\n(leg_length)", fontsize=9)
    ax.text(-0.78, 0.02, "L = torso_com_to_joint\n(torso_length)", fontsize=9)
    ax.text(0.03, 0.06, "joint (hip)", fontsize=9)
    ax.plot([0, 0.55], [0, 0], color="0.5", lw=1, ls="--")
    ax.add_patch(Arc((0, 0), 0.7, 0.7, theta1=math.degrees(theta), theta2=0, color="C1", lw=1.5))
    ax.text(0.37, -0.09, "θ: leg to the x axis", fontsize=9, color="C1")
    ax.add_patch(Arc((0, 0), 0.36, 0.36, theta1=math.degrees(theta + phi), theta2=math.degrees(theta),
                     color="C0", lw=1.5))
    ax.text(-0.05, -0.3, "φ: leg to torso\n(0 folded, ±π straight)", fontsize=9, color="C0")
    ax.text(-0.72, 0.33, "○ centres of mass\nL, l: centre of mass to the joint,\n"
            "not the segment's length\n(half of it for a uniform segment)", fontsize=9)
    ax.set_aspect("equal")
    ax.set_xlim(-0.8, 0.95)
    ax.set_ylim(-0.75, 0.55)
    ax.axis("off")
    ax.legend(loc="lower right", fontsize=9, frameon=False)
    ax.set_title("The acrobot's body parameters and angles (text Fig. 4)", fontsize=11)
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main(Path(__file__).with_name("images") / "body-parameters.png")
