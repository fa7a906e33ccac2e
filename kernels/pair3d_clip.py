"""Face clipping for 3D box contacts: the deepest point of an incident face over a reference
face (the witness of an overlapping face axis in ``pair3d_box``) and the contact polygon of
a face or an edge lying on a face (``pair3d_manifold``): the shared pieces.

Setting (reference box's frame): the reference face is the face ``x_i = s h_i`` of the
axis-aligned box of half edges ``hR`` centred at the origin (outward normal ``s e_i``,
toward the incident body); the incident box has half edges ``hI``, orientation ``C``
(nine floats, incident body axes in the reference frame) and centre ``c``. The incident
face is the incident box's face whose outward normal is most opposed to ``s e_i``. The
height of a point above the reference face is ``z = s x_i - h_i`` (negative: penetration).

Deepest point (``face_deepest``): the height is affine on the incident face, so its minimum
over the part of the incident face that projects (along ``e_i``) inside the reference face
is attained at a vertex of that convex polygon: an incident corner inside the reference
face, a reference corner lifted onto the incident face and inside it, or a crossing of an
incident edge with a side line of the reference face. All are enumerated (no clipping
buffers); "inside" is tested with the tolerance ``CLIP_TOL`` relative to the faces' half
extents. Segment clipping (``clip_segment_face``, Liang-Barsky) for a capsule over a face.
The contact polygon of the manifold (Sutherland-Hodgman clipping of the incident face
against the four side planes of the reference face) is in ``pair3d_manifold``, which holds
its buffers.
"""
import math

from numba import njit

from .cache_guard import guard

guard(__name__, __file__)

from .pair3d_shape import mat_tvec, mat_vec  # noqa: E402

CLIP_TOL = 1e-12    # inside tests: tolerance relative to the face half extents (-)


@njit(cache=True, _nrt=False, inline="always")
def _pick(x, y, z, i):
    return x if i == 0 else (y if i == 1 else z)


@njit(cache=True, _nrt=False)
def incident_face(C, i, s):
    """``(axis, sign)`` of the incident box's face most opposed to ``s e_i``: the largest
    ``|C[i][j]|`` with sign ``-sign(s C[i][j])`` (ties: the lowest axis)."""
    best = -1.0
    jb = 0
    for j in range(3):
        a = abs(C[3 * i + j])
        if a > best:
            best = a
            jb = j
    return jb, (-1.0 if s * C[3 * i + jb] > 0.0 else 1.0)


@njit(cache=True, _nrt=False, inline="always")
def _face_corner(C, cx, cy, cz, hI0, hI1, hI2, j, sj, m):
    """Corner ``m`` (0..3, counter-clockwise seen from outside up to orientation) of the
    incident face ``x_j = sj hI_j`` in the reference frame."""
    a = (j + 1) % 3
    b = (j + 2) % 3
    ua = 1.0 if (m == 1 or m == 2) else -1.0
    ub = 1.0 if m >= 2 else -1.0
    h0 = hI0 if a == 0 else (hI1 if a == 1 else hI2)
    h1 = hI0 if b == 0 else (hI1 if b == 1 else hI2)
    hj = hI0 if j == 0 else (hI1 if j == 1 else hI2)
    l0 = sj * hj if j == 0 else (ua * h0 if a == 0 else ub * h1)
    l1 = sj * hj if j == 1 else (ua * h0 if a == 1 else ub * h1)
    l2 = sj * hj if j == 2 else (ua * h0 if a == 2 else ub * h1)
    wx, wy, wz = mat_vec(C, l0, l1, l2)
    return cx + wx, cy + wy, cz + wz


