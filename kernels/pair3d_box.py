"""Gap, normal, witness points and features of two boxes in 3D.

Computed in **A's body frame** (A's centre at the origin, its edges along the axes): B's
centre ``c = R_A^T (x_B - x_A)`` and orientation ``C = R_A^T R_B`` (from ``q_A^* q_B``,
``pair3d_shape.rel_quat``), so that A's edges are exact coordinate directions.

Separating axes (Gottschalk, Lin & Manocha, OBBTree, SIGGRAPH 1996; Ericson, *Real-Time
Collision Detection*, sec. 4.4.1): along a unit axis ``u`` the separation is
``sigma(u) = |u . c| - sum_i hA_i |u . e_i| - sum_j hB_j |u . f_j|``, a lower bound of the
signed distance for every ``u``; the 15 axes are the 3 + 3 face normals and the 9 edge
products ``e_i x f_j``. In A's frame ``e_i x f_j`` is a copy of two components of ``f_j``:
exact, so the axis is exact however small the angle of the edges; only exactly parallel
edges (``|e_i x f_j| <= pair3d_shape.AXIS_MIN``) are skipped, their product vanishing and
the faces of the Minkowski difference it would give being then among the face normals.

* Overlapping (``max sigma <= 0``): ``g = max sigma``, minus the penetration depth, exact
  (the minimum translation of two convex polytopes is along a face normal of their
  Minkowski difference, all of which are among the 15 axes), for the relative pose ``C``,
  ``c`` as rounded (an error of a few ulps of the size). Face axes win ties: an edge
  product is taken only when it beats them by ``EDGE_BIAS_ULPS`` ulps of the pose's scale.
* Disjoint (``max sigma > 0``): the exact distance by closest features (the distance of
  two convex polytopes is realised by a vertex and the other body, or by two edges): the
  8 + 8 corners against the other box (``pair3d_rounded.point_box``) and the 12 x 12 edge
  pairs (``pair3d_rounded.seg_seg``; an edge pair is skipped when the distance of the edge
  midpoints minus the half lengths already exceeds the best distance). A corner in a face
  region gives the face normal and the distance along it exactly; two edges with interior
  closest points the normal ``+-e_i x f_j / |e_i x f_j|``, exact in direction.

Features: ``(FT_VERTEX, k)``, ``(FT_EDGE, e)`` or ``(FT_FACE, f)`` per body
(``pair3d_shape``): the lowest-dimensional features realising the distance (a box resting
flat on another is reported as a corner on a face; ``pair3d_manifold`` gives the whole
contact). Overlapping: the face of the axis and the other body's deepest corner, or the
two edges of an edge-product axis. Witness points when overlapping: for a face axis the
deepest point of the other body's incident face over that face (``pair3d_clip``), so that
both lie on the surfaces also when the faces are parallel; for an edge product the closest
points of the two edges.
"""
import math

from numba import njit

from .cache_guard import guard

guard(__name__, __file__)

from .pair3d_clip import face_deepest  # noqa: E402
from .pair3d_rounded import point_box, seg_seg  # noqa: E402
from .pair3d_shape import (AXIS_MIN, FT_EDGE, FT_FACE, FT_VERTEX, box_edge,  # noqa: E402
                           box_edge_index, mat_tvec, mat_vec)

EPS = 2.220446049250313e-16   # float64 machine epsilon
EDGE_BIAS_ULPS = 16.0          # an edge-product axis must beat the best face axis by this
#                                many ulps of the pose's scale (|c| + half edges) (-)


@njit(cache=True, _nrt=False, inline="always")
def _sep(C, hA0, hA1, hA2, hB0, hB1, hB2, cx, cy, cz, ux, uy, uz):
    """``(sigma(u), u . c)`` for unit ``u`` in A's frame."""
    ra = hA0 * abs(ux) + hA1 * abs(uy) + hA2 * abs(uz)
    rb = (hB0 * abs(ux * C[0] + uy * C[3] + uz * C[6])
          + hB1 * abs(ux * C[1] + uy * C[4] + uz * C[7])
          + hB2 * abs(ux * C[2] + uy * C[5] + uz * C[8]))
    uc = ux * cx + uy * cy + uz * cz
    return abs(uc) - ra - rb, uc


