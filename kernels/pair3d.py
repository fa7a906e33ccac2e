"""Body-body pair kinds in 3D (issue 16, item 1): the dispatcher table and the contact frame
of one instant (gap, normal, witness points, features, gap rate). Time of impact:
``pair3d_toi``; the contact points of a face or edge lying on a face: ``pair3d_manifold``.

Conventions (DESIGN §3, as ``pair2d``). ``n`` is the unit normal from B into A (the
direction in which the gap grows); ``g`` the signed gap (m): the distance of the surfaces
when disjoint, exact to round-off, else minus the penetration depth (exact for every pair
kind, to round-off of the size). Witness points ``pA``, ``pB``
(world, m) lie on the surfaces with ``pA - pB = g n``. Features (``pair3d_shape.FT_*``) say
what realises the gap on each body: a core vertex (box corner, capsule end cap, sphere), a
core edge (box edge, a capsule's side) or a box face. The gap rate is
``g' = n . (v_A(pA) - v_B(pB))`` with ``v(p) = v + w x (p - x)``: the derivative of the
distance of the fixed closest feature pair (envelope theorem, as in 2D).

A body is ``kind, rad, hx, hy, hz`` (``pair3d_shape``) and its ``flight3d`` state row ``st``
(float64[19]: ``x[0:3]``, unit quaternion ``q[3:7]`` body -> world, ``v[7:10]``, world
angular velocity ``w[10:13]``, ...).

Pair kinds (one line each in ``PAIR_TABLE``; a new pair kind is one function in its own
module, one line here and one branch in ``_frame_ordered``):

* ``PK_SPHERE_SPHERE``: frame as ``PK_ROUNDED``; time of impact in closed form
  (``toi3d.sphere_sphere_toi``);
* ``PK_ROUNDED``: sphere-capsule, capsule-capsule (``pair3d_rounded.rounded_frame``);
* ``PK_BOX_ROUNDED``: a box and a sphere or a capsule, the box first
  (``pair3d_rounded.box_rounded_frame``);
* ``PK_BOX_BOX``: ``pair3d_box.box_box_frame``.

``swap = 1`` in a table line means the pair kind's function takes the bodies as (B, A);
``frame_rel`` calls it so and flips the normal and exchanges the witnesses and features.
"""
import math

import numpy as np
from numba import njit

from .cache_guard import guard

guard(__name__, __file__)

from .pair3d_box import box_box_frame  # noqa: E402
from .pair3d_rounded import box_rounded_frame, rounded_frame  # noqa: E402
from .pair3d_shape import (N_SHAPE_KINDS, SH_BOX, SH_CAPSULE, SH_SPHERE,  # noqa: E402
                           mat_tvec, mat_vec, quat_matrix, rel_quat)

PK_NONE = -1
PK_SPHERE_SPHERE = 0
PK_ROUNDED = 1
PK_BOX_ROUNDED = 2
PK_BOX_BOX = 3
PAIR_KIND_NAMES = ("sphere-sphere", "rounded-rounded", "box-rounded", "box-box")

# The dispatcher table: (shape kind of A, shape kind of B, pair kind, swap), one line each.
PAIR_TABLE = (
    (SH_SPHERE, SH_SPHERE, PK_SPHERE_SPHERE, 0),
    (SH_SPHERE, SH_CAPSULE, PK_ROUNDED, 0),
    (SH_CAPSULE, SH_SPHERE, PK_ROUNDED, 0),
    (SH_CAPSULE, SH_CAPSULE, PK_ROUNDED, 0),
    (SH_BOX, SH_SPHERE, PK_BOX_ROUNDED, 0),
    (SH_BOX, SH_CAPSULE, PK_BOX_ROUNDED, 0),
    (SH_SPHERE, SH_BOX, PK_BOX_ROUNDED, 1),
    (SH_CAPSULE, SH_BOX, PK_BOX_ROUNDED, 1),
    (SH_BOX, SH_BOX, PK_BOX_BOX, 0),
)
PAIR_KIND = np.full((N_SHAPE_KINDS, N_SHAPE_KINDS), PK_NONE, dtype=np.int64)
PAIR_SWAP = np.zeros((N_SHAPE_KINDS, N_SHAPE_KINDS), dtype=np.int64)
for _a, _b, _k, _s in PAIR_TABLE:
    PAIR_KIND[_a, _b] = _k
    PAIR_SWAP[_a, _b] = _s