@njit(cache=True, _nrt=False)
def face_deepest(hR0, hR1, hR2, i, s, C, cx, cy, cz, hI0, hI1, hI2):
    """Lowest point (module docstring) of the incident face over the reference face
    ``x_i = s hR_i``: ``(z, px, py, pz, found)`` in the reference frame, ``p`` on the
    incident face; ``found = 0`` if the projections do not overlap."""
    j, sj = incident_face(C, i, s)
    a = (i + 1) % 3
    b = (i + 2) % 3
    hi = _pick(hR0, hR1, hR2, i)
    ha = _pick(hR0, hR1, hR2, a)
    hb = _pick(hR0, hR1, hR2, b)
    ta = CLIP_TOL * ha
    tb = CLIP_TOL * hb
    best = math.inf
    bx = by = bz = 0.0
    found = 0
    # incident corners inside the reference face, and edge crossings with its side lines
    for m in range(4):
        px, py, pz = _face_corner(C, cx, cy, cz, hI0, hI1, hI2, j, sj, m)
        qx, qy, qz = _face_corner(C, cx, cy, cz, hI0, hI1, hI2, j, sj, (m + 1) % 4)
        pa = _pick(px, py, pz, a)
        pb = _pick(px, py, pz, b)
        if abs(pa) <= ha + ta and abs(pb) <= hb + tb:
            z = s * _pick(px, py, pz, i) - hi
            if z < best:
                best, bx, by, bz, found = z, px, py, pz, 1
        qa = _pick(qx, qy, qz, a)
        qb = _pick(qx, qy, qz, b)
        for side in range(4):
            if side < 2:
                lim = ha if side == 0 else -ha
                den = qa - pa
                if den == 0.0:
                    continue
                t = (lim - pa) / den
                if t < 0.0 or t > 1.0:
                    continue
                other = pb + t * (qb - pb)
                if abs(other) > hb + tb:
                    continue
            else:
                lim = hb if side == 2 else -hb
                den = qb - pb
                if den == 0.0:
                    continue
                t = (lim - pb) / den
                if t < 0.0 or t > 1.0:
                    continue
                other = pa + t * (qa - pa)
                if abs(other) > ha + ta:
                    continue
            rx = px + t * (qx - px)
            ry = py + t * (qy - py)
            rz = pz + t * (qz - pz)
            z = s * _pick(rx, ry, rz, i) - hi
            if z < best:
                best, bx, by, bz, found = z, rx, ry, rz, 1
    # reference corners lifted along e_i onto the incident face's plane, inside it
    fx = C[j]
    fy = C[3 + j]
    fz = C[6 + j]
    fi = _pick(fx, fy, fz, i)
    hj = _pick(hI0, hI1, hI2, j)
    if fi != 0.0:
        for m in range(4):
            ua = ha if (m == 1 or m == 2) else -ha
            ub = hb if m >= 2 else -hb
            # point x with x_a = ua, x_b = ub on the plane f . (x - c) = sj hj
            fa = _pick(fx, fy, fz, a)
            fb = _pick(fx, fy, fz, b)
            ca = _pick(cx, cy, cz, a)
            cb = _pick(cx, cy, cz, b)
            ci = _pick(cx, cy, cz, i)
            xi = ci + (sj * hj - fa * (ua - ca) - fb * (ub - cb)) / fi
            px = xi if i == 0 else (ua if a == 0 else ub)
            py = xi if i == 1 else (ua if a == 1 else ub)
            pz = xi if i == 2 else (ua if a == 2 else ub)
            lx, ly, lz = mat_tvec(C, px - cx, py - cy, pz - cz)
            ok = True
            for l in range(3):
                if l == j:
                    continue
                hl = _pick(hI0, hI1, hI2, l)
                if abs(_pick(lx, ly, lz, l)) > hl * (1.0 + CLIP_TOL):
                    ok = False
            if ok:
                z = s * xi - hi
                if z < best:
                    best, bx, by, bz, found = z, px, py, pz, 1
    return best, bx, by, bz, found


@njit(cache=True, _nrt=False)
def clip_segment_face(ax, ay, az, dx, dy, dz, i, hR0, hR1, hR2):
    """Parameter range ``[t0, t1]`` of the segment ``a + d t`` (``t`` in [0, 1]) whose
    projection along ``e_i`` lies inside the reference face (the box's face normal to axis
    ``i``; Liang & Barsky, ACM TOG 3:1, 1984). Returns ``(t0, t1, ok)``; ``ok = 0`` if empty.
    The ends stay within the face (no tolerance), so points on them lie on its surface."""
    t0 = 0.0
    t1 = 1.0
    for l in range(3):
        if l == i:
            continue
        h = _pick(hR0, hR1, hR2, l)
        p = _pick(ax, ay, az, l)
        d = _pick(dx, dy, dz, l)
        if d == 0.0:
            if abs(p) > h:
                return 0.0, 0.0, 0
            continue
        ta = (-h - p) / d
        tb = (h - p) / d
        if ta > tb:
            ta, tb = tb, ta
        t0 = max(t0, ta)
        t1 = min(t1, tb)
        if t0 > t1:
            return 0.0, 0.0, 0
    return t0, t1, 1
