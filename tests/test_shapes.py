"""2D shapes: validation, areas and moments of inertia (uniform density), body frames."""
import math

import numpy as np
import pytest

from rbimpact.scene import Scene2D
from rbimpact.shapes import Box, Disk, Ellipse, Polygon, Rod


def mc_moment(inside, half_extent, n=400_000, seed=1):
    """Monte Carlo area and polar second moment about the origin per unit area."""
    rng = np.random.default_rng(seed)
    p = rng.uniform(-half_extent, half_extent, size=(n, 2))
    m = inside(p)
    area = (2 * half_extent) ** 2 * m.mean()
    return area, float(np.mean((p[m] ** 2).sum(axis=1)))


def test_disk_box_ellipse_closed_forms():
    d = Disk(0.3)
    assert d.area == pytest.approx(math.pi * 0.09)
    assert d.moment(2.0) == pytest.approx(0.5 * 2.0 * 0.09)
    b = Box(0.4, 0.2)
    assert b.area == pytest.approx(0.08)
    assert b.moment(3.0) == pytest.approx(3.0 * (0.16 + 0.04) / 12)
    np.testing.assert_allclose(b.vertices, [(-0.2, -0.1), (0.2, -0.1), (0.2, 0.1), (-0.2, 0.1)])
    e = Ellipse(0.5, 0.2)
    assert e.area == pytest.approx(math.pi * 0.1)
    assert e.moment(1.0) == pytest.approx((0.25 + 0.04) / 4)
    assert Ellipse(0.3, 0.3)._kernel()[0] == Disk(0.3)._kernel()[0]   # a circle is a disk


def test_polygon_matches_box_and_triangle_formulas():
    sq = Polygon([(1, 1), (3, 1), (3, 2), (1, 2)])
    assert sq.area == pytest.approx(2.0)
    assert sq.unit_moment == pytest.approx((4 + 1) / 12)
    np.testing.assert_allclose(sq.offset, (2.0, 1.5))
    np.testing.assert_allclose(sq.vertices.mean(axis=0), 0.0, atol=1e-15)
    # right triangle with legs a, b: I_centroid = m (a^2 + b^2) / 18
    tri = Polygon([(0, 0), (0.6, 0), (0, 0.3)])
    assert tri.area == pytest.approx(0.09)
    assert tri.unit_moment == pytest.approx((0.36 + 0.09) / 18)
    np.testing.assert_allclose(tri.offset, (0.2, 0.1))
    # clockwise input is reoriented counter-clockwise, same geometry
    cw = Polygon([(0, 0), (0, 0.3), (0.6, 0)])
    assert cw.area == pytest.approx(tri.area) and cw.unit_moment == pytest.approx(tri.unit_moment)
    v = cw.vertices
    e1 = np.roll(v, -1, 0) - v
    e2 = np.roll(v, -2, 0) - np.roll(v, -1, 0)
    cross = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    assert np.all(cross > 0)


def test_regular_polygon_tends_to_disk():
    k = np.arange(256)
    poly = Polygon(np.c_[np.cos(2 * np.pi * k / 256), np.sin(2 * np.pi * k / 256)])
    assert poly.area == pytest.approx(math.pi, rel=1e-3)
    assert poly.unit_moment == pytest.approx(0.5, rel=1e-3)


def test_rod_and_capsule():
    assert Rod(2.0).moment(3.0) == pytest.approx(3.0 * 4.0 / 12)
    assert Rod(2.0).area == 0.0
    cap = Rod(1.0, radius=0.2)
    assert cap.area == pytest.approx(0.4 + math.pi * 0.04)

    def inside(p):
        x = np.clip(p[:, 0], -0.5, 0.5)
        return (p[:, 0] - x) ** 2 + p[:, 1] ** 2 <= 0.04
    area, j = mc_moment(inside, 0.7)
    assert cap.area == pytest.approx(area, rel=1e-2)
    assert cap.unit_moment == pytest.approx(j, rel=1e-2)
    # radius -> 0 recovers the segment, continuously
    assert Rod(1.0, radius=1e-6).unit_moment == pytest.approx(1 / 12, rel=1e-4)


@pytest.mark.parametrize("make, match", [
    (lambda: Disk(0.0), "radius"),
    (lambda: Disk(-1.0), "radius"),
    (lambda: Disk(float("nan")), "finite"),
    (lambda: Disk("a"), "number"),
    (lambda: Box(1.0, -2.0), "height"),
    (lambda: Box(0.0, 1.0), "width"),
    (lambda: Rod(-1.0), "length"),
    (lambda: Rod(1.0, radius=-0.1), "radius"),
    (lambda: Ellipse(1.0, 0.0), "b"),
    (lambda: Polygon([(0, 0), (1, 0)]), "at least 3"),
    (lambda: Polygon([(0, 0), (1, 0), (2, 0)]), "zero area|convex"),
    (lambda: Polygon([(0, 0), (2, 0), (1, 0.3), (2, 2), (0, 2)]), "convex"),
    (lambda: Polygon([(0, 0), (1, 0), (1, 0), (0, 1)]), "distinct"),
    (lambda: Polygon([(0, 0), (1, 0), (float("nan"), 1)]), "finite"),
    (lambda: Polygon([(0, 0), (2, 0), (0, 1), (2, 1)]), "convex|self-intersecting"),
])
def test_invalid_shapes(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def test_pentagram_is_rejected():
    k = np.arange(5)
    star = np.c_[np.cos(4 * np.pi * k / 5), np.sin(4 * np.pi * k / 5)]
    with pytest.raises(ValueError, match="self-intersecting|convex"):
        Polygon(star)


def test_scene_validation_and_defaults():
    scene = Scene2D(gravity=(0.0, -9.81))
    i = scene.add_body(Box(0.2, 0.4), 2.0, (0.0, 1.0))
    assert i == 0 and scene.bodies[0].moment == pytest.approx(2.0 * 0.2 / 12)
    j = scene.add_body(Disk(0.1), 1.0, (1.0, 1.0), moment=0.5)
    assert j == 1 and scene.bodies[1].moment == 0.5
    floor = scene.add_floor(0.25)
    assert floor.index == 0 and floor.offset == 0.25
    wall = scene.add_plane((2.0, 0.0), (-3.0, 0.0))
    assert wall.normal == (-1.0, 0.0) and wall.offset == -2.0
    for bad in (dict(mass=0.0), dict(moment=-1.0), dict(angle=float("inf")),
                dict(angular_velocity="x"), dict(position=(1.0,))):
        kw = dict(shape=Disk(0.1), mass=1.0, position=(0.0, 2.0))
        kw.update(bad)
        with pytest.raises(ValueError):
            scene.add_body(**kw)
    with pytest.raises(ValueError, match="shape"):
        scene.add_body("disk", 1.0, (0.0, 0.0))
    with pytest.raises(ValueError, match="non-zero"):
        scene.add_plane((0.0, 0.0), (0.0, 0.0))
    with pytest.raises(ValueError, match="finite"):
        Scene2D(gravity=(0.0, float("nan")))
