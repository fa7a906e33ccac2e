"""The contact rows of 2D clusters built from the shapes (``kernels/cluster2d_rows.py``,
issue 16 item 2): normal cones of polygon, rod and disk vertices, and the rows of two
touching rounded polygons in every configuration (vertex on face, mirrored, face on face,
rounded vertex on vertex, two sharp corners).

Checked against independent computations: the pair frame (``pair2d.frame_rel``: gap and
normal by the separating-axis calculus) for the normal, a brute-force distance between the
two outlines (dense boundary samples) for the contact points, and ``cluster2d``'s own
kinematics of each row (``cluster_rates``: its gap must be 0 and its normal the pair's)."""
import math

import numpy as np
import pytest

from rbimpact.kernels import cluster2d as C
from rbimpact.kernels import cluster2d_rows as R
from rbimpact.kernels.pair2d import frame_rel
from rbimpact.kernels.pair2d_shape import SH_DISK, SH_POLY

BOX = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
HEX = [(math.cos(a), math.sin(a)) for a in np.arange(6) * math.pi / 3]


def shape(kind, verts, rad, scale=1.0):
    return kind, rad * scale, np.array(verts, float) * scale


SHAPES = {
    "box": shape(SH_POLY, [(-0.3, -0.1), (0.3, -0.1), (0.3, 0.1), (-0.3, 0.1)], 0.0),
    "hexagon": shape(SH_POLY, HEX, 0.0, 0.2),
    "capsule": shape(SH_POLY, [(-0.25, 0.0), (0.25, 0.0)], 0.07),
    "rod": shape(SH_POLY, [(-0.3, 0.0), (0.3, 0.0)], 0.0),
    "disk": shape(SH_DISK, [(0.0, 0.0)], 0.15),
}


def state(x, y, a):
    s = np.zeros(9)
    s[:3] = x, y, a
    return s


