"""Planning spatial bodies: the curvature of the momentum connection, the loop guesses, and plans
at zero and non-zero angular momentum, checked by the Pinocchio-driven simulation."""

import numpy as np
import pytest

import acroplan
from acroplan.core.basis import Legendre
from acroplan.families.spatial import rotations as rot
from acroplan.families.spatial.check import pinocchio_errors, pinocchio_segment
from acroplan.families.spatial.guess import Connection, curvature, loop_guesses
from acroplan.families.spatial.zoo import random_body, random_segment

pytest.importorskip("pinocchio")


def _holonomy(body, s0, i, j, rho, steps=400):
    """The body-frame rotation vector of a counter-clockwise circle of radius rho in (s_i, s_j) at
    L = 0, by RK4 on q' = q (0, Omega) / 2 with Omega = -A(s) s' (the model's own Omega)."""
    m = body.n_inputs

    def omega(sig):
        s = s0.copy()
        s[i] += rho * np.cos(2 * np.pi * sig)
        s[j] += rho * np.sin(2 * np.pi * sig)
        ds = np.zeros(m)
        ds[i] = -rho * 2 * np.pi * np.sin(2 * np.pi * sig)
        ds[j] = rho * 2 * np.pi * np.cos(2 * np.pi * sig)
        return body.angular_velocity(np.concatenate([[1.0, 0, 0, 0], s]), ds)

    q, h = np.array([1.0, 0.0, 0.0, 0.0]), 1.0 / steps
    for k in range(steps):
        t = k * h
        k1 = 0.5 * rot.xi(q) @ omega(t)
        k2 = 0.5 * rot.xi(q + h / 2 * k1) @ omega(t + h / 2)
        k3 = 0.5 * rot.xi(q + h / 2 * k2) @ omega(t + h / 2)
        k4 = 0.5 * rot.xi(q + h * k3) @ omega(t + h)
        q = q + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return rot.log(q)


def test_curvature_is_the_holonomy_of_small_loops():
    body = random_body(3, 4)
    s0 = np.array([0.3, -0.5, 0.8])
    F = curvature(Connection(body), s0[:, None])[:, :, 0]
    rho = 1e-3
    for p, (i, j) in enumerate([(0, 1), (0, 2), (1, 2)]):
        hol = _holonomy(body, s0, i, j, rho) / (np.pi * rho**2)
        # leading order: the error is O(rho) relative
        assert np.linalg.norm(hol - F[:, p]) < 5e-3 * np.linalg.norm(F[:, p])


def test_the_loop_guess_turns_the_body_toward_the_target():
    """At L = 0 and the shape back to itself the base motion does not turn the body at all; the loop
    guesses, ranked by the fast Runge-Kutta integration (which agrees with the compiled integrator),
    remove a good part of a small required turn."""
    from acroplan.core import backend

    body = random_body(5, 4)
    x0 = np.concatenate([[1.0, 0, 0, 0], [0.2, -0.4, 0.6]])
    x1 = np.concatenate([rot.exp([0.05, -0.03, 0.04]), [0.2, -0.4, 0.6]])
    basis = Legendre(6)
    g = loop_guesses(body, basis, x0, x1, 2.0)
    assert [k.kind for k in g] == ["loop", "loop", "loop", "base"]
    errs = []
    for k in g:
        y = backend.endpoint(body, basis, x0, 2.0, k.coefficients)[0]
        errs.append(rot.angle_between(y[:4], x1[:4]))
        assert abs(errs[-1] - k.predicted_error) < 1e-5
        assert np.max(np.abs(y[4:] - x1[4:])) < 1e-13  # the loops are closed: the joints end where asked
    assert errs[-1] == pytest.approx(np.linalg.norm([0.05, -0.03, 0.04]), abs=1e-13)
    assert errs[0] <= errs[1] + 1e-5 and errs[0] < 0.5 * errs[-1]


