"""Body-body pair kinds in 2D (issue 16, item 1): the dispatcher table and the contact frame
of one instant (gap, normal, witness points, features, gap rate). Time of impact:
``pair2d_toi``.

Conventions (DESIGN §3). ``n`` is the unit normal from B into A (the direction in which
the gap grows); ``g`` the signed gap (m): the distance of the boundaries when disjoint,
exact to round-off, else minus the penetration depth (exact for polygon pairs, a
first-order lower estimate for curved ones: see each pair module). Witness points
``pA``, ``pB`` (world, m) lie on the boundaries with ``pA - pB = g n``. Features
(``pair2d_shape.FT_*``) say what realises the gap on each body: a core vertex, a core
edge, or the ellipse's curve. The gap rate is ``g' = n . (v_A(pA) - v_B(pB))`` with
``v(p) = v + omega J (p - x)``, ``J (x, y) = (-y, x)``: the derivative of the distance of
the fixed closest feature pair (envelope theorem: the motion of the witness points along
the boundaries is tangent to them, and the normal's rotation is normal to ``pA - pB``).

A body is ``kind, rad, ea, eb, V, v0, nv`` (``pair2d_shape``) and its ``flight2d`` state
row ``st`` (``X, Y, ANGLE, VX, VY, OMEGA, ...``).

Pair kinds (one line each in ``PAIR_TABLE``; a new pair kind is one function in its own
module, one line here, and one branch in ``_frame_ordered``):

* ``PK_DISK_DISK``: two disks; frame as ``PK_ROUNDED``, time of impact by
  ``toi2d.disk_disk_toi`` (closed form in free flight);
* ``PK_ROUNDED``: two rounded convex polygons (disk, capsule/rod, box/polygon in any
  combination): ``pair2d_rounded``;
* ``PK_ELLIPSE_ROUNDED``: an ellipse and a disk, capsule or polygon (the ellipse first):
  ``pair2d_ellipse.ellipse_rounded_frame``;
* ``PK_ELLIPSE_ELLIPSE``: ``pair2d_ellipse.ellipse_ellipse_frame``.

``swap = 1`` in a table line means the pair kind's function takes the bodies as (B, A);
``frame_rel`` calls it so and flips the normal and exchanges the witnesses and features.
"""
import math

import numpy as np
from numba import njit

from .cache_guard import guard

guard(__name__, __file__)

from .flight2d import ANGLE, OMEGA, VX, VY, X, Y  # noqa: E402
from .pair2d_ellipse import ellipse_ellipse_frame, ellipse_rounded_frame  # noqa: E402
from .pair2d_rounded import rounded_frame  # noqa: E402
from .pair2d_shape import SH_DISK, SH_ELLIPSE, SH_POLY, ellipse_matrix  # noqa: E402

PK_NONE = -1
PK_DISK_DISK = 0
PK_ROUNDED = 1
PK_ELLIPSE_ROUNDED = 2
PK_ELLIPSE_ELLIPSE = 3
PAIR_KIND_NAMES = ("disk-disk", "rounded-rounded", "ellipse-rounded", "ellipse-ellipse")

# The dispatcher table: (shape kind of A, shape kind of B, pair kind, swap), one line each.
PAIR_TABLE = (
    (SH_DISK, SH_DISK, PK_DISK_DISK, 0),
    (SH_DISK, SH_POLY, PK_ROUNDED, 0),
    (SH_POLY, SH_DISK, PK_ROUNDED, 0),
    (SH_POLY, SH_POLY, PK_ROUNDED, 0),
    (SH_ELLIPSE, SH_DISK, PK_ELLIPSE_ROUNDED, 0),
    (SH_ELLIPSE, SH_POLY, PK_ELLIPSE_ROUNDED, 0),
    (SH_DISK, SH_ELLIPSE, PK_ELLIPSE_ROUNDED, 1),
    (SH_POLY, SH_ELLIPSE, PK_ELLIPSE_ROUNDED, 1),
    (SH_ELLIPSE, SH_ELLIPSE, PK_ELLIPSE_ELLIPSE, 0),
)
N_SHAPE_KINDS = 3
PAIR_KIND = np.full((N_SHAPE_KINDS, N_SHAPE_KINDS), PK_NONE, dtype=np.int64)
PAIR_SWAP = np.zeros((N_SHAPE_KINDS, N_SHAPE_KINDS), dtype=np.int64)
for _a, _b, _k, _s in PAIR_TABLE:
    PAIR_KIND[_a, _b] = _k
    PAIR_SWAP[_a, _b] = _s

