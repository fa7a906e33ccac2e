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
from rbimpact.bench_pairs import random_body, random_quat
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
        for it in range(24):
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


def test_features_of_known_poses():
    """The features realising the gap in poses where they are known: a sphere over a box's
    +z face, a box corner down on a face, two boxes' edges crossing, a capsule's side
    across a box edge, a capsule's end against a sphere; and swapped."""
    q0 = np.array([1.0, 0, 0, 0])
    qe = axis_quat((1, 0, 0), np.pi / 4)                  # an edge along x up / down
    qc = quat_mul(axis_quat((1, 1, 0), math.atan(math.sqrt(2))), q0)   # a corner down
    box = (SH_BOX, 0.0, 0.5, 0.5, 0.5)
    cases = [
        ((box, row((0, 0, 0), q0)), ((SH_SPHERE, 0.3, 0, 0, 0), row((0.1, 0.2, 1.0), q0)),
         (FT_FACE, 5, FT_VERTEX, 0)),
        ((box, row((0, 0, 0), q0)), (box, row((0.1, 0.1, 1.5), qc)), (FT_FACE, 5, FT_VERTEX,
                                                                         None)),
        ((box, row((0, 0, 0), qe)),
         (box, row((0.1, 0, 1.6), quat_mul(axis_quat((0, 0, 1), 1.0), qe))),
         (FT_EDGE, None, FT_EDGE, None)),
        ((box, row((0, 0, 0), qe)),
         ((SH_CAPSULE, 0.2, 0, 0, 1.0), row((0, 0.1, 1.0), axis_quat((1, 0, 0), np.pi / 2))),
         (FT_EDGE, None, FT_EDGE, 0)),
        (((SH_CAPSULE, 0.2, 0, 0, 1.0), row((0, 0, 0), q0)),
         ((SH_SPHERE, 0.3, 0, 0, 0), row((0.05, 0, 2.0), q0)), (FT_VERTEX, 1, FT_VERTEX, 0)),
    ]
    for (bA, stA), (bB, stB), want in cases:
        for sw in (0, 1):
            fr, fe = frame(bA, stA, bB, stB) if sw == 0 else frame(bB, stB, bA, stA)
            got = tuple(fe) if sw == 0 else (fe[2], fe[3], fe[0], fe[1])
            assert fr[FR_GAP] > 0.0
            for w, g in zip(want, got):
                assert w is None or w == g, (want, got, sw)


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


# ---- time of impact -------------------------------------------------------------------------

from rbimpact.kernels.flight3d import (N_WS, ROT_AXISYM, ROT_GENERAL,  # noqa: E402
                                       ROT_SPHERICAL, pose_at)
from rbimpact.kernels.pair3d_toi import pair_toi  # noqa: E402
from rbimpact.kernels.toi2d import TOI_MISSED, TOI_NOT_CONVERGED, TOI_OK  # noqa: E402

RTOL, ATOL, GAP_TOL, MAXIT = 1e-14, 1e-15, 1e-9, 200000
ROT_TOL, ROT_MAX = 1e-12, 100000


def rotation_of(body):
    """``(rk, axis, I1, I2, I3)`` for a unit mass (``pair3d_input.rotation``: the rotation
    kind the 3D simulation gives the shape)."""
    from rbimpact.pair3d_input import rotation
    k, r, hx, hy, hz = body
    if k == SH_SPHERE:
        return rotation(shapes3d.Sphere(r))
    if k == SH_CAPSULE:
        return rotation(shapes3d.Capsule(2 * hz, r))
    return rotation(shapes3d.Box3D((2 * hx, 2 * hy, 2 * hz)))


class Flight:
    """The exact flight of a body (``flight3d.pose_at``, the motion the kernel sees)."""

    def __init__(self, body, st):
        self.body = body
        self.st = st
        self.rot = rotation_of(body)
        self.ws = np.zeros(N_WS)
        self.ws[0] = -1.0
        self.pose = np.zeros(19)

    def at(self, s):
        rk, ax, I1, I2, I3 = self.rot
        rc = pose_at(self.st, rk, ax, I1, I2, I3, self.ws, s, ROT_TOL, ROT_MAX, self.pose)
        assert rc == 0
        return self.pose.copy()


def gap_at(fA, fB, s):
    fr, _ = frame(fA.body, fA.at(s), fB.body, fB.at(s))
    return fr[FR_GAP], fr[FR_RATE]


def reference_toi(fA, fB, S, n_scan):
    """First root with g' < 0 by a dense scan of the gap (``n_scan`` samples) and a
    bisection to 1e-14 s; ``inf`` if the scan sees none."""
    ss = np.linspace(0.0, S, n_scan + 1)
    gp = gap_at(fA, fB, 0.0)[0]
    for k in range(1, len(ss)):
        g = gap_at(fA, fB, ss[k])[0]
        if gp > 0.0 and g <= 0.0:
            lo, hi = ss[k - 1], ss[k]
            while hi - lo > 1e-14:
                mid = 0.5 * (lo + hi)
                if gap_at(fA, fB, mid)[0] > 0.0:
                    lo = mid
                else:
                    hi = mid
            return 0.5 * (lo + hi)
        gp = g
    return math.inf


def run_toi(fA, fB, S, t0=0.0):
    bA, bB = fA.body, fB.body
    rA, rB = fA.rot, fB.rot
    wsA = np.zeros(N_WS)
    wsB = np.zeros(N_WS)
    return pair_toi(*bA, fA.st, rA[0], rA[1], rA[2], rA[3], rA[4], wsA,
                    *bB, fB.st, rB[0], rB[1], rB[2], rB[3], rB[4], wsB,
                    t0, S, RTOL, ATOL, GAP_TOL, MAXIT, ROT_TOL, ROT_MAX,
                    np.zeros(19), np.zeros(19))


