"""Contact manifolds in 3D: the contact points of a box face, a box edge or a capsule lying
on a box face, as one cluster with one normal (for the stepper's simultaneous and
sequential policies, DESIGN §6), and the single witness pair otherwise.

When the contact normal of the frame (``pair3d.pair_frame``) is a box face's outward
normal within the slab's angle (the sine of the angle times the face's diameter at most
``slab``; a box resting flat may be realised by a corner, an edge crossing or a face, all
with that normal), that face is the *reference* face (the better aligned one if both
bodies have one) and the other body's contact feature is clipped to it (``pair3d_clip``, in
the reference body's frame):

* a box: its *incident* face (the face most opposed to the reference normal) is clipped
  against the four side planes of the reference face (Sutherland & Hodgman, CACM 17:32,
  1974; Ericson, *Real-Time Collision Detection*, sec. 8.3.4; at most 8 points, the
  buffers being the rows of ``mf`` itself);
* a capsule: its core segment is clipped to the reference face (Liang-Barsky), two points
  (one when only a point remains), each carrying the capsule's radius;
* a sphere: its single point.

Two capsules whose axes are within the slab's angle of parallel (side by side) give the
two ends of the common axial extent of their cores, with the normal normal to A's axis.

Of the clipped points those whose gap (height above the reference plane) is within
``slab`` (m) of the frame's gap ``g`` are kept: all four corners of a face resting flat,
the two ends of an edge lying on a face, one corner of a tilted box. ``slab`` is the
parallelism tolerance: a face (edge) tilted by an angle ``theta`` against the reference face
counts as lying on it when ``theta`` times its extent is below ``slab``. It is a length and
must scale with the bodies: ``manifold_slab`` gives ``SLAB_REL`` times the sum of their
sizes (largest distance of a surface point from the centre of mass), the default; the
stepper may pass its own contact tolerance.

Rows of ``mf`` (float64[MAX_MF, N_MF]): ``pA`` (world, on A's surface), ``pB`` (on B's),
the point's gap ``g_k`` (m), with ``pA - pB = g_k n`` for the cluster's one normal ``n``: the
reference face's (or the side-by-side capsules' common normal), written into the frame row
in place of the frame's (from which it differs by at most the slab's angle; for tilted
side-by-side capsules ``pA - pB = g_k n`` and ``pB`` on B's surface hold to about
``slab``). Otherwise (edge-edge and vertex contacts, spheres, crossing capsules) the
manifold is the frame's witness pair (one row).
"""
from numba import njit

from .cache_guard import guard

guard(__name__, __file__)

from .pair3d import FR_GAP, FR_NX, FR_NY, FR_NZ, FR_PAX, FR_PBX, pair_frame  # noqa: E402
from .pair3d_clip import clip_segment_face, incident_face, _face_corner  # noqa: E402
from .pair3d_shape import (SH_BOX, SH_CAPSULE, body_reach, mat_tvec,  # noqa: E402
                           mat_vec, quat_matrix, rel_quat)

MAX_MF = 8          # at most 8 points (a quadrilateral clipped by four planes)
N_MF = 7            # columns of a manifold row
MF_PAX = 0          # pA (world, m): MF_PAX + k
MF_PBX = 3          # pB (world, m): MF_PBX + k
MF_GAP = 6          # the point's gap (m)
SLAB_REL = 1e-9     # default slab: this fraction of the bodies' summed sizes (-)


@njit(cache=True, _nrt=False)
def manifold_slab(kA, rA, hxA, hyA, hzA, kB, rB, hxB, hyB, hzB):
    """The default parallelism tolerance (m): ``SLAB_REL`` times the sum of the two bodies'
    sizes (reach plus radius)."""
    return SLAB_REL * (body_reach(kA, hxA, hyA, hzA) + rA + body_reach(kB, hxB, hyB, hzB)
                       + rB)


@njit(cache=True, _nrt=False)
def _single(fr, mf):
    for j in range(3):
        mf[0, MF_PAX + j] = fr[FR_PAX + j]
        mf[0, MF_PBX + j] = fr[FR_PBX + j]
    mf[0, MF_GAP] = fr[FR_GAP]
    return 1


