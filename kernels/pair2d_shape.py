"""2D body geometry as the pair kernels see it: shape kinds, features, support functions.

A body is given to every pair kernel by seven arguments ``kind, rad, ea, eb, V, v0, nv``,
the encoding of ``rbimpact.shapes`` (``Shape._kernel()``) and of the stepper's scene tables
(``stepper2d``: ``B_KIND``, ``B_RADIUS``, ``B_EA``, ``B_EB``, ``verts``, ``B_FIRST``,
``B_COUNT``); body frame, centre of mass at the origin, units m:

* ``SH_DISK``: ``nv = 1`` vertex (its centre, normally (0, 0)) with radius ``rad > 0``;
* ``SH_POLY``: the *core* ``V[v0 : v0 + nv]`` swept by a disk of radius ``rad >= 0``
  (a "rounded convex polygon"): ``nv >= 3`` a convex polygon (``rad = 0``; box, polygon),
  ``nv = 2`` a rod (a segment when ``rad = 0``, a capsule otherwise);
* ``SH_ELLIPSE``: semi-axes ``ea`` (body x) and ``eb`` (body y), centred at the origin
  (``rad``, ``V`` unused).

Disks, capsules and polygons are one family: a convex core (point, segment, polygon)
plus a radius. Their boundary features are the core's vertices (``FT_VERTEX``: a corner,
or a circular arc of radius ``rad`` around it) and edges (``FT_EDGE``: edge ``i`` runs
from vertex ``i`` to vertex ``i + 1``, cyclically for ``nv >= 3``; a rod has one edge);
an ellipse's boundary is one smooth feature ``FT_CURVE``. The kernels accept polygon
vertices in either orientation (axes are tried with both signs); the Python front end
``rbimpact.pair2d_input`` stores them counter-clockwise.

Support functions (the separating-axis calculus every pair kind uses): for a unit
vector ``u``, ``h(u) = max_{p in body} u . p``. A rounded core: ``max_k u . V_k + rad``; an
ellipse with world matrix ``M = R diag(ea^2, eb^2) R^T`` centred at ``c``:
``h(u) = u . c + sqrt(u^T M u)``, attained at ``c + M u / sqrt(u^T M u)``.
"""
import math

from numba import njit

# shape kinds: equal to stepper2d.SH_* and rbimpact.shapes._SH_* (tests/test_pair2d.py)
SH_DISK = 0
SH_POLY = 1
SH_ELLIPSE = 2

# boundary features
FT_VERTEX = 0    # core vertex (a corner; an arc of radius rad when rounded)
FT_EDGE = 1      # core edge i: from vertex i to vertex i + 1
FT_CURVE = 2     # the ellipse's boundary (smooth); index 0


@njit(cache=True, _nrt=False, inline="always")
def n_edges(nv):
    """Number of core edges: 0 for a point, 1 for a segment, ``nv`` for a polygon."""
    if nv <= 1:
        return 0
    if nv == 2:
        return 1
    return nv


@njit(cache=True, _nrt=False, inline="always")
def vertex_at(V, v0, nv, k, x, y, c, s):
    """World position of core vertex ``k`` (0-based, cyclic) of a body at ``(x, y)`` whose
    angle has cosine ``c`` and sine ``s``."""
    j = v0 + (k % nv)
    px = V[j, 0]
    py = V[j, 1]
    return x + c * px - s * py, y + s * px + c * py


@njit(cache=True, _nrt=False, inline="always")
def ellipse_matrix(ea, eb, c, s):
    """World components ``(Mxx, Mxy, Myy)`` of ``M = R diag(ea^2, eb^2) R^T`` (m^2)."""
    a2 = ea * ea
    b2 = eb * eb
    return a2 * c * c + b2 * s * s, (a2 - b2) * c * s, a2 * s * s + b2 * c * c


@njit(cache=True, _nrt=False, inline="always")
def quad_h(mxx, mxy, myy, ux, uy):
    """``sqrt(u^T M u)``: the support of a centred ellipse along ``u`` (m); 0 for M = 0."""
    q = mxx * ux * ux + 2.0 * mxy * ux * uy + myy * uy * uy
    return math.sqrt(q) if q > 0.0 else 0.0


@njit(cache=True, _nrt=False, inline="always")
def quad_h_derivs(mxx, mxy, myy, ux, uy):
    """``h = sqrt(u^T M u)`` and its first two derivatives in the direction angle ``psi``
    of ``u = (cos psi, sin psi)`` (``u' = J u``, ``u'' = -u``):
    ``h' = (Ju)^T M u / h``, ``h'' = ((Ju)^T M (Ju) - h^2 - h'^2) / h``. Zeros for M = 0."""
    wx = -uy
    wy = ux
    q = mxx * ux * ux + 2.0 * mxy * ux * uy + myy * uy * uy
    if not q > 0.0:
        return 0.0, 0.0, 0.0
    h = math.sqrt(q)
    m1 = mxx * wx * ux + mxy * (wx * uy + wy * ux) + myy * wy * uy
    m2 = mxx * wx * wx + 2.0 * mxy * wx * wy + myy * wy * wy
    h1 = m1 / h
    return h, h1, (m2 - q - h1 * h1) / h


@njit(cache=True, _nrt=False)
def core_support(V, v0, nv, x, y, c, s, ux, uy):
    """``(max_k u . V_k, k)`` over the world core vertices (no radius). Ties: lowest k."""
    best = -math.inf
    kb = 0
    for k in range(nv):
        px, py = vertex_at(V, v0, nv, k, x, y, c, s)
        d = ux * px + uy * py
        if d > best:
            best = d
            kb = k
    return best, kb


@njit(cache=True, _nrt=False)
def body_reach(kind, rad, ea, eb, V, v0, nv):
    """``(K1, K2)`` (m): bounds on the first and second derivative, in the relative angle
    between an axis and the body, of the support of one support element (a core vertex, or
    the ellipse's support) measured from the centre of mass:

    * core vertex ``p``: ``u . R(theta) p`` has ``|d/dtheta| <= |p|``, ``|d2/dtheta2| <= |p|``,
      so ``K1 = K2 = max_k |V_k|`` (0 for a disk centred on its centre of mass);
    * ellipse: ``|h'| <= max(ea, eb)`` (the tangential coordinate of the support point) and
      ``h'' = rho - h`` with the radius of curvature ``rho`` in ``[eb^2/ea, ea^2/eb]``, so
      ``|h''| <= |ea^2 - eb^2| / min(ea, eb)`` (as ``toi2d``)."""
    if kind == SH_ELLIPSE:
        return max(ea, eb), abs(ea * ea - eb * eb) / min(ea, eb)
    r = 0.0
    for k in range(nv):
        j = v0 + k
        r = max(r, math.sqrt(V[j, 0] * V[j, 0] + V[j, 1] * V[j, 1]))
    return r, r
