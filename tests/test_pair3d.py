"""3D body-body pair kinds (kernels/pair3d*.py, issue 16 item 1): gap, normal, witness points
and features against a brute-force signed distance (the maximum over all unit axes of the
support-function separation, dense sampling of the sphere of directions then a local
refinement with scipy.optimize), near-parallel faces and edges, touching and overlapping
poses, invariance under a rigid motion and under swapping the bodies, the gap rate against a
finite difference along the flight, contact manifolds, time of impact against a scan and
bisection of the gap along the exact flight, and the input checks.

Conventions (DESIGN §3): ``n`` from B into A, ``pA - pB = g n``, ``g' < 0`` approaching."""
import math
import zlib

import numpy as np
import pytest
from scipy.optimize import minimize

from rbimpact import shapes3d
from rbimpact.kernels.pair3d import (FE_A_INDEX, FE_A_KIND, FE_B_INDEX, FE_B_KIND,
                                     FR_GAP, FR_NX, FR_PAX, FR_PBX, FR_RATE, N_FE, N_FR,
                                     PAIR_TABLE, PK_NONE, pair_frame, pair_kind)
from rbimpact.kernels.pair3d_shape import (FT_EDGE, FT_FACE, FT_VERTEX, SH_BOX, SH_CAPSULE,
                                           SH_SPHERE)

EPS = np.finfo(float).eps
SHAPES = ("sphere", "box", "capsule")
PAIRS = [(a, b) for i, a in enumerate(SHAPES) for b in SHAPES[i:]]
KIND = {"sphere": SH_SPHERE, "box": SH_BOX, "capsule": SH_CAPSULE}


def seed(*parts):
    """A fixed seed per test case (``hash`` of strings changes between runs)."""
    return zlib.crc32("-".join(map(str, parts)).encode())


# ---- random bodies and poses ---------------------------------------------------------------

def random_body(rng, name):
    """``(kind, rad, hx, hy, hz)`` of a random body of roughly unit size."""
    if name == "sphere":
        return (SH_SPHERE, rng.uniform(0.2, 1.0), 0.0, 0.0, 0.0)
    if name == "box":
        h = rng.uniform(0.15, 1.0, 3)
        return (SH_BOX, 0.0, h[0], h[1], h[2])
    return (SH_CAPSULE, rng.uniform(0.1, 0.5), 0.0, 0.0, rng.uniform(0.2, 1.0))


