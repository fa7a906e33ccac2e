"""Gap, normal, witness points and features of 3D pairs with a point or segment core:
sphere-sphere, sphere-capsule, capsule-capsule (``rounded_frame``) and a box against a
sphere or a capsule (``box_rounded_frame``); ``pair3d_shape`` for the encoding.

Every computation is done in **A's body frame** (A's centre at the origin, its axes the
coordinate axes): a capsule's axis and a box's edges are then coordinate directions, so the
cross products that give edge-edge normals are exact component swaps, and the relative
orientation ``R_A^T R_B`` comes from the quaternion product ``q_A^* q_B`` (accurate for a small
relative rotation). The caller rotates the normal and witness points to the world.

Sphere and capsule are a point or a segment swept by a sphere: the signed distance of two
such bodies is the distance of their cores minus ``rA + rB``, exact also when they overlap
(minus the penetration depth, as long as the cores are disjoint; intersecting cores give
``-rA - rB``, their exact depth, since two points or segments that meet are separated by
an arbitrarily small translation).

Segment-segment closest points (Ericson, *Real-Time Collision Detection*, 2005, sec.
5.1.9), with the line parameters written with the cross product ``m = d1 x d2`` (Lagrange's
identity): ``s = m . (d2 x r) / |m|^2``, ``r = p1 - p2``; for an axis-aligned ``d1`` (A's
axis or edge) ``m`` is exact, and ``s`` keeps a relative error ``eps / sin(angle)`` instead
of the ``eps / sin^2`` of the normal equations; ``t = (d2 . (r + s d1)) / |d2|^2`` follows
``s`` (so that ``pA - pB`` is along ``n`` to round-off of the size). When both
closest points are interior the normal is ``+-m / |m|`` and the distance ``|m . r| / |m|``
(exact direction also as the distance goes to 0). ``|m| <= SEG_PARALLEL |d1| |d2|``: parallel
(Ericson's branch ``s = 0``, exact for parallel segments).

Point-box (Ericson sec. 5.1.3): clamp to the box. Outside a single slab the normal is the
face normal and the distance ``|p_i| - h_i`` (exact); inside, the shallowest face gives
the exact penetration depth.

Segment-box distance, exact: ``F(t) = sum_i max(|a_i + d_i t| - h_i, 0)^2`` is convex and
``C^1``, and on each piece between the slab crossings (``a_i + d_i t = +-h_i``) a quadratic
fixed by the pattern of clamped axes (each below, inside or above its slab). Its minimiser
over ``[0, 1]`` is an end, a slab crossing, or the stationary point of one pattern's
quadratic: all 2 + 6 + 26 candidates are evaluated with ``F`` itself (a candidate of a
pattern not active there can only give a larger value). Overlapping (``F = 0``): separating
axes, the box's three face normals and ``e_i x d`` (exact components; skipped only when
``|e_i x d| <= AXIS_MIN |d|``, parallel),
both signs: ``g = max sigma - rB`` is minus the exact penetration depth (the Minkowski sum
of a box and a segment is a polytope with those face normals).

Witness points ``pA``, ``pB`` lie on the boundaries with ``pA - pB = g n`` (when overlapping,
``pB`` is B's deepest point along the axis and ``pA = pB + g n``).
"""
import math

from numba import njit

from .cache_guard import guard

guard(__name__, __file__)

from .pair3d_clip import clip_segment_face  # noqa: E402
from .pair3d_shape import (AXIS_MIN, FT_EDGE, FT_FACE, FT_VERTEX, SH_CAPSULE,  # noqa: E402
                           box_edge, box_edge_index, box_vertex_index)

SEG_PARALLEL = 1e-14    # sine of the angle below which two segments are parallel (-)


@njit(cache=True, _nrt=False, inline="always")
def _clamp01(x):
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    return x


