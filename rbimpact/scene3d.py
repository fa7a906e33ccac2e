"""3D scenes: rigid bodies and static half-spaces under uniform gravity.

    >>> from rbimpact import Scene3D, Sphere
    >>> scene = Scene3D(gravity=(0.0, 0.0, -9.81))
    >>> floor = scene.add_floor(0.0)
    >>> ball = scene.add_body(Sphere(0.05), 1.0, (0.0, 0.0, 1.05))

Units: m, kg, s, rad. Positions are those of the centres of mass; ``orientation`` is a
unit quaternion ``(w, x, y, z)`` rotating the body frame into the world (normalised here);
``angular_velocity`` is in the **world** frame (rad/s).
"""
from dataclasses import dataclass

import numpy as np

from ._validate import (body_energy_3d, energy_check, real as _real, real_array,
                        unit_vector, vector as _vec)
from .scene import _inverse_ok
from .shapes3d import Shape3D

__all__ = ["Scene3D", "Body3D", "Plane3D"]


@dataclass(frozen=True)
class Body3D:
    """A body of a 3D scene (read-only record; ``Scene3D.add_body`` creates it).
    ``inertia``: principal moments (kg m^2) about the body axes."""

    index: int
    shape: Shape3D
    mass: float
    inertia: tuple
    position: tuple
    orientation: tuple
    velocity: tuple
    angular_velocity: tuple


@dataclass(frozen=True)
class Plane3D:
    """A static half-space ``{y : normal . (y - point) >= 0}`` is free space; ``normal`` is
    the unit normal into the free side. ``index`` is its rank in the scene (events name it
    ``b = -1 - index``); use the object as a key of ``Simulation3D(pair_laws=...)``."""

    index: int
    point: tuple
    normal: tuple

    @property
    def offset(self):
        """``d`` in ``normal . y >= d`` (m)."""
        return float(np.dot(self.normal, self.point))


class Scene3D:
    """Rigid bodies and static half-spaces under uniform ``gravity`` (m/s^2)."""

    def __init__(self, gravity=(0.0, 0.0, -9.81)):
        self.gravity = tuple(float(x) for x in
                             _vec("Scene3D: gravity", gravity, 3, "(gx, gy, gz)", "m/s^2"))
        self.bodies = []
        self.planes = []
        self._energy = 0.0   # sum of |energies| of the bodies (J): must stay finite

    def add_body(self, shape, mass, position, orientation=(1.0, 0.0, 0.0, 0.0),
                 velocity=(0.0, 0.0, 0.0), angular_velocity=(0.0, 0.0, 0.0), inertia=None):
        """Add a body; returns its index (int).

        ``shape``: ``Sphere``, ``Box3D`` or ``Capsule``; ``mass`` (kg) > 0; ``position`` of
        the centre of mass (m); ``orientation`` a quaternion ``(w, x, y, z)`` (normalised);
        ``velocity`` (m/s); ``angular_velocity`` (rad/s, world frame); ``inertia``: the
        principal moments (kg m^2) about the body axes -- one number (spherical) or three
        -- by default those of the shape with uniform density. Each moment must be > 0
        and obey the triangle inequality ``I_i <= I_j + I_k`` of a real body. Every number
        must be a finite real (not a bool, string, None or complex), and the body's
        energies (``m |v|^2 / 2``, ``w.I w / 2``, ``m g.x``) and the scene's total must be
        finite in float64: ``ValueError`` otherwise.
        """
        if not isinstance(shape, Shape3D):
            raise ValueError(f"add_body: shape must be a Sphere, Box3D or Capsule, got "
                             f"{shape!r}")
        m = _real("add_body: mass", mass, "kg")
        if not m > 0.0:
            raise ValueError(f"add_body: mass must be > 0 (kg), got {mass!r}")
        _inverse_ok("mass", m, "kg")
        pos = _vec("add_body: position", position, 3, "(x, y, z)", "m")
        q = unit_vector("add_body: orientation (a quaternion (w, x, y, z))",
                        _vec("add_body: orientation", orientation, 4, "(w, x, y, z)"),
                        orientation)
        vel = _vec("add_body: velocity", velocity, 3, "(vx, vy, vz)", "m/s")
        w = _vec("add_body: angular_velocity", angular_velocity, 3, "(wx, wy, wz)", "rad/s")
        if inertia is None:
            I = shape.inertia(m)
            if not np.all(np.isfinite(I)):
                raise ValueError(f"add_body: the moments of inertia of {shape!r} with mass "
                                 f"{m:g} kg overflow float64; use a smaller mass or size, "
                                 f"or other units")
        else:
            I = real_array("add_body: inertia", inertia,
                           "one or three principal moments (kg m^2)").reshape(-1)
            if I.shape == (1,):
                I = np.repeat(I, 3)
            if I.shape != (3,):
                raise ValueError(f"add_body: inertia must be one or three principal moments "
                                 f"(kg m^2) about the body axes, got {inertia!r}")
            if not (np.all(np.isfinite(I)) and np.all(I > 0.0)):
                raise ValueError(f"add_body: principal moments must be finite and > 0 "
                                 f"(kg m^2), got {inertia!r}")
            for k in range(3):
                if I[k] > (I[(k + 1) % 3] + I[(k + 2) % 3]) * (1.0 + 1e-12):
                    raise ValueError(f"add_body: principal moments {I.tolist()} violate the "
                                     f"triangle inequality I_{k + 1} <= sum of the others")
        for k in range(3):
            if not I[k] > 0.0:
                raise ValueError(f"add_body: the moments of inertia of {shape!r} with mass "
                                 f"{m:g} kg underflow to 0; use a larger mass or size, or "
                                 f"give inertia=")
            _inverse_ok(f"principal moment I_{k + 1}", float(I[k]), "kg m^2")
        energy = energy_check(f"add_body (body {len(self.bodies)})",
                              body_energy_3d(m, I, pos, q, vel, w, self.gravity),
                              getattr(self, "_energy", 0.0))
        body = Body3D(len(self.bodies), shape, m, tuple(float(x) for x in I),
                      tuple(float(x) for x in pos), tuple(float(x) for x in q),
                      tuple(float(x) for x in vel), tuple(float(x) for x in w))
        self.bodies.append(body)
        self._energy = energy
        return body.index

    def add_plane(self, point, normal):
        """Add a static half-space through ``point`` (m) with ``normal`` pointing into the
        free side (normalised here); returns its ``Plane3D``."""
        pt = _vec("add_plane: point", point, 3, "(x, y, z)", "m")
        n = unit_vector("add_plane: normal", _vec("add_plane: normal", normal, 3,
                                                  "(nx, ny, nz)"), normal)
        plane = Plane3D(len(self.planes), tuple(float(x) for x in pt),
                        tuple(float(x) for x in n))
        self.planes.append(plane)
        return plane

    def add_floor(self, z=0.0):
        """Add the floor ``z >= z0`` (m); returns its ``Plane3D``."""
        z = _real("add_floor: z", z, "m")
        return self.add_plane((0.0, 0.0, z), (0.0, 0.0, 1.0))

    @property
    def n_bodies(self):
        return len(self.bodies)

    def __repr__(self):
        return (f"Scene3D(gravity={self.gravity}, {len(self.bodies)} bodies, "
                f"{len(self.planes)} planes)")
