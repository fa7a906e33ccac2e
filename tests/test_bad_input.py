"""Bad input gets a clear ValueError naming the argument and what is allowed (issue 13,
item 7): strings, ragged lists, complex numbers, None and booleans where numbers are
expected; law names that are not strings; counts beyond int64; states whose energy
overflows float64. Also the polygon's area, centroid and moment far from the origin
(item 3)."""
import math
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest

import rbimpact
from rbimpact import (Box, Box3D, Capsule, Disk, Ellipse, Law, Polygon, Rod, Scene2D,
                      Scene3D, Sphere)
from rbimpact._validate import (INT64_MAX, integer, real, real_array, vector,
                                scene_energy_check, validate_run_args, validate_tolerances)

W2 = [[2.5, -1.5], [-1.5, 2.5]]
NOT_NUMBERS = ["0.5", True, None, 1j, [0.5], np.array([0.5, 0.5]), b"1"]


def _raises(fn, *match):
    """``fn()`` raises ValueError whose message contains every string of ``match``;
    never a raw NumPy/Python message."""
    with pytest.raises(ValueError) as info:
        fn()
    msg = str(info.value)
    for m in match:
        assert m in msg, (m, msg)
    for raw in ("setting an array element", "could not convert", "float() argument",
                "too large to convert", "truth value of an array"):
        assert raw not in msg, msg
    return msg


# ---------------------------------------------------------------- the helpers

@pytest.mark.parametrize("bad", NOT_NUMBERS)
def test_real_refuses_what_is_not_a_real_number(bad):
    _raises(lambda: real("mass", bad, "kg"), "mass", "real number", "kg")


@pytest.mark.parametrize("good, expect", [(1, 1.0), (np.float32(0.5), 0.5), (np.int8(3), 3.0),
                                          (Fraction(1, 4), 0.25), (Decimal("0.5"), 0.5),
                                          (np.array(2.0), 2.0)])
def test_real_accepts_real_numbers(good, expect):
    assert real("x", good, "m") == expect


def test_real_refuses_non_finite_and_overflowing_values():
    for bad in (math.nan, math.inf, -math.inf, 10 ** 400, -(10 ** 400), Decimal("1e400")):
        _raises(lambda: real("t", bad, "s"), "t must be finite (s)")


@pytest.mark.parametrize("bad, why", [
    (["1", 2], "string"), ([True, 2.0], "boolean"), ([None, 1.0], "None"),
    ([1j, 2.0], "complex"), ([[1, 2], 3], "ragged"), ([[1.0], [1.0, 2.0]], "ragged"),
    (np.array([True, False]), "boolean"), (np.array(["1", "2"]), "string"),
    (np.array([1 + 0j, 2]), "complex"), ("12", "string"), (None, "None"),
    ([10 ** 400, 1], "too large")])
def test_vector_refuses_bad_elements_and_says_why(bad, why):
    _raises(lambda: vector("position", bad, 2, "(x, y)", "m"), "position",
            "2 real numbers (x, y) (m)", why)


def test_vector_accepts_mixed_numeric_types():
    v = vector("p", [1, np.float32(2.5)], 2, "(x, y)")
    assert v.dtype == np.float64 and v.tolist() == [1.0, 2.5]
    assert vector("p", (Fraction(1, 2), np.int64(3)), 2, "(x, y)").tolist() == [0.5, 3.0]
    assert vector("p", np.array([1, 2], dtype=object), 2, "(x, y)").tolist() == [1.0, 2.0]


def test_real_array_keeps_shape():
    a = real_array("W", [[1, 2], [3, 4]], "a 2x2 matrix")
    assert a.shape == (2, 2) and a.dtype == np.float64


@pytest.mark.parametrize("bad", [0, -1, 2 ** 63, 2 ** 70, 1e6, 1.5, True, "10", None, 1j])
def test_integer_refuses_non_integers_and_values_beyond_int64(bad):
    _raises(lambda: integer("max_events", bad), "max_events", "integer in [1, "
            f"{INT64_MAX}]")