@njit(cache=True, _nrt=False)
def box_sat(C, hA0, hA1, hA2, hB0, hB1, hB2, cx, cy, cz):
    """Best of the 15 separating axes: ``(sigma, nx, ny, nz, kind, i, j)`` with ``n`` the unit
    normal from B into A (A's frame), ``kind`` 0 (A's face normal ``i``), 1 (B's face
    normal ``j``), 2 (edge product ``e_i x f_j``)."""
    best = -math.inf
    bx = 1.0
    by = 0.0
    bz = 0.0
    bk = 0
    bi = 0
    bj = 0
    for i in range(3):
        ux = 1.0 if i == 0 else 0.0
        uy = 1.0 if i == 1 else 0.0
        uz = 1.0 if i == 2 else 0.0
        sg, uc = _sep(C, hA0, hA1, hA2, hB0, hB1, hB2, cx, cy, cz, ux, uy, uz)
        if sg > best:
            sgn = -1.0 if uc >= 0.0 else 1.0
            best, bx, by, bz, bk, bi, bj = sg, sgn * ux, sgn * uy, sgn * uz, 0, i, 0
    for j in range(3):
        ux = C[j]
        uy = C[3 + j]
        uz = C[6 + j]
        sg, uc = _sep(C, hA0, hA1, hA2, hB0, hB1, hB2, cx, cy, cz, ux, uy, uz)
        if sg > best:
            sgn = -1.0 if uc >= 0.0 else 1.0
            best, bx, by, bz, bk, bi, bj = sg, sgn * ux, sgn * uy, sgn * uz, 1, 0, j
    # an edge product must beat the face axes by more than their round-off: when a face is
    # parallel to the other body's face or edge the products of its edges are that face's
    # normal, and its face frame (witness inside the contact) is the meaningful one
    bias = EDGE_BIAS_ULPS * EPS * (abs(cx) + abs(cy) + abs(cz) + hA0 + hA1 + hA2 + hB0
                                   + hB1 + hB2)
    for i in range(3):
        for j in range(3):
            fx = C[j]
            fy = C[3 + j]
            fz = C[6 + j]
            # e_i x f: an exact component swap
            if i == 0:
                ux, uy, uz = 0.0, -fz, fy
            elif i == 1:
                ux, uy, uz = fz, 0.0, -fx
            else:
                ux, uy, uz = -fy, fx, 0.0
            m = math.sqrt(ux * ux + uy * uy + uz * uz)
            if not m > AXIS_MIN:
                continue
            ux /= m
            uy /= m
            uz /= m
            sg, uc = _sep(C, hA0, hA1, hA2, hB0, hB1, hB2, cx, cy, cz, ux, uy, uz)
            if sg > best + bias:
                sgn = -1.0 if uc >= 0.0 else 1.0
                best, bx, by, bz, bk, bi, bj = sg, sgn * ux, sgn * uy, sgn * uz, 2, i, j
    return best, bx, by, bz, bk, bi, bj


@njit(cache=True, _nrt=False, inline="always")
def _b_vertex(C, hB0, hB1, hB2, cx, cy, cz, k):
    """B's corner ``k`` in A's frame."""
    sx = (2.0 * (k & 1) - 1.0) * hB0
    sy = (2.0 * ((k >> 1) & 1) - 1.0) * hB1
    sz = (2.0 * ((k >> 2) & 1) - 1.0) * hB2
    wx, wy, wz = mat_vec(C, sx, sy, sz)
    return cx + wx, cy + wy, cz + wz


