"""2D scenes: rigid bodies and static half-planes under uniform gravity.

    >>> from rbimpact import Scene2D, Disk
    >>> scene = Scene2D(gravity=(0.0, -9.81))
    >>> floor = scene.add_floor(0.0)
    >>> ball = scene.add_body(Disk(0.05), 1.0, (0.0, 1.05))

Units: m, kg, s, rad. Positions are those of the centres of mass; angles are
counter-clockwise; ``angular_velocity`` in rad/s (counter-clockwise positive).
"""
import math
from dataclasses import dataclass

from ._validate import body_energy_2d, energy_check, real as _real, vector
from .shapes import Shape

__all__ = ["Scene2D", "Body", "Plane"]


@dataclass(frozen=True)
class Body:
    """A body of a scene (read-only record; ``Scene2D.add_body`` creates it)."""

    index: int
    shape: Shape
    mass: float
    moment: float
    position: tuple
    angle: float
    velocity: tuple
    angular_velocity: float


@dataclass(frozen=True)
class Plane:
    """A static half-plane ``{q : normal . (q - point) >= 0}`` is free space; ``normal`` is
    the unit normal pointing into the free side. ``index`` is its rank in the scene (the
    stepper's events name it ``b = -1 - index``). Use the object as a key of
    ``Simulation(pair_laws=...)``."""

    index: int
    point: tuple
    normal: tuple

    @property
    def offset(self):
        """``d`` in ``normal . q >= d`` (m)."""
        return self.normal[0] * self.point[0] + self.normal[1] * self.point[1]


def _inverse_ok(what, x, unit):
    """The stepper divides by masses and moments: 1/x must be finite (x >~ 5.6e-309)."""
    if not math.isfinite(1.0 / x):
        raise ValueError(f"add_body: {what} {x:g} {unit} is too small: its inverse overflows "
                         f"float64 (it must be at least ~5.6e-309 {unit}); use other units")


class Scene2D:
    """Rigid bodies and static half-planes under uniform ``gravity`` (m/s^2)."""

    def __init__(self, gravity=(0.0, -9.81)):
        g = vector("Scene2D: gravity", gravity, 2, "(gx, gy)", "m/s^2")
        self.gravity = (float(g[0]), float(g[1]))
        self.bodies = []
        self.planes = []
        self._energy = 0.0   # sum of |energies| of the bodies (J): must stay finite

    def add_body(self, shape, mass, position, angle=0.0, velocity=(0.0, 0.0),
                 angular_velocity=0.0, moment=None):
        """Add a body; returns its index (int).

        ``shape``: a ``Disk``, ``Box``, ``Polygon``, ``Rod`` or ``Ellipse``; ``mass`` (kg) > 0;
        ``position`` of the centre of mass (m); ``angle`` (rad); ``velocity`` (m/s);
        ``angular_velocity`` (rad/s); ``moment`` (kg m^2) > 0, by default that of the shape
        with uniform density. Every number must be a finite real (not a bool, string,
        None or complex), and the body's energies (``m |v|^2 / 2``, ``I w^2 / 2``,
        ``m g.x``) and the scene's total must be finite in float64: ``ValueError``
        otherwise.
        """
        if not isinstance(shape, Shape):
            raise ValueError(f"add_body: shape must be a Disk, Box, Polygon, Rod or Ellipse, "
                             f"got {shape!r}")
        m = _real("add_body: mass", mass, "kg")
        if not m > 0.0:
            raise ValueError(f"add_body: mass must be > 0 (kg), got {mass!r}")
        _inverse_ok("mass", m, "kg")
        pos = vector("add_body: position", position, 2, "(x, y)", "m")
        ang = _real("add_body: angle", angle, "rad")
        vel = vector("add_body: velocity", velocity, 2, "(vx, vy)", "m/s")
        w = _real("add_body: angular_velocity", angular_velocity, "rad/s")
        if moment is None:
            inertia = shape.moment(m)
            if not inertia > 0.0:
                raise ValueError(f"add_body: the moment of inertia of {shape!r} with mass "
                                 f"{m:g} kg underflows to 0; use a larger mass or size, or "
                                 f"give moment=")
            if not math.isfinite(inertia):
                raise ValueError(f"add_body: the moment of inertia of {shape!r} with mass "
                                 f"{m:g} kg overflows float64; use a smaller mass or size, "
                                 f"or other units")
        else:
            inertia = _real("add_body: moment", moment, "kg m^2")
            if not inertia > 0.0:
                raise ValueError(f"add_body: moment must be > 0 (kg m^2), got {moment!r}")
        _inverse_ok("moment of inertia", inertia, "kg m^2")
        energy = energy_check(f"add_body (body {len(self.bodies)})",
                              body_energy_2d(m, inertia, pos, vel, w, self.gravity),
                              getattr(self, "_energy", 0.0))
        body = Body(len(self.bodies), shape, m, float(inertia), (float(pos[0]), float(pos[1])), ang,
                    (float(vel[0]), float(vel[1])), w)
        self.bodies.append(body)
        self._energy = energy
        return body.index

    def add_plane(self, point, normal):
        """Add a static half-plane through ``point`` (m) with ``normal`` pointing into the
        free side (normalised here); returns its ``Plane``."""
        pt = vector("add_plane: point", point, 2, "(x, y)", "m")
        n = vector("add_plane: normal", normal, 2, "(nx, ny)")
        norm = math.hypot(n[0], n[1])
        if not norm > 0.0:
            raise ValueError(f"add_plane: normal must be non-zero, got {normal!r}")
        n = n / norm
        plane = Plane(len(self.planes), (float(pt[0]), float(pt[1])), (float(n[0]), float(n[1])))
        self.planes.append(plane)
        return plane

    def add_floor(self, y=0.0):
        """Add the floor ``y >= y0`` (m); returns its ``Plane``."""
        y = _real("add_floor: y", y, "m")
        return self.add_plane((0.0, y), (0.0, 1.0))

    @property
    def n_bodies(self):
        return len(self.bodies)

    def __repr__(self):
        return (f"Scene2D(gravity={self.gravity}, {len(self.bodies)} bodies, "
                f"{len(self.planes)} planes)")
