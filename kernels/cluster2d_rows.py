"""The contact rows of a 2D cluster (``cluster2d``) built from the scene's shapes: which
features of two touching bodies, or of a body and a plane, carry the persistent contact,
as rows of ``cluster2d``'s contact table (columns ``CC_*``; issue 16 item 2).

Shapes are the rounded convex polygons of ``pair2d_shape`` (``SH_DISK``, ``SH_POLY``: a
core ``V[v0 : v0 + nv]``, counter-clockwise, swept by a disk of radius ``rad``) and ellipses
(semi-axes ``ea, eb`` on the body axes: ``cluster2d``'s curved feature, ``CC_AEA``). A
body's state row is ``flight2d``'s (``X, Y, ANGLE, ...``).

Features (DESIGN §3: ``n`` points from B into A):

* a *point* feature is a core vertex ``k`` with the body's radius (a disk's centre, a
  capsule's end, a polygon's corner with radius 0); its *normal cone* is the set of
  outward normals of the boundary there, as body-frame angles ``[lo, hi]``
  (``vertex_cone``): between the outward normals of its two edges (a polygon), the half
  plane away from the other end (a rod), unbounded (a disk);
* a *face* is a core edge ``i`` (``V_i`` to ``V_i+1``) offset by the radius, on one side
  (a rod's edge has two): its outward unit normal and its extent ``[0, |V_i+1 - V_i|]``
  along ``t = (n_y, -n_x)`` from ``V_i`` (up to sign), as ``cluster2d``'s ``KIND_FACE``
  reads them.

A touching pair (``pair_rows``; ``n`` the pair frame's normal, ``pair2d.frame_rel``) is
classified by the core vertices of each body on its extreme support along ``n`` within
``tol`` (A's lowest, B's highest):

* one on each side: a vertex on a vertex, ``KIND_ROUND`` (refused when both are sharp
  corners: the normal of two touching corners is not defined by them);
* one on A's side, two on B's: A's vertex on B's face (``KIND_FACE``); the mirror with A
  and B exchanged (the face's body is B of the row, its normal from it into the point's
  body);
* two on each side with an overlap longer than ``FACE_RTOL L``: face on face, the two
  ``KIND_FACE`` contacts at the ends of the overlap (each end is a vertex of one body on
  the other's face).

Candidates (inactive rows whose gap ``cluster2d`` watches) of a vertex on a face: the
vertex's neighbours on the same face line, the landing of the adjacent face (the only way
two convex bodies touching at a vertex on a face can touch elsewhere without the vertex
first leaving the face, a ``CE_FEATURE`` event). Planes (``plane_rows``): every core vertex
within ``tol`` is an active ``KIND_PLANE`` row, every other one a candidate.

An ellipse touches a convex body at one point, and keeps touching it there (it has no flat
piece): ``ellipse_rows`` makes it the row's A, on B's vertex (``KIND_ROUND``, B's cone
watched), on B's face (``KIND_FACE``, B's extent watched) or on B's boundary when B is an
ellipse too (``KIND_ROUND``, nothing watched); no candidates. Against a plane
(``ellipse_plane_rows``) it is one row, active within ``tol``, else a candidate. When its
contact point leaves B's vertex cone or B's face, ``switch_row`` moves it onto B's adjacent
face or end vertex; the ellipse's own cone is the whole circle.
"""
import math

from numba import njit

from .cache_guard import guard

guard(__name__, __file__)

from . import cluster2d as cl  # noqa: E402
from .flight2d import ANGLE, OMEGA, VX, VY, X, Y  # noqa: E402
from .pivot2d import ellipse_support3  # noqa: E402

INF = math.inf

FACE_RTOL = 1e-12
"""A face-on-face overlap shorter than ``FACE_RTOL L`` (L the larger core reach) is one
point (``stepper2d.PAIR_FACE_RTOL``'s rule at an impact)."""

# pair_rows status (>= 0: the number of active rows written)
PR_CORNERS = -1     # two sharp corners touch: the normal is not defined by the features
PR_GEOMETRY = -2    # no feature pair matches the support sets (collinear core vertices, a
#                     vertex off the face it touches): not classified