def random_quat(rng):
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def quat_mat(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def quat_mul(a, b):
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    return np.array([a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
                     a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
                     a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
                     a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0])


def axis_quat(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.r_[math.cos(angle / 2), math.sin(angle / 2) * axis]


def row(x, q, v=(0, 0, 0), w=(0, 0, 0), a=(0, 0, 0)):
    st = np.zeros(19)
    st[0:3] = x
    st[3:7] = q
    st[7:10] = v
    st[10:13] = w
    st[13:16] = a
    return st


def size_of(body):
    k, r, hx, hy, hz = body
    return r + math.sqrt(hx * hx + hy * hy + hz * hz)


# ---- independent geometry: support functions and signed distance functions ----------------

def support(body, x, R, U):
    """``h(u) = max_{p in body} u . p`` for the rows of ``U`` (unit)."""
    k, r, hx, hy, hz = body
    c = U @ x
    if k == SH_SPHERE:
        return c + r
    if k == SH_CAPSULE:
        a = R[:, 2] * hz
        return c + np.abs(U @ a) + r
    L = U @ R          # components along the body axes
    return c + hx * np.abs(L[:, 0]) + hy * np.abs(L[:, 1]) + hz * np.abs(L[:, 2])


def sdf(body, x, R, P):
    """Signed distance of the points ``P`` (rows) to the body's surface."""
    k, r, hx, hy, hz = body
    Q = (np.atleast_2d(P) - x) @ R       # body frame
    if k == SH_SPHERE:
        return np.linalg.norm(Q, axis=1) - r
    if k == SH_CAPSULE:
        z = np.clip(Q[:, 2], -hz, hz)
        return np.hypot(np.hypot(Q[:, 0], Q[:, 1]), Q[:, 2] - z) - r
    h = np.array([hx, hy, hz])
    d = np.abs(Q) - h
    out = np.linalg.norm(np.maximum(d, 0.0), axis=1)
    return out + np.minimum(np.max(d, axis=1), 0.0)


def _fib(n):
    i = np.arange(n) + 0.5
    phi = np.arccos(1 - 2 * i / n)
    th = math.pi * (1 + 5 ** 0.5) * i
    return np.c_[np.cos(th) * np.sin(phi), np.sin(th) * np.sin(phi), np.cos(phi)]


FIB = _fib(2000)


def brute_gap(bA, xA, RA, bB, xB, RB, starts=3):
    """Signed distance ``max_u [-h_A(-u) - h_B(u)]`` over unit axes ``u`` (from B into A)
    and its axis: dense sampling of the sphere of directions, then Nelder-Mead (which copes
    with the ridges of the separation) in a local chart around each of the best samples."""
    def sig(U):
        return -support(bA, xA, RA, -U) - support(bB, xB, RB, U)
    s = sig(FIB)
    best = -math.inf
    bu = None
    for j in np.argsort(s)[::-1][:starts]:
        u0 = FIB[j]
        e1 = np.cross(u0, [1.0, 0, 0] if abs(u0[0]) < 0.9 else [0, 1.0, 0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(u0, e1)

        def axis(p):
            u = u0 + p[0] * e1 + p[1] * e2
            return u / np.linalg.norm(u)

        def f(p):
            return -sig(axis(p)[None, :])[0]
        res = minimize(f, [0.0, 0.0], method="Nelder-Mead",
                       options={"xatol": 1e-11, "fatol": 1e-16, "maxiter": 2000,
                                "initial_simplex": [[0, 0], [0.05, 0], [0, 0.05]]})
        if -res.fun > best:
            best = -res.fun
            bu = axis(res.x)
    return best, bu


def frame(bA, stA, bB, stB):
    fr = np.zeros(N_FR)
    fe = np.zeros(N_FE, np.int64)
    g = pair_frame(*bA, stA, *bB, stB, fr, fe)
    assert g == fr[FR_GAP] or (np.isnan(g) and np.isnan(fr[FR_GAP]))
    return fr, fe


def random_pose_pair(rng, bA, bB, mode):
    """Two poses at a gap of roughly ``mode``: 'far', 'near' (touching to 1e-3 of the
    size), 'overlap'."""
    qA = random_quat(rng)
    qB = random_quat(rng)
    xA = rng.uniform(-1, 1, 3)
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    s = size_of(bA) + size_of(bB)
    # bisect the centre distance along u for a target gap measured by the kernel
    target = {"far": rng.uniform(0.05, 1.0) * s, "near": rng.uniform(-1e-3, 1e-3) * s,
              "overlap": -rng.uniform(0.01, 0.3) * min(size_of(bA), size_of(bB))}[mode]
    lo, hi = 0.0, 3.0 * s
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        fr, _ = frame(bA, row(xA, qA), bB, row(xA + mid * u, qB))
        if fr[FR_GAP] < target:
            lo = mid
        else:
            hi = mid
    return row(xA, qA), row(xA + 0.5 * (lo + hi) * u, qB)


def check_frame(bA, stA, bB, stB, fr, tol):
    """Witness points on the surfaces, ``pA - pB = g n``, ``n`` a unit vector along which
    the separation equals the gap: for ``g > 0`` these certify the exact distance (two
    surface points at distance ``g``, and no pair closer by the separating-axis
    inequality); for ``g <= 0`` that ``g`` is not above the signed distance."""
    RA = quat_mat(stA[3:7])
    RB = quat_mat(stB[3:7])
    n = fr[FR_NX:FR_NX + 3]
    pA = fr[FR_PAX:FR_PAX + 3]
    pB = fr[FR_PBX:FR_PBX + 3]
    g = fr[FR_GAP]
    assert abs(np.linalg.norm(n) - 1.0) < 1e-14
    assert abs(sdf(bA, stA[:3], RA, pA)[0]) < tol
    assert abs(sdf(bB, stB[:3], RB, pB)[0]) < tol
    assert np.linalg.norm(pA - pB - g * n) < tol
    sig = -support(bA, stA[:3], RA, -n[None, :])[0] - support(bB, stB[:3], RB, n[None, :])[0]
    assert abs(sig - g) < tol


# ---- the table ------------------------------------------------------------------------------

def test_table_covers_every_pair_and_kind_codes_agree():
    from rbimpact.kernels import stepper3d
    assert (SH_SPHERE, SH_BOX, SH_CAPSULE) == (stepper3d.SH_SPHERE, stepper3d.SH_BOX,
                                               stepper3d.SH_CAPSULE)
    assert (SH_SPHERE, SH_BOX, SH_CAPSULE) == (shapes3d._SH_SPHERE, shapes3d._SH_BOX,
                                               shapes3d._SH_CAPSULE)
    seen = {(a, b) for a, b, _, _ in PAIR_TABLE}
    assert seen == {(a, b) for a in range(3) for b in range(3)}
    for a, b, k, s in PAIR_TABLE:
        assert pair_kind(a, b) == (k, s)
        assert k != PK_NONE
    assert pair_kind(3, 0)[0] == PK_NONE and pair_kind(0, -1)[0] == PK_NONE
    fr, fe = frame((7, 0.1, 0, 0, 0), row((0, 0, 0), (1, 0, 0, 0)),
                   (SH_SPHERE, 0.1, 0, 0, 0), row((1, 0, 0), (1, 0, 0, 0)))
    assert np.isnan(fr[FR_GAP]) and list(fe) == [-1, -1, -1, -1]
    from rbimpact.kernels import pair2d
    assert (FE_A_KIND, FE_A_INDEX, FE_B_KIND, FE_B_INDEX, N_FE) == (
        pair2d.FE_A_KIND, pair2d.FE_A_INDEX, pair2d.FE_B_KIND, pair2d.FE_B_INDEX, pair2d.N_FE)


# ---- gap, normal, witness points against the brute force -----------------------------------

@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_gap_against_brute_force(pair):
    """Far, touching (to 1e-3 of the size) and overlapping poses, both orders: the gap
    against the brute-force maximum of the separation to 1e-14 of the size, the normal
    against its maximiser (to 1e-6: the separation is flat there), the frame's own
    certificate (``check_frame``)."""
    worst = 0.0
    for mode in ("far", "near", "overlap"):
        rng = np.random.default_rng(seed("brute", *pair, mode))
        for it in range(14):
            a, b = pair if it % 2 == 0 else pair[::-1]
            bA = random_body(rng, a)
            bB = random_body(rng, b)
            stA, stB = random_pose_pair(rng, bA, bB, mode)
            fr, fe = frame(bA, stA, bB, stB)
            size = size_of(bA) + size_of(bB)
            check_frame(bA, stA, bB, stB, fr, 1e-14 * size)
            gb, ub = brute_gap(bA, stA[:3], quat_mat(stA[3:7]), bB, stB[:3],
                               quat_mat(stB[3:7]))
            worst = max(worst, abs(fr[FR_GAP] - gb) / size)
            assert abs(fr[FR_GAP] - gb) < 1e-14 * size, (mode, it, fr[FR_GAP], gb)
            if abs(gb) > 1e-3 * size:
                assert np.linalg.norm(fr[FR_NX:FR_NX + 3] - ub) < 1e-6
    print(f"{pair}: worst gap error {worst:.1e} of the size")


@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_disjoint_certificate_many_poses(pair):
    """300 disjoint poses per pair (gaps from 1e-9 to 1 of the size): two surface points
    at distance ``g`` and a separating axis along which the separation is ``g``, which
    together certify the exact distance."""
    rng = np.random.default_rng(seed("cert", *pair))
    for it in range(300):
        a, b = pair if it % 2 == 0 else pair[::-1]
        bA = random_body(rng, a)
        bB = random_body(rng, b)
        stA, stB = random_pose_pair(rng, bA, bB, "far")
        if it % 3 == 0:      # push toward contact: gaps down to 1e-9 of the size
            d = stB[:3] - stA[:3]
            fr, _ = frame(bA, stA, bB, stB)
            u = d / np.linalg.norm(d)
            stB[:3] -= u * fr[FR_GAP] * (1 - 10.0 ** rng.uniform(-9, -1)) / max(
                -np.dot(u, fr[FR_NX:FR_NX + 3]), 0.2)
        fr, fe = frame(bA, stA, bB, stB)
        size = size_of(bA) + size_of(bB)
        check_frame(bA, stA, bB, stB, fr, 2e-14 * size)


# ---- near-parallel faces and edges, touching and overlapping -------------------------------

THETAS = (0.0, 1e-13, 1e-10, 1e-8, 1e-5, 1e-2)
GAPS = (1e-3, 1e-9, 0.0, -1e-9, -1e-3)


def parallel_case(kind, theta, gap, rng):
    """Two bodies whose faces, edges or axes are ``theta`` from parallel, the lower body A
    and B placed so that B's lowest point is at height ``gap`` above A's top (before the
    scene is rotated and moved at random)."""
    if kind == "face-face":
        bA = (SH_BOX, 0.0, 1.0, 0.8, 0.5)
        bB = (SH_BOX, 0.0, 0.4, 0.3, 0.2)
        qA = np.array([1.0, 0, 0, 0])
        qB = quat_mul(axis_quat(rng.normal(size=2).tolist() + [0.0], theta),
                      axis_quat((0, 0, 1), rng.uniform(0, 2 * np.pi)))
        off = np.r_[rng.uniform(-0.4, 0.4, 2), 0.0]
    elif kind == "edge-edge":
        bA = (SH_BOX, 0.0, 1.0, 0.5, 0.5)
        bB = (SH_BOX, 0.0, 0.7, 0.3, 0.3)
        qA = axis_quat((1, 0, 0), np.pi / 4)
        qB = quat_mul(axis_quat((0, 0, 1), theta), axis_quat((1, 0, 0), np.pi / 4))
        off = np.r_[rng.uniform(-0.2, 0.2), 0.0, 0.0]
    elif kind == "capsule-face":
        bA = (SH_BOX, 0.0, 1.0, 0.8, 0.5)
        bB = (SH_CAPSULE, 0.2, 0.0, 0.0, 0.6)
        qA = np.array([1.0, 0, 0, 0])
        qB = quat_mul(axis_quat((0, 1, 0), np.pi / 2 + theta),
                      axis_quat((1, 0, 0), 0.0))
        qB = quat_mul(axis_quat((0, 0, 1), rng.uniform(0, 2 * np.pi)), qB)
        off = np.r_[rng.uniform(-0.2, 0.2, 2), 0.0]
    elif kind == "capsule-edge":
        bA = (SH_BOX, 0.0, 1.0, 0.5, 0.5)
        bB = (SH_CAPSULE, 0.2, 0.0, 0.0, 0.6)
        qA = axis_quat((1, 0, 0), np.pi / 4)
        qB = quat_mul(axis_quat((0, 0, 1), theta), axis_quat((0, 1, 0), np.pi / 2))
        off = np.r_[rng.uniform(-0.2, 0.2), 0.0, 0.0]
    else:   # capsule-capsule
        bA = (SH_CAPSULE, 0.3, 0.0, 0.0, 1.0)
        bB = (SH_CAPSULE, 0.2, 0.0, 0.0, 0.6)
        qA = axis_quat((0, 1, 0), np.pi / 2)
        qB = quat_mul(axis_quat((0, 0, 1), theta), axis_quat((0, 1, 0), np.pi / 2))
        off = np.r_[rng.uniform(-0.2, 0.2), 0.0, 0.0]
    top = max(support(bA, np.zeros(3), quat_mat(qA), np.array([[0, 0, 1.0]])))
    low = -support(bB, np.zeros(3), quat_mat(qB), np.array([[0, 0, -1.0]]))[0]
    xB = off + np.r_[0, 0, top - low + gap]
    Q = random_quat(rng)
    M = quat_mat(Q)
    T = rng.uniform(-5, 5, 3)
    return bA, row(T, quat_mul(Q, qA)), bB, row(T + M @ xB, quat_mul(Q, qB))


@pytest.mark.parametrize("kind", ["face-face", "edge-edge", "capsule-face", "capsule-edge",
                                  "capsule-capsule"])
def test_near_parallel(kind):
    """Faces, edges and capsule axes 0 to 1e-2 rad from parallel, 1e-3 of the size apart
    down to 1e-3 overlapping: the gap not below the brute force's maximum by more than
    3e-14 of the size and never above the signed distance (the frame's certificate)."""
    rng = np.random.default_rng(seed("parallel", kind))
    worst = 0.0
    for theta in THETAS:
        for gap in GAPS:
            bA, stA, bB, stB = parallel_case(kind, theta, gap, rng)
            size = size_of(bA) + size_of(bB)
            for sw in (0, 1):
                if sw:
                    bA, stA, bB, stB = bB, stB, bA, stA
                fr, fe = frame(bA, stA, bB, stB)
                check_frame(bA, stA, bB, stB, fr, 3e-14 * size)
                gb, _ = brute_gap(bA, stA[:3], quat_mat(stA[3:7]), bB, stB[:3],
                                  quat_mat(stB[3:7]))
                tol = 3e-14 * size
                # check_frame certifies g <= the signed distance (= it when g > 0); the
                # brute force's maximum is a lower bound of it, found to about 1e-12 on
                # the sharp ridges of these poses
                assert fr[FR_GAP] > gb - tol, (theta, gap, fr[FR_GAP], gb)
                worst = max(worst, abs(fr[FR_GAP] - gb) / size)
    print(f"{kind}: largest |g - brute| {worst:.1e} of the size")