def random_throw(rng, a, b, spin):
    """Two bodies ``3 size`` apart thrown at each other (with a lateral offset, so that
    some miss), spinning at ``spin`` (rad/s times size / speed)."""
    bA = random_body(rng, a)
    bB = random_body(rng, b)
    size = size_of(bA) + size_of(bB)
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    speed = rng.uniform(0.5, 2.0)
    xA = rng.uniform(-1, 1, 3)
    off = rng.normal(size=3) * 0.4 * size
    xB = xA + 2.0 * size * u + off
    w = lambda: rng.normal(size=3) * spin * speed / size
    g = np.array([0.0, 0.0, -9.81])
    stA = row(xA, random_quat(rng), v=speed * u + rng.normal(size=3) * 0.1, w=w(), a=g)
    stB = row(xB, random_quat(rng), v=-speed * u * rng.uniform(0, 1), w=w(),
              a=g * rng.uniform(0, 1))
    return Flight(bA, stA), Flight(bB, stB), 4.0 * size / speed


def aimed_throw(rng, a, b, spin):
    """``random_throw`` aimed so that most throws hit."""
    fA, fB, S = random_throw(rng, a, b, spin)
    size = size_of(fA.body) + size_of(fB.body)
    # aim: B's start so that the centres meet at S/2 up to a lateral miss of 0.3 size
    s = 0.5 * S
    stA, stB = fA.st, fB.st
    xa = stA[:3] + stA[7:10] * s + 0.5 * stA[13:16] * s * s
    xb = stB[:3] + stB[7:10] * s + 0.5 * stB[13:16] * s * s
    stB[:3] += (xa - xb) + rng.normal(size=3) * 0.3 * size
    return fA, fB, S


def check_toi(fA, fB, S, s, code, n_scan):
    """``s`` against the scan-and-bisection reference: equal to 1e-12 s when both find a
    root; a root the scan stepped over must be a real one (g = 0, g' < 0 there, and no
    sign change of the scan before it); none missed."""
    g0 = gap_at(fA, fB, 0.0)[0]
    if g0 < -GAP_TOL:
        assert (s, code) == (0.0, TOI_MISSED)
        return None
    assert code == TOI_OK
    ref = reference_toi(fA, fB, S, n_scan)
    assert not s > ref + 1e-12, (s, ref)         # no root missed
    if math.isfinite(s) and s < ref - 1e-12:
        # a contact shorter than the scan's step: a real root, with the gap positive before
        g, gd = gap_at(fA, fB, s)
        size = size_of(fA.body) + size_of(fB.body)
        assert abs(g) < 1e-12 * size and gd < 0.0, (s, g, gd)
        assert min(gap_at(fA, fB, x)[0] for x in np.linspace(0, s, 200)[:-1]) > 0.0
        return s
    assert s == ref or abs(s - ref) <= 1e-12, (s, ref)
    return ref


@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_toi_against_bisection(pair):
    """60 throws per pair (both orders), spins up to 100 (omega size / speed), under
    unequal gravity: the kernel's time against a dense scan (600 samples) and bisection of
    the gap along the exact flight, to 1e-12 s; no earlier root missed; the same time with
    the bodies swapped; Mirtich's closing-speed bound above |g'| along the flight."""
    rng = np.random.default_rng(seed("toi", *pair))
    hits = 0
    for it in range(60):
        a, b = pair if it % 2 == 0 else pair[::-1]
        spin = (0.0, 1.0, 10.0, 100.0)[it % 4]
        fA, fB, S = aimed_throw(rng, a, b, spin)
        s, code = run_toi(fA, fB, S)
        ref = check_toi(fA, fB, S, s, code, 600)
        hits += ref is not None and math.isfinite(ref)
        s2, code2 = run_toi(fB, fA, S)                 # swapping the bodies
        assert code2 == code and (s2 == s or abs(s2 - s) <= 1e-12), (s, s2)
        # Mirtich's linear bound dominates the gap rate along the flight
        if it % 4 == 0:
            from rbimpact.kernels.flight3d import rotation_bounds
            from rbimpact.kernels.pair3d_toi import closing_speed_bound
            from rbimpact.kernels.pair3d_shape import body_reach
            WA, AA = rotation_bounds(fA.st, *fA.rot[2:], fA.rot[0], fA.rot[1], S)
            WB, AB = rotation_bounds(fB.st, *fB.rot[2:], fB.rot[0], fB.rot[1], S)
            V = closing_speed_bound(fA.st, fB.st, body_reach(fA.body[0], *fA.body[2:])
                                    + fA.body[1], body_reach(fB.body[0], *fB.body[2:])
                                    + fB.body[1], WA * (1 + 1e-6), AA * (1 + 1e-6),
                                    WB * (1 + 1e-6), AB * (1 + 1e-6), S)
            rates = [abs(gap_at(fA, fB, x)[1]) for x in np.linspace(0, S, 50)]
            assert max(rates) <= V
    assert hits >= 30