# slots of the frame row written by pair_frame (float64[N_FR])
FR_GAP = 0      # g (m)
FR_NX = 1       # unit normal from B into A
FR_NY = 2
FR_PAX = 3      # witness point on A (world, m)
FR_PAY = 4
FR_PBX = 5      # witness point on B (world, m)
FR_PBY = 6
FR_RATE = 7     # g' (m/s)
N_FR = 8
# slots of the feature row (int64[N_FE])
FE_A_KIND = 0   # pair2d_shape.FT_* of A
FE_A_INDEX = 1  # its vertex or edge index (0 for a curve)
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
def _frame_ordered(pk, rA, eaA, ebA, VA, iA, nA, thA, rB, eaB, ebB, VB, iB, nB, dx, dy, thB):
    """The pair kind's frame, A at the origin, B's centre at ``(dx, dy)``."""
    cA = math.cos(thA)
    sA = math.sin(thA)
    cB = math.cos(thB)
    sB = math.sin(thB)
    if pk == PK_ROUNDED or pk == PK_DISK_DISK:
        return rounded_frame(VA, iA, nA, rA, cA, sA, VB, iB, nB, rB, dx, dy, cB, sB)
    if pk == PK_ELLIPSE_ROUNDED:
        axx, axy, ayy = ellipse_matrix(eaA, ebA, cA, sA)
        return ellipse_rounded_frame(axx, axy, ayy, VB, iB, nB, rB, dx, dy, cB, sB)
    if pk == PK_ELLIPSE_ELLIPSE:
        axx, axy, ayy = ellipse_matrix(eaA, ebA, cA, sA)
        bxx, bxy, byy = ellipse_matrix(eaB, ebB, cB, sB)
        return ellipse_ellipse_frame(axx, axy, ayy, dx, dy, bxx, bxy, byy)
    nan = math.nan
    return nan, nan, nan, nan, nan, nan, nan, -1, -1, -1, -1


@njit(cache=True, _nrt=False)
def frame_rel(kA, rA, eaA, ebA, VA, iA, nA, thA, kB, rB, eaB, ebB, VB, iB, nB, dx, dy, thB):
    """Gap and frame with A's centre at the origin and B's at ``(dx, dy)`` (angles ``thA``,
    ``thB``). Returns ``(g, nx, ny, pAx, pAy, pBx, pBy, fa, ia, fb, ib)``, witness points
    relative to A's centre. NaNs and features -1 for an unknown pair of kinds."""
    pk, sw = pair_kind(kA, kB)
    if sw == 0:
        return _frame_ordered(pk, rA, eaA, ebA, VA, iA, nA, thA, rB, eaB, ebB, VB, iB, nB,
                              dx, dy, thB)
    g, nx, ny, pbx, pby, pax, pay, fb, ib, fa, ia = _frame_ordered(
        pk, rB, eaB, ebB, VB, iB, nB, thB, rA, eaA, ebA, VA, iA, nA, -dx, -dy, thA)
    return g, -nx, -ny, pax + dx, pay + dy, pbx + dx, pby + dy, fa, ia, fb, ib


@njit(cache=True, _nrt=False, inline="always")
def point_rate(nx, ny, pax, pay, pbx, pby, vax, vay, wa, vbx, vby, wb):
    """``n . (v_A(pA) - v_B(pB))`` (m/s) with witness points relative to each body's
    centre (``pa``, ``pb``), centre velocities ``v`` and angular velocities ``w``."""
    ux = (vax - wa * pay) - (vbx - wb * pby)
    uy = (vay + wa * pax) - (vby + wb * pbx)
    return nx * ux + ny * uy


@njit(cache=True, _nrt=False)
def pair_gap_rate(stA, stB, fr):
    """Gap rate ``g' = n . (v_A(pA) - v_B(pB))`` (m/s) of the frame row ``fr`` (``FR_*``,
    world witness points) for the state rows ``stA``, ``stB`` (``flight2d``)."""
    return point_rate(fr[FR_NX], fr[FR_NY], fr[FR_PAX] - stA[X], fr[FR_PAY] - stA[Y],
                      fr[FR_PBX] - stB[X], fr[FR_PBY] - stB[Y], stA[VX], stA[VY],
                      stA[OMEGA], stB[VX], stB[VY], stB[OMEGA])


@njit(cache=True, _nrt=False)
def pair_frame(kA, rA, eaA, ebA, VA, iA, nA, stA, kB, rB, eaB, ebB, VB, iB, nB, stB, fr, fe):
    """Contact frame of bodies A and B at the instant of their state rows ``stA``, ``stB``
    (``flight2d``: ``X, Y, ANGLE, VX, VY, OMEGA``): writes ``fr`` (float64[N_FR]: gap,
    normal from B into A, world witness points, gap rate) and ``fe`` (int64[N_FE]:
    features), returns the gap (m). Unknown kinds: NaN gap, features -1."""
    g, nx, ny, pax, pay, pbx, pby, fa, ia, fb, ib = frame_rel(
        kA, rA, eaA, ebA, VA, iA, nA, stA[ANGLE], kB, rB, eaB, ebB, VB, iB, nB,
        stB[X] - stA[X], stB[Y] - stA[Y], stB[ANGLE])
    dx = stB[X] - stA[X]
    dy = stB[Y] - stA[Y]
    fr[FR_GAP] = g
    fr[FR_NX] = nx
    fr[FR_NY] = ny
    fr[FR_PAX] = stA[X] + pax
    fr[FR_PAY] = stA[Y] + pay
    fr[FR_PBX] = stA[X] + pbx
    fr[FR_PBY] = stA[Y] + pby
    fr[FR_RATE] = point_rate(nx, ny, pax, pay, pbx - dx, pby - dy, stA[VX], stA[VY],
                             stA[OMEGA], stB[VX], stB[VY], stB[OMEGA])
    fe[FE_A_KIND] = fa
    fe[FE_A_INDEX] = ia
    fe[FE_B_KIND] = fb
    fe[FE_B_INDEX] = ib
    return g