def outline(sh, st, n=4000):
    """Dense samples of the boundary of a rounded core (world)."""
    kind, rad, V = sh
    c, s = math.cos(st[2]), math.sin(st[2])
    W = V @ np.array([[c, s], [-s, c]]) + st[:2]
    pts = []
    if len(W) >= 2:
        m = len(W) if len(W) >= 3 else 1
        for i in range(m):
            p, q = W[i], W[(i + 1) % len(W)]
            u = np.linspace(0.0, 1.0, n // 4)[:, None]
            e = q - p
            nrm = np.array([e[1], -e[0]]) / np.hypot(*e)
            for sg in ((1.0, -1.0) if len(W) == 2 else (1.0,)):
                pts.append(p + u * e + sg * rad * nrm)
    if rad > 0.0:
        th = np.linspace(0.0, 2 * math.pi, n)[:, None]
        for p in W:
            pts.append(p + rad * np.hstack([np.cos(th), np.sin(th)]))
    else:
        pts.append(W)
    return np.vstack(pts)


def frame(A, sa, B, sb):
    V = np.vstack([A[2], B[2]])
    return V, frame_rel(A[0], A[1], 0.0, 0.0, V, 0, len(A[2]), sa[2], B[0], B[1], 0.0, 0.0, V,
                        len(A[2]), len(B[2]), sb[0] - sa[0], sb[1] - sa[1], sb[2])


def touching(A, B, angle_a, angle_b, direction):
    """A placed along ``direction`` from B (at the origin) and moved along the pair's
    normal until the gap is 0 (to round-off)."""
    sa = state(direction[0], direction[1], angle_a)
    sb = state(0.0, 0.0, angle_b)
    for _ in range(4):
        V, fr = frame(A, sa, B, sb)
        g, nx, ny = fr[0], fr[1], fr[2]
        sa[0] -= g * nx
        sa[1] -= g * ny
    return V, sa, sb


def rows(A, sa, B, sb, tol=1e-9, mu=0.4):
    V, fr = frame(A, sa, B, sb)
    act = np.zeros((2, C.N_CC))
    cand = np.zeros((2, C.N_CC))
    na, nc = R.pair_rows(V, 0, len(A[2]), A[1], sa, 0, len(A[2]), len(B[2]), B[1], sb, 1,
                         fr[1], fr[2], tol, mu, act, cand)
    return fr, na, nc, act, cand


def kin(sa, sb, table, k):
    bodies = np.zeros((2, C.N_CB))
    bodies[0, :6] = sa[:6]
    bodies[1, :6] = sb[:6]
    bodies[:, C.CB_M] = 1.0
    bodies[:, C.CB_I] = 1.0
    out = np.zeros(7)
    C.cluster_rates(bodies, table, k, np.zeros((2, 3)), np.zeros(C.work_size(2, 0)), out)
    return out


def test_vertex_cones():
    V = np.array(BOX, float)
    got = [R.vertex_cone(V, 0, 4, k) for k in range(4)]
    want = [(-math.pi, -math.pi / 2), (-math.pi / 2, 0.0), (0.0, math.pi / 2),
            (math.pi / 2, math.pi)]
    for (lo, hi), (wl, wh) in zip(got, want):
        assert math.isclose(math.cos(lo), math.cos(wl), abs_tol=1e-15)
        assert math.isclose(math.sin(lo), math.sin(wl), abs_tol=1e-15)
        assert hi - lo == pytest.approx(wh - wl, abs=1e-15)
    # the same box listed clockwise: the same cones
    Vc = V[::-1].copy()
    for k in range(4):
        lo, hi = R.vertex_cone(Vc, 0, 4, k)
        lo2, hi2 = got[3 - k]
        assert math.isclose(math.cos(lo), math.cos(lo2), abs_tol=1e-15)
        assert math.isclose(math.sin(lo), math.sin(lo2), abs_tol=1e-15)
        assert hi - lo == pytest.approx(hi2 - lo2, abs=1e-15)
    rod = np.array([(-0.3, 0.0), (0.3, 0.0)])
    lo, hi = R.vertex_cone(rod, 0, 2, 1)
    assert (lo, hi) == pytest.approx((-math.pi / 2, math.pi / 2), abs=1e-15)
    assert R.vertex_cone(np.zeros((1, 2)), 0, 1, 0) == (-math.inf, math.inf)


def check_rows(A, sa, B, sb, fr, na, act, L):
    """Each active row: the kernel's gap 0 and its normal the pair's (to round-off), its
    contact point on both outlines (brute force), inside its feature ranges."""
    pa = outline(A, sa)
    pb = outline(B, sb)
    for k in range(na):
        out = kin(sa, sb, act, k)
        assert abs(out[0]) <= 1e-12 * L, (k, out)
        # the row's A is the point body: its normal is the pair's, or the opposite; two
        # sharp corners (the pair's normal undefined): a face normal along which the two
        # outlines do not overlap (the separating-axis choice)
        sgn = 1.0 if int(act[k, C.CC_A]) == 0 else -1.0
        corners = fr[7] == 0 and fr[9] == 0 and A[1] + B[1] == 0.0
        if corners:
            u = sgn * out[5:7]
            assert np.min(pa @ u) - np.max(pb @ u) >= -1e-12 * L
        else:
            assert sgn * out[5] == pytest.approx(fr[1], abs=1e-9)
            assert sgn * out[6] == pytest.approx(fr[2], abs=1e-9)
        # the contact point: the point feature's centre moved by its radius against n
        st = sa if int(act[k, C.CC_A]) == 0 else sb
        c, s = math.cos(st[2]), math.sin(st[2])
        px = st[0] + c * act[k, C.CC_PAX] - s * act[k, C.CC_PAY] - act[k, C.CC_RA] * out[5]
        py = st[1] + s * act[k, C.CC_PAX] + c * act[k, C.CC_PAY] - act[k, C.CC_RA] * out[6]
        for P in (pa, pb):
            assert np.min(np.hypot(P[:, 0] - px, P[:, 1] - py)) <= 2e-3 * L


@pytest.mark.parametrize("a_name", sorted(SHAPES))
@pytest.mark.parametrize("b_name", sorted(SHAPES))
def test_rows_of_random_touching_pairs(a_name, b_name):
    """Random touching poses of every pair of shapes: classified (no refusal for a pose
    that is not two sharp corners), rows with gap 0, the pair's normal, points on both
    outlines."""
    A = SHAPES[a_name]
    B = SHAPES[b_name]
    rng = np.random.default_rng(7)
    L = 0.7
    n_ok = 0
    for _ in range(20):
        phi = rng.uniform(0.0, 2 * math.pi)
        V, sa, sb = touching(A, B, rng.uniform(0, 2 * math.pi), rng.uniform(0, 2 * math.pi),
                             (2.0 * math.cos(phi), 2.0 * math.sin(phi)))
        fr, na, nc, act, cand = rows(A, sa, B, sb)
        if na == R.PR_CORNERS:
            assert A[1] + B[1] == 0.0
            continue
        assert na in (1, 2), na
        check_rows(A, sa, B, sb, fr, na, act, L)
        n_ok += 1
    assert n_ok >= 15


def test_face_on_face_overlap_ends():
    """A small box lying on a wide one, shifted right: the two contacts are A's left bottom
    corner on B's top face and B's top right corner on A's bottom face, each with gap 0."""
    A = shape(SH_POLY, BOX, 0.0)
    B = shape(SH_POLY, [(-1, -0.5), (1, -0.5), (1, 0.5), (-1, 0.5)], 0.0)
    sa = state(0.8, 1.0, 0.0)
    sb = state(0.0, 0.0, 0.0)
    fr, na, nc, act, cand = rows(A, sa, B, sb)
    assert (na, nc) == (2, 0)
    kinds = sorted((int(act[k, C.CC_A]), act[k, C.CC_PAX], act[k, C.CC_PAY]) for k in range(2))
    assert kinds == [(0, -0.5, -0.5), (1, 1.0, 0.5)]
    check_rows(A, sa, B, sb, fr, na, act, 2.0)
    # the extent of each face contains its contact point's coordinate
    for k in range(2):
        out = kin(sa, sb, act, k)
        assert abs(out[0]) <= 1e-15


def test_vertex_on_face_candidates_are_the_landing_neighbours():
    """A box tilted on its corner on a face: one contact (its corner on the face), the two
    neighbouring corners as candidates against the same face (their gaps: the heights of
    those corners above the face)."""
    A = shape(SH_POLY, BOX, 0.0)
    B = shape(SH_POLY, [(-1, -0.5), (1, -0.5), (1, 0.5), (-1, 0.5)], 0.0)
    a = 0.3
    c, s = math.cos(a), math.sin(a)
    ys = [s * x + c * y for x, y in BOX]
    sa = state(0.1, 0.5 - min(ys), a)
    sb = state(0.0, 0.0, 0.0)
    fr, na, nc, act, cand = rows(A, sa, B, sb)
    assert (na, nc) == (1, 2)
    check_rows(A, sa, B, sb, fr, na, act, 2.0)
    heights = sorted(kin(sa, sb, cand, k)[0] for k in range(2))
    want = sorted(sa[1] + y - 0.5 for y in ys if y != min(ys) and y != max(ys))
    assert heights == pytest.approx(want, abs=1e-15)


def test_two_sharp_corners_take_the_best_face():
    """A box's corner exactly on another box's corner (tilted): the contact normal is the
    face normal of greatest separation, and the rows describe the corner on that face."""
    A = shape(SH_POLY, BOX, 0.0)
    B = shape(SH_POLY, BOX, 0.0)
    a = 0.4
    c, s = math.cos(a), math.sin(a)
    W = [(c * x - s * y, s * x + c * y) for x, y in BOX]
    k = int(np.argmin([w[1] for w in W]))
    # A's lowest corner 1e-7 m to the right of B's top right corner, at its height
    sa = state(0.5 - W[k][0] + 1e-7, 0.5 - W[k][1], a)
    sb = state(0.0, 0.0, 0.0)
    fr, na, nc, act, cand = rows(A, sa, B, sb)
    assert na == 1, na
    # B's corner on A's face (A's corner is beyond B's top face)
    assert int(act[0, C.CC_A]) == 1
    out = kin(sa, sb, act, 0)
    assert abs(out[0]) <= 1e-7


def test_plane_rows_split_active_and_candidates():
    V = np.array(BOX, float)
    act = np.zeros((4, C.N_CC))
    cand = np.zeros((4, C.N_CC))
    # resting flat: two active, two candidates 1 m up
    assert R.plane_rows(V, 0, 4, 0.0, state(0.0, 0.5, 0.0), 0, 0.0, 1.0, 0.0, 1e-9, 0.3,
                        act, 4, cand, 4) == (2, 2)
    assert sorted(act[:2, C.CC_PAY]) == [-0.5, -0.5]
    assert sorted(cand[:2, C.CC_PAY]) == [0.5, 0.5]
    # no room: nothing written, (-1, -1)
    assert R.plane_rows(V, 0, 4, 0.0, state(0.0, 0.5, 0.0), 0, 0.0, 1.0, 0.0, 1e-9, 0.3,
                        act, 1, cand, 4) == (-1, -1)