def _closest_approach(fA, fB, S, n=400):
    """Time and gap of the closest approach on ``[0, S]`` (scan, then golden section)."""
    ss = np.linspace(0, S, n + 1)
    gs = [gap_at(fA, fB, s)[0] for s in ss]
    k = int(np.argmin(gs))
    lo, hi = ss[max(k - 1, 0)], ss[min(k + 1, n)]
    phi = (math.sqrt(5) - 1) / 2
    for _ in range(80):
        m1 = hi - phi * (hi - lo)
        m2 = lo + phi * (hi - lo)
        if gap_at(fA, fB, m1)[0] < gap_at(fA, fB, m2)[0]:
            hi = m2
        else:
            lo = m1
    sm = 0.5 * (lo + hi)
    return sm, gap_at(fA, fB, sm)[0]


@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_toi_grazing(pair):
    """Throws shifted so that the closest approach is a graze: 1e-7 of the size clear
    (no impact: the kernel must not report one there) or 1e-7 deep (an impact the kernel
    must find, at the first root, against a bisection between the start of the closest
    approach's neighbourhood and its minimum); spins 0 and 10."""
    rng = np.random.default_rng(seed("graze", *pair))
    done = [0, 0]
    for it in range(12):
        a, b = pair if it % 2 == 0 else pair[::-1]
        fA, fB, S = aimed_throw(rng, a, b, (0.0, 10.0)[it % 2])
        size = size_of(fA.body) + size_of(fB.body)
        target = (1e-7 if it % 4 < 2 else -1e-7) * size
        # shift B's start toward A by gm - target along the normal at the closest approach
        # (repeated: the closest approach moves with the shift)
        for _ in range(8):
            sm2, gm2 = _closest_approach(fA, fB, S)
            if abs(gm2 - target) < 0.1 * abs(target):
                break
            fr, _ = frame(fA.body, fA.at(sm2), fB.body, fB.at(sm2))
            fB.st[:3] += fr[FR_NX:FR_NX + 3] * (gm2 - target)
            fB.ws[0] = -1.0
        if gap_at(fA, fB, 0.0)[0] <= 0.0 or abs(gm2 - target) > 0.5 * abs(target) or \
                sm2 > 0.99 * S:
            continue    # no graze inside the window
        s, code = run_toi(fA, fB, S)
        assert code == TOI_OK
        done[target > 0] += 1
        if target > 0:
            # no root near the graze; any root reported must be a real one elsewhere
            if math.isfinite(s):
                g, gd = gap_at(fA, fB, s)
                assert abs(g) < 1e-12 * size and gd < 0.0 and abs(s - sm2) > 1e-6 * S
        else:
            lo, hi = 0.0, sm2
            ss = np.linspace(0, sm2, 401)
            for k in range(1, 401):           # the first sign change before the minimum
                if gap_at(fA, fB, ss[k])[0] <= 0.0:
                    lo, hi = ss[k - 1], ss[k]
                    break
            while hi - lo > 1e-14:
                mid = 0.5 * (lo + hi)
                if gap_at(fA, fB, mid)[0] > 0.0:
                    lo = mid
                else:
                    hi = mid
            assert abs(s - 0.5 * (lo + hi)) <= 1e-12, (s, lo, hi)
    print(pair, "grazes: hits", done[0], "misses", done[1])
    assert min(done) >= 2


# ---- gap rate, invariance, the bound of the time of impact ---------------------------------

@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_gap_rate_against_finite_difference(pair):
    """``g'`` of the frame against a central difference of the gap along the exact flight
    (step 1e-6 s) on 30 disjoint and overlapping poses per pair, spinning bodies; poses
    where the closest features change within the step are skipped (a kink of the gap)."""
    rng = np.random.default_rng(seed("rate", *pair))
    checked = 0
    for it in range(30):
        a, b = pair if it % 2 == 0 else pair[::-1]
        bA = random_body(rng, a)
        bB = random_body(rng, b)
        stA, stB = random_pose_pair(rng, bA, bB, ("far", "near", "overlap")[it % 3])
        stA[7:10] = rng.normal(size=3)
        stB[7:10] = rng.normal(size=3)
        stA[10:13] = rng.normal(size=3) * 2
        stB[10:13] = rng.normal(size=3) * 2
        fA = Flight(bA, stA)
        fB = Flight(bB, stB)
        h = 1e-6
        frs = [frame(bA, fA.at(s), bB, fB.at(s)) for s in (-h, 0.0, h)]
        if not all(np.array_equal(frs[1][1], f[1]) for f in frs):
            continue
        fd = (frs[2][0][FR_GAP] - frs[0][0][FR_GAP]) / (2 * h)
        rate = frs[1][0][FR_RATE]
        assert abs(fd - rate) < 1e-7 * (1.0 + abs(rate)), (it, fd, rate)
        checked += 1
    assert checked >= 20


SWAP_ULPS = 16
"""The gap of (A, B) and of (B, A) agree to this many ulps of the sum of the bodies' sizes:
each frame brings the other body into its own coordinates (a quaternion product, a
rotation, a projection: about ten roundings at the coordinates' scale), and swapped the
roundings differ. 4 held on earlier machines; an AVX-512 machine, whose compiled code
contracts other products into fused multiply-adds, gave 6 (box-box, 0.997 m apart)."""