def test_the_screened_ranking_gives_the_guesses_of_the_full_one(monkeypatch):
    """The loop candidates are screened with SCREEN_STEPS Runge-Kutta steps and the SCREENED best
    integrated again with FAST_STEPS (guess module docstring, step 5): on 20 random chains and
    drifts the guesses are those of ranking every candidate with FAST_STEPS, in the same order, with
    the same predicted errors (to 1e-12 rad), for at most 60% of the points of the compiled map."""
    from acroplan.families.spatial import guess

    points = []
    fast = guess.fast_attitudes

    def counted(body, q0, T, S, dS):
        points.append(np.shape(S)[1] * np.shape(S)[2])
        return fast(body, q0, T, S, dS)

    monkeypatch.setattr(guess, "fast_attitudes", counted)
    rng = np.random.default_rng(7)
    assert guess.FAST_STEPS % guess.SCREEN_STEPS == 0
    full_points = screened_points = 0
    for k in range(20):
        seg = random_segment(rng, 3 + k % 3, momentum=bool(k % 2))
        monkeypatch.setattr(guess, "SCREENED", 10**9)
        points.clear()
        full = loop_guesses(seg.body, Legendre(10), seg.x0, seg.x1, seg.T)
        full_points += sum(points)
        monkeypatch.setattr(guess, "SCREENED", 24)
        points.clear()
        screened = loop_guesses(seg.body, Legendre(10), seg.x0, seg.x1, seg.T)
        screened_points += sum(points)
        # the same candidates (their coefficients are built, not integrated: equal exactly); their
        # predicted errors to 1e-12 rad, since the second pass integrates them in another batch of
        # the compiled kernel, whose lanes may round differently on another processor
        assert [(g.kind, g.compliant) for g in screened] == [(g.kind, g.compliant) for g in full]
        for a, b in zip(screened, full):
            assert np.array_equal(a.coefficients, b.coefficients)
            assert abs(a.predicted_error - b.predicted_error) <= 1e-12
    assert screened_points <= 0.6 * full_points


def test_the_fast_integrator_converges_at_fourth_order():
    from acroplan.families.spatial.guess import fast_attitudes

    body = random_body(2, 3, L=(0.4, -0.2, 0.9))
    q0 = rot.normalize(np.array([0.3, 0.5, -0.2, 0.8]))
    ref = None
    errs = []
    for N in (256, 16, 32):
        sig = np.linspace(0, 1, 2 * N + 1)
        S = np.stack([0.3 + np.sin(3 * sig), -0.2 + sig**2])[:, None, :]
        dS = np.stack([3 * np.cos(3 * sig), 2 * sig])[:, None, :]
        q = fast_attitudes(body, q0, 1.7, S, dS)[:, 0]
        if ref is None:
            ref = q
        else:
            errs.append(rot.angle_between(q, ref))
    assert errs[1] < errs[0] / 10  # halving the step divides the error by about 16