def test_integer_limits():
    assert integer("n", INT64_MAX) == INT64_MAX
    assert integer("n", np.int32(5)) == 5
    assert integer("n", 1e5, integral_float=True) == 100000
    _raises(lambda: integer("n", 1e30, integral_float=True), "n must be an integer")
    _raises(lambda: integer("n", math.inf, integral_float=True), "n must be an integer")


# ---------------------------------------------------------------- shapes

@pytest.mark.parametrize("make, what", [
    (lambda x: Disk(x), "Disk: radius"), (lambda x: Box(x, 1.0), "Box: width"),
    (lambda x: Box(1.0, x), "Box: height"), (lambda x: Rod(x), "Rod: length"),
    (lambda x: Rod(1.0, radius=x), "Rod: radius"), (lambda x: Ellipse(x, 1.0), "Ellipse: a"),
    (lambda x: Ellipse(1.0, x), "Ellipse: b"), (lambda x: Sphere(x), "Sphere: radius"),
    (lambda x: Capsule(x, 0.1), "Capsule: length"),
    (lambda x: Capsule(1.0, x), "Capsule: radius")])
@pytest.mark.parametrize("bad", NOT_NUMBERS)
def test_shape_sizes_refuse_what_is_not_a_number(make, what, bad):
    _raises(lambda: make(bad), what, "real number", "(m)")


@pytest.mark.parametrize("bad, why", [
    ([("0", 0), (1, 0), (0, 1)], "string"), ([(0, 0), (1, 0), (0, None)], "None"),
    ([(0, 0), (True, 0), (0, 1)], "boolean"), ([(0, 0), (1j, 0), (0, 1)], "complex"),
    ([(0, 0), (1, 0), (0,)], "ragged"), ("abc", "string")])
def test_polygon_vertices_refuse_bad_elements(bad, why):
    _raises(lambda: Polygon(bad), "Polygon: vertices", "points (x, y)", why)


@pytest.mark.parametrize("bad, why", [
    ("abc", "string"), ([1, "2", 3], "string"), ([1, True, 1], "boolean"), (None, "None"),
    ([[1, 2], [3]], "ragged"), ([1, 2], "three edge lengths"), (1j, "complex")])
def test_box3d_size_refuses_bad_input(bad, why):
    _raises(lambda: Box3D(bad), "Box3D: size", why)


def test_shape_moment_and_inertia_take_a_real_mass():
    _raises(lambda: Disk(1.0).moment("2"), "mass", "kg")
    _raises(lambda: Sphere(1.0).inertia(True), "mass", "kg")
    assert Disk(2.0).moment(np.float32(1.0)) == 2.0


# ---------------------------------------------------------------- scenes

@pytest.mark.parametrize("kw, what", [
    (dict(mass="1"), "mass"), (dict(mass=True), "mass"), (dict(mass=None), "mass"),
    (dict(mass=1j), "mass"), (dict(position=("0", 1.0)), "position"),
    (dict(position=(True, 1.0)), "position"), (dict(position=[[0.0], [1.0, 2.0]]), "position"),
    (dict(position=None), "position"), (dict(angle="0"), "angle"), (dict(angle=1j), "angle"),
    (dict(angle=None), "angle"), (dict(velocity=(None, 0.0)), "velocity"),
    (dict(velocity=(0.0, 1j)), "velocity"), (dict(angular_velocity=True), "angular_velocity"),
    (dict(angular_velocity=[1.0]), "angular_velocity"), (dict(moment="1"), "moment")])
def test_scene2d_add_body_refuses_bad_numbers(kw, what):
    args = dict(mass=1.0, position=(0.0, 1.0))
    args.update(kw)
    scene = Scene2D()
    _raises(lambda: scene.add_body(Disk(0.1), **args), f"add_body: {what}")
    assert scene.bodies == []