@njit(cache=True, _nrt=False)
def seg_seg(p1x, p1y, p1z, d1x, d1y, d1z, p2x, p2y, p2z, d2x, d2y, d2z):
    """Closest points ``p1 + s d1`` and ``p2 + t d2`` (``s, t`` in [0, 1], exactly 0 or 1 when
    clamped) of two segments (either may be a point, ``d = 0``). Returns ``(s, t, dist, nx,
    ny, nz)`` with ``n`` the unit normal from segment 2 toward segment 1 (``+-m/|m|`` for
    interior points of non-parallel segments; when ``dist = 0`` a direction normal to both,
    or to ``d1``)."""
    rx = p1x - p2x
    ry = p1y - p2y
    rz = p1z - p2z
    a = d1x * d1x + d1y * d1y + d1z * d1z
    e = d2x * d2x + d2y * d2y + d2z * d2z
    f = d2x * rx + d2y * ry + d2z * rz
    mx = d1y * d2z - d1z * d2y
    my = d1z * d2x - d1x * d2z
    mz = d1x * d2y - d1y * d2x
    m2 = mx * mx + my * my + mz * mz
    nonpar = m2 > SEG_PARALLEL * SEG_PARALLEL * a * e and m2 > 0.0
    if a == 0.0 and e == 0.0:
        s = 0.0
        t = 0.0
    elif a == 0.0:
        s = 0.0
        t = _clamp01(f / e)
    else:
        c = d1x * rx + d1y * ry + d1z * rz
        if e == 0.0:
            t = 0.0
            s = _clamp01(-c / a)
        else:
            b = d1x * d2x + d1y * d2y + d1z * d2z
            if nonpar:
                # s = m . (d2 x r) / |m|^2 (Lagrange's identity for (b f - c e) / (a e - b^2))
                ux = d2y * rz - d2z * ry
                uy = d2z * rx - d2x * rz
                uz = d2x * ry - d2y * rx
                s = _clamp01((mx * ux + my * uy + mz * uz) / m2)
                # t follows s (the projection of p1 + s d1 on segment 2): the witness
                # points then differ along n to round-off of the size, not eps / sin
                t = (b * s + f) / e
            else:
                s = 0.0
                t = (b * s + f) / e
            if t <= 0.0:
                t = 0.0
                s = _clamp01(-c / a)
            elif t >= 1.0:
                t = 1.0
                s = _clamp01((b - c) / a)
    if nonpar and s > 0.0 and s < 1.0 and t > 0.0 and t < 1.0:
        m = math.sqrt(m2)
        h = (mx * rx + my * ry + mz * rz) / m
        if h < 0.0:
            return s, t, -h, -mx / m, -my / m, -mz / m
        return s, t, h, mx / m, my / m, mz / m
    wx = rx + s * d1x - t * d2x
    wy = ry + s * d1y - t * d2y
    wz = rz + s * d1z - t * d2z
    dist = math.sqrt(wx * wx + wy * wy + wz * wz)
    if dist > 0.0:
        return s, t, dist, wx / dist, wy / dist, wz / dist
    if nonpar:
        m = math.sqrt(m2)
        return s, t, 0.0, mx / m, my / m, mz / m
    return (s, t, 0.0) + any_normal(d1x, d1y, d1z)


@njit(cache=True, _nrt=False, inline="always")
def any_normal(dx, dy, dz):
    """A unit vector normal to ``d`` (``z^`` for ``d = 0``), deterministic."""
    if dx == 0.0 and dy == 0.0:
        return 1.0, 0.0, 0.0
    L = math.sqrt(dx * dx + dy * dy)
    return -dy / L, dx / L, 0.0


@njit(cache=True, _nrt=False, inline="always")
def _clamp_axis(p, h):
    """Clamp a coordinate to ``[-h, h]``: ``(q, side)``, side -1/0/+1."""
    if p > h:
        return h, 1
    if p < -h:
        return -h, -1
    return p, 0