@pytest.mark.parametrize("L", [(0.0, 0.0, 0.0), (0.4, -0.2, 0.9)])
def test_the_compiled_runge_kutta_kernel_is_the_scheme_written_out(L):
    """fast_attitudes' compiled steps (guess._build_rk4_kernel, KERNEL_STEPS a call) against the
    classical Runge-Kutta scheme written out here with the body's own inertia and coupling
    (SpatialBody.momentum_map, numpy's solve): 20 steps, so that the last call holds 4; three
    motions at once. Both are the same arithmetic in another order: 1e-12."""
    from acroplan.families.spatial.collocation_parts import _quad
    from acroplan.families.spatial.guess import KERNEL_STEPS, fast_attitudes

    body = random_body(4, 4, L=L)
    N, T = 20, 1.3
    assert N % KERNEL_STEPS != 0
    q0 = rot.normalize(np.array([0.3, 0.5, -0.2, 0.8]))
    sig = np.linspace(0, 1, 2 * N + 1)
    amp = np.array([[0.4, -0.3, 0.7], [0.9, 0.2, -0.5], [-0.6, 0.8, 0.3]])  # (m, K)
    assert body.n_inputs == amp.shape[0]
    S = amp[:, :, None] * np.sin(np.pi * sig)[None, None, :] + 0.1
    dS = amp[:, :, None] * (np.pi * np.cos(np.pi * sig))[None, None, :]
    got = fast_attitudes(body, q0, T, S, dS)
    Q = _quad(T * np.asarray(L))

    def f(q, k, j):
        I, A = body.momentum_map(S[:, j, k])  # noqa: E741
        Om = np.linalg.solve(I, np.einsum("a,iab,b->i", q, Q, q) - A @ dS[:, j, k])
        return 0.5 * rot.qmul(q, np.concatenate([[0.0], Om]))

    h = 1.0 / N
    for j in range(S.shape[1]):
        q = q0.copy()
        for step in range(N):
            k = 2 * step
            k1 = f(q, k, j)
            k2 = f(q + 0.5 * h * k1, k + 1, j)
            k3 = f(q + 0.5 * h * k2, k + 1, j)
            k4 = f(q + h * k3, k + 2, j)
            q = q + (h / 6.0) * (k1 + 2 * k2 + 2 * k3 + k4)
        assert np.max(np.abs(got[:, j] - q / np.linalg.norm(q))) < 1e-12
    assert abs(np.linalg.norm(q) - 1.0) > 1e-12 or not any(L)  # the drift's scheme leaves the sphere


def test_the_compiled_kernel_gives_the_same_numbers_in_threads():
    """Each thread calls its own copy of the compiled steps (guess._rk4_kernel): eight calls at
    once, on 200 motions each, give the serial call's numbers bit for bit."""
    import concurrent.futures

    from acroplan.families.spatial.guess import fast_attitudes

    body = random_body(5, 4, L=(0.4, -0.2, 0.9))
    rng = np.random.default_rng(3)
    sig = np.linspace(0, 1, 97)
    amp = rng.normal(size=(body.n_inputs, 200, 1))
    S, dS = amp * np.sin(np.pi * sig), amp * np.pi * np.cos(np.pi * sig)
    q0 = rot.normalize(np.array([0.3, 0.5, -0.2, 0.8]))
    want = fast_attitudes(body, q0, 1.1, S, dS)
    with concurrent.futures.ThreadPoolExecutor(4) as ex:
        outs = list(ex.map(lambda _: fast_attitudes(body, q0, 1.1, S, dS), range(8)))
    assert all(np.array_equal(o, want) for o in outs)


def test_the_loop_plane_has_a_canonical_basis():
    """_decomposable: scale a ^ b is the bivector's best rank-two part (the skew matrix's two
    largest singular values), a and b orthonormal, and (a, b) do not turn within their plane when
    the bivector changes in its last bits (the singular value decomposition's basis of a repeated
    singular value is any pair: it did, and a bundled dive's plan changed with it)."""
    from acroplan.families.spatial.guess import _decomposable

    rng = np.random.default_rng(7)
    for m in (2, 3, 4, 5):
        pairs = [(i, j) for i in range(m) for j in range(i + 1, m)]
        for _ in range(20):
            Bv = rng.normal(size=len(pairs))
            Bm = np.zeros((m, m))
            for p, (i, j) in enumerate(pairs):
                Bm[i, j], Bm[j, i] = Bv[p], -Bv[p]
            a, b, scale = _decomposable(Bv, m)
            assert abs(a @ a - 1) < 1e-14 and abs(b @ b - 1) < 1e-14 and abs(a @ b) < 1e-14
            U, sv, Vt = np.linalg.svd(Bm)
            best = U[:, :2] @ np.diag(sv[:2]) @ Vt[:2]
            assert np.max(np.abs(scale * (np.outer(a, b) - np.outer(b, a)) - best)) < 1e-12
            assert scale == pytest.approx(sv[0], rel=1e-12)
            for _ in range(5):
                a2, b2, _ = _decomposable(Bv * (1 + 1e-13 * rng.normal(size=Bv.size)), m)
                assert np.max(np.abs(a2 - a)) < 1e-9 and np.max(np.abs(b2 - b)) < 1e-9