@njit(cache=True, _nrt=False)
def vertex_cone(V, v0, nv, k):
    """Normal cone ``(lo, hi)`` (rad, body frame, ``hi - lo <= pi``) of core vertex k:
    ``(-inf, inf)`` for a disk (``nv = 1``), the half plane away from the other end for a
    rod (``nv = 2``), between the outward normals of the two edges at k for a polygon
    (either orientation)."""
    if nv <= 1:
        return -INF, INF
    j = v0 + k
    if nv == 2:
        o = v0 + 1 - k
        a = math.atan2(V[j, 1] - V[o, 1], V[j, 0] - V[o, 0])
        return a - 0.5 * math.pi, a + 0.5 * math.pi
    area = 0.0
    for i in range(nv):
        p = v0 + i
        q = v0 + (i + 1) % nv
        area += V[p, 0] * V[q, 1] - V[q, 0] * V[p, 1]
    sg = 1.0 if area > 0.0 else -1.0
    p = v0 + (k - 1) % nv
    q = v0 + (k + 1) % nv
    # outward normals of edge (p, k) and edge (k, q): the edge direction turned by -90 deg
    # (counter-clockwise outline; +90 deg clockwise)
    a_prev = math.atan2(-sg * (V[j, 0] - V[p, 0]), sg * (V[j, 1] - V[p, 1]))
    a_next = math.atan2(-sg * (V[q, 0] - V[j, 0]), sg * (V[q, 1] - V[j, 1]))
    if sg > 0.0:
        lo = a_prev
        d = a_next - a_prev
    else:
        lo = a_next
        d = a_prev - a_next
    d = d % (2.0 * math.pi)
    return lo, lo + d


@njit(cache=True, _nrt=False)
def _support(V, v0, nv, st, nx, ny, sg, tol):
    """The core vertices of a body (state row st) on its extreme support along ``sg n``
    within ``tol`` (m): ``(count, k_lo, tau_lo, k_hi, tau_hi)``, the vertices with the least
    and the greatest tangential coordinate ``tau = t . p`` (``t = (n_y, -n_x)``, world)."""
    c = math.cos(st[ANGLE])
    s = math.sin(st[ANGLE])
    best = -INF
    for k in range(nv):
        px = c * V[v0 + k, 0] - s * V[v0 + k, 1]
        py = s * V[v0 + k, 0] + c * V[v0 + k, 1]
        best = max(best, sg * (nx * px + ny * py))
    cnt = 0
    klo = -1
    khi = -1
    tlo = INF
    thi = -INF
    for k in range(nv):
        px = st[X] + c * V[v0 + k, 0] - s * V[v0 + k, 1]
        py = st[Y] + s * V[v0 + k, 0] + c * V[v0 + k, 1]
        d = sg * (nx * (px - st[X]) + ny * (py - st[Y]))
        if d >= best - tol:
            cnt += 1
            tau = ny * px - nx * py
            if tau < tlo:
                tlo = tau
                klo = k
            if tau > thi:
                thi = tau
                khi = k
    return cnt, klo, tlo, khi, thi


@njit(cache=True, _nrt=False)
def _face_edge(nv, k1, k2):
    """The edge index joining core vertices k1 and k2 (adjacent), or -1."""
    if nv == 2:
        return 0
    if (k1 + 1) % nv == k2:
        return k1
    if (k2 + 1) % nv == k1:
        return k2
    return -1


@njit(cache=True, _nrt=False)
def row_clear(out, r, kind, a, b, mu):
    """Row r of out cleared: kind, bodies (cluster rows a, b; b -1 for a plane), friction
    mu, open cones and ranges, mode slip along +t (the caller's features go on top)."""
    for j in range(cl.N_CC):
        out[r, j] = 0.0
    out[r, cl.CC_KIND] = kind
    out[r, cl.CC_A] = a
    out[r, cl.CC_B] = b
    out[r, cl.CC_ALO] = -INF
    out[r, cl.CC_AHI] = INF
    out[r, cl.CC_BLO] = -INF
    out[r, cl.CC_BHI] = INF
    out[r, cl.CC_MU] = mu
    out[r, cl.CC_MODE] = cl.MODE_SLIP_POS


@njit(cache=True, _nrt=False)
def _row_point(out, r, kind, a, b, V, va, na, ka, rA, mu):
    """Row r of out: kind, bodies (cluster rows a, b), A's point feature (vertex ka of the
    core V[va : va + na], radius rA) and its cone; the rest cleared."""
    row_clear(out, r, kind, a, b, mu)
    out[r, cl.CC_PAX] = V[va + ka, 0]
    out[r, cl.CC_PAY] = V[va + ka, 1]
    out[r, cl.CC_RA] = rA
    lo, hi = vertex_cone(V, va, na, ka)
    out[r, cl.CC_ALO] = lo
    out[r, cl.CC_AHI] = hi