@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_invariance_rigid_motion_and_swap(pair):
    """Moving the whole scene (rotation, then translation by 1 km) moves the frame along
    (gap to 4 ulps of the coordinates' scale, normal and witnesses rotated); swapping A and B
    keeps the gap (to ``SWAP_ULPS`` of the bodies' size), flips the normal, swaps witnesses
    and features; scaling the scene by 1e-6 and 1e6 scales the gap and keeps the normal and
    features."""
    rng = np.random.default_rng(seed("inv", *pair))
    for it in range(30):
        a, b = pair if it % 2 == 0 else pair[::-1]
        bA = random_body(rng, a)
        bB = random_body(rng, b)
        stA, stB = random_pose_pair(rng, bA, bB, ("far", "near", "overlap")[it % 3])
        fr, fe = frame(bA, stA, bB, stB)
        size = size_of(bA) + size_of(bB)
        # swap
        fs, es = frame(bB, stB, bA, stA)
        assert abs(fs[FR_GAP] - fr[FR_GAP]) <= SWAP_ULPS * EPS * size
        assert np.allclose(fs[FR_NX:FR_NX + 3], -fr[FR_NX:FR_NX + 3], atol=1e-12)
        if abs(fr[FR_GAP]) > 1e-6 * size:   # unique closest points
            assert np.allclose(fs[FR_PAX:FR_PAX + 3], fr[FR_PBX:FR_PBX + 3], atol=1e-9)
            assert np.allclose(fs[FR_PBX:FR_PBX + 3], fr[FR_PAX:FR_PAX + 3], atol=1e-9)
            assert list(es) == [fe[2], fe[3], fe[0], fe[1]]
        # rigid motion
        Q = random_quat(rng)
        M = quat_mat(Q)
        T = rng.normal(size=3) * 1000.0
        mA = row(M @ stA[:3] + T, quat_mul(Q, stA[3:7]))
        mB = row(M @ stB[:3] + T, quat_mul(Q, stB[3:7]))
        fm, em = frame(bA, mA, bB, mB)
        assert abs(fm[FR_GAP] - fr[FR_GAP]) <= 4 * EPS * (size + np.linalg.norm(T))
        assert np.allclose(fm[FR_NX:FR_NX + 3], M @ fr[FR_NX:FR_NX + 3], atol=1e-12)
        if abs(fr[FR_GAP]) > 1e-6 * size:
            assert np.allclose(fm[FR_PAX:FR_PAX + 3], M @ fr[FR_PAX:FR_PAX + 3] + T,
                               atol=1e-9)
            assert list(em) == list(fe)
        # scale: the whole scene 1e-6 and 1e6 times as large (every tolerance is relative)
        for k in (1e-6, 1e6):
            sA = (bA[0], bA[1] * k, bA[2] * k, bA[3] * k, bA[4] * k)
            sB = (bB[0], bB[1] * k, bB[2] * k, bB[3] * k, bB[4] * k)
            fk, ek = frame(sA, row(stA[:3] * k, stA[3:7]), sB, row(stB[:3] * k, stB[3:7]))
            assert abs(fk[FR_GAP] / k - fr[FR_GAP]) <= 1e-14 * size
            assert np.allclose(fk[FR_NX:FR_NX + 3], fr[FR_NX:FR_NX + 3], atol=1e-12)
            if abs(fr[FR_GAP]) > 1e-6 * size:
                assert list(ek) == list(fe)


def test_toi_bound_dominates_second_derivative():
    """The bound ``M`` of ``pair3d_toi.axis_bound`` against a finite-difference second
    derivative of every core-vertex term ``g_kl`` along the axis path of each mode (world,
    turning with A, with B, at a constant rate), on spinning boxes and capsules."""
    from rbimpact.kernels.pair3d_shape import body_reach, core_vertex, n_core
    from rbimpact.kernels.pair3d_toi import AX_A, AX_B, AX_EDGE, AX_WORLD, axis_bound
    from rbimpact.kernels.flight3d import rotation_bounds
    rng = np.random.default_rng(seed("bound"))
    ratios = []
    for it in range(24):
        a, b = [("box", "box"), ("box", "capsule"), ("capsule", "capsule")][it % 3]
        fA, fB, S = random_throw(rng, a, b, 10.0)
        H = 0.05 * S
        (kA, _, *hA), (kB, _, *hB) = fA.body, fB.body
        KA = body_reach(kA, *hA)
        KB = body_reach(kB, *hB)
        WA, AA = rotation_bounds(fA.st, *fA.rot[2:], fA.rot[0], fA.rot[1], S)
        WB, AB = rotation_bounds(fB.st, *fB.rot[2:], fB.rot[0], fB.rot[1], S)
        n0 = rng.normal(size=3)
        n0 /= np.linalg.norm(n0)
        c = rng.normal(size=3) * 5
        for mode in (AX_WORLD, AX_A, AX_B, AX_EDGE):
            pA0, pB0 = fA.at(0.0), fB.at(0.0)
            cc = {AX_WORLD: np.zeros(3), AX_A: pA0[10:13], AX_B: pB0[10:13], AX_EDGE: c}[mode]
            if mode == AX_EDGE:         # the solver keeps c normal to n
                cc = cc - (cc @ n0) * n0
            M = axis_bound(mode, *cc, *n0, fA.st, fB.st, 0.0, H, pA0, pB0, KA, WA, AA, KB,
                           WB, AB)
            RA0 = quat_mat(pA0[3:7])
            RB0 = quat_mat(pB0[3:7])

            def terms(s):
                pa, pb = fA.at(s), fB.at(s)
                if mode == AX_A:
                    n = quat_mat(pa[3:7]) @ RA0.T @ n0
                elif mode == AX_B:
                    n = quat_mat(pb[3:7]) @ RB0.T @ n0
                elif mode == AX_EDGE:
                    n = quat_mat(axis_quat(cc, np.linalg.norm(cc) * s)) @ n0
                else:
                    n = n0
                RA = quat_mat(pa[3:7])
                RB = quat_mat(pb[3:7])
                out = []
                for k in range(n_core(kA)):
                    ak = pa[:3] + RA @ np.array(core_vertex(kA, *hA, k))
                    for l in range(n_core(kB)):
                        bl = pb[:3] + RB @ np.array(core_vertex(kB, *hB, l))
                        out.append(n @ (ak - bl))
                return np.array(out)
            h = 1e-3 * H
            worst = 0.0
            for s in np.linspace(0.0, H - 2 * h, 12):
                d2 = (terms(s + 2 * h) - 2 * terms(s + h) + terms(s)) / (h * h)
                worst = max(worst, np.max(np.abs(d2)))
            assert worst <= M * (1 + 1e-3) + 1e-6, (mode, worst, M)
            ratios.append(worst / M)
    print("largest |g_kl''| / M:", max(ratios), "median", np.median(ratios))
    assert max(ratios) > 0.05       # the bound is not vacuous


