"""3D body geometry as the pair kernels see it: shape kinds, cores, features, rotations.

A body is given to every 3D pair kernel by five scalars ``kind, rad, hx, hy, hz``, the
encoding of ``rbimpact.shapes3d`` (``Shape3D._kernel()``) and of ``stepper3d``'s scene tables
(``B_KIND``, ``B_RADIUS``, ``B_HALF + k``); body frame, centre of mass at the origin,
principal axes along the body axes, units m:

* ``SH_SPHERE``: its centre (one core vertex at the origin) with radius ``rad > 0``;
* ``SH_BOX``: half edges ``(hx, hy, hz)``, ``rad = 0``; eight core vertices;
* ``SH_CAPSULE``: the core segment from ``(0, 0, -hz)`` to ``(0, 0, hz)`` (``hz`` half the
  distance of the cap centres) swept by a sphere of radius ``rad > 0``; ``hx = hy = 0``.

All three are one family, as in 2D (``pair2d_shape``): a convex *core* (a point, a
segment, a box) swept by a sphere of radius ``rad``, so the distance of two bodies is the
distance of their cores minus ``rA + rB`` and the support of a body along a unit ``u`` is
``max_k u . V_k + rad`` over its core vertices ``V_k``.

Features (codes shared with ``pair2d_shape`` where they agree):

* ``FT_VERTEX``: core vertex ``k``: box corner ``k = ix + 2 iy + 4 iz`` with ``i = 0`` for
  the negative and 1 for the positive half edge (the order of ``Box3D.vertices``); a
  capsule's cap centre ``k = 0`` at ``-hz``, ``k = 1`` at ``+hz`` (the order of its stepper
  features); a sphere's centre ``k = 0``;
* ``FT_EDGE``: box edge ``e = 4 i + m`` parallel to body axis ``i``, at the signs of axes
  ``j = (i + 1) % 3`` (bit 0 of ``m``) and ``k = (i + 2) % 3`` (bit 1); a capsule's core
  segment ``e = 0`` (a point of its cylindrical side);
* ``FT_FACE``: box face ``f = 2 i + (1 if +h_i else 0)``, outward normal ``+-e_i``.
"""
import math

from numba import njit

from .pair2d_shape import FT_EDGE, FT_VERTEX  # noqa: F401  (shared feature codes)

# shape kinds: equal to stepper3d.SH_* and rbimpact.shapes3d._SH_* (tests/test_pair3d.py)
SH_SPHERE = 0
SH_BOX = 1
SH_CAPSULE = 2
N_SHAPE_KINDS = 3

FT_FACE = 3      # a box face (pair2d_shape's FT_CURVE = 2 is the ellipse's boundary)

# An edge-product separating axis ``e x f`` (A's frame, ``e`` a coordinate axis, so its
# components are copies of ``f``'s: exact) shorter than this is skipped (-). Any axis gives
# a valid lower bound of the signed distance, and an axis built from exact components is
# exact however small the angle, so only exactly parallel edges (whose products the face
# normals replace) need skipping; the value only keeps the squares of the components away
# from underflow.
AXIS_MIN = 1e-140


@njit(cache=True, _nrt=False, inline="always")
def n_core(kind):
    """Number of core vertices: 1 (sphere), 8 (box), 2 (capsule)."""
    if kind == SH_BOX:
        return 8
    if kind == SH_CAPSULE:
        return 2
    return 1


@njit(cache=True, _nrt=False, inline="always")
def core_vertex(kind, hx, hy, hz, k):
    """Body-frame core vertex ``k`` (m); see the module docstring for the numbering."""
    if kind == SH_BOX:
        return ((2.0 * (k & 1) - 1.0) * hx, (2.0 * ((k >> 1) & 1) - 1.0) * hy,
                (2.0 * ((k >> 2) & 1) - 1.0) * hz)
    if kind == SH_CAPSULE:
        return 0.0, 0.0, (2.0 * k - 1.0) * hz
    return 0.0, 0.0, 0.0