@njit(cache=True, _nrt=False, inline="always")
def _edge_normal(V, v0, nv, e):
    """A unit normal of core edge e (body frame; its side not chosen) and the edge vector
    (V_e to V_e+1)."""
    i = v0 + e
    j = v0 + (e + 1) % nv
    ex = V[j, 0] - V[i, 0]
    ey = V[j, 1] - V[i, 1]
    el = math.hypot(ex, ey)
    return ey / el, -ex / el, ex, ey


@njit(cache=True, _nrt=False)
def _row_face(out, r, V, vb, nb, e, rB, stB, nx, ny):
    """B's face of row r: edge e of the core V[vb : vb + nb] offset by rB, on the side of
    the world normal n (a rod's edge has two); its point, outward normal (body frame) and
    extent."""
    i = vb + e
    fx, fy, ex, ey = _edge_normal(V, vb, nb, e)
    c = math.cos(stB[ANGLE])
    s = math.sin(stB[ANGLE])
    bx = c * nx + s * ny            # n in B's body frame
    by = -s * nx + c * ny
    if fx * bx + fy * by < 0.0:
        fx = -fx
        fy = -fy
    out[r, cl.CC_KIND] = cl.KIND_FACE
    out[r, cl.CC_PBX] = V[i, 0]
    out[r, cl.CC_PBY] = V[i, 1]
    out[r, cl.CC_RB] = rB
    out[r, cl.CC_NX] = fx
    out[r, cl.CC_NY] = fy
    s1 = fy * ex - fx * ey          # t . (V_j - V_i), t = (n_y, -n_x) in the body frame
    out[r, cl.CC_BLO] = min(0.0, s1)
    out[r, cl.CC_BHI] = max(0.0, s1)


@njit(cache=True, _nrt=False)
def _separation(V, va, na, rA, stA, vb, nb, rB, stB, nx, ny):
    """Separation of A and B along the unit axis n (from B into A): ``min_A n . a -
    max_B n . b`` over the rounded cores (m; the separating-axis calculus)."""
    ca = math.cos(stA[ANGLE])
    sa = math.sin(stA[ANGLE])
    cb = math.cos(stB[ANGLE])
    sb = math.sin(stB[ANGLE])
    lo = INF
    for k in range(na):
        px = stA[X] + ca * V[va + k, 0] - sa * V[va + k, 1]
        py = stA[Y] + sa * V[va + k, 0] + ca * V[va + k, 1]
        lo = min(lo, nx * px + ny * py)
    hi = -INF
    for k in range(nb):
        px = stB[X] + cb * V[vb + k, 0] - sb * V[vb + k, 1]
        py = stB[Y] + sb * V[vb + k, 0] + cb * V[vb + k, 1]
        hi = max(hi, nx * px + ny * py)
    return lo - rA - (hi + rB)


@njit(cache=True, _nrt=False)
def _edge_axis(V, v0, nv, e, st, sg):
    """World unit normal of core edge e (outward for a polygon; either side of a rod),
    times sg."""
    i = v0 + e
    j = v0 + (e + 1) % nv
    fx, fy, _, _ = _edge_normal(V, v0, nv, e)
    c = math.cos(st[ANGLE])
    s = math.sin(st[ANGLE])
    if nv >= 3:
        # outward: away from the core's centre of mass (the body origin)
        if fx * (V[i, 0] + V[j, 0]) + fy * (V[i, 1] + V[j, 1]) < 0.0:
            fx = -fx
            fy = -fy
    return sg * (c * fx - s * fy), sg * (s * fx + c * fy)


@njit(cache=True, _nrt=False)
def _best_face_axis(V, va, na, rA, stA, ka, vb, nb, rB, stB, kb, nx, ny):
    """The contact normal of two touching vertices ka (of A) and kb (of B) whose supports
    along n do not name a face: among the normals of the edges at ka and at kb (as
    normals from B into A, turned towards n), the one of greatest separation (the
    separating-axis choice); n itself when no edge qualifies."""
    best = -INF
    bx = nx
    by = ny
    for side in range(2):
        v0 = va if side == 0 else vb
        nv = na if side == 0 else nb
        k = ka if side == 0 else kb
        st = stA if side == 0 else stB
        if nv < 2:
            continue
        for d in range(2):
            e = k if d == 0 else (k - 1) % nv
            if nv == 2:
                e = 0
            ux, uy = _edge_axis(V, v0, nv, e, st, -1.0 if side == 0 else 1.0)
            if ux * nx + uy * ny < 0.0:
                if nv >= 3:
                    continue
                ux = -ux
                uy = -uy
            sep = _separation(V, va, na, rA, stA, vb, nb, rB, stB, ux, uy)
            if sep > best:
                best = sep
                bx = ux
                by = uy
    return bx, by


