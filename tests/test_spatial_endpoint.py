"""The endpoint map of spatial bodies by Gauss collocation (acroplan.families.spatial.collocation).

Checked against an independent tight integration (heyoka's Taylor integrator of the model's own
fields in extended precision, ``long double`` at tolerance 1e-19, the whole state, no collocation),
its Jacobian against the reference's directional derivatives, central finite differences and the
Taylor integrator's variational equations, and its bookkeeping (panels, unit quaternion,
determinism, threads, wild inputs).
"""

import concurrent.futures
import math

import numpy as np
import pytest

from acroplan.core import backend
from acroplan.core.basis import Legendre
from acroplan.families.spatial import SpatialBody, collocation
from acroplan.families.spatial import rotations as rot
from acroplan.families.spatial.examples import falling_cat_turn
from acroplan.families.spatial.zoo import random_segment


def tight_endpoint(body, basis, x0, T, c):
    """x(T) by heyoka's Taylor integrator of the model's fields (f + G u) in long double, tol 1e-19."""
    return backend.reference_endpoint(body, basis, x0, T, c)


def state_error(y, ref):
    return max(rot.angle_between(y[:4] / np.linalg.norm(y[:4]), ref[:4] / np.linalg.norm(ref[:4])),
               float(np.abs(y[4:] - ref[4:]).max()))


def cat_case(n):
    """The bundled cat from its start, with a loop of the size its plans make."""
    cat, kw = falling_cat_turn()
    x0 = np.array([kw[k][0] for k in cat.state_names])
    rng = np.random.default_rng(22)
    c = np.zeros((3, n))
    c[:, :6] = rng.normal(scale=[4.0, 6.0, 3.0, 2.0, 1.0, 0.5], size=(3, 6))
    c[:, 6:] = rng.normal(scale=0.3, size=(3, n - 6))
    return cat, x0, 0.5, c


def random_case(seed, links, momentum, n, tree=False, scale=1.0):
    rng = np.random.default_rng(seed)
    p = random_segment(rng, links, momentum=momentum, tree=tree)
    c = np.zeros((p.body.n_inputs, n))
    c[:, :6] = scale * p.coefficients
    c[:, 6:] = 0.3 * rng.normal(size=(p.body.n_inputs, n - 6))
    return p.body, p.x0, p.T, c


CASES = {
    "cat n=6": lambda: cat_case(6),
    "cat n=14": lambda: cat_case(14),
    "3 links L=0 n=10": lambda: random_case(1, 3, False, 10, scale=2.0),
    "4 links L!=0 n=10": lambda: random_case(2, 4, True, 10, scale=2.0),
    "5 links L!=0 n=6": lambda: random_case(3, 5, True, 6),
    "5-link tree L=0 n=14": lambda: random_case(4, 5, False, 14, tree=True),
}


@pytest.mark.parametrize("name", list(CASES))
def test_endpoint_and_jacobian_meet_a_tight_integration(name):
    """x(T) against the long-double reference at 1e-12; the Jacobian against the reference's own
    directional derivatives, in three random directions v of the coefficients: central differences
    at h and h/2 combined by Richardson's rule (error O(h^4)), at h = 1e-3, agree with J v to 1e-10
    of |J v| (measured: at most 2.8e-12 over these cases; the double-precision rounding of the
    reference's output, about 1e-16 / h, is the floor). A wrong column of J shows in every random
    direction."""
    body, x0, T, c = CASES[name]()
    basis = Legendre(c.shape[1])
    y, J = collocation.endpoint(body, basis, x0, T, c)
    ref = tight_endpoint(body, basis, x0, T, c)
    assert state_error(y, ref) <= 1e-12
    assert abs(np.linalg.norm(y[:4]) - 1.0) <= 1e-14  # Gauss collocation keeps |q|
    # the core's back end uses the family's map
    y2, J2 = backend.endpoint(body, basis, x0, T, c)
    assert np.array_equal(y, y2) and np.array_equal(J, J2)
    B = body.tangent_jacobian(y, J)
    rng = np.random.default_rng(7)
    h = 1e-3

    def central(v, h):
        yp, ym = (tight_endpoint(body, basis, x0, T, c + s * h * v) for s in (1.0, -1.0))
        return (body.diff(ref, yp) - body.diff(ref, ym)) / (2 * h)

    for _ in range(3):
        v = rng.normal(size=c.shape)
        richardson = (4 * central(v, h / 2) - central(v, h)) / 3
        Jv = B @ v.ravel()
        assert np.abs(richardson - Jv).max() <= 1e-10 * np.abs(Jv).max()