@pytest.mark.parametrize("momentum", [False, True])
def test_random_segments_are_planned_and_checked_by_pinocchio(momentum):
    for seed in range(3):
        p = random_segment(100 + seed, 3, momentum=momentum)
        res = acroplan.plan(p.body, conditions="free", **p.plan_kwargs())
        assert res.success, res.message
        seg = res.segments[0]
        assert seg.verified_error < 1e-9 and res.verified
        # the Pinocchio-driven motion of the planned input ends on the target
        x = pinocchio_segment(p.body, p.x0, p.T, seg.basis, seg.basis_coefficients)
        assert rot.angle_between(x[:4], p.x1[:4]) < 1e-9 and np.max(np.abs(x[4:] - p.x1[4:])) < 1e-9
        # the quaternion stays unit along the plan
        from acroplan.families.spatial.check import norm_drift

        assert norm_drift(res) < 1e-13


def test_a_plan_through_waypoints_with_attitudes_in_any_form():
    body = random_body(8, 3)
    kw = rot.attitude_states([[1, 0, 0, 0], {"euler_deg": [10, 5, -8]}, {"rotvec_deg": [0, 0, 20]}])
    res = acroplan.plan(body, times=[0, 1.5, 3.0], q1=[0.0, 0.5, 0.0], q2=[0.0, -0.3, 0.0], **kw)
    assert res.success, res.message
    assert res.verified and max(s.verified_error for s in res.segments) < 1e-9
    end = res.evaluate([3.0]).states[:, 0]
    assert rot.angle_between(end[:4], rot.exp(np.radians([0, 0, 20]))) < 1e-9


def test_the_check_catches_a_wrong_plan():
    p = random_segment(104, 3)
    res = acroplan.plan(p.body, conditions="free", **p.plan_kwargs())
    seg = res.segments[0]
    import dataclasses

    bad = dataclasses.replace(seg, basis_coefficients=seg.basis_coefficients * (1 + 1e-6))
    assert pinocchio_errors(p.body, p.x0, [seg])[0] < 1e-9
    assert pinocchio_errors(p.body, p.x0, [bad])[0] > 1e-8


def test_unit_quaternions_are_required():
    body = random_body(1, 3)
    with pytest.raises(acroplan.InvalidInputError, match="attitude: the end quaternion"):
        acroplan.plan(body, times=[0, 1], qw=[1, 1], qx=[0, 0.1], qy=[0, 0], qz=[0, 0], q1=[0, 0], q2=[0, 0])


def test_drawings(tmp_path):
    """The equivalent boxes have the links' principal moments; the animation has the frames asked for."""
    from PIL import Image

    from acroplan.families.spatial import drawing
    from acroplan.families.spatial.zoo import astronaut

    body = astronaut()
    for i, half, V in drawing.equivalent_boxes(body):
        a, b, c = 2 * half
        mass = body.links[i].mass
        moments = mass / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
        assert np.allclose(V @ np.diag(moments) @ V.T, body.links[i].inertia_matrix, atol=1e-12)
    p = random_segment(100, 3)
    res = acroplan.plan(p.body, conditions="free", verify=False, **p.plan_kwargs())
    frames = drawing.animate(res, tmp_path / "a.gif", fps=4, dpi=30, speed=1.0)  # real time
    assert frames == int(np.ceil(p.T * 4)) + 1 and Image.open(tmp_path / "a.gif").n_frames == frames
    # by default a motion shorter than MIN_SECONDS is played slower, so that it lasts that long
    from acroplan.core.animation import MIN_SECONDS

    frames = drawing.animate(res, tmp_path / "b.gif", fps=4, dpi=30)
    assert frames == int(np.ceil(max(p.T, MIN_SECONDS) * 4)) + 1
    fig = drawing.attitude_figure(res)
    lines = fig.axes[0].get_lines()
    assert [ln.get_label() for ln in lines[:3]] == ["somersault", "tilt", "twist"]
    # the plotted angles are the Yeadon angles of the plan's end attitude
    end = res.evaluate([p.T]).states[:4, 0]
    ang = rot.to_euler(end)
    for k in range(3):
        assert abs((lines[k].get_ydata()[-1] - ang[k] + 180) % 360 - 180) < 1e-6