@njit(cache=True, _nrt=False)
def _clip_plane(mf, src, dst, n, l, sg, h):
    """Sutherland-Hodgman step: the ``n`` points in columns ``src`` of ``mf`` clipped to
    ``sg x_l <= h``, written to columns ``dst``; returns the new count."""
    m = 0
    if n == 0:
        return 0
    px = mf[n - 1, src]
    py = mf[n - 1, src + 1]
    pz = mf[n - 1, src + 2]
    dp = sg * (px if l == 0 else (py if l == 1 else pz)) - h
    for k in range(n):
        qx = mf[k, src]
        qy = mf[k, src + 1]
        qz = mf[k, src + 2]
        dq = sg * (qx if l == 0 else (qy if l == 1 else qz)) - h
        if (dp <= 0.0) != (dq <= 0.0):       # the edge crosses the plane: add the crossing
            t = dp / (dp - dq)
            if m < MAX_MF:
                mf[m, dst] = px + t * (qx - px)
                mf[m, dst + 1] = py + t * (qy - py)
                mf[m, dst + 2] = pz + t * (qz - pz)
                m += 1
        if dq <= 0.0 and m < MAX_MF:
            mf[m, dst] = qx
            mf[m, dst + 1] = qy
            mf[m, dst + 2] = qz
            m += 1
        px, py, pz, dp = qx, qy, qz, dq
    return m