# ---- the Python checks ---------------------------------------------------------------------

def test_input_checks():
    from rbimpact.pair3d_input import body_geometry, rotation, shape_geometry, state
    assert shape_geometry(shapes3d.Sphere(0.5)) == (SH_SPHERE, 0.5, 0.0, 0.0, 0.0)
    assert shape_geometry(shapes3d.Box3D((1, 2, 3))) == (SH_BOX, 0.0, 0.5, 1.0, 1.5)
    assert shape_geometry(shapes3d.Capsule(2.0, 0.3)) == (SH_CAPSULE, 0.3, 0.0, 0.0, 1.0)
    bad = [((5,), "shape kind"), ((True,), "shape kind"),
           ((SH_SPHERE, 0.0), "radius"), ((SH_SPHERE, -1.0), "radius"),
           ((SH_SPHERE, math.nan), "radius"), ((SH_SPHERE, 1.0, (0, 0, 1)), "half"),
           ((SH_BOX, 0.0, (1, 0, 1)), "half"), ((SH_BOX, 0.1, (1, 1, 1)), "radius"),
           ((SH_BOX, 0.0, (1, 1)), "half"), ((SH_BOX, 0.0, (1, math.inf, 1)), "finite"),
           ((SH_CAPSULE, 0.2, (0, 0, 0)), "half"), ((SH_CAPSULE, 0.2, (1, 0, 1)), "axis"),
           ((SH_CAPSULE, 0.0, (0, 0, 1)), "radius"), ((SH_BOX, 0.0, "abc"), "half")]
    for args, word in bad:
        with pytest.raises(ValueError, match=word):
            body_geometry(*args)
    st = state([1, 2, 3, 1, 0, 0, 0])
    assert st.shape == (19,) and st[3] == 1.0 and not st[7:].any()
    for v, word in [([0, 0, 0, 2, 0, 0, 0], "length 1"), ([0, 0, 0, 0, 0, 0, 0], "length 1"),
                    ([0, 0, 0, 1, 0, 0], "7 numbers"), ([0, 0, math.nan, 1, 0, 0, 0], "finite"),
                    ("x", "7 numbers")]:
        with pytest.raises(ValueError, match=word):
            state(v)
    assert rotation(shapes3d.Sphere(1.0))[0] == ROT_SPHERICAL
    assert rotation(shapes3d.Capsule(1.0, 0.2))[:2] == (ROT_AXISYM, 2)
    assert rotation(shapes3d.Box3D((1, 2, 3)))[0] == ROT_GENERAL
    with pytest.raises(ValueError, match="mass"):
        rotation(shapes3d.Sphere(1.0), -1.0)
    # the checked encodings drive the kernels
    bA = body_geometry(SH_BOX, 0.0, (0.5, 0.5, 0.5))
    bB = body_geometry(SH_CAPSULE, 0.25, (0, 0, 0.5))
    fr, fe = frame(bA, state([0, 0, 0, 1, 0, 0, 0]), bB, state([2, 0, 0, 1, 0, 0, 0]))
    assert fr[FR_GAP] == pytest.approx(1.25, abs=1e-15)
    assert list(fe) == [FT_FACE, 1, FT_VERTEX, 0]     # lowest-dimensional: an end cap


# ---- contact manifolds ----------------------------------------------------------------------

from rbimpact.kernels.pair3d_manifold import (MAX_MF, MF_GAP, MF_PAX, MF_PBX,  # noqa: E402
                                              N_MF, manifold_slab, pair_manifold)


def manifold(bA, stA, bB, stB, slab=None):
    if slab is None:
        slab = manifold_slab(*bA, *bB)
    fr = np.zeros(N_FR)
    fe = np.zeros(N_FE, np.int64)
    mf = np.full((MAX_MF, N_MF), np.nan)
    n = pair_manifold(*bA, stA, *bB, stB, slab, fr, fe, mf)
    return n, mf[:n], fr, fe


def _in_box(body, st, P, tol):
    """Points P inside-or-on the box body (body frame |x_i| <= h_i + tol)."""
    Q = (P - st[:3]) @ quat_mat(st[3:7])
    return np.all(np.abs(Q) <= np.array(body[2:]) + tol, axis=1)


