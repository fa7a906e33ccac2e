"""Gap, normal, witness points and features of two rounded convex polygons in 2D (disk,
capsule, convex polygon in any combination; ``pair2d_shape`` for the encoding).

Each body is a convex core (point, segment or polygon) swept by a disk of radius ``r``,
so the signed distance of the bodies is that of their cores minus ``rA + rB``.

Disjoint cores (exact to round-off): the distance of two convex polygons is attained
between a vertex of one and an edge (or a vertex) of the other; every vertex of A is
projected on every edge of B and vice versa (point-segment distances, O(nA nB)). The
closest pair ``(cA, cB)`` gives ``n = (cA - cB) / |cA - cB|`` (from B into A, DESIGN §3;
for a vertex against an edge's interior, the edge's normal and the distance along it, which
stay exact as the gap goes to 0),
the gap ``g = |cA - cB| - rA - rB`` and the witness points ``pA = cA - rA n``,
``pB = cB + rB n`` (so ``pA - pB = g n``).

Disjointness is decided on the separating-axis inequality: for any unit ``n``,
``sigma(n) = min_A n . a - max_B n . b`` is at most the signed distance, with equality at
the optimal axis. The cores are disjoint iff ``sigma`` along the closest pair's direction
is positive.

Intersecting cores (``g <= -rA - rB``): ``g = max sigma - rA - rB`` over the edge normals of
both cores (both signs; a segment's normal included). For polygons this is exactly minus
the penetration depth (the minimum translation distance: the Minkowski difference is a
polygon whose edge normals are those of the cores); for degenerate cores (points,
collinear segments) it is 0, their depth. The witness point of the body whose vertex
supports the axis is that vertex (moved by its radius); the other is ``p -/+ g n``.

Features: ``(FT_VERTEX, k)`` or ``(FT_EDGE, e)`` per body (``pair2d_shape``); a projection
strictly inside an edge gives the edge, a clamped one the vertex.

All coordinates are relative to A's centre (``xA = yA = 0``) for accuracy far from the
origin; the caller adds A's position to the witness points.
"""
import math

from numba import njit

from .cache_guard import guard

guard(__name__, __file__)

from .pair2d_shape import FT_EDGE, FT_VERTEX, n_edges, vertex_at  # noqa: E402


@njit(cache=True, _nrt=False, inline="always")
def _point_segment(px, py, ax, ay, bx, by):
    """Closest point ``q`` of segment ``ab`` to ``p``: ``(|p - q|^2, t, qx, qy)``, ``t`` in [0, 1]
    its parameter (exactly 0 or 1 when clamped, then ``q`` is the endpoint itself)."""
    ex = bx - ax
    ey = by - ay
    L2 = ex * ex + ey * ey
    t = ((px - ax) * ex + (py - ay) * ey) / L2 if L2 > 0.0 else 0.0
    if t <= 0.0:
        t = 0.0
        qx = ax
        qy = ay
    elif t >= 1.0:
        t = 1.0
        qx = bx
        qy = by
    else:
        qx = ax + t * ex
        qy = ay + t * ey
    dx = px - qx
    dy = py - qy
    return dx * dx + dy * dy, t, qx, qy


@njit(cache=True, _nrt=False)
def core_sep(VA, iA, nA, xA, yA, cA, sA, VB, iB, nB, xB, yB, cB, sB, ux, uy):
    """``sigma(u) = min_k u . a_k - max_l u . b_l`` of the two cores along unit ``u`` (m),
    with the supporting vertices ``(sigma, k, l)``."""
    lo = math.inf
    kb = 0
    for k in range(nA):
        px, py = vertex_at(VA, iA, nA, k, xA, yA, cA, sA)
        d = ux * px + uy * py
        if d < lo:
            lo = d
            kb = k
    hi = -math.inf
    lb = 0
    for l in range(nB):
        px, py = vertex_at(VB, iB, nB, l, xB, yB, cB, sB)
        d = ux * px + uy * py
        if d > hi:
            hi = d
            lb = l
    return lo - hi, kb, lb