@njit(cache=True, _nrt=False, inline="always")
def _core_reach(V, v0, nv):
    """The farthest core vertex's distance from the body's centre (m)."""
    R = 0.0
    for k in range(nv):
        R = max(R, math.hypot(V[v0 + k, 0], V[v0 + k, 1]))
    return R


@njit(cache=True, _nrt=False)
def pair_rows(V, va, na, rA, stA, ra, vb, nb, rB, stB, rb, nx, ny, tol, mu, act, cand):
    """The contact rows of two touching rounded polygons A (core ``V[va : va + na]``,
    radius ``rA``, state row ``stA``, cluster row ``ra``) and B (likewise), ``n`` the unit
    normal from B into A (world), ``tol`` (m) the support tolerance (the stepper's
    ``gap_tol``), ``mu`` the pair's friction. Writes the active rows into ``act[0:2]`` and
    the candidate rows into ``cand[0:2]`` (float64[>= 2, N_CC] each); returns
    ``(n_active, n_candidates)``, or ``(PR_*, 0)`` when the contact is not classified
    (module docstring). Two touching sharp corners, or a vertex beyond the face its
    support names, take the edge normal at either vertex of greatest separation
    (``_best_face_axis``) and are classified again once."""
    L = max(_core_reach(V, va, na) + rA, _core_reach(V, vb, nb) + rB)
    tl = tol + FACE_RTOL * L
    status = PR_GEOMETRY
    for attempt in range(2):
        cA, aklo, atlo, akhi, athi = _support(V, va, na, stA, nx, ny, -1.0, tl)
        cB, bklo, btlo, bkhi, bthi = _support(V, vb, nb, stB, nx, ny, 1.0, tl)
        status = PR_GEOMETRY
        if cA >= 2 and cB >= 2:
            lo = max(atlo, btlo)
            hi = min(athi, bthi)
            if hi - lo > FACE_RTOL * L:
                eA = _face_edge(na, aklo, akhi)
                eB = _face_edge(nb, bklo, bkhi)
                if eA < 0 or eB < 0:
                    return PR_GEOMETRY, 0
                # each end of the overlap: a vertex of the body whose support ends there
                for end in range(2):
                    if (end == 0 and atlo >= btlo) or (end == 1 and athi <= bthi):
                        ka = aklo if end == 0 else akhi
                        _row_point(act, end, cl.KIND_FACE, ra, rb, V, va, na, ka, rA, mu)
                        _row_face(act, end, V, vb, nb, eB, rB, stB, nx, ny)
                    else:
                        kb = bklo if end == 0 else bkhi
                        _row_point(act, end, cl.KIND_FACE, rb, ra, V, vb, nb, kb, rB, mu)
                        _row_face(act, end, V, va, na, eA, rA, stA, -nx, -ny)
                return 2, 0
        elif cA == 1 and cB >= 2:
            eB = _face_edge(nb, bklo, bkhi)
            if eB >= 0 and btlo - tl <= atlo <= bthi + tl:
                return 1, _vertex_on_face(act, 0, cand, ra, rb, V, va, na, aklo, rA, vb, nb,
                                          eB, rB, stB, nx, ny, mu)
        elif cB == 1 and cA >= 2:
            eA = _face_edge(na, aklo, akhi)
            if eA >= 0 and atlo - tl <= btlo <= athi + tl:
                return 1, _vertex_on_face(act, 0, cand, rb, ra, V, vb, nb, bklo, rB, va, na,
                                          eA, rA, stA, -nx, -ny, mu)
        elif cA == 1 and cB == 1:
            if rA + rB > 0.0:
                _row_point(act, 0, cl.KIND_ROUND, ra, rb, V, va, na, aklo, rA, mu)
                _round_b(act, 0, V, vb, nb, bklo, rB)
                return 1, 0
            status = PR_CORNERS
        if attempt == 0:
            nx, ny = _best_face_axis(V, va, na, rA, stA, aklo, vb, nb, rB, stB, bklo, nx, ny)
    return status, 0