def resting_case(rng, other, tilt, gap):
    """Body B (a box or a capsule) lying on the top face of box A, tilted by ``tilt``
    about a random horizontal axis, its lowest point ``gap`` above; scene moved at random."""
    bA = (SH_BOX, 0.0, *rng.uniform(0.4, 1.0, 3))
    if other == "box":
        bB = (SH_BOX, 0.0, *rng.uniform(0.2, 0.8, 3))
        q = axis_quat((0, 0, 1), rng.uniform(0, 2 * np.pi))
    elif other == "edge":
        bB = (SH_BOX, 0.0, *rng.uniform(0.2, 0.8, 3))
        q = quat_mul(axis_quat((0, 0, 1), rng.uniform(0, 2 * np.pi)),
                     axis_quat((1, 0, 0), rng.uniform(0.3, 1.2)))
    else:
        bB = (SH_CAPSULE, rng.uniform(0.05, 0.3), 0.0, 0.0, rng.uniform(0.2, 0.8))
        q = quat_mul(axis_quat((0, 0, 1), rng.uniform(0, 2 * np.pi)),
                     axis_quat((0, 1, 0), np.pi / 2))
    ax = rng.normal(size=2)
    qB = quat_mul(axis_quat([ax[0], ax[1], 0.0], tilt), q)
    low = -support(bB, np.zeros(3), quat_mat(qB), np.array([[0, 0, -1.0]]))[0]
    # the lowest feature's centre (corners, or cap centres, within 1e-6 of the lowest)
    RB = quat_mat(qB)
    if bB[0] == SH_BOX:
        V = np.array([[sx * bB[2], sy * bB[3], sz * bB[4]] for sx in (-1, 1)
                      for sy in (-1, 1) for sz in (-1, 1)]) @ RB.T
    else:
        V = np.array([[0, 0, -bB[4]], [0, 0, bB[4]]]) @ RB.T
    foot = V[V[:, 2] < V[:, 2].min() + 1e-6].mean(axis=0)
    xB = np.r_[rng.uniform(-0.6, 0.6, 2) * np.array(bA[2:4]) - foot[:2], bA[4] - low + gap]
    Q = random_quat(rng)
    M = quat_mat(Q)
    T = rng.uniform(-3, 3, 3)
    return bA, row(T, Q), bB, row(T + M @ xB, quat_mul(Q, qB))


def check_manifold(bA, stA, bB, stB, n, mf, fr, slab, tol=None):
    """Every point on both surfaces with ``pA - pB = g_k n`` (to ``tol``, default 1e-13 of
    the size) and its gap within the slab above the frame's."""
    size = size_of(bA) + size_of(bB)
    tol = 1e-13 * size if tol is None else tol
    nrm = fr[FR_NX:FR_NX + 3]
    assert 1 <= n <= MAX_MF
    for k in range(n):
        pA, pB, g = mf[k, MF_PAX:MF_PAX + 3], mf[k, MF_PBX:MF_PBX + 3], mf[k, MF_GAP]
        assert abs(sdf(bA, stA[:3], quat_mat(stA[3:7]), pA)[0]) < tol
        assert abs(sdf(bB, stB[:3], quat_mat(stB[3:7]), pB)[0]) < tol
        assert np.linalg.norm(pA - pB - g * nrm) < tol
        assert fr[FR_GAP] - tol <= g <= fr[FR_GAP] + slab + tol


@pytest.mark.parametrize("other", ["box", "edge", "capsule"])
def test_manifold_resting(other):
    """A box face, a box edge or a capsule resting on a box face (tilts below the slab,
    gaps from 1e-9 of the size apart to 1e-9 overlapping): the expected number of points
    (face: 3 to 8, edge and capsule: 2, or 1 for a capsule hanging over a side), every
    point on both surfaces with ``pA - pB = g_k n``, and the points span the contact: every
    sample of the reference face under the incident face (or segment) lies in their hull."""
    from scipy.spatial import Delaunay
    rng = np.random.default_rng(seed("manifold", other))
    counts = []
    for it in range(30):
        tilt = (0.0, 1e-14, 1e-12)[it % 3]
        gap = (1e-9, 0.0, -1e-9)[it % 3 - 1]
        bA, stA, bB, stB = resting_case(rng, other, tilt, gap)
        size = size_of(bA) + size_of(bB)
        slab = manifold_slab(*bA, *bB)
        n, mf, fr, fe = manifold(bA, stA, bB, stB)
        check_manifold(bA, stA, bB, stB, n, mf, fr, slab)
        counts.append(n)
        # the contact region, sampled on A's top face (the reference frame: A's axes)
        RA = quat_mat(stA[3:7])
        h = np.array(bA[2:])
        S = np.c_[rng.uniform(-1, 1, (4000, 2)) * h[:2], np.full(4000, h[2])]
        W = stA[:3] + S @ RA.T                       # world points on A's top face
        up = RA[:, 2]
        if other == "capsule":
            # under the capsule's core segment: within 1e-3 of its vertical projection
            RB = quat_mat(stB[3:7])
            a0 = stB[:3] - RB[:, 2] * bB[4]
            d = 2 * RB[:, 2] * bB[4]
            rel = W - a0
            t = np.clip((rel @ d - (rel @ up) * (d @ up)) / (d @ d - (d @ up) ** 2), 0, 1)
            lat = rel - np.outer(t, d)
            lat -= np.outer(lat @ up, up)
            under = (np.linalg.norm(lat, axis=1) < 1e-3 * size) & (t > 0) & (t < 1)
            if n == 2:
                seg = mf[:, MF_PAX:MF_PAX + 3]
                e = seg[1] - seg[0]
                tt = (W[under] - seg[0]) @ e / (e @ e)
                assert np.all((tt > -1e-9) & (tt < 1 + 1e-9))
            continue
        # B's footprint: the top face points whose vertical line meets B within slab
        Q = (W + up * (fr[FR_GAP] + 0.5 * slab) - stB[:3]) @ quat_mat(stB[3:7])
        under = np.all(np.abs(Q) <= np.array(bB[2:]) * (1 + 1e-9), axis=1)
        P = mf[:, MF_PAX:MF_PAX + 3]
        L2 = (P - stA[:3]) @ RA[:, :2]                # manifold points in face coordinates
        if other == "edge":
            assert n == 2
            # the two points are the ends of the part of B's lowest edge over A's face
            RB = quat_mat(stB[3:7])
            V = stB[:3] + np.array([[sx * bB[2], sy * bB[3], sz * bB[4]] for sx in (-1, 1)
                                    for sy in (-1, 1) for sz in (-1, 1)]) @ RB.T
            hgt = (V - stA[:3]) @ up
            e0, e1 = V[np.argsort(hgt)[:2]]
            t = np.linspace(0, 1, 2001)
            E = e0 + np.outer(t, e1 - e0)
            over = np.all(np.abs((E - stA[:3]) @ RA[:, :2]) <= h[:2], axis=1)
            pts = mf[:, MF_PBX:MF_PBX + 3]
            tp = np.sort((pts - e0) @ (e1 - e0) / ((e1 - e0) @ (e1 - e0)))
            assert abs(tp[0] - t[over].min()) < 1e-3 and abs(tp[1] - t[over].max()) < 1e-3
            continue
        assert n >= 3
        inside = Delaunay(L2).find_simplex(S[under, :2], tol=1e-9) >= 0
        assert np.all(inside), (it, n, np.sum(~inside))
    print(other, "counts", counts)