@njit(cache=True, _nrt=False)
def _closest_cores(VA, iA, nA, xA, yA, cA, sA, VB, iB, nB, xB, yB, cB, sB):
    """Closest points of the two cores assuming they are disjoint: ``(dist, nx, ny, cAx,
    cAy, cBx, cBy, fa, ia, fb, ib)``. The pair is chosen on the point-segment distances;
    a vertex against an edge's interior then takes its normal from the edge (exact
    direction: the difference of two nearly equal points would tilt it by
    ``eps |p| / dist``) and its distance along that normal."""
    best = math.inf
    side = 0            # 0: vertex-vertex, 1: A's vertex on B's edge, 2: B's vertex on A's edge
    rax = ray = rbx = rby = 0.0
    fa = FT_VERTEX
    ia = 0
    fb = FT_VERTEX
    ib = 0
    eB = n_edges(nB)
    for k in range(nA):
        px, py = vertex_at(VA, iA, nA, k, xA, yA, cA, sA)
        if eB == 0:
            qx, qy = vertex_at(VB, iB, nB, 0, xB, yB, cB, sB)
            d2 = (px - qx) ** 2 + (py - qy) ** 2
            if d2 < best:
                best = d2
                rax, ray, rbx, rby = px, py, qx, qy
                fa, ia, fb, ib, side = FT_VERTEX, k, FT_VERTEX, 0, 0
            continue
        for e in range(eB):
            ax, ay = vertex_at(VB, iB, nB, e, xB, yB, cB, sB)
            bx, by = vertex_at(VB, iB, nB, e + 1, xB, yB, cB, sB)
            d2, t, qx, qy = _point_segment(px, py, ax, ay, bx, by)
            if d2 < best:
                best = d2
                rax, ray, rbx, rby = px, py, qx, qy
                fa, ia = FT_VERTEX, k
                if t == 0.0:
                    fb, ib, side = FT_VERTEX, e, 0
                elif t == 1.0:
                    fb, ib, side = FT_VERTEX, (e + 1) % nB, 0
                else:
                    fb, ib, side = FT_EDGE, e, 1
    eA = n_edges(nA)
    for l in range(nB):
        px, py = vertex_at(VB, iB, nB, l, xB, yB, cB, sB)
        for e in range(eA):
            ax, ay = vertex_at(VA, iA, nA, e, xA, yA, cA, sA)
            bx, by = vertex_at(VA, iA, nA, e + 1, xA, yA, cA, sA)
            d2, t, qx, qy = _point_segment(px, py, ax, ay, bx, by)
            if d2 < best:
                best = d2
                rax, ray, rbx, rby = qx, qy, px, py
                fb, ib = FT_VERTEX, l
                if t == 0.0:
                    fa, ia, side = FT_VERTEX, e, 0
                elif t == 1.0:
                    fa, ia, side = FT_VERTEX, (e + 1) % nA, 0
                else:
                    fa, ia, side = FT_EDGE, e, 2
    if side == 0:
        dist = math.sqrt(best)
        if dist > 0.0:
            return dist, (rax - rbx) / dist, (ray - rby) / dist, rax, ray, rbx, rby, fa, ia, fb, ib
        return 0.0, 1.0, 0.0, rax, ray, rbx, rby, fa, ia, fb, ib
    # a vertex against an edge's interior: the edge's unit normal m, oriented to the vertex
    if side == 1:
        ax, ay = vertex_at(VB, iB, nB, ib, xB, yB, cB, sB)
        bx, by = vertex_at(VB, iB, nB, ib + 1, xB, yB, cB, sB)
        px, py = rax, ray
    else:
        ax, ay = vertex_at(VA, iA, nA, ia, xA, yA, cA, sA)
        bx, by = vertex_at(VA, iA, nA, ia + 1, xA, yA, cA, sA)
        px, py = rbx, rby
    ex = bx - ax
    ey = by - ay
    L = math.sqrt(ex * ex + ey * ey)
    mx = ey / L
    my = -ex / L
    h = mx * (px - ax) + my * (py - ay)
    if h < 0.0:
        mx = -mx
        my = -my
        h = -h
    qx = px - h * mx
    qy = py - h * my
    if side == 1:       # m points from B's edge to A's vertex: n = m
        return h, mx, my, px, py, qx, qy, fa, ia, fb, ib
    return h, -mx, -my, qx, qy, px, py, fa, ia, fb, ib