@pytest.mark.parametrize("kw, what", [
    (dict(mass="1"), "mass"), (dict(mass=False), "mass"),
    (dict(position=(0.0, "0", 1.0)), "position"), (dict(position=(0.0, 1.0)), "position"),
    (dict(orientation=(1, 0, 0, "0")), "orientation"),
    (dict(orientation=(True, 0, 0, 0)), "orientation"),
    (dict(orientation=(1j, 0, 0, 0)), "orientation"),
    (dict(velocity=(0.0, None, 0.0)), "velocity"),
    (dict(angular_velocity=[[0.0, 1.0], [2.0]]), "angular_velocity"),
    (dict(inertia=[1.0, "1.0", 1.0]), "inertia"), (dict(inertia=True), "inertia"),
    (dict(inertia=[[1.0], [1.0, 1.0]]), "inertia")])
def test_scene3d_add_body_refuses_bad_numbers(kw, what):
    args = dict(mass=1.0, position=(0.0, 0.0, 1.0))
    args.update(kw)
    scene = Scene3D()
    _raises(lambda: scene.add_body(Sphere(0.1), **args), f"add_body: {what}")
    assert scene.bodies == []


def test_planes_floors_and_gravity_refuse_bad_numbers():
    s2, s3 = Scene2D(), Scene3D()
    _raises(lambda: s2.add_plane(("0", 0.0), (0.0, 1.0)), "add_plane: point", "string")
    _raises(lambda: s2.add_plane((0.0, 0.0), (0.0, True)), "add_plane: normal", "boolean")
    _raises(lambda: s2.add_plane((0.0, 0.0), (0.0, 1.0, 0.0)), "add_plane: normal")
    _raises(lambda: s3.add_plane((0.0, 0.0, 0.0), (0.0, 0.0, 1j)), "add_plane: normal")
    _raises(lambda: s3.add_plane([[0.0], [0.0, 0.0]], (0, 0, 1)), "add_plane: point", "ragged")
    _raises(lambda: s2.add_floor("0"), "add_floor: y", "string")
    _raises(lambda: s3.add_floor(None), "add_floor: z", "None")
    _raises(lambda: Scene2D(gravity=(0.0, "-9.81")), "Scene2D: gravity", "string")
    _raises(lambda: Scene3D(gravity=(0.0, 0.0, None)), "Scene3D: gravity", "None")
    assert s2.planes == [] and s3.planes == []


# ---------------------------------------------------------------- energy overflow

ENERGY = "energy is not representable"


def test_scene2d_refuses_a_state_whose_energy_overflows():
    scene = Scene2D()
    _raises(lambda: scene.add_body(Disk(0.1), 1.0, (0.0, 1.0), velocity=(0.0, -1e155)),
            "add_body", ENERGY, "kinetic")
    # |v|^2 overflows even though m |v|^2 / 2 would not, mathematically: the stepper
    # computes v.v first
    _raises(lambda: scene.add_body(Disk(0.1), 1e-20, (0.0, 1.0), velocity=(1e155, 0.0)),
            ENERGY)
    _raises(lambda: scene.add_body(Disk(0.1), 1.0, (0.0, 1.0), angular_velocity=1e160),
            ENERGY, "rotational")
    _raises(lambda: scene.add_body(Disk(0.1), 1e300, (0.0, 1e10)), ENERGY, "gravitational")
    assert scene.bodies == []
    scene.add_body(Disk(0.1), 1.0, (0.0, 1.0), velocity=(0.0, -1e153))      # representable
    scene.add_body(Disk(0.1), 1.0, (5.0, 1.0), velocity=(1.3e154, 0.0))    # 8.45e307 J
    scene.add_body(Disk(0.1), 1.0, (7.0, 1.0), velocity=(1.3e154, 0.0))
    # each body alone is finite, but the scene's energies sum to inf
    _raises(lambda: scene.add_body(Disk(0.1), 1.0, (9.0, 1.0), velocity=(1.3e154, 0.0)),
            ENERGY, "sum")
    assert len(scene.bodies) == 3