@pytest.mark.parametrize("name", ["3 links L=0 n=10", "4 links L!=0 n=10"])
def test_the_taylor_integrators_variational_equations_agree(name):
    """heyoka's Taylor integrator with its variational equations in the coefficients (the core's
    route for bodies without a map of their own) gives the collocation's x(T) and Jacobian, at
    L = 0 and L != 0 (compiling it costs seconds a case, so two cases; the Jacobian of every case
    is checked against the reference above)."""
    body, x0, T, c = CASES[name]()
    basis = Legendre(c.shape[1])
    y, J = collocation.endpoint(body, basis, x0, T, c)
    yt, Jt = backend.taylor_endpoint(body, basis, x0, T, c)
    assert state_error(y, yt) <= 1e-12
    A, B = body.tangent_jacobian(yt, Jt), body.tangent_jacobian(y, J)
    assert np.abs(A - B).max() <= 1e-10 * np.abs(A).max()


@pytest.mark.parametrize("name", ["cat n=6", "4 links L!=0 n=10"])
def test_jacobian_against_finite_differences(name):
    body, x0, T, c = CASES[name]()
    basis = Legendre(c.shape[1])
    y, J = collocation.endpoint(body, basis, x0, T, c)
    Jt = body.tangent_jacobian(y, J)
    h = 1e-6
    flat = c.ravel()
    fd = np.empty_like(Jt)
    for k in range(flat.size):
        e = np.zeros_like(flat)
        e[k] = h
        yp, _ = collocation.endpoint(body, basis, x0, T, (flat + e).reshape(c.shape), jacobian=False)
        ym, _ = collocation.endpoint(body, basis, x0, T, (flat - e).reshape(c.shape), jacobian=False)
        fd[:, k] = (body.diff(y, yp) - body.diff(y, ym)) / (2 * h)
    assert np.abs(fd - Jt).max() <= 1e-6 * max(1.0, np.abs(Jt).max())


def test_panels_and_determinism():
    body, x0, T, c = CASES["cat n=6"]()
    basis = Legendre(6)
    seg = collocation._Segment(body, basis, x0, T, c)
    widths = collocation._solve(seg)[1]
    assert math.isclose(widths.sum(), 1.0, rel_tol=0, abs_tol=1e-15)
    assert 2 <= widths.size <= 16  # the cat's 0.5 s turn: about 100 Gauss nodes
    y1, J1 = collocation.endpoint(body, basis, x0, T, c)
    y2, J2 = collocation.endpoint(body, basis, x0, T, c)
    assert np.array_equal(y1, y2) and np.array_equal(J1, J2)


#: a motion eight times the zoo's, whose panels go below the first four levels (to 1/32)
LARGE = "4 links L!=0 n=10, 4x"


@pytest.mark.parametrize("name", list(CASES) + [LARGE])
def test_the_first_levels_at_once_keep_the_panels_of_the_bisection(name, monkeypatch):
    """The layout's first levels evaluated in one call (collocation_parts.FIRST_LEVELS) keep the
    panels that bisection level by level keeps (FIRST_LEVELS = 1: the two halves, then their
    children as needed), with the same node data and endpoint to the last bit: a panel's numbers
    depend on the panel alone."""
    from acroplan.families.spatial import collocation_parts as cp

    body, x0, T, c = random_case(2, 4, True, 10, scale=8.0) if name == LARGE else CASES[name]()
    basis = Legendre(c.shape[1])
    runs = []
    for levels in (1, 4):
        monkeypatch.setattr(cp, "FIRST_LEVELS", levels)
        st, wd, d = cp._layout(collocation._Segment(body, basis, x0, T, c))
        runs.append((st, wd, d, *collocation.endpoint(body, basis, x0, T, c)))
    (st1, wd1, d1, y1, J1), (st4, wd4, d4, y4, J4) = runs
    if name.startswith("cat"):  # panels of several levels
        assert np.unique(wd1).size >= 2
    if name == LARGE:  # and bisection on from the fourth
        assert wd1.min() == 1 / 32
    assert np.array_equal(st1, st4) and np.array_equal(wd1, wd4)
    assert all(np.array_equal(d1[k], d4[k]) for k in d1)
    assert np.array_equal(y1, y4) and np.array_equal(J1, J4)