@njit(cache=True, _nrt=False)
def _vertex_on_face(out, r, cand, a, b, V, va, na, ka, rA, vb, nb, e, rB, stB, nx, ny, mu):
    """Active row r of out: vertex ka of body a on face e of body b (normal n from b into
    a); candidate rows cand[0:]: ka's neighbours on the same face. Returns the number of
    candidates."""
    _row_point(out, r, cl.KIND_FACE, a, b, V, va, na, ka, rA, mu)
    _row_face(out, r, V, vb, nb, e, rB, stB, nx, ny)
    m = 0
    if na >= 2:
        for d in range(2):
            kn = (ka + (1 if d == 0 else na - 1)) % na
            if kn == ka or (d == 1 and na == 2):
                continue
            _row_point(cand, m, cl.KIND_FACE, a, b, V, va, na, kn, rA, mu)
            _row_face(cand, m, V, vb, nb, e, rB, stB, nx, ny)
            m += 1
    return m


@njit(cache=True, _nrt=False)
def plane_rows(V, v0, nv, rad, st, r, nx, ny, d, tol, mu, act, max_act, cand, max_cand):
    """The rows of body row r (core ``V[v0 : v0 + nv]``, radius ``rad``, state row st)
    against the plane ``n . q >= d``: every core vertex within ``tol`` (m) of it an active
    ``KIND_PLANE`` row (into ``act``, at most ``max_act``), every other one a candidate
    (into ``cand``, at most ``max_cand``). Returns ``(n_active, n_candidates)``, or
    ``(-1, -1)`` (nothing written) when they do not fit."""
    c = math.cos(st[ANGLE])
    s = math.sin(st[ANGLE])
    na = 0
    for k in range(nv):
        px = st[X] + c * V[v0 + k, 0] - s * V[v0 + k, 1]
        py = st[Y] + s * V[v0 + k, 0] + c * V[v0 + k, 1]
        if nx * px + ny * py - d - rad <= tol:
            na += 1
    if na > max_act or nv - na > max_cand:
        return -1, -1
    ma = 0
    mc = 0
    for k in range(nv):
        px = st[X] + c * V[v0 + k, 0] - s * V[v0 + k, 1]
        py = st[Y] + s * V[v0 + k, 0] + c * V[v0 + k, 1]
        if nx * px + ny * py - d - rad <= tol:
            out = act
            m = ma
            ma += 1
        else:
            out = cand
            m = mc
            mc += 1
        _row_point(out, m, cl.KIND_PLANE, r, -1, V, v0, nv, k, rad, mu)
        out[m, cl.CC_NX] = nx
        out[m, cl.CC_NY] = ny
        out[m, cl.CC_D] = d
    return ma, mc


@njit(cache=True, _nrt=False)
def _row_ellipse(out, r, kind, a, b, ea, eb, mu, nx, ny):
    """Row r of out: kind, bodies (cluster rows a, b), A's ellipse (semi-axes ea, eb), the
    normal's angle from the world normal n (``CC_PSI``), open cones; the rest cleared."""
    row_clear(out, r, kind, a, b, mu)
    out[r, cl.CC_AEA] = ea
    out[r, cl.CC_AEB] = eb
    out[r, cl.CC_PSI] = math.atan2(ny, nx)


@njit(cache=True, _nrt=False)
def ellipse_rows(ea, eb, ra, V, vb, nb, rB, eab, ebb, stB, rb, nx, ny, tol, mu, act):
    """The contact row of an ellipse A (semi-axes ``ea, eb``, cluster row ``ra``) touching
    B (cluster row ``rb``, state row ``stB``): an ellipse (``eab, ebb > 0``), or a rounded
    polygon (core ``V[vb : vb + nb]``, radius ``rB``); ``n`` the unit normal from B into A
    (world, the pair frame's), ``tol`` (m) the support tolerance, ``mu`` the friction.
    Writes ``act[0]``; returns ``(1, 0)``, or ``(PR_GEOMETRY, 0)`` (module docstring)."""
    if eab > 0.0:
        _row_ellipse(act, 0, cl.KIND_ROUND, ra, rb, ea, eb, mu, nx, ny)
        act[0, cl.CC_BEA] = eab
        act[0, cl.CC_BEB] = ebb
        return 1, 0
    L = _core_reach(V, vb, nb) + rB
    cB, bklo, btlo, bkhi, bthi = _support(V, vb, nb, stB, nx, ny, 1.0,
                                          tol + FACE_RTOL * max(L, ea, eb))
    if cB == 1:
        _row_ellipse(act, 0, cl.KIND_ROUND, ra, rb, ea, eb, mu, nx, ny)
        _round_b(act, 0, V, vb, nb, bklo, rB)
        return 1, 0
    e = _face_edge(nb, bklo, bkhi)
    if cB < 1 or e < 0:
        return PR_GEOMETRY, 0
    _row_ellipse(act, 0, cl.KIND_FACE, ra, rb, ea, eb, mu, nx, ny)
    _row_face(act, 0, V, vb, nb, e, rB, stB, nx, ny)
    return 1, 0