def test_scene3d_refuses_a_state_whose_energy_overflows():
    scene = Scene3D()
    _raises(lambda: scene.add_body(Sphere(0.1), 1.0, (0, 0, 1), velocity=(0, 0, -1e155)),
            ENERGY, "kinetic")
    _raises(lambda: scene.add_body(Box3D(0.1), 1.0, (0, 0, 1), angular_velocity=(0, 1e160, 0)),
            ENERGY, "rotational")
    assert scene.bodies == []
    scene.add_body(Sphere(0.1), 1.0, (0, 0, 1), velocity=(0, 0, -1e153))
    assert math.isfinite(scene_energy_check("Simulation3D", scene))


def test_scene_energy_check_catches_a_scene_changed_after_add_body():
    from dataclasses import replace
    scene = Scene2D()
    scene.add_body(Disk(0.1), 1.0, (0.0, 1.0))
    scene.bodies[0] = replace(scene.bodies[0], velocity=(1e200, 0.0))
    _raises(lambda: scene_energy_check("Simulation", scene), "Simulation: body 0", ENERGY)


# ---------------------------------------------------------------- laws

@pytest.mark.parametrize("name", [["routh"], ("routh",), None, 3, b"routh", {"routh": 1}])
def test_law_name_must_be_a_string_and_the_message_lists_the_laws(name):
    msg = _raises(lambda: Law(name, e=0.5), "law name must be a string")
    for known in rbimpact.LAWS:
        assert known in msg
    _raises(lambda: rbimpact.resolve(name, [-1.0, 0.0], W2, e=0.5), "kane_levinson")


@pytest.mark.parametrize("key", ["e", "mu", "e_t"])
@pytest.mark.parametrize("bad", NOT_NUMBERS)
def test_law_parameters_refuse_what_is_not_a_number(key, bad):
    params = {"e": 0.5, key: bad}
    _raises(lambda: Law("brach", **params), f"parameter {key!r}", "real number", "[")


@pytest.mark.parametrize("bad", [["newton"], np.array(["newton", "poisson"]), 2, None, True])
def test_routh_restitution_must_be_one_of_the_names(bad):
    _raises(lambda: Law("routh", e=0.5, restitution=bad), "restitution must be one of",
            "energetic")


def test_law_parameters_still_accept_numpy_and_fraction_scalars():
    law = Law("brach", e=np.float32(0.5), mu=Fraction(3, 10), e_t=np.int64(0))
    assert law.params_dict == {"e": 0.5, "mu": 0.3, "e_t": 0.0}


@pytest.mark.parametrize("v, W, what, why", [
    (["-1", 0.0], W2, "v must be", "string"), ([True, 0.0], W2, "v must be", "boolean"),
    ([None, 0.0], W2, "v must be", "None"), ([-1j, 0.0], W2, "v must be", "complex"),
    ([[-1.0], [0.0, 1.0]], W2, "v must be", "ragged"),
    ([-1.0, 0.0], [[2.5, -1.5], [-1.5]], "W must be", "ragged"),
    ([-1.0, 0.0], [[2.5, "-1.5"], [-1.5, 2.5]], "W must be", "string"),
    ([-1.0, 0.0], [[2.5, None], [-1.5, 2.5]], "W must be", "None"),
    ([-1.0, 0.0], [[True, 0.0], [0.0, True]], "W must be", "boolean"),
    ([-1.0, 0.0], np.array(W2) + 0j, "W must be", "complex"),
    ([-1.0, 0.0], [[10 ** 400, 0.0], [0.0, 1.0]], "W must be", "too large")])
def test_resolve_refuses_bad_contacts(v, W, what, why):
    _raises(lambda: rbimpact.resolve("kane_levinson", v, W, e=0.5, mu=0.3), what, why)
    _raises(lambda: Law("routh", e=0.5).resolve(v, W), what, why)