def test_threads_give_the_same_numbers():
    body, x0, T, c = CASES["4 links L!=0 n=10"]()
    basis = Legendre(10)
    y, J = collocation.endpoint(body, basis, x0, T, c)
    with concurrent.futures.ThreadPoolExecutor(4) as ex:
        outs = list(ex.map(lambda _: collocation.endpoint(body, basis, x0, T, c), range(8)))
    assert all(np.array_equal(o[0], y) and np.array_equal(o[1], J) for o in outs)


def test_wild_input_raises_an_integration_error():
    body, x0, T, c = CASES["cat n=6"]()
    with pytest.raises(backend.IntegrationError, match="too large to integrate"):
        collocation.endpoint(body, Legendre(6), x0, T, 1e6 * c)


def test_momentum_and_joint_rows():
    """The joint rows are exact (polynomials), and with L != 0 the body-frame momentum R(q)^T L
    the collocation carries matches the attitude it returns."""
    body, x0, T, c = CASES["4 links L!=0 n=10"]()
    basis = Legendre(10)
    y, J = collocation.endpoint(body, basis, x0, T, c)
    B1 = basis.integral([1.0])[0]
    assert np.allclose(y[4:], x0[4:] + T * (c @ B1), rtol=0, atol=1e-14)
    m, n = c.shape
    for j in range(m):
        row = np.zeros(m * n)
        row[j * n:(j + 1) * n] = T * B1
        assert np.array_equal(J[4 + j], row)
    seg = collocation._Segment(body, basis, x0, T, c)
    sol = collocation._solve(seg)
    Lam = sol[7][0]
    Y = sol[4]
    R = np.array([[rot.to_matrix(q / np.linalg.norm(q)) for q in panel] for panel in Y])
    assert np.abs(np.einsum("pnji,j->pni", R, np.array(body.L)) - Lam).max() <= 1e-10 * np.linalg.norm(body.L)


def test_a_body_without_momentum_uses_the_linear_solve():
    body, x0, T, c = CASES["4 links L!=0 n=10"]()
    still = SpatialBody(body.links)
    basis = Legendre(10)
    y, _ = collocation.endpoint(still, basis, x0, T, c)
    assert state_error(y, tight_endpoint(still, basis, x0, T, c)) <= 1e-12


def test_the_attitudes_derivative_map_is_made_of_right_multiplications():
    """collocation._attitude builds each panel's M (module docstring) from its first row alone: S
    and the F_j are quaternion right multiplications, so M commutes with left multiplications and
    each 4 x 4 block is the right multiplication by the quaternion of its first row. Checked
    against M from all four right-hand sides of the transposed system, on the cat's panels, to
    rounding; and the commutation itself, M (1 (x) L(p)) = L(p) M, for a random quaternion p."""
    from acroplan.families.spatial import collocation_parts as parts

    body, x0, T, c = CASES["cat n=14"]()
    seg = collocation._Segment(body, Legendre(14), x0, T, c)
    starts, widths, d = parts._layout(seg)
    Om = d["w"]
    P, N = widths.size, seg.N
    Fq = parts._right(Om)
    S = parts._blocks(seg, widths, Fq)
    rhs = (seg.b[:, None, None] * np.swapaxes(Fq, -1, -2)).reshape(P, 4 * N, 4)
    full = np.stack([np.linalg.solve(S[k].T, rhs[k]) for k in range(P)])          # M^T, four columns
    M_full = np.swapaxes(full.reshape(P, N, 4, 4), -1, -2)
    _, _, Phi, Z, _ = collocation._attitude(seg, widths, Om)
    M_built = (Z - seg.b[None, :, None, None] * np.eye(4)) / widths[:, None, None, None]
    # Z_j = b_j 1 + H sum_i M_i a_ij: recover sum_i M_i a_ij from both and compare
    want = (seg.a.T @ M_full.reshape(P, N, 16)).reshape(P, N, 4, 4)
    assert np.abs(M_built - want).max() <= 1e-13 * max(1.0, np.abs(want).max())
    assert np.abs(Phi - (np.eye(4) + widths[:, None, None] * M_full.sum(axis=1))).max() <= 1e-13
    p = np.random.default_rng(3).normal(size=4)
    Lp = parts._left(p)
    assert np.abs(M_full @ Lp - Lp @ M_full).max() <= 1e-13 * np.abs(M_full).max()