@njit(cache=True, _nrt=False)
def _closest(C, hA0, hA1, hA2, hB0, hB1, hB2, cx, cy, cz):
    """Exact distance of two disjoint boxes by closest features (module docstring).
    Returns ``(dist, n, pA, pB, fa, ia, fb, ib)`` (A's frame, ``n`` from B into A)."""
    best = math.inf
    rnx = rny = rnz = 0.0
    ax = ay = az = bx = by = bz = 0.0
    fa = ia = fb = ib = 0
    # B's corners against box A
    for k in range(8):
        px, py, pz = _b_vertex(C, hB0, hB1, hB2, cx, cy, cz, k)
        d, ux, uy, uz, qx, qy, qz, f, i = point_box(px, py, pz, hA0, hA1, hA2)
        if d < best:
            best = d
            rnx, rny, rnz = -ux, -uy, -uz
            ax, ay, az, bx, by, bz = qx, qy, qz, px, py, pz
            fa, ia, fb, ib = f, i, FT_VERTEX, k
    # A's corners against box B (in B's frame: C^T (a - c))
    for k in range(8):
        sx = (2.0 * (k & 1) - 1.0) * hA0
        sy = (2.0 * ((k >> 1) & 1) - 1.0) * hA1
        sz = (2.0 * ((k >> 2) & 1) - 1.0) * hA2
        px, py, pz = mat_tvec(C, sx - cx, sy - cy, sz - cz)
        d, ux, uy, uz, qx, qy, qz, f, i = point_box(px, py, pz, hB0, hB1, hB2)
        if d < best:
            best = d
            rnx, rny, rnz = mat_vec(C, ux, uy, uz)      # from B toward A's corner
            wx, wy, wz = mat_vec(C, qx, qy, qz)
            ax, ay, az, bx, by, bz = sx, sy, sz, cx + wx, cy + wy, cz + wz
            fa, ia, fb, ib = FT_VERTEX, k, f, i
    # edge pairs
    for ea in range(12):
        a0x, a0y, a0z, a1x, a1y, a1z = box_edge(hA0, hA1, hA2, ea)
        la = 0.5 * math.sqrt((a1x - a0x) ** 2 + (a1y - a0y) ** 2 + (a1z - a0z) ** 2)
        max_ = 0.5 * (a0x + a1x)
        may = 0.5 * (a0y + a1y)
        maz = 0.5 * (a0z + a1z)
        for eb in range(12):
            e0x, e0y, e0z, e1x, e1y, e1z = box_edge(hB0, hB1, hB2, eb)
            b0x, b0y, b0z = mat_vec(C, e0x, e0y, e0z)
            b1x, b1y, b1z = mat_vec(C, e1x, e1y, e1z)
            b0x += cx
            b0y += cy
            b0z += cz
            b1x += cx
            b1y += cy
            b1z += cz
            lb = 0.5 * math.sqrt((e1x - e0x) ** 2 + (e1y - e0y) ** 2 + (e1z - e0z) ** 2)
            mdx = 0.5 * (b0x + b1x) - max_
            mdy = 0.5 * (b0y + b1y) - may
            mdz = 0.5 * (b0z + b1z) - maz
            if math.sqrt(mdx * mdx + mdy * mdy + mdz * mdz) - la - lb >= best:
                continue
            s, t, d, nx, ny, nz = seg_seg(a0x, a0y, a0z, a1x - a0x, a1y - a0y, a1z - a0z,
                                          b0x, b0y, b0z, b1x - b0x, b1y - b0y, b1z - b0z)
            if d < best and s > 0.0 and s < 1.0 and t > 0.0 and t < 1.0:
                best = d
                rnx, rny, rnz = nx, ny, nz
                ax = a0x + s * (a1x - a0x)
                ay = a0y + s * (a1y - a0y)
                az = a0z + s * (a1z - a0z)
                bx = b0x + t * (b1x - b0x)
                by = b0y + t * (b1y - b0y)
                bz = b0z + t * (b1z - b0z)
                fa, ia, fb, ib = FT_EDGE, ea, FT_EDGE, eb
    return best, rnx, rny, rnz, ax, ay, az, bx, by, bz, fa, ia, fb, ib