@njit(cache=True, _nrt=False)
def ellipse_plane_rows(ea, eb, st, r, nx, ny, d, tol, mu, act, max_act, cand, max_cand):
    """The row of an ellipse (semi-axes ``ea, eb``, state row st, cluster row r) against the
    plane ``n . q >= d``: active when its gap is within ``tol`` (m), else a candidate.
    Returns ``(n_active, n_candidates)``, or ``(-1, -1)`` when it does not fit."""
    h, _, _ = ellipse_support3(ea, eb, st[ANGLE], nx, ny)     # the support along -n
    on = nx * st[X] + ny * st[Y] - d - h <= tol
    if (on and max_act < 1) or (not on and max_cand < 1):
        return -1, -1
    out = act if on else cand
    _row_ellipse(out, 0, cl.KIND_PLANE, r, -1, ea, eb, mu, nx, ny)
    out[0, cl.CC_NX] = nx
    out[0, cl.CC_NY] = ny
    out[0, cl.CC_D] = d
    return (1, 0) if on else (0, 1)


# ---- feature switches (cluster2d's CE_FEATURE) ----------------------------------------------

SW_SWITCHED = 1     # the row now describes the contact on the next feature
SW_LANDING = 2      # A's face lands on B's face or on the plane: an impact instant


@njit(cache=True, _nrt=False)
def _vertex_index(V, v0, nv, px, py):
    """The index of the core vertex whose body-frame coordinates are (px, py) (rows copy
    them exactly), or -1."""
    for k in range(nv):
        if V[v0 + k, 0] == px and V[v0 + k, 1] == py:
            return k
    return -1


@njit(cache=True, _nrt=False)
def _adjacent_face(V, v0, nv, k, st, ux, uy):
    """The core edge at vertex k (k - 1 or k; a rod's one edge) whose outward normal (world,
    body state row st) is closest to the direction u; -1 for a disk."""
    if nv <= 1:
        return -1
    if nv == 2:
        return 0
    best = -INF
    eb = -1
    for d in range(2):
        e = k if d == 0 else (k - 1) % nv
        fx, fy = _edge_axis(V, v0, nv, e, st, 1.0)
        if fx * ux + fy * uy > best:
            best = fx * ux + fy * uy
            eb = e
    return eb


@njit(cache=True, _nrt=False)
def row_normal(table, k, stA, stB):
    """The unit normal (world, from B into A) of row k of a contact table at the state rows
    stA, stB of its bodies (``cluster2d``'s kinematics: a face's rotated normal, the plane's,
    or the centres' direction of two point features)."""
    kind = table[k, cl.CC_KIND]
    if kind == cl.KIND_PLANE:
        return table[k, cl.CC_NX], table[k, cl.CC_NY]
    cb = math.cos(stB[ANGLE])
    sb = math.sin(stB[ANGLE])
    if kind == cl.KIND_FACE:
        return (cb * table[k, cl.CC_NX] - sb * table[k, cl.CC_NY],
                sb * table[k, cl.CC_NX] + cb * table[k, cl.CC_NY])
    pax, pay, _, pbx, pby, _ = cl.feature_circles(table, k, stA[X], stA[Y], stA[ANGLE],
                                                  stB[X], stB[Y], stB[ANGLE])
    ca = math.cos(stA[ANGLE])
    sa = math.sin(stA[ANGLE])
    dx = stA[X] + ca * pax - sa * pay - stB[X] - cb * pbx + sb * pby
    dy = stA[Y] + sa * pax + ca * pay - stB[Y] - sb * pbx - cb * pby
    d = math.hypot(dx, dy)
    return dx / d, dy / d


