"""The reproducers of issue #25 through the command line, for a before/after table: each case is a
problem (or sweep) file in a folder of its own, run by ``python -m acroplan`` in a fresh process
with the given source tree first on ``PYTHONPATH`` (``--src``: the sources of another commit, for
example ``git archive 639160b src | tar -x -C /tmp/old``), one JSON line per case: the exit code
(negative: killed by that signal; ``timeout``: still running at ``--timeout`` seconds), the seconds,
the number of lines on stderr, the first and the last.

    python benchmarks/reproduce_25.py                      # this checkout's sources
    python benchmarks/reproduce_25.py --src /tmp/old/src   # another commit's
    python benchmarks/reproduce_25.py --only chain mass    # the cases whose names hold a word

The files are written with this checkout's package (its URDF writers and the bundled cat), so the
same files go to both runs. Items 4, 6 and 7 (orphaned workers, corrupted stores, code named by a
store) need a store made first and are left to their tests (``tests/test_sweep_reliability.py``).
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import re
import resource
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).parents[1]

CAT_PLAN = """
[plan]
times = [0.0, 0.5]
attitude = [[0.0, 0.984807753012208, 0.0, 0.17364817766693036],
            [0.984807753012208, 0.0, 0.17364817766693036, 0.0]]
bend = ["40*(pi/180)", "40*(pi/180)"]
side = [0.0, 0.0]
twist = [0.0, 0.0]
conditions = "free"
"""
PLANAR = ('[body]\nurdf = "body.urdf"\nangular_momentum = 0.0\n[plan]\ntimes = [0.0, 3.0]\ntheta = [0.0, 0.4]\n'
          'q1 = [1.0, 1.0]\nq2 = [1.0, 1.0]\nconditions = "free"\n')
SPATIAL = '[body]\nurdf = "body.urdf"\nangular_momentum = [0.0, 0.0, 0.0]\n' + CAT_PLAN
YEADON = ('[body]\nyeadon = "me.txt"\nangular_momentum = 60.0\n[plan]\ntimes = [0, 1]\ntheta = [0, 1]\n'
          'phi = [-3, -3]\n')


def chain(n: int) -> str:
    inertial = '<inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.2"/></inertial>'
    links = [f'<link name="l{i}">{inertial}</link>' for i in range(n)]
    joints = [f'<joint name="j{i}" type="continuous"><parent link="l{i - 1}"/><child link="l{i}"/>'
              f'<origin xyz="1 0 0"/><axis xyz="0 0 1"/></joint>' for i in range(1, n)]
    return '<?xml version="1.0"?>\n<robot name="chain">\n' + "\n".join(links + joints) + "\n</robot>\n"


def write_cases(root: pathlib.Path) -> pathlib.Path:
    """The case folders under ``root/a/b`` (``root/a`` holds a file named by ``../..``)."""
    sys.path.insert(0, str(ROOT / "tests"))
    import texts

    from acroplan.families.human.yeadon_body import sample_measurements
    from acroplan.families.planar import three_rods
    from acroplan.families.planar import to_urdf as planar_urdf
    from acroplan.families.spatial.urdf import to_urdf as spatial_urdf
    from acroplan.families.spatial.zoo import falling_cat
    from acroplan.io import examples as bundled

    cases = root / "a" / "b"
    cases.mkdir(parents=True)
    (root / "a" / "secret.urdf").write_text('api_token = "not-a-urdf"\n')
    cat_urdf, rods_urdf = spatial_urdf(falling_cat()), planar_urdf(three_rods())
    cat_toml = re.sub(r"\ntime_limit = .*", "", bundled.text("falling-cat"))
    free_cat = re.sub(r"\n(start|end)_rate = .*", "", cat_toml)
    measurements = pathlib.Path(sample_measurements("male1")).read_text()
    sweep = texts.problem(theta="2.0", phi='"-pi"', conditions="free") + (
        '\n[sweep]\nplan = false\nderived = ["least_P0", "most_P0"]\nchunk_size = 5\n')

    def case(name, toml, cmd="plan", **files):
        d = cases / name
        d.mkdir()
        (d / "p.toml").write_text(toml)
        (d / "cmd").write_text(cmd)
        for k, v in files.items():
            (d / k.replace("_", ".")).write_text(v)

    def mass(urdf, old, value):
        return urdf.replace(f'<mass value="{old}"/>', f'<mass value="{value}"/>', 1)

    case("1-chain3831-planar", PLANAR, body_urdf=chain(3831))
    case("1-chain3831-spatial", SPATIAL, body_urdf=chain(3831))
    case("1-chain3831-sweep", PLANAR + "[sweep]\nchunk_size = 5\n[sweep.grid]\nT = [1.0, 2.0]\n", "sweep",
         body_urdf=chain(3831))
    case("2-yeadon-8.9MB", YEADON, me_txt=measurements + "\n# " + "x" * 8_900_000 + "\n")
    case("3-sweep-num-1e9", sweep + "\n[sweep.grid]\nT = {start = 1.0, stop = 2.0, num = 1000000000}\n", "sweep")
    case("3-sweep-sample-1e12", sweep + "\n[sweep.sample]\nn = 1000000000000\nT = [0.5, 2.0]\n", "sweep")
    for v in ("nan", "inf", "heavy"):
        case(f"5-spatial-mass-{v}", SPATIAL, body_urdf=mass(cat_urdf, 2, v))
    case("5-spatial-mass-0-inertia", SPATIAL, body_urdf=mass(cat_urdf, 2, 0))
    for name, path in (("etc-passwd", "/etc/passwd"), ("proc-environ", "/proc/self/environ"),
                       ("dotdot", "../../secret.urdf"), ("dotdot-missing", "../../nothing-here.urdf")):
        case(f"8-urdf-{name}", SPATIAL.replace('"body.urdf"', f'"{path}"'))
    case("8-yeadon-config-token", YEADON.replace("me.txt", "config.txt"),
         config_txt="# my settings\napi_token: SECRET-123\nuser = root\n")
    case("9-planar-mass-1e300", PLANAR, body_urdf=mass(rods_urdf, 1, "1e300"))
    case("9-spatial-mass-1e300", SPATIAL, body_urdf=mass(cat_urdf, 2, "1e300"))
    for L in ("1e3", "1e4", "1e6"):
        case(f"9-spatial-L-{L}", cat_toml.replace("angular_momentum = [0.0, 0.0, 0.0]",
                                                  f"angular_momentum = [{L}, 0.0, 0.0]"))
    for name, opt in (("energy", 'objective = "energy"'), ("tau_max", "tau_max = 50.0")):
        case(f"9-spatial-n3-{name}", free_cat.replace("[options]\n", f"[options]\nn_coefficients = 3\n{opt}\n"))
    case("9-urdf-x5000-planar", PLANAR.replace('"body.urdf"', '"' + "x" * 5000 + '"'))
    case("9-urdf-x5000-spatial", SPATIAL.replace('"body.urdf"', '"' + "x" * 5000 + '"'))
    case("9-sweep-derived-3.14", sweep.replace('derived = ["least_P0", "most_P0"]', "derived = -3.14")
         + "\n[sweep.grid]\nT = [0.5, 1.0]\n", "sweep")
    case("10-spatial-mass-1e-300", SPATIAL, body_urdf=mass(cat_urdf, 2, "1e-300"))
    case("10-urdfdom-noise", SPATIAL, body_urdf=cat_urdf.replace('type="revolute"', 'type="revolving"', 1))
    for v in ("nan", "0", "-70"):
        case(f"10-yeadon-totalmass-{v}", YEADON, me_txt=measurements + f"\ntotalmass: {v}\n")
    return cases


def run(src: str | None, cases: pathlib.Path, out: pathlib.Path, only, timeout: float):
    env = dict(os.environ, PYTHONWARNINGS="default")
    if src:
        env["PYTHONPATH"] = src
    for d in sorted(p for p in cases.iterdir() if p.is_dir()):
        if only and not any(o in d.name for o in only):
            continue
        cmd = (d / "cmd").read_text()
        dest = out / (d.name + (".zarr" if cmd == "sweep" else ""))
        extra = ["--force", "--no-plots", "--time-limit", "60"] if cmd == "plan" else []
        t = time.perf_counter()
        try:  # at most 8 GB of address space: a reproducer that allocates without bound fails, not the machine
            r = subprocess.run([sys.executable, "-m", "acroplan", cmd, str(d / "p.toml"), "--out", str(dest), *extra],
                               env=env, capture_output=True, text=True, timeout=timeout,
                               preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_AS, (8 << 30, 8 << 30)))
            code, err = r.returncode, r.stderr
        except subprocess.TimeoutExpired as e:
            code, err = "timeout", e.stderr.decode() if isinstance(e.stderr, bytes) else (e.stderr or "")
        lines = [ln for ln in err.strip().splitlines() if ln.strip()]
        print(json.dumps({"case": d.name, "exit": code, "s": round(time.perf_counter() - t, 1), "lines": len(lines),
                          "left": sorted(p.name for p in out.glob(dest.name + "*")),
                          "first": lines[0][:300] if lines else "", "last": lines[-1][:300] if lines else ""}),
              flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--src", help="a source tree to run (first on PYTHONPATH); default: as installed")
    ap.add_argument("--only", nargs="*", default=[], help="run the cases whose names hold one of these")
    ap.add_argument("--timeout", type=float, default=200.0, help="seconds per case")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        d = pathlib.Path(d)
        cases = write_cases(d / "cases")
        (d / "out").mkdir()
        run(args.src, cases, d / "out", args.only, args.timeout)


if __name__ == "__main__":
    main()