@njit(cache=True, _nrt=False)
def pair_manifold(kA, rA, hxA, hyA, hzA, stA, kB, rB, hxB, hyB, hzB, stB, slab, fr, fe, mf):
    """Contact frame (``fr``, ``fe`` as ``pair3d.pair_frame``) and contact points (rows of
    ``mf``, float64[MAX_MF, N_MF]) of bodies A and B; returns the number of points. See the
    module docstring; ``slab`` (m) is the parallelism tolerance (``manifold_slab``)."""
    g = pair_frame(kA, rA, hxA, hyA, hzA, stA, kB, rB, hxB, hyB, hzB, stB, fr, fe)
    if not g == g:
        return 0
    nx = fr[FR_NX]
    ny = fr[FR_NY]
    nz = fr[FR_NZ]
    # the reference face: a box face whose outward normal is within the slab's angle of
    # the contact normal (-n for A's, +n for B's); the better aligned if both are
    if kA == SH_CAPSULE and kB == SH_CAPSULE:
        return _capsules(rA, hzA, stA, rB, hzB, stB, g, slab, fr, mf)
    fA, cosA = _aligned_face(kA, hxA, hyA, hzA, stA, -nx, -ny, -nz, slab)
    fB, cosB = _aligned_face(kB, hxB, hyB, hzB, stB, nx, ny, nz, slab)
    if fA < 0 and fB < 0:
        return _single(fr, mf)
    refA = fA >= 0 and (fB < 0 or cosA >= cosB)
    f = fA if refA else fB
    if refA:
        st_r, st_o = stA, stB
        h0, h1, h2 = hxA, hyA, hzA
        ko, ro, o0, o1, o2 = kB, rB, hxB, hyB, hzB
    else:
        st_r, st_o = stB, stA
        h0, h1, h2 = hxB, hyB, hzB
        ko, ro, o0, o1, o2 = kA, rA, hxA, hyA, hzA
    if ko != SH_BOX and ko != SH_CAPSULE:
        return _single(fr, mf)
    R = quat_matrix(st_r[3], st_r[4], st_r[5], st_r[6])
    cx, cy, cz = mat_tvec(R, st_o[0] - st_r[0], st_o[1] - st_r[1], st_o[2] - st_r[2])
    q0, q1, q2, q3 = rel_quat(st_r[3], st_r[4], st_r[5], st_r[6], st_o[3], st_o[4],
                              st_o[5], st_o[6])
    C = quat_matrix(q0, q1, q2, q3)
    i = f // 2
    s = 1.0 if f % 2 == 1 else -1.0     # outward normal s e_i of the reference face
    hi = h0 if i == 0 else (h1 if i == 1 else h2)
    n = 0
    if ko == SH_BOX:
        j, sj = incident_face(C, i, s)
        for m in range(4):
            px, py, pz = _face_corner(C, cx, cy, cz, o0, o1, o2, j, sj, m)
            mf[m, 0] = px
            mf[m, 1] = py
            mf[m, 2] = pz
        n = 4
        src = 0
        for l in range(3):
            if l == i:
                continue
            hl = h0 if l == 0 else (h1 if l == 1 else h2)
            n = _clip_plane(mf, src, 3 - src, n, l, 1.0, hl)
            src = 3 - src
            n = _clip_plane(mf, src, 3 - src, n, l, -1.0, hl)
            src = 3 - src
    else:
        # the capsule's core segment, clipped to the face; its surface points toward it
        bx = C[2]
        by = C[5]
        bz = C[8]
        ax = cx - o2 * bx
        ay = cy - o2 * by
        az = cz - o2 * bz
        t0, t1, ok = clip_segment_face(ax, ay, az, 2.0 * o2 * bx, 2.0 * o2 * by,
                                       2.0 * o2 * bz, i, h0, h1, h2)
        if not ok:
            return _single(fr, mf)
        src = 0
        for k in range(2):
            t = t0 if k == 0 else t1
            mf[k, 0] = ax + 2.0 * o2 * bx * t - (ro * s if i == 0 else 0.0)
            mf[k, 1] = ay + 2.0 * o2 * by * t - (ro * s if i == 1 else 0.0)
            mf[k, 2] = az + 2.0 * o2 * bz * t - (ro * s if i == 2 else 0.0)
        n = 1 if t1 == t0 else 2
    # the cluster's normal: the reference face's (from B into A)
    ex = 1.0 if i == 0 else 0.0
    ey = 1.0 if i == 1 else 0.0
    ez = 1.0 if i == 2 else 0.0
    mx, my, mz = mat_vec(R, s * ex, s * ey, s * ez)
    sg = -1.0 if refA else 1.0
    # keep the points within slab of the frame's gap; write the witness pairs (world)
    out = 0
    for k in range(n):
        px = mf[k, src]
        py = mf[k, src + 1]
        pz = mf[k, src + 2]
        z = s * (px if i == 0 else (py if i == 1 else pz)) - hi
        if z > g + slab:
            continue
        # the point on the reference face: p - z s e_i
        rx = px - (z * s if i == 0 else 0.0)
        ry = py - (z * s if i == 1 else 0.0)
        rz = pz - (z * s if i == 2 else 0.0)
        wx, wy, wz = mat_vec(R, px, py, pz)
        ux, uy, uz = mat_vec(R, rx, ry, rz)
        if refA:
            mf[out, MF_PAX] = st_r[0] + ux
            mf[out, MF_PAX + 1] = st_r[1] + uy
            mf[out, MF_PAX + 2] = st_r[2] + uz
            mf[out, MF_PBX] = st_r[0] + wx
            mf[out, MF_PBX + 1] = st_r[1] + wy
            mf[out, MF_PBX + 2] = st_r[2] + wz
        else:
            mf[out, MF_PAX] = st_r[0] + wx
            mf[out, MF_PAX + 1] = st_r[1] + wy
            mf[out, MF_PAX + 2] = st_r[2] + wz
            mf[out, MF_PBX] = st_r[0] + ux
            mf[out, MF_PBX + 1] = st_r[1] + uy
            mf[out, MF_PBX + 2] = st_r[2] + uz
        mf[out, MF_GAP] = z
        out += 1
    if out == 0:
        return _single(fr, mf)
    fr[FR_NX] = sg * mx
    fr[FR_NY] = sg * my
    fr[FR_NZ] = sg * mz
    return out