@njit(cache=True, _nrt=False, inline="always")
def box_vertex_index(sx, sy, sz):
    """Corner index of the signs ``s = +-1`` of the three coordinates."""
    return (1 if sx > 0.0 else 0) + (2 if sy > 0.0 else 0) + (4 if sz > 0.0 else 0)


@njit(cache=True, _nrt=False, inline="always")
def box_edge_index(i, sj, sk):
    """Index of the box edge parallel to axis ``i`` at the signs ``sj``, ``sk`` of axes
    ``(i + 1) % 3`` and ``(i + 2) % 3``."""
    return 4 * i + (1 if sj > 0.0 else 0) + (2 if sk > 0.0 else 0)


@njit(cache=True, _nrt=False, inline="always")
def box_edge(hx, hy, hz, e):
    """Body-frame endpoints ``(a, b)`` of box edge ``e`` (six floats), ``b - a = 2 h_i e_i``."""
    i = e // 4
    m = e % 4
    s1 = 2.0 * (m & 1) - 1.0
    s2 = 2.0 * ((m >> 1) & 1) - 1.0
    if i == 0:
        return -hx, s1 * hy, s2 * hz, hx, s1 * hy, s2 * hz
    if i == 1:
        return s2 * hx, -hy, s1 * hz, s2 * hx, hy, s1 * hz
    return s1 * hx, s2 * hy, -hz, s1 * hx, s2 * hy, hz


@njit(cache=True, _nrt=False)
def body_reach(kind, hx, hy, hz):
    """Largest distance of a core vertex from the centre of mass (m): 0 for a sphere,
    ``hz`` for a capsule, the half diagonal for a box. The distance of the farthest
    boundary point is this plus ``rad``."""
    if kind == SH_BOX:
        return math.sqrt(hx * hx + hy * hy + hz * hz)
    if kind == SH_CAPSULE:
        return abs(hz)
    return 0.0


@njit(cache=True, _nrt=False, inline="always")
def quat_matrix(q0, q1, q2, q3):
    """Rotation matrix of the unit quaternion ``(w, x, y, z)`` (body -> world, as
    ``flight3d.rotmat``) as nine floats, row by row: ``R[i][j] = world_i . body_j``."""
    return (1.0 - 2.0 * (q2 * q2 + q3 * q3), 2.0 * (q1 * q2 - q0 * q3), 2.0 * (q1 * q3 + q0 * q2),
            2.0 * (q1 * q2 + q0 * q3), 1.0 - 2.0 * (q1 * q1 + q3 * q3), 2.0 * (q2 * q3 - q0 * q1),
            2.0 * (q1 * q3 - q0 * q2), 2.0 * (q2 * q3 + q0 * q1), 1.0 - 2.0 * (q1 * q1 + q2 * q2))


@njit(cache=True, _nrt=False, inline="always")
def rel_quat(a0, a1, a2, a3, b0, b1, b2, b3):
    """``a^* b``: B's orientation in A's body frame (its matrix is ``R_A^T R_B``, accurate
    to round-off also for a small relative rotation)."""
    return (a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3,
            a0 * b1 - a1 * b0 - a2 * b3 + a3 * b2,
            a0 * b2 + a1 * b3 - a2 * b0 - a3 * b1,
            a0 * b3 - a1 * b2 + a2 * b1 - a3 * b0)


@njit(cache=True, _nrt=False, inline="always")
def mat_vec(R, x, y, z):
    """``R (x, y, z)`` for a nine-float matrix."""
    return (R[0] * x + R[1] * y + R[2] * z, R[3] * x + R[4] * y + R[5] * z,
            R[6] * x + R[7] * y + R[8] * z)


@njit(cache=True, _nrt=False, inline="always")
def mat_tvec(R, x, y, z):
    """``R^T (x, y, z)`` for a nine-float matrix."""
    return (R[0] * x + R[3] * y + R[6] * z, R[1] * x + R[4] * y + R[7] * z,
            R[2] * x + R[5] * y + R[8] * z)