@njit(cache=True, _nrt=False)
def _round_b(table, k, V, vb, nb, kb, rB):
    """B's point feature of a KIND_ROUND row k: vertex kb, radius rB, its normal cone."""
    table[k, cl.CC_PBX] = V[vb + kb, 0]
    table[k, cl.CC_PBY] = V[vb + kb, 1]
    table[k, cl.CC_RB] = rB
    lo, hi = vertex_cone(V, vb, nb, kb)
    table[k, cl.CC_BLO] = lo
    table[k, cl.CC_BHI] = hi


@njit(cache=True, _nrt=False)
def _far_end(V, table, k, fr, vb, nb):
    """The core vertex of B at the end of row k's face that its contact point leaves across
    (range ``fr``), or -1."""
    e = _vertex_index(V, vb, nb, table[k, cl.CC_PBX], table[k, cl.CC_PBY])
    if e < 0:
        return -1
    if nb == 2:
        e = 0
    s1 = table[k, cl.CC_BLO] + table[k, cl.CC_BHI]     # the far end's coordinate (one is 0)
    far = (fr == cl.FR_BHI) == (s1 > 0.0)
    return (e + 1) % nb if far else e


@njit(cache=True, _nrt=False)
def _switch_ellipse(V, table, k, fr, nx, ny, vb, nb, rB, stB):
    """``switch_row`` for an ellipse A (normal n at the switch): off B's face onto its end
    vertex, out of B's vertex cone onto the adjacent face."""
    kind = table[k, cl.CC_KIND]
    if table[k, cl.CC_BEA] > 0.0 or kind == cl.KIND_PLANE or fr == cl.FR_ALO or fr == cl.FR_AHI:
        return PR_GEOMETRY
    a = table[k, cl.CC_A]
    b = table[k, cl.CC_B]
    ea = table[k, cl.CC_AEA]
    eb = table[k, cl.CC_AEB]
    mu = table[k, cl.CC_MU]
    mode = table[k, cl.CC_MODE]
    if kind == cl.KIND_FACE:
        kend = _far_end(V, table, k, fr, vb, nb)
        if kend < 0:
            return PR_GEOMETRY
        _row_ellipse(table, k, cl.KIND_ROUND, a, b, ea, eb, mu, nx, ny)
        _round_b(table, k, V, vb, nb, kend, rB)
    else:
        kb = _vertex_index(V, vb, nb, table[k, cl.CC_PBX], table[k, cl.CC_PBY])
        e = _adjacent_face(V, vb, nb, kb, stB, nx, ny) if kb >= 0 else -1
        if e < 0:
            return PR_GEOMETRY
        _row_ellipse(table, k, cl.KIND_FACE, a, b, ea, eb, mu, nx, ny)
        _row_face(table, k, V, vb, nb, e, rB, stB, nx, ny)
    table[k, cl.CC_MODE] = mode
    return SW_SWITCHED