@njit(cache=True, _nrt=False)
def _aligned_face(k, hx, hy, hz, st, ux, uy, uz, slab):
    """The face of box ``k`` (else -1) whose outward normal is closest to the world unit
    ``u``, if the sine of their angle times the face's diameter is at most ``slab``:
    ``(face, cos)``."""
    if k != SH_BOX:
        return -1, 0.0
    R = quat_matrix(st[3], st[4], st[5], st[6])
    lx, ly, lz = mat_tvec(R, ux, uy, uz)
    ax = abs(lx)
    ay = abs(ly)
    az = abs(lz)
    if ax >= ay and ax >= az:
        i, c, l, sn2, d2 = 0, ax, lx, ly * ly + lz * lz, hy * hy + hz * hz
    elif ay >= az:
        i, c, l, sn2, d2 = 1, ay, ly, lx * lx + lz * lz, hx * hx + hz * hz
    else:
        i, c, l, sn2, d2 = 2, az, lz, lx * lx + ly * ly, hx * hx + hy * hy
    if 4.0 * sn2 * d2 > slab * slab:
        return -1, 0.0
    return 2 * i + (1 if l > 0.0 else 0), c


@njit(cache=True, _nrt=False)
def _capsules(rA, hA, stA, rB, hB, stB, g, slab, fr, mf):
    """Two capsules lying side by side (axes within the slab's angle: the sine times the
    longer core at most ``slab``): the two ends of the common axial extent of their cores,
    in A's frame, with the normal ``m`` normal to A's axis through the middle of that extent;
    else the frame's single pair."""
    R = quat_matrix(stA[3], stA[4], stA[5], stA[6])
    cx, cy, cz = mat_tvec(R, stB[0] - stA[0], stB[1] - stA[1], stB[2] - stA[2])
    q0, q1, q2, q3 = rel_quat(stA[3], stA[4], stA[5], stA[6], stB[3], stB[4], stB[5], stB[6])
    C = quat_matrix(q0, q1, q2, q3)
    bx = C[2]
    by = C[5]
    bz = C[8]
    if 4.0 * (bx * bx + by * by) * max(hA, hB) ** 2 > slab * slab:
        return _single(fr, mf)
    z0 = cz - hB * bz
    z1 = cz + hB * bz
    lo = max(-hA, min(z0, z1))
    hi = min(hA, max(z0, z1))
    if lo > hi or z0 == z1:
        return _single(fr, mf)
    # the lateral offset of B's core from A's axis at the middle of the common extent
    zm = 0.5 * (lo + hi)
    tm = (zm - z0) / (z1 - z0)
    wx = -(cx + (2.0 * tm - 1.0) * hB * bx)
    wy = -(cy + (2.0 * tm - 1.0) * hB * by)
    L = (wx * wx + wy * wy) ** 0.5
    if not L > 0.0:
        return _single(fr, mf)
    mx = wx / L
    my = wy / L
    n = 1 if hi == lo else 2
    out = 0
    for k in range(n):
        z = lo if k == 0 else hi
        t = (z - z0) / (z1 - z0)
        px = cx + (2.0 * t - 1.0) * hB * bx      # B's core point at the same height
        py = cy + (2.0 * t - 1.0) * hB * by
        gk = mx * (0.0 - px) + my * (0.0 - py) - rA - rB
        if gk > g + slab:
            continue
        ax, ay, az = mat_vec(R, -rA * mx, -rA * my, z)
        ux, uy, uz = mat_vec(R, px + rB * mx, py + rB * my, z)
        mf[out, MF_PAX] = stA[0] + ax
        mf[out, MF_PAX + 1] = stA[1] + ay
        mf[out, MF_PAX + 2] = stA[2] + az
        mf[out, MF_PBX] = stA[0] + ux
        mf[out, MF_PBX + 1] = stA[1] + uy
        mf[out, MF_PBX + 2] = stA[2] + uz
        mf[out, MF_GAP] = gk
        out += 1
    if out == 0:
        return _single(fr, mf)
    nx, ny, nz = mat_vec(R, mx, my, 0.0)
    fr[FR_NX] = nx
    fr[FR_NY] = ny
    fr[FR_NZ] = nz
    return out
