"""2D rigid shapes: validation, area, moment of inertia (uniform density), contact features.

Every shape is described in its body frame, with the **centre of mass at the origin**: a
body's ``position`` in a scene is the position of its centre of mass and its ``angle``
rotates the body frame counter-clockwise (rad). Units: m, kg, kg m^2.

Contact features (what the stepper's time-of-impact search tracks, see
``rbimpact.kernels.toi2d``):

* ``Disk(radius)``: its centre, carrying the radius;
* ``Box(width, height)`` and ``Polygon(vertices)``: every corner (radius 0);
* ``Rod(length, radius=0.0)``: its two end points, carrying ``radius`` (a segment when 0,
  a capsule otherwise);
* ``Ellipse(a, b)``: its support point ``sqrt(a^2 (n.e1)^2 + b^2 (n.e2)^2)`` along a plane
  normal (``a`` along the body x axis).

Shapes are immutable; invalid sizes raise ``ValueError`` with the offending value.
"""
import math

import numpy as np

from ._validate import SIZE_MAX, SIZE_MIN, ValueShape, real as _real, real_array, size as _size

__all__ = ["Shape", "Disk", "Box", "Polygon", "Rod", "Ellipse"]

# shape kinds of the compiled stepper (kernels/stepper2d.py: SH_*)
_SH_DISK, _SH_POLY, _SH_ELLIPSE = 0, 1, 2


class Shape(ValueShape):
    """Base class. Subclasses define ``area`` (m^2), ``unit_moment`` (m^2: moment of inertia
    about the centre of mass per unit mass, uniform density), ``bounding_radius`` (m) and
    the kernel encoding ``_kernel()`` -> (kind, rounding radius, a, b, vertices[n, 2])."""

    def moment(self, mass):
        """Moment of inertia (kg m^2) about the centre of mass for ``mass`` (kg), uniform
        density."""
        return _real(f"{type(self).__name__}.moment: mass", mass, "kg") * self.unit_moment



class Disk(Shape):
    """A disk of ``radius`` (m) > 0."""

    def __init__(self, radius):
        self.radius = _size("Disk", "radius", radius)

    @property
    def area(self):
        return math.pi * self.radius ** 2

    @property
    def unit_moment(self):
        return 0.5 * self.radius ** 2

    @property
    def bounding_radius(self):
        return self.radius

    def _kernel(self):
        return _SH_DISK, self.radius, 0.0, 0.0, np.zeros((1, 2))

    def _key(self):
        return (self.radius,)

    def __repr__(self):
        return f"Disk(radius={self.radius!r})"


class Polygon(Shape):
    """A convex polygon given by its ``vertices`` (sequence of (x, y), m), in either
    orientation. Repeated, collinear-degenerate or non-convex outlines raise ``ValueError``.

    The body frame is the given frame shifted to the centroid: ``self.vertices`` are the
    corners relative to the centre of mass, counter-clockwise; ``self.offset`` is the
    centroid in the given coordinates (``vertices = given - offset``).
    """

    def __init__(self, vertices, _name="Polygon"):
        v = real_array(f"{_name}: vertices", vertices,
                       "a sequence of at least 3 points (x, y) in m")
        if v.ndim != 2 or v.shape[1] != 2 or v.shape[0] < 3:
            raise ValueError(f"{_name}: vertices must be at least 3 points (x, y), got shape "
                             f"{v.shape}")
        if not np.all(np.isfinite(v)):
            raise ValueError(f"{_name}: vertices must be finite, got {vertices!r}")
        # All geometry in coordinates relative to the vertex mean ``ref``: a small polygon
        # far from the origin would otherwise lose its area, centroid and moment to
        # cancellation (x_i y_j - x_j y_i of large coordinates). ``v - ref`` is exact for
        # vertices within a factor 2 of ``ref`` (Sterbenz), the case that matters.
        ref = v.mean(axis=0)
        d = v - ref
        e = np.roll(d, -1, axis=0) - d
        scale = float(np.max(np.abs(d)))
        if scale == 0.0 or np.any(np.hypot(e[:, 0], e[:, 1]) <= 1e-12 * scale):
            raise ValueError(f"{_name}: vertices must be distinct consecutive points")
        if not SIZE_MIN <= scale <= SIZE_MAX:
            raise ValueError(f"{_name}: the polygon's size ({scale:.3g} m from the vertex "
                             f"mean) must be between {SIZE_MIN:g} and {SIZE_MAX:g} m, so that "
                             f"its area and moment of inertia are representable in float64")
        dn = np.roll(d, -1, axis=0)
        area2 = float(np.sum(d[:, 0] * dn[:, 1] - dn[:, 0] * d[:, 1]))
        if area2 == 0.0:
            raise ValueError(f"{_name}: the outline has zero signed area (degenerate or "
                             f"self-intersecting), not a convex polygon")
        if area2 < 0.0:  # clockwise: reverse to counter-clockwise
            v, d = v[::-1].copy(), d[::-1].copy()
            e = np.roll(d, -1, axis=0) - d
            dn = np.roll(d, -1, axis=0)
        en = np.roll(e, -1, axis=0)
        cross = e[:, 0] * en[:, 1] - e[:, 1] * en[:, 0]
        tol = 1e-12 * scale * scale
        if np.any(cross <= tol):
            bad = int(np.argmin(cross))
            raise ValueError(f"{_name}: the polygon is not strictly convex (turn at vertex "
                             f"{(bad + 1) % len(v)} is {'reflex' if cross[bad] < 0 else 'flat'}"
                             f"); give the vertices of a convex polygon")
        # winding number 1 (a star polygon turns twice): total turning must be 2 pi
        ang = np.arctan2(cross, np.sum(e * en, axis=1))
        if abs(float(np.sum(ang)) - 2 * math.pi) > 1e-6:
            raise ValueError(f"{_name}: the outline is self-intersecting, not a convex polygon")
        c = d[:, 0] * dn[:, 1] - dn[:, 0] * d[:, 1]
        A = 0.5 * float(np.sum(c))
        cd = np.array([float(np.sum((d[:, 0] + dn[:, 0]) * c)),
                       float(np.sum((d[:, 1] + dn[:, 1]) * c))]) / (6.0 * A)
        self.offset = ref + cd
        self.vertices = d - cd
        self.vertices.setflags(write=False)
        self.offset.setflags(write=False)
        # second moment about the centroid, from the centred vertices (no parallel-axis
        # subtraction, so nothing cancels)
        w = self.vertices
        wn = np.roll(w, -1, axis=0)
        c = w[:, 0] * wn[:, 1] - wn[:, 0] * w[:, 1]
        J = float(np.sum(c * (w[:, 0] ** 2 + w[:, 0] * wn[:, 0] + wn[:, 0] ** 2
                              + w[:, 1] ** 2 + w[:, 1] * wn[:, 1] + wn[:, 1] ** 2))) / 12.0
        self._area = 0.5 * float(np.sum(c))
        self._unit_moment = J / self._area

    @property
    def area(self):
        return self._area

    @property
    def unit_moment(self):
        return self._unit_moment

    @property
    def bounding_radius(self):
        return float(np.max(np.hypot(self.vertices[:, 0], self.vertices[:, 1])))

    def _kernel(self):
        return _SH_POLY, 0.0, 0.0, 0.0, np.array(self.vertices, dtype=float)

    def _key(self):
        return tuple(map(tuple, np.round(self.vertices, 15)))

    def __repr__(self):
        return f"Polygon({self.vertices.tolist()!r})"


