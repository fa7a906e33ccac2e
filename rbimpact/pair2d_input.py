"""Checks of the 2D pair kernels' inputs (``kernels/pair2d*.py``), which never raise: each
function returns the kernel encoding or raises ``ValueError`` saying what is wrong.

Body encoding (``kernels/pair2d_shape.py``): ``(kind, rad, ea, eb, V)`` with ``V`` a
float64[n, 2] C-contiguous table of body-frame core vertices (m), counter-clockwise for
polygons; pass ``V, 0, len(V)`` as ``V, v0, nv``.
"""
import math

import numpy as np

from ._validate import real_array, size, vector
from .kernels.pair2d_shape import SH_DISK, SH_ELLIPSE, SH_POLY

__all__ = ["body_geometry", "shape_geometry", "pose"]

_KINDS = {SH_DISK: "disk", SH_POLY: "polygon/rod", SH_ELLIPSE: "ellipse"}
CONVEX_TOL = 1e-12   # a turn below CONVEX_TOL * size^2 (cross product of edges) is not convex


def body_geometry(kind, radius=0.0, a=0.0, b=0.0, vertices=None):
    """The kernel encoding ``(kind, rad, ea, eb, V)`` of one body, checked:

    * ``SH_DISK``: ``radius > 0`` (m); ``vertices`` one point (default the origin);
    * ``SH_POLY``: ``vertices`` 2 points (a rod: a segment, or a capsule if ``radius > 0``)
      or at least 3 forming a strictly convex polygon (either orientation; returned
      counter-clockwise); ``radius >= 0``;
    * ``SH_ELLIPSE``: semi-axes ``a > 0``, ``b > 0`` (m).

    Raises ``ValueError`` for an unknown kind, a non-finite or non-positive size, a
    non-convex, repeated or degenerate outline."""
    if isinstance(kind, bool) or kind not in _KINDS:
        raise ValueError(f"pair2d: shape kind must be one of {sorted(_KINDS)} "
                         f"({', '.join(_KINDS.values())}), got {kind!r}")
    if kind == SH_ELLIPSE:
        ea = size("pair2d ellipse", "a", a)
        eb = size("pair2d ellipse", "b", b)
        return kind, 0.0, ea, eb, np.zeros((1, 2))
    if kind == SH_DISK:
        r = size("pair2d disk", "radius", radius)
        V = np.zeros((1, 2)) if vertices is None else _points("pair2d disk", vertices)
        if V.shape[0] != 1:
            raise ValueError(f"pair2d disk: vertices must be one point (its centre), got "
                             f"{V.shape[0]}")
        return kind, r, 0.0, 0.0, V
    r = size("pair2d polygon/rod", "radius", radius, allow_zero=True)
    if vertices is None:
        raise ValueError("pair2d polygon/rod: vertices are required")
    V = _points("pair2d polygon/rod", vertices)
    n = V.shape[0]
    if n < 2:
        raise ValueError(f"pair2d polygon/rod: at least 2 vertices (a rod) are needed, got "
                         f"{n}; a single point with a radius is a disk (SH_DISK)")
    scale = float(np.max(np.abs(V - V.mean(axis=0))))
    e = np.roll(V, -1, axis=0) - V
    if scale == 0.0 or np.any(np.hypot(e[:, 0], e[:, 1]) <= 1e-12 * scale):
        raise ValueError("pair2d polygon/rod: vertices must be distinct consecutive points")
    if n == 2:
        return kind, r, 0.0, 0.0, V
    en = np.roll(e, -1, axis=0)
    cross = e[:, 0] * en[:, 1] - e[:, 1] * en[:, 0]
    tol = CONVEX_TOL * scale * scale
    if np.all(cross < -tol):
        V = V[::-1].copy()
    elif not np.all(cross > tol):
        raise ValueError("pair2d polygon: the outline is not strictly convex (a reflex or "
                         "flat turn); give the vertices of a convex polygon in order")
    e = np.roll(V, -1, axis=0) - V
    en = np.roll(e, -1, axis=0)
    turn = np.arctan2(e[:, 0] * en[:, 1] - e[:, 1] * en[:, 0], np.sum(e * en, axis=1))
    if abs(float(np.sum(turn)) - 2.0 * math.pi) > 1e-6:
        raise ValueError("pair2d polygon: the outline is self-intersecting (it turns more "
                         "than once), not a convex polygon")
    return kind, r, 0.0, 0.0, np.ascontiguousarray(V)


def _points(what, vertices):
    V = real_array(f"{what}: vertices", vertices, "a sequence of points (x, y) in m")
    if V.ndim != 2 or V.shape[1] != 2:
        raise ValueError(f"{what}: vertices must be points (x, y), got shape {V.shape}")
    if not np.all(np.isfinite(V)):
        raise ValueError(f"{what}: vertices must be finite")
    return np.ascontiguousarray(V, dtype=np.float64)


def shape_geometry(shape):
    """The checked kernel encoding of an ``rbimpact.shapes`` shape (``Shape._kernel()``)."""
    kind, rad, ea, eb, V = shape._kernel()
    return body_geometry(kind, rad, ea, eb, V)


def pose(value, what="pose"):
    """A state row for the pair kernels: 3 numbers ``(x, y, angle)`` (m, rad; zero
    velocities and accelerations) or a full ``flight2d`` row of 9, all finite, as
    float64[9]."""
    v = real_array(what, value, "3 numbers (x, y, angle) or a state row of 9")
    v = v.reshape(-1)
    if v.shape[0] not in (3, 9):
        raise ValueError(f"{what} must be 3 numbers (x, y, angle) or a state row of 9, got "
                         f"{v.shape[0]}")
    v = vector(what, v, v.shape[0], "(x, y, angle[, vx, vy, omega, ax, ay, alpha])")
    out = np.zeros(9)
    out[:v.shape[0]] = v
    return out