@pytest.mark.parametrize("name", ["cat n=14", "4 links L!=0 n=10"])
def test_samples_meet_the_taylor_integrator(name):
    """Dense states: the collocation cut at the samples, each a panel's end, against the Taylor
    integrator's dense output."""
    body, x0, T, c = CASES[name]()
    basis = Legendre(c.shape[1])
    s = np.concatenate([[0.0], np.sort(np.random.default_rng(5).uniform(0, 1, 40)), [1.0]])
    X = backend.sample(body, basis, x0, T, c, s)
    Xt = backend.taylor_sample(body, basis, x0, T, c, s)
    assert X.shape == Xt.shape == (body.n_states, s.size)
    assert max(state_error(X[:, k], Xt[:, k]) for k in range(s.size)) <= 1e-12
    assert np.allclose(X[:, -1], collocation.endpoint(body, basis, x0, T, c, jacobian=False)[0], rtol=0, atol=1e-13)
    assert np.array_equal(X[:, 0], x0)


def test_compiled_maps_are_stored_and_read_back_by_the_next_process(monkeypatch, tmp_path):
    """Issue #22 (the falling cat's command line): a compiled function of ``compile_once`` is kept on
    disk beside heyoka's cache and read back by a later process instead of being built again (heyoka's
    own cache saves the LLVM compilation, not the code generation before it: 0.1-0.7 s a function);
    what is read back gives the same numbers bit for bit; a damaged file is built anew; no disk cache,
    nothing stored."""
    cat, _ = falling_cat_turn()
    monkeypatch.setattr(backend, "_marker", lambda key: tmp_path / "marker")
    built = []

    def build():
        built.append(1)
        return collocation._build(cat, light=True)

    key = ("test-stored-map", cat.links.parents)
    monkeypatch.setattr(backend, "_ONCE", {})
    first = backend.compile_once(key, build)
    stored = backend._stored(key)
    assert built == [1] and stored.exists() and stored.parent == tmp_path
    monkeypatch.setattr(backend, "_ONCE", {})  # as in the next process
    again = backend.compile_once(key, build)
    assert built == [1] and again is not first
    pts = np.random.default_rng(3).normal(size=(6, 50))
    pars = backend._repeated(cat._param_tuple, 50)
    assert np.array_equal(first(pts, pars=pars), again(pts, pars=pars))
    stored.write_bytes(b"not a compiled function")
    monkeypatch.setattr(backend, "_ONCE", {})
    backend.compile_once(key, build)
    assert built == [1, 1] and stored.stat().st_size > 1000  # built anew and stored again
    monkeypatch.setattr(backend, "_marker", lambda key: None)  # no disk cache
    assert backend._stored(key) is None


def test_the_store_of_compiled_maps_is_trimmed_least_recently_used_first(tmp_path):
    """The store of compiled functions is bounded (``backend.STORE_LIMIT``): past the limit the least
    recently used files go first (a read marks a file used), other files of the folder stay."""
    import os

    for k, age in enumerate((300, 200, 100)):
        f = tmp_path / f"f{k}.cfunc"
        f.write_bytes(b"x" * 1000)
        os.utime(f, (f.stat().st_atime - age, f.stat().st_mtime - age))
    (tmp_path / "marker").write_bytes(b"y" * 5000)
    backend._trim(tmp_path, limit=2500)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f1.cfunc", "f2.cfunc", "marker"]
    backend._trim(tmp_path, limit=1000)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f2.cfunc", "marker"]


@pytest.mark.parametrize("name", ["cat n=6", "4 links L!=0 n=10"])
def test_forward_differences_on_the_points_panels(name):
    """Within backend.perturbations_of(c) (the optimiser's constraint Hessians), the endpoint at
    c + eps e_k is integrated on c's panels, the momentum's Newton iterations started from c's
    solution: every column of the Jacobian's forward differences within 1e-7 of the plain ones
    (relative to the largest; the differences themselves err by about eps = 1e-7), an input far
    from c integrated as always (bit for bit), and the endpoint near c within 1e-13."""
    body, x0, T, c = CASES[name]()
    n = 6 if name.startswith("cat") else 10
    basis = Legendre(n)
    c = np.asarray(c, dtype=float).reshape(-1)
    _, J0 = collocation.endpoint(body, basis, x0, T, c)
    plain, near = [], []
    for k in range(c.size):
        ck = c.copy()
        ck[k] += 1e-7
        plain.append((collocation.endpoint(body, basis, x0, T, ck)[1] - J0) / 1e-7)
    with backend.perturbations_of(body, basis, x0, T, c):
        for k in range(c.size):
            ck = c.copy()
            ck[k] += 1e-7
            near.append((collocation.endpoint(body, basis, x0, T, ck)[1] - J0) / 1e-7)
        far = 1.1 * c
        y_far, J_far = collocation.endpoint(body, basis, x0, T, far)
        ck = c.copy()
        ck[0] += 1e-7
        y_near = collocation.endpoint(body, basis, x0, T, ck)[0]
    P, N = np.array(plain), np.array(near)
    assert np.abs(P - N).max() <= 1e-7 * np.abs(P).max()
    y2, J2 = collocation.endpoint(body, basis, x0, T, far)
    assert np.array_equal(y_far, y2) and np.array_equal(J_far, J2)
    assert np.abs(y_near - collocation.endpoint(body, basis, x0, T, ck)[0]).max() < 1e-13