class Box(Polygon):
    """A rectangle ``width`` x ``height`` (m), both > 0, axis-aligned in the body frame."""

    def __init__(self, width, height):
        self.width = _size("Box", "width", width)
        self.height = _size("Box", "height", height)
        w, h = 0.5 * self.width, 0.5 * self.height
        super().__init__([(-w, -h), (w, -h), (w, h), (-w, h)], _name="Box")
        self._unit_moment = (self.width ** 2 + self.height ** 2) / 12.0

    def __repr__(self):
        return f"Box(width={self.width!r}, height={self.height!r})"


class Rod(Shape):
    """A rod of ``length`` (m) > 0 along the body x axis: a segment when ``radius`` = 0,
    a capsule (segment swept by a disk of ``radius`` m) otherwise. Its contact features
    are its two ends (with the radius). A segment's moment of inertia is m L^2 / 12; a
    capsule's is that of a uniform rectangle plus two half-disks."""

    def __init__(self, length, radius=0.0):
        self.length = _size("Rod", "length", length)
        self.radius = _size("Rod", "radius", radius, allow_zero=True)
        self.vertices = np.array([[-0.5 * self.length, 0.0], [0.5 * self.length, 0.0]])
        self.vertices.setflags(write=False)

    @property
    def area(self):
        r, L = self.radius, self.length
        return 2.0 * r * L + math.pi * r * r

    @property
    def unit_moment(self):
        r, L = self.radius, self.length
        if r == 0.0:
            return L * L / 12.0
        rect = 2.0 * r * L
        rect_I = rect * (L * L + 4.0 * r * r) / 12.0
        half = 0.5 * math.pi * r * r
        k = 4.0 * r / (3.0 * math.pi)              # centroid of a half-disk from its flat side
        half_I = half * r * r / 2.0 - half * k * k + half * (0.5 * L + k) ** 2
        return (rect_I + 2.0 * half_I) / (rect + 2.0 * half)

    @property
    def bounding_radius(self):
        return 0.5 * self.length + self.radius

    def _kernel(self):
        return _SH_POLY, self.radius, 0.0, 0.0, np.array(self.vertices, dtype=float)

    def _key(self):
        return (self.length, self.radius)

    def __repr__(self):
        return f"Rod(length={self.length!r}, radius={self.radius!r})"


class Ellipse(Shape):
    """An ellipse with semi-axis ``a`` (m) along the body x axis and ``b`` (m) along y."""

    def __init__(self, a, b):
        self.a = _size("Ellipse", "a", a)
        self.b = _size("Ellipse", "b", b)

    @property
    def area(self):
        return math.pi * self.a * self.b

    @property
    def unit_moment(self):
        return 0.25 * (self.a ** 2 + self.b ** 2)

    @property
    def bounding_radius(self):
        return max(self.a, self.b)

    def _kernel(self):
        if self.a == self.b:   # a circle: exactly a disk for contacts
            return _SH_DISK, self.a, 0.0, 0.0, np.zeros((1, 2))
        return _SH_ELLIPSE, 0.0, self.a, self.b, np.zeros((1, 2))

    def _key(self):
        return (self.a, self.b)

    def __repr__(self):
        return f"Ellipse(a={self.a!r}, b={self.b!r})"