# slots of the frame row written by pair_frame (float64[N_FR])
FR_GAP = 0      # g (m)
FR_NX = 1       # unit normal from B into A
FR_NY = 2
FR_NZ = 3
FR_PAX = 4      # witness point on A (world, m)
FR_PAY = 5
FR_PAZ = 6
FR_PBX = 7      # witness point on B (world, m)
FR_PBY = 8
FR_PBZ = 9
FR_RATE = 10    # g' (m/s)
N_FR = 11
# slots of the feature row (int64[N_FE]); the same as pair2d's
FE_A_KIND = 0   # pair3d_shape.FT_* of A
FE_A_INDEX = 1  # its vertex, edge or face index
FE_B_KIND = 2
FE_B_INDEX = 3
N_FE = 4


@njit(cache=True, _nrt=False)
def pair_kind(kA, kB):
    """``(pair kind, swap)`` of shape kinds ``kA``, ``kB`` (``PK_NONE`` if unknown)."""
    if kA < 0 or kB < 0 or kA >= N_SHAPE_KINDS or kB >= N_SHAPE_KINDS:
        return PK_NONE, 0
    return PAIR_KIND[kA, kB], PAIR_SWAP[kA, kB]


@njit(cache=True, _nrt=False)
def _frame_ordered(pk, rA, hxA, hyA, hzA, a0, a1, a2, a3, kA, kB, rB, hxB, hyB, hzB,
                   b0, b1, b2, b3, dx, dy, dz):
    """The pair kind's frame in A's body frame, B's centre at world offset ``d``; returns
    the 15 values with ``n``, ``pA``, ``pB`` rotated to world axes (relative to A's
    centre)."""
    RA = quat_matrix(a0, a1, a2, a3)
    cx, cy, cz = mat_tvec(RA, dx, dy, dz)
    r0, r1, r2, r3 = rel_quat(a0, a1, a2, a3, b0, b1, b2, b3)
    C = quat_matrix(r0, r1, r2, r3)
    if pk == PK_ROUNDED or pk == PK_SPHERE_SPHERE:
        hA = hzA if kA == SH_CAPSULE else 0.0
        hB = hzB if kB == SH_CAPSULE else 0.0
        res = rounded_frame(kA, rA, hA, kB, rB, hB, cx, cy, cz, C[2], C[5], C[8])
    elif pk == PK_BOX_ROUNDED:
        hB = hzB if kB == SH_CAPSULE else 0.0
        res = box_rounded_frame(hxA, hyA, hzA, kB, rB, hB, cx, cy, cz, C[2], C[5], C[8])
    elif pk == PK_BOX_BOX:
        res = box_box_frame(C, hxA, hyA, hzA, hxB, hyB, hzB, cx, cy, cz)
    else:
        nan = math.nan
        return nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, -1, -1, -1, -1
    g, nx, ny, nz, pax, pay, paz, pbx, pby, pbz, fa, ia, fb, ib = res
    nx, ny, nz = mat_vec(RA, nx, ny, nz)
    pax, pay, paz = mat_vec(RA, pax, pay, paz)
    pbx, pby, pbz = mat_vec(RA, pbx, pby, pbz)
    return g, nx, ny, nz, pax, pay, paz, pbx, pby, pbz, fa, ia, fb, ib