@pytest.mark.parametrize("d", [2, 3])
def test_resolve_refuses_a_contact_whose_energy_overflows(d):
    W = np.eye(d)
    v = np.zeros(d)
    v[0] = -1e155
    for name in rbimpact.LAWS:
        _raises(lambda: rbimpact.resolve(name, v, W, e=0.5), ENERGY, "v.W^-1 v")
    # a tiny W (a huge mass) makes the same speed's energy overflow too
    v[0] = -1e100
    _raises(lambda: rbimpact.resolve("smith", v, 1e-150 * W, e=0.5), ENERGY)
    v[0] = -1e153                                  # representable: resolved
    imp = rbimpact.resolve("routh", v, W, e=0.5)
    assert math.isfinite(imp.dE) and np.all(np.isfinite(imp.v_f))


# ---------------------------------------------------------------- Simulation / run

TOL = {"gap_tol": (1e-9, "m", ""), "zeno_speed": (None, "m/s", ""),
       "toi_max_iter": (100_000, "-", ""), "stall_events": (10_000, "-", "")}


def test_validate_run_args():
    assert validate_run_args(2, np.int32(5)) == (2.0, 5)
    assert validate_run_args(np.float32(0.5), INT64_MAX) == (0.5, INT64_MAX)
    for t in (0, -1.0, math.inf, math.nan, "1", None, True, 1j, 10 ** 400, [1.0]):
        _raises(lambda: validate_run_args(t, 10), "run: t_end")
    for n in (0, -3, 2 ** 63, 2 ** 70, 1e6, 1.5, "10", None, True, 1j):
        _raises(lambda: validate_run_args(1.0, n), "run: max_events", "integer in [1, ")


def test_validate_tolerances():
    assert validate_tolerances("Simulation", TOL, {}) == {
        "gap_tol": 1e-9, "zeno_speed": None, "toi_max_iter": 100_000, "stall_events": 10_000}
    tol = validate_tolerances("Simulation", TOL, {"zeno_speed": 0.01, "toi_max_iter": 1e3,
                                                  "gap_tol": np.float32(0.5)})
    assert tol["zeno_speed"] == 0.01 and tol["toi_max_iter"] == 1000
    assert type(tol["toi_max_iter"]) is int and tol["gap_tol"] == 0.5
    with pytest.raises(TypeError, match="unknown keyword 'gap_toll'.*gap_tol \\(m\\)"):
        validate_tolerances("Simulation", TOL, {"gap_toll": 1.0})
    for bad in ("1e-9", True, None, 1j, -1.0, math.inf, 10 ** 400, [1e-9]):
        _raises(lambda: validate_tolerances("Simulation", TOL, {"gap_tol": bad}),
                "Simulation: gap_tol", "(m)")
    for bad in (1e30, 2 ** 70, 0, 1.5, "10", True):
        _raises(lambda: validate_tolerances("Simulation3D", TOL, {"toi_max_iter": bad}),
                "Simulation3D: toi_max_iter", "integer")


@pytest.mark.parametrize("kw", [dict(toi_max_iter=2 ** 70), dict(toi_max_iter=1e30),
                                dict(gap_tol=10 ** 400)])
def test_simulation_keywords_beyond_float64_or_int64(kw):
    scene = Scene2D()
    scene.add_floor()
    scene.add_body(Disk(0.1), 1.0, (0.0, 1.0))
    _raises(lambda: rbimpact.Simulation(scene, Law("routh", e=0.5), **kw),
            "Simulation: " + next(iter(kw)))


@pytest.mark.parametrize("args", [(1.0, 2 ** 63), (1.0, 2 ** 70), (10 ** 400, 10)])
def test_simulation_run_arguments_beyond_int64_or_float64(args):
    scene = Scene2D()
    scene.add_floor()
    scene.add_body(Disk(0.1), 1.0, (0.0, 1.0))
    sim = rbimpact.Simulation(scene, Law("routh", e=0.5))
    _raises(lambda: sim.run(*args), "run: ")


# ---------------------------------------------------------------- polygon geometry (item 3)

def _square(s):
    h = 0.5 * s
    return np.array([(-h, -h), (h, -h), (h, h), (-h, h)])