def test_manifold_tilted_and_single():
    """A box tilted well above the slab touches with one corner (one point); a tilt of
    1e-6 rad over a face of extent ~1 exceeds the default slab (1e-9 of the size), so the
    face is not flat (fewer than 4 points) unless the slab is widened to 1e-5 of the size;
    sphere and capsule pairs give the frame's single witness pair."""
    rng = np.random.default_rng(seed("manifold-tilt"))
    for it in range(10):
        bA, stA, bB, stB = resting_case(rng, "box", 0.3, 1e-6)
        n, mf, fr, _ = manifold(bA, stA, bB, stB)
        assert n == 1
        check_manifold(bA, stA, bB, stB, n, mf, fr, 0.0)
        bA, stA, bB, stB = resting_case(rng, "box", 1e-6, 0.0)
        size = size_of(bA) + size_of(bB)
        n, mf, fr, _ = manifold(bA, stA, bB, stB)
        assert n < 4
        n, mf, fr, _ = manifold(bA, stA, bB, stB, slab=1e-5 * size)
        assert n >= 4
        check_manifold(bA, stA, bB, stB, n, mf, fr, 1e-5 * size)
    for pair in [("sphere", "box"), ("capsule", "capsule"), ("sphere", "capsule")]:
        bA = random_body(rng, pair[0])
        bB = random_body(rng, pair[1])
        stA, stB = random_pose_pair(rng, bA, bB, "near")
        n, mf, fr, _ = manifold(bA, stA, bB, stB)
        assert n == 1 and np.array_equal(mf[0, MF_PAX:MF_PAX + 3], fr[FR_PAX:FR_PAX + 3])


def test_toi_special_cases():
    """Touching and separating at s = 0 (no impact there), touching and approaching (impact
    at 0), overlapping (TOI_MISSED), an empty window, a box sliding flat over a box at a
    constant gap of 1e-12 (no impact, in few steps), a face falling flat onto a face (exact,
    few steps), fast spin (omega size / speed = 1000) against the scan (and the
    integrator's step limit reported for a general box), an unknown pair of kinds (NaN,
    TOI_NOT_CONVERGED)."""
    import rbimpact.kernels.pair3d_toi as pt
    bA = (SH_BOX, 0.0, 1.0, 1.0, 0.5)
    bB = (SH_BOX, 0.0, 0.5, 0.5, 0.5)
    q = np.array([1.0, 0, 0, 0])

    def toi(stA, stB, S=1.0, maxit=MAXIT, a=bA, b=bB):
        fA, fB = Flight(a, stA), Flight(b, stB)
        rA, rB = fA.rot, fB.rot
        return pt.pair_toi(*a, stA, rA[0], rA[1], *rA[2:], np.zeros(N_WS),
                           *b, stB, rB[0], rB[1], *rB[2:], np.zeros(N_WS),
                           0.0, S, RTOL, ATOL, GAP_TOL, maxit, ROT_TOL, ROT_MAX,
                           np.zeros(19), np.zeros(19))
    # touching (gap 0), separating / approaching
    assert toi(row((0, 0, 0), q), row((0, 0, 1.0), q, v=(0, 0, 1))) == (math.inf, TOI_OK)
    assert toi(row((0, 0, 0), q), row((0, 0, 1.0), q, v=(0, 0, -1))) == (0.0, TOI_OK)
    assert toi(row((0, 0, 0), q), row((0, 0, 0.9), q)) == (0.0, TOI_MISSED)
    assert toi(row((0, 0, 0), q), row((0, 0, 2.0), q, v=(0, 0, -1)), S=0.0)[0] == math.inf
    # sliding flat at a constant gap under the same gravity: no impact, few steps
    g = (0, 0, -9.81)
    s, code = toi(row((0, 0, 0), q, a=g), row((0, 0, 1.0 + 1e-12), q, v=(0.3, 0.1, 0), a=g),
                  maxit=200)
    assert (s, code) == (math.inf, TOI_OK)
    # a cube (spherical inertia) spinning about the normal on a face at a gap of 1e-12,
    # and a capsule lying on it spinning about the normal: no impact, few steps
    cube = (SH_BOX, 0.0, 0.5, 0.5, 0.5)
    assert toi(row((0, 0, 0), q), row((0, 0, 1.0 + 1e-12), q, v=(0.3, 0.1, 0), w=(0, 0, 30)),
               maxit=200, b=cube) == (math.inf, TOI_OK)
    cap = (SH_CAPSULE, 0.2, 0.0, 0.0, 0.6)
    assert toi(row((0, 0, 0), q), row((0, 0, 0.7 + 1e-12), axis_quat((0, 1, 0), np.pi / 2),
                                      w=(0, 0, 30)), maxit=200, b=cap) == (math.inf, TOI_OK)
    # a face falling flat onto a face: exact time, few steps
    st = row((0, 0, 1.5), q, v=(0, 0, -1.0))
    s, code = toi(row((0, 0, 0), q), st, maxit=40)
    assert code == TOI_OK and abs(s - 0.5) < 1e-14
    # fast spin (capsules: closed-form rotation; a box of three different moments spinning
    # 1000 turns would exceed the integrator's ROT_MAX steps: TOI_ROT_FAILED, by design)
    rng = np.random.default_rng(seed("fastspin"))
    for it in range(6):
        fA, fB, S = aimed_throw(rng, "capsule", ("capsule", "sphere")[it % 2], 1000.0)
        s, code = run_toi(fA, fB, S)
        check_toi(fA, fB, S, s, code, 4000)
    from rbimpact.kernels.toi3d import TOI_ROT_FAILED
    fA, fB, S = aimed_throw(rng, "box", "box", 1000.0)
    assert run_toi(fA, fB, S)[1] == TOI_ROT_FAILED
    # unknown kinds
    s, code = toi(row((0, 0, 0), q), row((0, 0, 3.0), q), a=(5, 0.0, 1, 1, 1))
    assert math.isnan(s) and code == TOI_NOT_CONVERGED