@njit(cache=True, _nrt=False)
def frame_rel(kA, rA, hxA, hyA, hzA, a0, a1, a2, a3, kB, rB, hxB, hyB, hzB, b0, b1, b2, b3,
              dx, dy, dz):
    """Gap and frame with A's centre at the origin and B's at ``d`` (orientations ``a``, ``b``
    unit quaternions). Returns ``(g, nx, ny, nz, pAx, pAy, pAz, pBx, pBy, pBz, fa, ia, fb,
    ib)``, world axes, witness points relative to A's centre. NaNs and features -1 for an
    unknown pair of kinds."""
    pk, sw = pair_kind(kA, kB)
    if sw == 0:
        return _frame_ordered(pk, rA, hxA, hyA, hzA, a0, a1, a2, a3, kA, kB, rB, hxB, hyB,
                              hzB, b0, b1, b2, b3, dx, dy, dz)
    g, nx, ny, nz, pbx, pby, pbz, pax, pay, paz, fb, ib, fa, ia = _frame_ordered(
        pk, rB, hxB, hyB, hzB, b0, b1, b2, b3, kB, kA, rA, hxA, hyA, hzA, a0, a1, a2, a3,
        -dx, -dy, -dz)
    return (g, -nx, -ny, -nz, pax + dx, pay + dy, paz + dz, pbx + dx, pby + dy, pbz + dz,
            fa, ia, fb, ib)


@njit(cache=True, _nrt=False, inline="always")
def point_rate(nx, ny, nz, pax, pay, paz, pbx, pby, pbz, vax, vay, vaz, wax, way, waz,
               vbx, vby, vbz, wbx, wby, wbz):
    """``n . (v_A(pA) - v_B(pB))`` (m/s), witness points relative to each body's centre,
    ``v`` centre velocities, ``w`` world angular velocities."""
    ux = (vax + way * paz - waz * pay) - (vbx + wby * pbz - wbz * pby)
    uy = (vay + waz * pax - wax * paz) - (vby + wbz * pbx - wbx * pbz)
    uz = (vaz + wax * pay - way * pax) - (vbz + wbx * pby - wby * pbx)
    return nx * ux + ny * uy + nz * uz


@njit(cache=True, _nrt=False)
def pair_frame(kA, rA, hxA, hyA, hzA, stA, kB, rB, hxB, hyB, hzB, stB, fr, fe):
    """Contact frame of bodies A and B at the instant of their ``flight3d`` state rows
    ``stA``, ``stB``: writes ``fr`` (float64[N_FR]: gap, normal from B into A, world witness
    points, gap rate) and ``fe`` (int64[N_FE]: features), returns the gap (m). Unknown
    kinds: NaN gap, features -1."""
    dx = stB[0] - stA[0]
    dy = stB[1] - stA[1]
    dz = stB[2] - stA[2]
    g, nx, ny, nz, pax, pay, paz, pbx, pby, pbz, fa, ia, fb, ib = frame_rel(
        kA, rA, hxA, hyA, hzA, stA[3], stA[4], stA[5], stA[6],
        kB, rB, hxB, hyB, hzB, stB[3], stB[4], stB[5], stB[6], dx, dy, dz)
    fr[FR_GAP] = g
    fr[FR_NX] = nx
    fr[FR_NY] = ny
    fr[FR_NZ] = nz
    fr[FR_PAX] = stA[0] + pax
    fr[FR_PAY] = stA[1] + pay
    fr[FR_PAZ] = stA[2] + paz
    fr[FR_PBX] = stA[0] + pbx
    fr[FR_PBY] = stA[1] + pby
    fr[FR_PBZ] = stA[2] + pbz
    fr[FR_RATE] = point_rate(nx, ny, nz, pax, pay, paz, pbx - dx, pby - dy, pbz - dz,
                             stA[7], stA[8], stA[9], stA[10], stA[11], stA[12],
                             stB[7], stB[8], stB[9], stB[10], stB[11], stB[12])
    fe[FE_A_KIND] = fa
    fe[FE_A_INDEX] = ia
    fe[FE_B_KIND] = fb
    fe[FE_B_INDEX] = ib
    return g