def _exact_polygon(pts):
    """Area, centroid and unit moment (about the centroid) of the polygon whose vertices
    are exactly the given floats, in rational arithmetic."""
    q = [(Fraction(float(x)), Fraction(float(y))) for x, y in pts]
    A2 = Sx = Sy = J = Fraction(0)
    for (x0, y0), (x1, y1) in zip(q, q[1:] + q[:1]):
        c = x0 * y1 - x1 * y0
        A2 += c
        Sx += (x0 + x1) * c
        Sy += (y0 + y1) * c
        J += c * (x0 * x0 + x0 * x1 + x1 * x1 + y0 * y0 + y0 * y1 + y1 * y1)
    A = A2 / 2
    cx, cy = Sx / (6 * A), Sy / (6 * A)
    return A, (cx, cy), J / 12 / A - (cx * cx + cy * cy)


def test_small_square_far_from_the_origin_same_moment_as_centred():
    # side 2^-10 m (about 1 mm) at about 1e3 m (1024): every vertex is exact in float64,
    # so the far square is exactly the centred one, moved
    s, off = 2.0 ** -10, (1024.0, -1024.0)
    centred = Polygon(_square(s))
    far = Polygon(_square(s) + off)
    assert centred.unit_moment == pytest.approx(s * s / 6.0, rel=1e-15)
    assert far.unit_moment == pytest.approx(centred.unit_moment, rel=1e-12)
    assert far.area == pytest.approx(s * s, rel=1e-12)
    np.testing.assert_allclose(far.offset, off, rtol=0, atol=2e-13)
    np.testing.assert_allclose(far.vertices, centred.vertices, rtol=0, atol=1e-12 * s)


@pytest.mark.parametrize("offset", [(1e3, 0.0), (-3e4, 7e4), (1e6, 1e6)])
def test_small_polygon_far_from_the_origin_matches_exact_rational_geometry(offset):
    s = 1e-3
    for pts in (_square(s) + offset,
                np.array([(0.0, 0.0), (4e-3, 1e-3), (3e-3, 3e-3), (-1e-3, 2e-3)]) + offset):
        p = Polygon(pts)
        A, (cx, cy), unit = _exact_polygon(pts)
        assert p.unit_moment == pytest.approx(float(unit), rel=1e-12)
        assert p.area == pytest.approx(float(A), rel=1e-12)
        np.testing.assert_allclose(p.offset, [float(cx), float(cy)], rtol=0,
                                   atol=2 * np.spacing(max(map(abs, offset))))
        exact = np.array([[float(x - cx), float(y - cy)] for x, y in
                          ((Fraction(float(a)), Fraction(float(b))) for a, b in pts)])
        np.testing.assert_allclose(p.vertices, exact, rtol=0, atol=1e-12 * s)


def test_triangle_and_regular_polygon_closed_forms_anywhere():
    # a triangle with sides a, b, c: I / m = (a^2 + b^2 + c^2) / 36 about its centroid
    tri = np.array([(0.0, 0.0), (4e-3, 0.0), (0.0, 3e-3)])
    th = 0.7
    R = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    for off in ((0.0, 0.0), (2e3, -5e2), (1e5, 1e5)):
        p = Polygon(tri @ R.T + off)
        assert p.unit_moment == pytest.approx((9 + 16 + 25) * 1e-6 / 36.0, rel=1e-11)
        assert p.area == pytest.approx(6e-6, rel=1e-11)
        np.testing.assert_allclose(p.offset, np.array([4e-3, 3e-3]) / 3 @ R.T + off,
                                   rtol=0, atol=1e-11 + 4 * np.spacing(1e5))
    # a regular n-gon of circumradius r: I / m = r^2 (1 + 2 cos^2(pi/n)) / 6
    for n in (3, 5, 6, 17):
        r = 2e-3
        a = 2 * math.pi * np.arange(n) / n + 0.3
        pts = r * np.column_stack([np.cos(a), np.sin(a)])
        exact = r * r * (1 + 2 * math.cos(math.pi / n) ** 2) / 6.0
        for off in ((0.0, 0.0), (1e3, 2e3)):
            p = Polygon(pts + off)
            assert p.unit_moment == pytest.approx(exact, rel=1e-11), (n, off)
            assert p.area == pytest.approx(0.5 * n * r * r * math.sin(2 * math.pi / n),
                                           rel=1e-11)