def test_manifold_capsules_side_by_side():
    """Two capsules lying side by side (axes 0 to 1e-12 rad from parallel, gaps 1e-9 of the
    size apart to 1e-9 overlapping, random axial offsets): two points at the ends of the
    common axial extent of the cores, on both surfaces, ``pA - pB = g_k n`` (to the slab:
    the tilt times the length), gaps within the slab of the frame's; crossing capsules give
    one point."""
    rng = np.random.default_rng(seed("manifold-capsules"))
    for it in range(30):
        rA_, rB_ = rng.uniform(0.05, 0.3, 2)
        hA, hB = rng.uniform(0.2, 1.0, 2)
        bA = (SH_CAPSULE, rA_, 0.0, 0.0, hA)
        bB = (SH_CAPSULE, rB_, 0.0, 0.0, hB)
        tilt = (0.0, 1e-14, 1e-12)[it % 3]
        gap = (1e-9, 0.0, -1e-9)[(it // 3) % 3]
        off = rng.uniform(-0.8, 0.8) * (hA + hB)
        qB = axis_quat(rng.normal(size=3), tilt)
        xB = np.r_[rA_ + rB_ + gap, 0.0, off]
        Q = random_quat(rng)
        T = rng.uniform(-3, 3, 3)
        stA = row(T, Q)
        stB = row(T + quat_mat(Q) @ xB, quat_mul(Q, qB))
        size = size_of(bA) + size_of(bB)
        slab = manifold_slab(*bA, *bB)
        n, mf, fr, fe = manifold(bA, stA, bB, stB)
        lo, hi = max(-hA, off - hB), min(hA, off + hB)
        if lo >= hi:
            assert n == 1
            continue
        assert n == 2
        # tilted side by side: the residuals are of the tilt times the length (<= slab)
        check_manifold(bA, stA, bB, stB, n, mf, fr, slab, tol=slab + 1e-13 * size)
        ax = quat_mat(Q)[:, 2]
        z = np.sort((mf[:, MF_PAX:MF_PAX + 3] - T) @ ax)
        assert abs(z[0] - lo) < 1e-12 * size and abs(z[1] - hi) < 1e-12 * size
    bA = (SH_CAPSULE, 0.2, 0.0, 0.0, 1.0)
    n, mf, fr, fe = manifold(bA, row((0, 0, 0), (1, 0, 0, 0)), bA,
                             row((0.4, 0, 0), axis_quat((1, 0, 0), 0.5)))
    assert n == 1


def test_toi_scale_invariance():
    """Lengths, speeds and accelerations scaled by 1e-3 and 1e3 (spins kept): the same time
    of impact to 1e-12 s (the bound and the steps scale; the time tolerances do not)."""
    rng = np.random.default_rng(seed("toi-scale"))
    for it in range(12):
        pair = PAIRS[it % len(PAIRS)]
        fA, fB, S = aimed_throw(rng, *pair, (0.0, 10.0)[it % 2])
        s, code = run_toi(fA, fB, S)
        for k in (1e-3, 1e3):
            def scaled(f):
                b = f.body
                st = f.st.copy()
                for c in (slice(0, 3), slice(7, 10), slice(13, 16)):
                    st[c] *= k
                return Flight((b[0], b[1] * k, b[2] * k, b[3] * k, b[4] * k), st)
            sk, ck = run_toi(scaled(fA), scaled(fB), S)
            assert ck == code and (sk == s or abs(sk - s) <= 1e-12), (pair, k, s, sk)