def test_a_plan_is_evaluated_at_thousands_of_times():
    """result.evaluate at 5000 times of a 3-D plan (an animation's frames): the collocation's panels
    are cut at the times a chunk at a time (collocation.SAMPLE_CHUNK; cut at all 5000 at once they
    passed the bound on panels, MAX_PANELS, and the call raised "the input is too large to
    integrate"); the states are those of the same times evaluated 500 at a time, to rounding, with
    unit quaternions."""
    import acroplan

    body, kw = falling_cat_turn()
    r = acroplan.plan(body, verify=False, **kw)
    t = np.linspace(r.times[0], r.times[-1], 5000)
    big = r.evaluate(t, effort=False).states
    parts = np.concatenate([r.evaluate(t[i:i + 500], effort=False).states for i in range(0, t.size, 500)], axis=1)
    assert big.shape == (7, 5000)
    np.testing.assert_allclose(big, parts, rtol=0, atol=1e-13)
    np.testing.assert_allclose(np.linalg.norm(big[:4], axis=0), 1.0, rtol=0, atol=1e-13)


def test_the_complex_attitude_equations_are_the_real_ones():
    """collocation._attitude solves each panel's 4N x 4N real system as a 2N x 2N complex one:
    with a quaternion q = z1 + z2 j as the pair (z1, z2) = (q0 + i q1, q2 + i q3), the real matrix
    of a complex matrix, entry by entry [[Re, -Im], [Im, Re]], is the real S (built from the 4 x 4
    matrices of q -> q (0, w) / 2) to rounding; and the attitude solved either way agrees to
    1e-14 (stage values, the panels' maps of perturbations)."""
    from scipy.linalg import lapack

    from acroplan.families.spatial import collocation_parts as parts

    body, x0, T, c = CASES["cat n=6"]()
    seg = collocation._Segment(body, Legendre(c.shape[1]), x0, T, c)
    rng = np.random.default_rng(5)
    P, N = 3, seg.N
    widths = np.array([0.2, 0.3, 0.5])
    Om = rng.normal(scale=4.0, size=(P, N, 3))
    Sc = collocation._complex_blocks(seg, widths, Om)
    real = np.empty((P, 4 * N, 4 * N))
    real[:, 0::2, 0::2] = Sc.real
    real[:, 0::2, 1::2] = -Sc.imag
    real[:, 1::2, 0::2] = Sc.imag
    real[:, 1::2, 1::2] = Sc.real
    S = parts._blocks(seg, widths, collocation._right(Om))
    assert np.abs(real - S).max() <= 1e-15 * np.abs(S).max()
    ys, Y, Phi, Z, _ = collocation._attitude(seg, widths, Om)
    # the same panels by the real LU: stage values and the panels' maps of perturbations
    Fq = collocation._right(Om)
    e = np.zeros(4 * N)
    e[0::4] = 1.0
    rhs = (seg.b[:, None] * np.swapaxes(Fq, -1, -2)[:, :, :, 0]).reshape(P, 4 * N)
    for k in range(P):
        lu, piv, _ = lapack.dgetrf(S[k])
        Yl = lapack.dgetrs(lu, piv, e)[0].reshape(N, 4)
        assert np.abs(collocation._left(ys[k][None])[0] @ Yl.T - Y[k].T).max() <= 1e-14
        x = lapack.dgetrs(lu, piv, rhs[k], trans=1)[0].reshape(N, 4)
        Phi_k = np.eye(4) + widths[k] * collocation._rightq(x * collocation._CONJ).sum(axis=0)
        assert np.abs(Phi_k - Phi[k]).max() <= 1e-14
    assert abs(np.linalg.norm(ys[-1]) - 1.0) <= 1e-14  # Gauss collocation keeps |q|