@njit(cache=True, _nrt=False)
def _best_edge_axis(VA, iA, nA, xA, yA, cA, sA, VB, iB, nB, xB, yB, cB, sB, which, best,
                    bnx, bny, bw, be):
    """Try both normals of every edge of body ``which`` (0: A, 1: B) as separating axes;
    keep the largest ``sigma``. Returns ``(best, nx, ny, which, edge)``."""
    V = VA if which == 0 else VB
    i0 = iA if which == 0 else iB
    nv = nA if which == 0 else nB
    x = xA if which == 0 else xB
    y = yA if which == 0 else yB
    c = cA if which == 0 else cB
    s = sA if which == 0 else sB
    for e in range(n_edges(nv)):
        ax, ay = vertex_at(V, i0, nv, e, x, y, c, s)
        bx, by = vertex_at(V, i0, nv, e + 1, x, y, c, s)
        ex = bx - ax
        ey = by - ay
        L = math.sqrt(ex * ex + ey * ey)
        if not L > 0.0:
            continue
        for sg in (1.0, -1.0):
            ux = sg * ey / L
            uy = -sg * ex / L
            sig, _, _ = core_sep(VA, iA, nA, xA, yA, cA, sA, VB, iB, nB, xB, yB, cB, sB, ux, uy)
            if sig > best:
                best, bnx, bny, bw, be = sig, ux, uy, which, e
    return best, bnx, bny, bw, be


@njit(cache=True, _nrt=False)
def rounded_frame(VA, iA, nA, rA, cA, sA, VB, iB, nB, rB, xB, yB, cB, sB):
    """Signed gap and contact frame of two rounded convex polygons, A at the origin.

    ``(V, i, n, r)`` the core vertex table, first row, count and radius of each body;
    ``(c, s)`` cosine and sine of its angle; ``(xB, yB)`` B's centre relative to A's.
    Returns ``(g, nx, ny, pAx, pAy, pBx, pBy, fa, ia, fb, ib)`` (m; ``n`` from B into A;
    witness points relative to A's centre; features ``pair2d_shape.FT_*`` and indices)."""
    dist, nx, ny, cax, cay, cbx, cby, fa, ia, fb, ib = _closest_cores(
        VA, iA, nA, 0.0, 0.0, cA, sA, VB, iB, nB, xB, yB, cB, sB)
    if dist > 0.0:
        sig, _, _ = core_sep(VA, iA, nA, 0.0, 0.0, cA, sA, VB, iB, nB, xB, yB, cB, sB, nx, ny)
        if sig > 0.0:   # disjoint cores: the closest pair is exact
            return (dist - rA - rB, nx, ny, cax - rA * nx, cay - rA * ny, cbx + rB * nx,
                    cby + rB * ny, fa, ia, fb, ib)
    # intersecting (or touching) cores: the largest separation over the edge normals
    best = -math.inf
    bnx = 1.0
    bny = 0.0
    bw = -1
    be = 0
    best, bnx, bny, bw, be = _best_edge_axis(VA, iA, nA, 0.0, 0.0, cA, sA, VB, iB, nB, xB,
                                             yB, cB, sB, 0, best, bnx, bny, bw, be)
    best, bnx, bny, bw, be = _best_edge_axis(VA, iA, nA, 0.0, 0.0, cA, sA, VB, iB, nB, xB,
                                             yB, cB, sB, 1, best, bnx, bny, bw, be)
    if bw < 0:      # two points, or a point on a segment's line: depth 0
        best = 0.0
    best = min(best, 0.0)
    g = best - rA - rB
    _, k, l = core_sep(VA, iA, nA, 0.0, 0.0, cA, sA, VB, iB, nB, xB, yB, cB, sB, bnx, bny)
    if bw == 0:     # A's edge against B's supporting vertex
        qx, qy = vertex_at(VB, iB, nB, l, xB, yB, cB, sB)
        pbx = qx + rB * bnx
        pby = qy + rB * bny
        return g, bnx, bny, pbx + g * bnx, pby + g * bny, pbx, pby, FT_EDGE, be, FT_VERTEX, l
    qx, qy = vertex_at(VA, iA, nA, k, 0.0, 0.0, cA, sA)
    pax = qx - rA * bnx
    pay = qy - rA * bny
    if bw == 1:     # A's supporting vertex against B's edge
        return g, bnx, bny, pax, pay, pax - g * bnx, pay - g * bny, FT_VERTEX, k, FT_EDGE, be
    return g, bnx, bny, pax, pay, pax - g * bnx, pay - g * bny, FT_VERTEX, k, FT_VERTEX, l