def test_far_polygon_orientation_and_convexity_are_judged_relative():
    s = 1e-3
    cw = Polygon((_square(s) + (1e5, 0.0))[::-1])        # clockwise: reversed, same body
    assert cw.unit_moment == pytest.approx(s * s / 6.0, rel=1e-12)
    with pytest.raises(ValueError, match="convex"):
        Polygon(np.array([(0, 0), (2, 0), (1, 0.3), (2, 2), (0, 2)]) * 1e-3 + (1e4, 0))


def test_huge_or_tiny_quaternions_and_normals_are_normalised_not_zeroed():
    s3 = Scene3D()
    for scale in (1e200, 1e-200, 1.0):
        i = s3.add_body(Sphere(0.1), 1.0, (0.0, 0.0, 1.0), orientation=(scale, 0, 0, scale))
        np.testing.assert_allclose(s3.bodies[i].orientation, (0.5 ** 0.5, 0, 0, 0.5 ** 0.5),
                                   rtol=1e-15)
        plane = s3.add_plane((0.0, 0.0, 0.0), (0.0, 0.0, scale))
        assert plane.normal == (0.0, 0.0, 1.0)
        s2 = Scene2D()
        assert s2.add_plane((0.0, 0.0), (0.0, scale)).normal == (0.0, 1.0)
    _raises(lambda: s3.add_body(Sphere(0.1), 1.0, (0, 0, 1), orientation=(0, 0, 0, 0)),
            "orientation", "non-zero")
    _raises(lambda: s3.add_plane((0, 0, 0), (0, 0, 0)), "add_plane: normal must be non-zero")


def test_sizes_whose_area_volume_or_moment_overflow_are_refused():
    for make in (lambda x: Disk(x), lambda x: Box(x, 1.0), lambda x: Rod(x),
                 lambda x: Ellipse(1.0, x), lambda x: Sphere(x), lambda x: Box3D(x),
                 lambda x: Capsule(1.0, x)):
        for bad in (1e160, 1e-170):
            _raises(lambda: make(bad), "between 1e-100 and 1e+100 m")
    assert Rod(1.0, radius=0.0).radius == 0.0
    _raises(lambda: Rod(1.0, radius=1e-120), "must be 0 or between")
    for k in (1e160, 1e-170):
        _raises(lambda: Polygon(np.array([(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]) * k),
                "Polygon: the polygon's size", "between 1e-100 and 1e+100 m")
    # a representable shape with a mass too large for its moment
    _raises(lambda: Scene2D().add_body(Disk(1e100), 1e200, (0.0, 2e100)),
            "add_body: the moment of inertia", "overflows")
    _raises(lambda: Scene3D().add_body(Sphere(1e100), 1e200, (0.0, 0.0, 2e100)),
            "add_body: the moments of inertia", "overflow")


def test_masses_and_moments_must_have_finite_inverses():
    _raises(lambda: Scene2D().add_body(Disk(0.1), 1e-310, (0.0, 1.0)), "mass", "too small",
            "inverse")
    _raises(lambda: Scene2D().add_body(Disk(0.1), 1.0, (0.0, 1.0), moment=1e-310),
            "moment of inertia", "too small")
    _raises(lambda: Scene2D().add_body(Disk(1e-100), 1e-200, (0.0, 1.0)), "underflows")
    _raises(lambda: Scene3D().add_body(Sphere(0.1), 5e-324, (0.0, 0.0, 1.0)), "mass")
    _raises(lambda: Scene3D().add_body(Sphere(0.1), 1.0, (0.0, 0.0, 1.0), inertia=1e-310),
            "principal moment I_1", "too small")
    _raises(lambda: Scene3D().add_body(Sphere(1e-100), 1e-200, (0.0, 0.0, 1.0)), "underflow")
    Scene2D().add_body(Disk(1e-50), 1e-200, (0.0, 1.0))          # tiny but representable