@njit(cache=True, _nrt=False)
def point_box(px, py, pz, hx, hy, hz):
    """Point ``p`` against the axis-aligned box of half edges ``h`` centred at the origin.
    Returns ``(dist, ux, uy, uz, qx, qy, qz, fk, fi)``: signed distance (negative inside:
    minus the depth below the shallowest face), ``u`` the unit outward direction from the box
    to the point, ``q`` the box's boundary point, and its feature (``FT_FACE``, ``FT_EDGE``,
    ``FT_VERTEX`` and index)."""
    qx, sx = _clamp_axis(px, hx)
    qy, sy = _clamp_axis(py, hy)
    qz, sz = _clamp_axis(pz, hz)
    nc = abs(sx) + abs(sy) + abs(sz)
    if nc == 0:         # inside: the shallowest face (ties: the lowest axis, the + side)
        dx = hx - abs(px)
        dy = hy - abs(py)
        dz = hz - abs(pz)
        if dx <= dy and dx <= dz:
            sg = 1.0 if px >= 0.0 else -1.0
            return -dx, sg, 0.0, 0.0, sg * hx, py, pz, FT_FACE, 1 if sg > 0.0 else 0
        if dy <= dz:
            sg = 1.0 if py >= 0.0 else -1.0
            return -dy, 0.0, sg, 0.0, px, sg * hy, pz, FT_FACE, 3 if sg > 0.0 else 2
        sg = 1.0 if pz >= 0.0 else -1.0
        return -dz, 0.0, 0.0, sg, px, py, sg * hz, FT_FACE, 5 if sg > 0.0 else 4
    if nc == 1:         # a face: exact normal and distance
        if sx != 0:
            return abs(px) - hx, float(sx), 0.0, 0.0, qx, qy, qz, FT_FACE, 1 if sx > 0 else 0
        if sy != 0:
            return abs(py) - hy, 0.0, float(sy), 0.0, qx, qy, qz, FT_FACE, 3 if sy > 0 else 2
        return abs(pz) - hz, 0.0, 0.0, float(sz), qx, qy, qz, FT_FACE, 5 if sz > 0 else 4
    wx = px - qx
    wy = py - qy
    wz = pz - qz
    dist = math.sqrt(wx * wx + wy * wy + wz * wz)
    if nc == 3:
        return (dist, wx / dist, wy / dist, wz / dist, qx, qy, qz, FT_VERTEX,
                box_vertex_index(float(sx), float(sy), float(sz)))
    if sx == 0:
        e = box_edge_index(0, float(sy), float(sz))
    elif sy == 0:
        e = box_edge_index(1, float(sz), float(sx))
    else:
        e = box_edge_index(2, float(sx), float(sy))
    return dist, wx / dist, wy / dist, wz / dist, qx, qy, qz, FT_EDGE, e


@njit(cache=True, _nrt=False, inline="always")
def _excess2(x, h):
    """``max(|x| - h, 0)^2``."""
    u = abs(x) - h
    return u * u if u > 0.0 else 0.0


@njit(cache=True, _nrt=False, inline="always")
def _F(ax, ay, az, dx, dy, dz, hx, hy, hz, t):
    """Squared distance of ``a + d t`` to the box."""
    return (_excess2(ax + dx * t, hx) + _excess2(ay + dy * t, hy)
            + _excess2(az + dz * t, hz))


