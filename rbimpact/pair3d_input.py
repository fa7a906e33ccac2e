"""Checks of the 3D pair kernels' inputs (``kernels/pair3d*.py``), which never raise: each
function returns the kernel encoding or raises ``ValueError`` saying what is wrong.

Body encoding (``kernels/pair3d_shape.py``): ``(kind, rad, hx, hy, hz)``, five scalars, as
the 3D stepper's scene table holds them (``B_KIND``, ``B_RADIUS``, ``B_HALF + k``). Pass them
unpacked before each body's state row: ``pair_frame(*bodyA, stA, *bodyB, stB, fr, fe)``.
"""
import math

import numpy as np

from ._validate import real_array, size, vector
from .kernels.pair3d_shape import SH_BOX, SH_CAPSULE, SH_SPHERE

__all__ = ["body_geometry", "shape_geometry", "state", "rotation"]

_KINDS = {SH_SPHERE: "sphere", SH_BOX: "box", SH_CAPSULE: "capsule"}
QUAT_TOL = 1e-9     # |q| may differ from 1 by this much (renormalised); more is an error


def body_geometry(kind, radius=0.0, half=(0.0, 0.0, 0.0)):
    """The kernel encoding ``(kind, rad, hx, hy, hz)`` of one body, checked:

    * ``SH_SPHERE``: ``radius > 0`` (m), ``half`` zero;
    * ``SH_BOX``: ``half`` three half edges > 0 (m), ``radius`` 0;
    * ``SH_CAPSULE``: ``radius > 0``, ``half = (0, 0, L/2)`` with ``L/2 > 0`` the half distance
      of the cap centres along the body z axis.

    Raises ``ValueError`` for an unknown kind, a non-finite, negative or missing size, or
    a size the kind does not have."""
    if isinstance(kind, (bool, np.bool_)) or kind not in _KINDS:
        raise ValueError(f"pair3d: shape kind must be one of {sorted(_KINDS)} "
                         f"({', '.join(_KINDS.values())}), got {kind!r}")
    name = f"pair3d {_KINDS[kind]}"
    h = vector(f"{name}: half", half, 3, "(hx, hy, hz)", "m")
    if kind == SH_BOX:
        r = size(name, "radius", radius, allow_zero=True)
        if r != 0.0:
            raise ValueError(f"{name}: radius must be 0 (rounded boxes are not a 3D shape "
                             f"kind), got {radius!r}")
        hx, hy, hz = (size(name, f"half[{k}]", float(h[k])) for k in range(3))
        return kind, 0.0, hx, hy, hz
    r = size(name, "radius", radius)
    if kind == SH_SPHERE:
        if np.any(h != 0.0):
            raise ValueError(f"{name}: half must be (0, 0, 0), got {tuple(h)}")
        return kind, r, 0.0, 0.0, 0.0
    if h[0] != 0.0 or h[1] != 0.0:
        raise ValueError(f"{name}: half must be (0, 0, L/2) (the axis is body z), got "
                         f"{tuple(h)}")
    hz = size(name, "half[2] (half the distance of the cap centres)", float(h[2]))
    return kind, r, 0.0, 0.0, hz


def shape_geometry(shape):
    """The checked kernel encoding of an ``rbimpact.shapes3d`` shape."""
    kind, rad, half, _ = shape._kernel()
    return body_geometry(kind, rad, half)


def state(value, what="state"):
    """A ``flight3d`` state row for the pair kernels: 7 numbers ``(x, y, z, qw, qx, qy, qz)``
    (m; unit quaternion body -> world; zero velocities and accelerations) or a full row of
    19, all finite, the quaternion of length 1 within ``QUAT_TOL`` (returned renormalised),
    as float64[19]."""
    v = real_array(what, value, "7 numbers (x, y, z, qw, qx, qy, qz) or a state row of 19")
    v = v.reshape(-1)
    if v.shape[0] not in (7, 19):
        raise ValueError(f"{what} must be 7 numbers (x, y, z, qw, qx, qy, qz) or a state "
                         f"row of 19, got {v.shape[0]}")
    v = vector(what, v, v.shape[0], "(x, q[, v, w, a, al])")
    out = np.zeros(19)
    out[:v.shape[0]] = v
    n = math.sqrt(float(np.sum(out[3:7] ** 2)))
    if not abs(n - 1.0) <= QUAT_TOL:
        raise ValueError(f"{what}: the orientation quaternion (columns 3:7) must have length "
                         f"1 (within {QUAT_TOL:g}), got length {n!r}")
    out[3:7] /= n
    return out


def rotation(shape, mass=1.0):
    """``(rk, axis, I1, I2, I3)`` for ``pair3d_toi.pair_toi``: the rotation kind and symmetry
    axis (``flight3d.ROT_*``, the rule of ``rbimpact.simulation3d.rotation_kind``) and the
    principal moments (kg m^2) of a ``shapes3d`` shape of ``mass`` (kg), uniform density."""
    from .simulation3d import rotation_kind
    inertia = shape.inertia(mass)
    if not np.all(np.isfinite(inertia)) or not np.all(inertia > 0.0):
        raise ValueError(f"pair3d: the moments of inertia of {shape!r} with mass {mass!r} "
                         f"must be finite and > 0, got {inertia}")
    rk, axis = rotation_kind(tuple(float(x) for x in inertia))
    return rk, axis, float(inertia[0]), float(inertia[1]), float(inertia[2])