@njit(cache=True, _nrt=False)
def box_box_frame(C, hA0, hA1, hA2, hB0, hB1, hB2, cx, cy, cz):
    """Signed gap and contact frame of two boxes in A's frame (``C`` = ``R_A^T R_B`` as nine
    floats, ``c`` B's centre). Returns ``(g, n, pA, pB, fa, ia, fb, ib)`` (15 values)."""
    sig, nx, ny, nz, kind, i, j = box_sat(C, hA0, hA1, hA2, hB0, hB1, hB2, cx, cy, cz)
    if sig > 0.0:
        return _closest(C, hA0, hA1, hA2, hB0, hB1, hB2, cx, cy, cz)
    g = sig
    if kind == 0 or kind == 2:
        # B's deepest corner along n (the most toward A): max n . b
        hi = -math.inf
        kb = 0
        for k in range(8):
            px, py, pz = _b_vertex(C, hB0, hB1, hB2, cx, cy, cz, k)
            d = nx * px + ny * py + nz * pz
            if d > hi:
                hi = d
                kb = k
    if kind == 0:
        px, py, pz = _b_vertex(C, hB0, hB1, hB2, cx, cy, cz, kb)
        m = nx if i == 0 else (ny if i == 1 else nz)
        # the deepest point of B's incident face over A's face (ties of a parallel face)
        z, qx, qy, qz, found = face_deepest(hA0, hA1, hA2, i, -1.0 if m > 0.0 else 1.0, C,
                                            cx, cy, cz, hB0, hB1, hB2)
        if found:
            px, py, pz = qx, qy, qz
        return (g, nx, ny, nz, px + g * nx, py + g * ny, pz + g * nz, px, py, pz, FT_FACE,
                2 * i + (1 if -m > 0.0 else 0), FT_VERTEX, kb)
    if kind == 1:
        # A's deepest corner along -n: min n . a
        lo = math.inf
        ka = 0
        for k in range(8):
            sx = (2.0 * (k & 1) - 1.0) * hA0
            sy = (2.0 * ((k >> 1) & 1) - 1.0) * hA1
            sz = (2.0 * ((k >> 2) & 1) - 1.0) * hA2
            d = nx * sx + ny * sy + nz * sz
            if d < lo:
                lo = d
                ka = k
        sx = (2.0 * (ka & 1) - 1.0) * hA0
        sy = (2.0 * ((ka >> 1) & 1) - 1.0) * hA1
        sz = (2.0 * ((ka >> 2) & 1) - 1.0) * hA2
        m = nx * C[j] + ny * C[3 + j] + nz * C[6 + j]      # n in B's frame, component j
        # the deepest point of A's incident face over B's face, in B's frame
        CT = (C[0], C[3], C[6], C[1], C[4], C[7], C[2], C[5], C[8])
        ox, oy, oz = mat_tvec(C, -cx, -cy, -cz)
        z, qx, qy, qz, found = face_deepest(hB0, hB1, hB2, j, 1.0 if m > 0.0 else -1.0, CT,
                                            ox, oy, oz, hA0, hA1, hA2)
        if found:
            wx, wy, wz = mat_vec(C, qx, qy, qz)
            sx = cx + wx
            sy = cy + wy
            sz = cz + wz
        return (g, nx, ny, nz, sx, sy, sz, sx - g * nx, sy - g * ny, sz - g * nz, FT_VERTEX,
                ka, FT_FACE, 2 * j + (1 if m > 0.0 else 0))
    # edge product: A's edge along e_i lowest along n, B's edge along f_j highest along n
    ja = (i + 1) % 3
    ka_ = (i + 2) % 3
    nja = nx if ja == 0 else (ny if ja == 1 else nz)
    nka = nx if ka_ == 0 else (ny if ka_ == 1 else nz)
    ea = box_edge_index(i, -1.0 if nja >= 0.0 else 1.0, -1.0 if nka >= 0.0 else 1.0)
    mbx, mby, mbz = mat_tvec(C, nx, ny, nz)         # n in B's frame
    jb = (j + 1) % 3
    kb_ = (j + 2) % 3
    njb = mbx if jb == 0 else (mby if jb == 1 else mbz)
    nkb = mbx if kb_ == 0 else (mby if kb_ == 1 else mbz)
    eb = box_edge_index(j, 1.0 if njb >= 0.0 else -1.0, 1.0 if nkb >= 0.0 else -1.0)
    a0x, a0y, a0z, a1x, a1y, a1z = box_edge(hA0, hA1, hA2, ea)
    e0x, e0y, e0z, e1x, e1y, e1z = box_edge(hB0, hB1, hB2, eb)
    b0x, b0y, b0z = _b_offset(C, cx, cy, cz, e0x, e0y, e0z)
    b1x, b1y, b1z = _b_offset(C, cx, cy, cz, e1x, e1y, e1z)
    s, t, _, _, _, _ = seg_seg(a0x, a0y, a0z, a1x - a0x, a1y - a0y, a1z - a0z,
                               b0x, b0y, b0z, b1x - b0x, b1y - b0y, b1z - b0z)
    pax = a0x + s * (a1x - a0x)
    pay = a0y + s * (a1y - a0y)
    paz = a0z + s * (a1z - a0z)
    return (g, nx, ny, nz, pax, pay, paz, pax - g * nx, pay - g * ny, paz - g * nz,
            FT_EDGE, ea, FT_EDGE, eb)


@njit(cache=True, _nrt=False, inline="always")
def _b_offset(C, cx, cy, cz, x, y, z):
    wx, wy, wz = mat_vec(C, x, y, z)
    return cx + wx, cy + wy, cz + wz