@njit(cache=True, _nrt=False)
def segment_box_param(ax, ay, az, dx, dy, dz, hx, hy, hz):
    """Parameter ``t`` in [0, 1] of the point of segment ``a + d t`` closest to the box
    (exact minimiser of ``F``, module docstring) and ``F`` there (m^2)."""
    bt = 0.0
    bF = _F(ax, ay, az, dx, dy, dz, hx, hy, hz, 0.0)
    F1 = _F(ax, ay, az, dx, dy, dz, hx, hy, hz, 1.0)
    if F1 < bF:
        bt = 1.0
        bF = F1
    # slab crossings
    for i in range(3):
        a = ax if i == 0 else (ay if i == 1 else az)
        d = dx if i == 0 else (dy if i == 1 else dz)
        h = hx if i == 0 else (hy if i == 1 else hz)
        if d == 0.0:
            continue
        for sg in (-1.0, 1.0):
            t = (sg * h - a) / d
            if t > 0.0 and t < 1.0:
                Ft = _F(ax, ay, az, dx, dy, dz, hx, hy, hz, t)
                if Ft < bF:
                    bF = Ft
                    bt = t
    # stationary points of the 26 clamp patterns
    for pat in range(27):
        sx = pat % 3 - 1
        sy = (pat // 3) % 3 - 1
        sz = pat // 9 - 1
        num = 0.0
        den = 0.0
        if sx != 0:
            num += dx * (ax - sx * hx)
            den += dx * dx
        if sy != 0:
            num += dy * (ay - sy * hy)
            den += dy * dy
        if sz != 0:
            num += dz * (az - sz * hz)
            den += dz * dz
        if not den > 0.0:
            continue
        t = _clamp01(-num / den)
        Ft = _F(ax, ay, az, dx, dy, dz, hx, hy, hz, t)
        if Ft < bF:
            bF = Ft
            bt = t
    return bt, bF


@njit(cache=True, _nrt=False, inline="always")
def _seg_feature(t):
    """Capsule feature of a core parameter: an end cap (vertex 0 or 1) or the side."""
    if t == 0.0:
        return FT_VERTEX, 0
    if t == 1.0:
        return FT_VERTEX, 1
    return FT_EDGE, 0


@njit(cache=True, _nrt=False)
def rounded_frame(kA, rA, hA, kB, rB, hB, cx, cy, cz, bx, by, bz):
    """Two point/segment cores (sphere or capsule) in A's frame: A's core from ``(0, 0, -hA)``
    to ``(0, 0, hA)`` (``hA = 0`` for a sphere), B's centred at ``c`` with unit axis ``b``
    and half length ``hB``. Returns ``(g, n, pA, pB, fa, ia, fb, ib)`` (15 values, A's frame)."""
    s, t, dist, nx, ny, nz = seg_seg(0.0, 0.0, -hA, 0.0, 0.0, 2.0 * hA,
                                     cx - hB * bx, cy - hB * by, cz - hB * bz,
                                     2.0 * hB * bx, 2.0 * hB * by, 2.0 * hB * bz)
    cax = 0.0
    cay = 0.0
    caz = -hA + 2.0 * hA * s
    tb = 2.0 * t - 1.0
    cbx = cx + tb * hB * bx
    cby = cy + tb * hB * by
    cbz = cz + tb * hB * bz
    fa, ia = _seg_feature(s) if kA == SH_CAPSULE else (FT_VERTEX, 0)
    fb, ib = _seg_feature(t) if kB == SH_CAPSULE else (FT_VERTEX, 0)
    return (dist - rA - rB, nx, ny, nz, cax - rA * nx, cay - rA * ny, caz - rA * nz,
            cbx + rB * nx, cby + rB * ny, cbz + rB * nz, fa, ia, fb, ib)


@njit(cache=True, _nrt=False)
def _seg_box_sep(hx, hy, hz, ax, ay, az, dx, dy, dz, ux, uy, uz):
    """Largest separation of the box (A) and segment core ``a + d t`` (B) along ``+-u``:
    ``(sigma, sign)`` with the normal from B into A ``sign * u``."""
    ra = hx * abs(ux) + hy * abs(uy) + hz * abs(uz)
    p0 = ux * ax + uy * ay + uz * az
    p1 = p0 + ux * dx + uy * dy + uz * dz
    lo = min(p0, p1)
    hi = max(p0, p1)
    sp = -ra - hi       # A on the +u side of B
    sm = lo - ra        # A on the -u side
    if sp >= sm:
        return sp, 1.0
    return sm, -1.0


@njit(cache=True, _nrt=False)
def box_rounded_frame(hx, hy, hz, kB, rB, hB, cx, cy, cz, bx, by, bz):
    """Box A (half edges ``h``) at the origin of its own frame against a sphere or capsule B
    (centre ``c``, unit axis ``b``, half length ``hB``, radius ``rB``). Returns
    ``(g, n, pA, pB, fa, ia, fb, ib)`` (15 values, A's frame; ``n`` from B into A)."""
    ax = cx - hB * bx
    ay = cy - hB * by
    az = cz - hB * bz
    dx = 2.0 * hB * bx
    dy = 2.0 * hB * by
    dz = 2.0 * hB * bz
    if hB == 0.0 or kB != SH_CAPSULE:
        t = 0.0
        F = 0.0
    else:
        t, F = segment_box_param(ax, ay, az, dx, dy, dz, hx, hy, hz)
    fb, ib = _seg_feature(t) if kB == SH_CAPSULE else (FT_VERTEX, 0)
    px = ax + dx * t
    py = ay + dy * t
    pz = az + dz * t
    if F > 0.0 or kB != SH_CAPSULE or hB == 0.0:
        dist, ux, uy, uz, qx, qy, qz, fa, ia = point_box(px, py, pz, hx, hy, hz)
        if dist >= 0.0 or kB != SH_CAPSULE or hB == 0.0:
            if fa == FT_EDGE and fb == FT_EDGE:
                # box edge against the capsule's side: exact normal by the cross product
                e0x, e0y, e0z, e1x, e1y, e1z = box_edge(hx, hy, hz, ia)
                s2, t2, dist, ux, uy, uz = seg_seg(ax, ay, az, dx, dy, dz, e0x, e0y, e0z,
                                                   e1x - e0x, e1y - e0y, e1z - e0z)
                qx = e0x + t2 * (e1x - e0x)
                qy = e0y + t2 * (e1y - e0y)
                qz = e0z + t2 * (e1z - e0z)
                px = ax + dx * s2
                py = ay + dy * s2
                pz = az + dz * s2
                fb, ib = _seg_feature(s2)
                if t2 == 0.0 or t2 == 1.0:
                    e0 = ia // 4
                    fa = FT_VERTEX
                    ia = _edge_end_vertex(ia, e0, t2)
            # n from B into A is -u (u points from the box to B's core point)
            if dist >= 0.0:
                return (dist - rB, -ux, -uy, -uz, qx, qy, qz, px - rB * ux, py - rB * uy,
                        pz - rB * uz, fa, ia, fb, ib)
            # B's centre inside the box: exact depth below the shallowest face
            g = dist - rB
            pbx = px - rB * ux
            pby = py - rB * uy
            pbz = pz - rB * uz
            return (g, -ux, -uy, -uz, pbx - g * ux, pby - g * uy, pbz - g * uz, pbx, pby,
                    pbz, fa, ia, fb, ib)
    # the capsule's core meets the box: separating axes (faces, then edge x axis)
    best = -math.inf
    nx = 1.0
    ny = 0.0
    nz = 0.0
    bw = 0
    bi = 0
    for i in range(3):
        ux = 1.0 if i == 0 else 0.0
        uy = 1.0 if i == 1 else 0.0
        uz = 1.0 if i == 2 else 0.0
        sg, sgn = _seg_box_sep(hx, hy, hz, ax, ay, az, dx, dy, dz, ux, uy, uz)
        if sg > best:
            best = sg
            nx = sgn * ux
            ny = sgn * uy
            nz = sgn * uz
            bw = 0
            bi = i
    L = math.sqrt(dx * dx + dy * dy + dz * dz)
    for i in range(3):
        # e_i x d
        if i == 0:
            ux, uy, uz = 0.0, -dz, dy
        elif i == 1:
            ux, uy, uz = dz, 0.0, -dx
        else:
            ux, uy, uz = -dy, dx, 0.0
        m = math.sqrt(ux * ux + uy * uy + uz * uz)
        if not m > AXIS_MIN * L:
            continue
        ux /= m
        uy /= m
        uz /= m
        sg, sgn = _seg_box_sep(hx, hy, hz, ax, ay, az, dx, dy, dz, ux, uy, uz)
        if sg > best:
            best = sg
            nx = sgn * ux
            ny = sgn * uy
            nz = sgn * uz
            bw = 1
            bi = i
    g = min(best, 0.0) - rB
    if bw == 0:
        # A's face (outward normal -n) against B's deepest end (ties: the side)
        p0 = nx * ax + ny * ay + nz * az
        p1 = p0 + nx * dx + ny * dy + nz * dz
        if p0 > p1:
            t = 0.0
            fb, ib = FT_VERTEX, 0
        elif p1 > p0:
            t = 1.0
            fb, ib = FT_VERTEX, 1
        else:
            t = 0.5
            fb, ib = FT_EDGE, 0
        # the deepest point of the part of the core over A's face (a parallel capsule's
        # ends may hang over the face's sides)
        t0, t1, ok = clip_segment_face(ax, ay, az, dx, dy, dz, bi, hx, hy, hz)
        if ok:
            q0 = p0 + t0 * (p1 - p0)
            q1 = p0 + t1 * (p1 - p0)
            if q0 > q1:
                t = t0
            elif q1 > q0:
                t = t1
            else:
                t = 0.5 * (t0 + t1)
            fb, ib = _seg_feature(t)
        m_i = nx if bi == 0 else (ny if bi == 1 else nz)
        fa = FT_FACE
        ia = 2 * bi + (1 if -m_i > 0.0 else 0)
        pbx = ax + dx * t + rB * nx
        pby = ay + dy * t + rB * ny
        pbz = az + dz * t + rB * nz
        return (g, nx, ny, nz, pbx + g * nx, pby + g * ny, pbz + g * nz, pbx, pby, pbz, fa,
                ia, fb, ib)
    # A's edge parallel to axis bi (the one lowest along n) against the capsule's side
    j = (bi + 1) % 3
    k = (bi + 2) % 3
    nj = nx if j == 0 else (ny if j == 1 else nz)
    nk = nx if k == 0 else (ny if k == 1 else nz)
    ia = box_edge_index(bi, -1.0 if nj >= 0.0 else 1.0, -1.0 if nk >= 0.0 else 1.0)
    e0x, e0y, e0z, e1x, e1y, e1z = box_edge(hx, hy, hz, ia)
    s2, t2, _, _, _, _ = seg_seg(ax, ay, az, dx, dy, dz, e0x, e0y, e0z, e1x - e0x, e1y - e0y,
                                 e1z - e0z)
    pbx = ax + dx * s2 + rB * nx
    pby = ay + dy * s2 + rB * ny
    pbz = az + dz * s2 + rB * nz
    return (g, nx, ny, nz, pbx + g * nx, pby + g * ny, pbz + g * nz, pbx, pby, pbz, FT_EDGE,
            ia, FT_EDGE, 0)


@njit(cache=True, _nrt=False, inline="always")
def _edge_end_vertex(e, i, t):
    """Corner index of the end ``t`` (0: -h_i, 1: +h_i) of box edge ``e`` along axis ``i``."""
    m = e % 4
    s1 = 2.0 * (m & 1) - 1.0
    s2 = 2.0 * ((m >> 1) & 1) - 1.0
    si = 2.0 * t - 1.0
    if i == 0:
        return box_vertex_index(si, s1, s2)
    if i == 1:
        return box_vertex_index(s2, si, s1)
    return box_vertex_index(s1, s2, si)