def _figures(folder):  # pragma: no cover - run by hand: python tests/test_spatial_planning.py docs/images
    """Plan the bundled examples and draw them (a family module may not call the front door)."""
    import pathlib

    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from acroplan.families.spatial import drawing
    from acroplan.families.spatial.examples import EXAMPLES

    out = pathlib.Path(folder)
    for name, make in EXAMPLES.items():
        body, kw = make()
        res = acroplan.plan(body, **kw)
        print(name, res.status, res.message)
        if not res.success:
            continue
        drawing.save_strobe(res, out / f"spatial-{name}-strobe.png", poses=7 if len(res.segments) > 1 else 6)
        fig = drawing.attitude_figure(res)
        FigureCanvasAgg(fig)
        fig.savefig(out / f"spatial-{name}-angles.png", dpi=90)
        if name in ("falling-cat", "twisting-somersault", "astronaut-somersault"):
            speed = 0.25 if name == "falling-cat" else 1.0
            drawing.animate(res, out / f"spatial-{name}.gif", fps=15, speed=speed, dpi=64)
        if name == "falling-cat":
            _kane_scher_numbers(res)


def _kane_scher_numbers(res):  # pragma: no cover
    """The angle between the halves' axes and the direction of the bend over the planned motion."""
    body = res.system
    t = np.linspace(res.times[0], res.times[-1], 401)
    X = res.evaluate(t).states
    gam, psi, twist = [], [], []
    for x in X.T:
        Rs, _, _ = body.link_poses(x)
        a = Rs[body.links.index("front")][:, 0]
        b = -Rs[body.links.index("rear")][:, 0]
        gam.append(np.degrees(np.arccos(np.clip(-a @ b, -1, 1))))
        # the bend's direction about the front half's axis, in its frame (0: forward, 90: to its left)
        d = Rs[body.links.index("front")].T @ (a + b)
        psi.append(np.degrees(np.arctan2(d[1], -d[2])))
        twist.append(np.degrees(x[6]))
    psi = np.unwrap(np.radians(psi))
    print(f"angle between the halves: min {min(gam):.1f} max {max(gam):.1f} deg; the bend's direction turns by "
          f"{np.degrees(psi[-1] - psi[0]):.1f} deg; twist joint within [{min(twist):.1f}, {max(twist):.1f}] deg")


def test_the_polish_of_a_refined_loop_ends_on_the_refinements_last_evaluation(monkeypatch):
    """A loop refined to the target is polished by path deformation, whose first step evaluated the
    same input again (to rounding). refine returns its last evaluation (the endpoint map and its
    Jacobian at its coefficients exactly), and solve_segment's initial_endpoint ends the polish
    on it when no correction is needed: the same plan to the last bit, evaluations fewer (here
    two, one per interval)."""
    from acroplan.families.spatial import strategy
    from acroplan.families.spatial.examples import twisting_somersault

    body, kw = twisting_somersault()
    reused = acroplan.plan(body, verify=False, **kw)
    real = strategy.refine
    monkeypatch.setattr(strategy, "refine", lambda *a, **k: real(*a, **k)[:3] + (None,))
    again = acroplan.plan(body, verify=False, **kw)
    assert reused.success and again.success and len(reused.segments) == len(again.segments) == 2
    for a, b in zip(reused.segments, again.segments):
        assert np.array_equal(a.coefficients, b.coefficients)
    assert again.evaluations - reused.evaluations == 2


if __name__ == "__main__":  # pragma: no cover
    import sys

    _figures(sys.argv[1] if len(sys.argv) > 1 else "docs/images")

