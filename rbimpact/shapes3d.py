"""3D rigid shapes: validation, volume, principal moments of inertia, contact features.

Every shape is described in its body frame with the **centre of mass at the origin** and
its principal axes along the body axes: a body's ``position`` is that of its centre of
mass and its ``orientation`` (unit quaternion ``(w, x, y, z)``) rotates the body frame into
the world. Units: m, kg, kg m^2.

Shapes and their contact features (what the 3D stepper's time-of-impact search tracks,
see ``rbimpact.kernels.toi3d``):

* ``Sphere(radius)``: its centre, carrying the radius. Solid: ``I = 2/5 m r^2``.
* ``Box3D(size)``: full edge lengths ``(a, b, c)`` along the body x, y, z axes (a single
  number makes a cube); its eight corners. ``I = m/12 (b^2 + c^2, a^2 + c^2, a^2 + b^2)``.
* ``Capsule(length, radius)``: a cylinder of ``length`` (m, the distance between the
  centres of the two hemispherical end caps, > 0) and ``radius`` along the **body z
  axis**, closed by two hemispheres; its features are the two cap centres
  ``(0, 0, +-length/2)`` carrying the radius. Uniform density: with ``m_c`` the mass of the
  cylinder and ``m_h`` of one hemisphere, ``I_z = m_c r^2/2 + 2 (2/5) m_h r^2`` and
  ``I_x = I_y = m_c (L^2/12 + r^2/4) + 2 m_h (2 r^2/5 + L^2/4 + 3 L r/8)``
  (the hemisphere's own moment 83/320 m_h r^2 about its centre of mass, shifted by
  ``L/2 + 3r/8``).

Shapes are immutable; invalid sizes raise ``ValueError`` with the offending value.
"""
import math

import numpy as np

from ._validate import ValueShape, real as _real, real_array, size as _size

__all__ = ["Shape3D", "Sphere", "Box3D", "Capsule"]

# shape kinds of the compiled stepper (kernels/stepper3d.py: SH_*)
_SH_SPHERE, _SH_BOX, _SH_CAPSULE = 0, 1, 2


class Shape3D(ValueShape):
    """Base class. Subclasses define ``volume`` (m^3), ``unit_inertia`` (principal moments
    per unit mass about the body axes, m^2, uniform density), ``bounding_radius`` (m) and
    the kernel encoding ``_kernel()`` -> (kind, feature radius, half extents (3,),
    features (n, 3))."""

    def inertia(self, mass):
        """Principal moments of inertia (kg m^2, float64[3]) about the body axes for
        ``mass`` (kg), uniform density."""
        m = _real(f"{type(self).__name__}.inertia: mass", mass, "kg")
        return np.array([m * float(k) for k in self.unit_inertia])   # inf on overflow



class Sphere(Shape3D):
    """A solid sphere of ``radius`` (m) > 0."""

    def __init__(self, radius):
        self.radius = _size("Sphere", "radius", radius)

    @property
    def volume(self):
        return 4.0 / 3.0 * math.pi * self.radius ** 3

    @property
    def unit_inertia(self):
        k = 0.4 * self.radius ** 2
        return (k, k, k)

    @property
    def bounding_radius(self):
        return self.radius

    def _kernel(self):
        return _SH_SPHERE, self.radius, np.zeros(3), np.zeros((1, 3))

    def _key(self):
        return (self.radius,)

    def __repr__(self):
        return f"Sphere(radius={self.radius!r})"


class Box3D(Shape3D):
    """A rectangular box with full edge lengths ``size`` = ``(a, b, c)`` (m) along the body
    x, y, z axes, or a cube when ``size`` is one number."""

    def __init__(self, size):
        vals = real_array("Box3D: size", size,
                          "a number or three edge lengths (a, b, c) in m").reshape(-1)
        if np.ndim(size) == 0:
            s = _size("Box3D", "size", size)
            self.size = (s, s, s)
        else:
            if vals.shape != (3,):
                raise ValueError(f"Box3D: size must be a number or three edge lengths "
                                 f"(a, b, c) in m, got {size!r}")
            self.size = tuple(_size("Box3D", f"size[{k}]", float(x))
                              for k, x in enumerate(vals))

    @property
    def half(self):
        return np.array(self.size) * 0.5

    @property
    def volume(self):
        a, b, c = self.size
        return a * b * c

    @property
    def unit_inertia(self):
        a, b, c = self.size
        return ((b * b + c * c) / 12.0, (a * a + c * c) / 12.0, (a * a + b * b) / 12.0)

    @property
    def bounding_radius(self):
        return 0.5 * math.sqrt(sum(x * x for x in self.size))

    @property
    def vertices(self):
        """The eight corners (m, body frame), x fastest."""
        h = self.half
        return np.array([[sx * h[0], sy * h[1], sz * h[2]]
                         for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)])

    def _kernel(self):
        return _SH_BOX, 0.0, self.half, self.vertices

    def _key(self):
        return self.size

    def __repr__(self):
        return f"Box3D(size={self.size!r})"


class Capsule(Shape3D):
    """A capsule along the **body z axis**: a cylinder of ``length`` (m, between the two
    cap centres) and ``radius`` (m), closed by two hemispheres (total length
    ``length + 2 radius``)."""

    def __init__(self, length, radius):
        self.length = _size("Capsule", "length", length)
        self.radius = _size("Capsule", "radius", radius)

    @property
    def volume(self):
        r, L = self.radius, self.length
        return math.pi * r * r * L + 4.0 / 3.0 * math.pi * r ** 3

    @property
    def unit_inertia(self):
        r, L = self.radius, self.length
        vc = math.pi * r * r * L
        vh = 2.0 / 3.0 * math.pi * r ** 3
        V = vc + 2.0 * vh
        mc = vc / V
        mh = vh / V
        iz = mc * r * r / 2.0 + 2.0 * 0.4 * mh * r * r
        ix = mc * (L * L / 12.0 + r * r / 4.0) + 2.0 * mh * (0.4 * r * r + L * L / 4.0
                                                              + 3.0 * L * r / 8.0)
        return (ix, ix, iz)

    @property
    def bounding_radius(self):
        return 0.5 * self.length + self.radius

    def _kernel(self):
        h = 0.5 * self.length
        return (_SH_CAPSULE, self.radius, np.array([0.0, 0.0, h]),
                np.array([[0.0, 0.0, -h], [0.0, 0.0, h]]))

    def _key(self):
        return (self.length, self.radius)

    def __repr__(self):
        return f"Capsule(length={self.length!r}, radius={self.radius!r})"