@njit(cache=True, _nrt=False)
def switch_row(V, table, k, fr, va, na, rA, stA, vb, nb, rB, stB):
    """Rewrite row k of a contact table for the feature its contact point moves onto when
    its range ``fr`` (``cluster2d.FR_*``) is left (``CE_FEATURE``), at the state rows stA,
    stB of its bodies A and B (cores ``V[va : va + na]``, ``V[vb : vb + nb]``, radii rA,
    rB; B unused for a plane):

    * a point-face contact leaving the face's extent: the point feature on the face's end
      vertex (``KIND_ROUND``); two sharp corners: the face's end corner on the point
      body's edge at its corner that faces back along the face (the mirror
      ``KIND_FACE``: A and B exchanged, the slip's sign with them);
    * a round-round contact leaving a vertex's normal cone: the other point feature on
      that vertex's edge on the cone's side (``KIND_FACE``, mirrored when the vertex is
      A's);
    * the point feature's own cone in a point-face or plane contact: A's adjacent face
      lies on the face or the plane, ``SW_LANDING`` (the neighbour vertex lands: an
      impact, nothing rewritten);
    * an ellipse A (``_switch_ellipse``): off B's face onto its end vertex, out of B's
      vertex cone onto the adjacent face.

    The mode (stick, or slip along the row's t) is kept. Returns ``SW_SWITCHED``,
    ``SW_LANDING`` or ``PR_GEOMETRY`` (a feature not found in the cores)."""
    kind = table[k, cl.CC_KIND]
    nx, ny = row_normal(table, k, stA, stB)
    if table[k, cl.CC_AEA] > 0.0:
        return _switch_ellipse(V, table, k, fr, nx, ny, vb, nb, rB, stB)
    ka = _vertex_index(V, va, na, table[k, cl.CC_PAX], table[k, cl.CC_PAY])
    if ka < 0:
        return PR_GEOMETRY
    mu = table[k, cl.CC_MU]
    mode = table[k, cl.CC_MODE]
    a = table[k, cl.CC_A]
    b = table[k, cl.CC_B]
    if fr == cl.FR_ALO or fr == cl.FR_AHI:
        if kind != cl.KIND_ROUND:
            return SW_LANDING
        kb = _vertex_index(V, vb, nb, table[k, cl.CC_PBX], table[k, cl.CC_PBY])
        e = _adjacent_face(V, va, na, ka, stA, -nx, -ny)
        if kb < 0 or e < 0:
            return PR_GEOMETRY
        _row_point(table, k, cl.KIND_FACE, b, a, V, vb, nb, kb, rB, mu)
        _row_face(table, k, V, va, na, e, rA, stA, -nx, -ny)
        table[k, cl.CC_MODE] = -mode if mode != cl.MODE_STICK else mode
        return SW_SWITCHED
    if kind == cl.KIND_ROUND:
        kb = _vertex_index(V, vb, nb, table[k, cl.CC_PBX], table[k, cl.CC_PBY])
        e = _adjacent_face(V, vb, nb, kb, stB, nx, ny)
        if kb < 0 or e < 0:
            return PR_GEOMETRY
        _row_point(table, k, cl.KIND_FACE, a, b, V, va, na, ka, rA, mu)
        _row_face(table, k, V, vb, nb, e, rB, stB, nx, ny)
        table[k, cl.CC_MODE] = mode
        return SW_SWITCHED
    if kind != cl.KIND_FACE:
        return PR_GEOMETRY
    kend = _far_end(V, table, k, fr, vb, nb)
    if kend < 0:
        return PR_GEOMETRY
    if rA + rB > 0.0:
        _row_point(table, k, cl.KIND_ROUND, a, b, V, va, na, ka, rA, mu)
        _round_b(table, k, V, vb, nb, kend, rB)
        table[k, cl.CC_MODE] = mode
        return SW_SWITCHED
    # two sharp corners: B's end corner on A's edge at ka facing back along the face
    sg = 1.0 if fr == cl.FR_BHI else -1.0
    dx = sg * ny            # the direction the contact point left along (t = (n_y, -n_x))
    dy = -sg * nx
    ea = _adjacent_face(V, va, na, ka, stA, -dx, -dy)
    if ea < 0:
        return PR_GEOMETRY
    _row_point(table, k, cl.KIND_FACE, b, a, V, vb, nb, kend, rB, mu)
    _row_face(table, k, V, va, na, ea, rA, stA, -nx, -ny)
    table[k, cl.CC_MODE] = -mode if mode != cl.MODE_STICK else mode
    return SW_SWITCHED


@njit(cache=True, _nrt=False)
def row_rate(table, k, stA, stB):
    """The gap rate (m/s) of row k at the state rows stA, stB (velocity columns ``VX, VY,
    OMEGA``; stB unused for a plane): ``n . (v_A(p) - v_B(p))`` at the contact point
    ``p = cA - rA n`` (``cluster2d``: the exact derivative of the row's gap)."""
    nx, ny = row_normal(table, k, stA, stB)
    pax, pay, rA, _, _, _ = cl.feature_circles(table, k, stA[X], stA[Y], stA[ANGLE], stB[X],
                                               stB[Y], stB[ANGLE])
    ca = math.cos(stA[ANGLE])
    sa = math.sin(stA[ANGLE])
    px = ca * pax - sa * pay - rA * nx
    py = sa * pax + ca * pay - rA * ny
    ux = stA[VX] - stA[OMEGA] * py
    uy = stA[VY] + stA[OMEGA] * px
    if table[k, cl.CC_KIND] != cl.KIND_PLANE:
        bx = stA[X] + px - stB[X]
        by = stA[Y] + py - stB[Y]
        ux -= stB[VX] - stB[OMEGA] * by
        uy -= stB[VY] + stB[OMEGA] * bx
    return nx * ux + ny * uy
