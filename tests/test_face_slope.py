"""A box on a face, or a capsule on its side, thrown across a slope (issue 13: the face
slide's curving slip, 3D): without spin the body slides as a puck, ``dv/dt = a e_s - k
v/|v|`` with ``a = g sin(theta)`` down the slope ``e_s`` and ``k = mu g cos(theta)`` (the
pressure centre moves along the slip, so friction has no moment about the normal and no
spin starts). Its slip direction turns, so the face's features are held and the motion
integrated (``stepper3d._integrate_slide``, ``pivot3d``) until the slip stops; the body then
rests (mu > tan(theta)) or slides on for ever turning down the slope.

Reference: the closed-form sliding-puck-on-an-incline solution (the same as
``tests/test_sphere_slope.py`` with the sphere's rolling factor 1 + m r^2 / I replaced by 1)
and an independent SciPy integration of the puck (solve_ivp, rtol 1e-12).
"""
import math

import numpy as np
import pytest

from rbimpact import Box3D, Capsule, Law, Scene3D, Simulation

from _slope_helpers import slip_stop_time

G = 9.81


def _qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)


def _slope(theta, shape, v0, mu):
    """The plane through the origin tilted by theta about x (down-slope direction +y in
    the plane, normal n) and a body lying on it at rest on a face (box 0.2 x 0.1 x 0.06 m)
    or on its side (capsule of length 0.3 m, radius 0.03 m, axis along x), started with
    velocity v0 along the plane and no spin."""
    n = np.array([0.0, math.sin(theta), math.cos(theta)])
    scene = Scene3D(gravity=(0.0, 0.0, -G))
    scene.add_plane((0.0, 0.0, 0.0), tuple(n))
    tilt = (math.cos(theta / 2), -math.sin(theta / 2), 0.0, 0.0)      # body z -> n
    if shape == "box":
        body, h, q = Box3D((0.2, 0.1, 0.06)), 0.03, tilt
    else:
        body, h = Capsule(0.3, 0.03), 0.03
        q = _qmul(tilt, (math.cos(math.pi / 4), 0.0, math.sin(math.pi / 4), 0.0))
    scene.add_body(body, mass=1.0, position=tuple(h * n), orientation=q,
                   velocity=tuple(v0))
    return Simulation(scene, Law("kane_levinson", e=0.0, mu=mu)), n, h


def _down(theta):
    n = np.array([0.0, math.sin(theta), math.cos(theta)])
    g = np.array([0.0, 0.0, -G])
    gt = g - (g @ n) * n
    return gt / np.linalg.norm(gt)


def _stick_time(v0, theta, mu, eps):
    """Time at which the puck's speed has fallen to ``eps`` (``_slope_helpers``, with the
    sphere's rolling factor replaced by 1: ``q = mu / tan(theta)``)."""
    q = mu / math.tan(theta)
    return slip_stop_time(v0, _down(theta), G * math.sin(theta), q, eps), q


def _puck(theta, mu, x0, v0, t_end):
    """SciPy reference: the puck's centre until its speed falls to 1e-6 m/s."""
    from scipy.integrate import solve_ivp
    n = np.array([0.0, math.sin(theta), math.cos(theta)])
    g = np.array([0.0, 0.0, -G])
    N = -(g @ n)

    def f(t, y):
        v = y[3:6]
        return np.concatenate([v, g + N * n - mu * N * v / np.linalg.norm(v)])

    def stop(t, y):
        return np.linalg.norm(y[3:6]) - 1e-6
    stop.terminal = True
    return solve_ivp(f, (0.0, t_end), np.concatenate([x0, v0]), rtol=1e-12, atol=1e-14,
                     events=stop, dense_output=True)


CASES = [
    ("box", 0.3, 0.5, (1.0, 0.0, 0.0)),                              # straight across
    ("box", 0.2, 0.6, (0.8, -0.5, 0.5 * math.tan(0.2))),            # across and up
    ("box", 0.4, 0.55, (-0.6, 0.3, -0.3 * math.tan(0.4))),          # across and down
]


@pytest.mark.parametrize("shape, theta, mu, v0", CASES)
def test_slide_across_slope_stops_at_the_closed_form_time_and_rests(shape, theta, mu, v0):
    sim, n, h = _slope(theta, shape, v0, mu)
    res = sim.run(1.5)
    assert res.status == "done"
    kinds = list(res.events["kind"])
    assert "pivot" in kinds and kinds[-1] == "rest", kinds
    v0 = np.asarray(v0, float)
    t_ref, q = _stick_time(v0, theta, mu, sim.tolerances["slip_eps"])
    assert q > 1.0
    t_stick = float(res.events["t"][kinds.index("stick")])
    assert t_stick == pytest.approx(t_ref, rel=1e-7, abs=1e-9)
    ts = np.linspace(0.0, 1.5, 301)
    s = res.sample(ts)
    # on the plane, not turning (a puck), at rest after the stick, no energy created
    assert np.max(np.abs(s["position"][:, 0] @ n - h)) < 1e-9 * h
    V = np.linalg.norm(v0) + math.sqrt(G * h)
    assert np.max(np.abs(s["angular_velocity"][:, 0])) < 1e-9 * V / h
    after = ts > t_stick
    assert np.ptp(s["position"][after, 0], axis=0).max() == 0.0
    E = res.energy(ts)
    assert np.all(np.diff(E) <= 1e-12 * abs(E[0]))


@pytest.mark.parametrize("shape, theta, mu, v0", CASES)
def test_slide_across_slope_agrees_with_the_puck(shape, theta, mu, v0):
    sim, n, h = _slope(theta, shape, v0, mu)
    res = sim.run(0.6)
    v0 = np.asarray(v0, float)
    ref = _puck(theta, mu, h * n, v0, 0.6)
    t_stop = ref.t_events[0][0] if len(ref.t_events[0]) else 0.6
    ts = np.linspace(0.0, t_stop, 9)[1:-1]
    s = res.sample(ts)
    y = ref.sol(ts)
    V = np.linalg.norm(v0) + math.sqrt(G * h)
    assert np.max(np.abs(s["position"][:, 0] - y[0:3].T)) < 1e-9 * h
    assert np.max(np.abs(s["velocity"][:, 0] - y[3:6].T)) < 1e-9 * V


def test_weak_friction_slides_on_and_turns_down_the_slope():
    """q = mu / tan(theta) < 1: friction cannot stop the slip; its direction tends to the
    slope's, the box stays flat on its face."""
    theta, mu = 0.5, 0.1
    sim, n, h = _slope(theta, "box", (1.5, 0.0, 0.0), mu)
    res = sim.run(1.0)
    assert res.status == "done"
    assert "stick" not in list(res.events["kind"])
    ts = np.linspace(0.0, 1.0, 201)
    s = res.sample(ts)
    assert np.max(np.abs(s["position"][:, 0] @ n - h)) < 1e-9 * h
    E = res.energy(ts)
    assert np.all(np.diff(E) <= 1e-12 * abs(E[0]))
    v = s["velocity"][-1, 0]
    assert v @ _down(theta) / np.linalg.norm(v) > 0.9


def test_capsule_slides_along_its_axis_then_rolls_down_the_slope():
    """A capsule on its side thrown along its axis across the slope: its slip turns down
    the slope, friction then turns it about its axis, and once both caps stick it rolls
    straight down, its axis fixed, with ``a = g sin(theta) / (1 + I_a / (m r^2))`` (I_a:
    the moment about the axis of a cylinder and two hemispheres of one density)."""
    theta, mu, L, r = 0.25, 0.5, 0.3, 0.03
    sim, n, h = _slope(theta, "capsule", (1.2, 0.0, 0.0), mu)
    res = sim.run(1.0)
    assert res.status == "done"
    kinds = list(res.events["kind"])
    assert "pivot" in kinds and "stick" in kinds, kinds
    t_stick = float(res.events["t"][kinds.index("stick")])
    ts = np.linspace(0.0, 1.0, 401)
    s = res.sample(ts)
    assert np.max(np.abs(s["position"][:, 0] @ n - r)) < 1e-9 * r
    E = res.energy(ts)
    assert np.all(np.diff(E) <= 1e-9 * abs(E[0]))
    vc, vs = math.pi * r * r * L, 4.0 / 3.0 * math.pi * r ** 3
    Ia = (vc / (vc + vs)) * r * r / 2 + (vs / (vc + vs)) * 0.4 * r * r      # m = 1 kg
    # rolling: the axis keeps the direction it had when the caps stuck (friction turned
    # it a little while the capsule slid and rolled at once)
    axis = s["orientation"][:, 0]
    late = ts > t_stick
    w, x, y, z = axis[late].T
    ax = np.stack([2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)], 1)
    assert np.ptp(ax, axis=0).max() < 1e-8     # (integrated: about 40 rad of rolling)
    ep = np.cross(n, ax[0])                 # rolling direction, in the plane across the axis
    es = _down(theta)
    ep *= np.sign(ep @ es)
    t1, t2 = t_stick + 0.1 * (1 - t_stick), 1.0
    v = res.sample([t1, t2])["velocity"][:, 0]
    assert (v[1] - v[0]) @ ep / (t2 - t1) == pytest.approx(
        G * math.sin(theta) * (es @ ep) / (1 + Ia / (r * r)), rel=1e-9)
    assert abs((v[1] - v[0]) @ ax[0]) < 1e-8 * np.linalg.norm(v[1])  # not along its axis


def _capsule_axis_moment(L, r):
    """Moment (kg m^2) about its axis of a 1 kg capsule (cylinder of length L and two
    hemispheres of radius r, one density): ``m_c r^2 / 2 + m_s 2 r^2 / 5``."""
    vc, vs = math.pi * r * r * L, 4.0 / 3.0 * math.pi * r ** 3
    return (vc / (vc + vs)) * r * r / 2 + (vs / (vc + vs)) * 0.4 * r * r


def test_capsule_thrown_across_its_axis_slides_then_rolls():
    """On a level floor, thrown across its axis without spin: friction spins it up about the
    axis until the contact line sticks; its angular momentum about the contact line is
    kept, so it then rolls at ``v0 / (1 + I_a / (m r^2))`` (it used to stop the run: "a
    capsule on its side sliding across its axis ... is not supported")."""
    L, r, v0, mu = 0.3, 0.03, 1.0, 0.4
    sim, n, h = _slope(0.0, "capsule", (0.0, v0, 0.0), mu)
    res = sim.run(1.0)
    assert res.status == "done"
    kinds = list(res.events["kind"])
    assert "pivot" in kinds and "stick" in kinds, kinds
    t_stick = float(res.events["t"][kinds.index("stick")])
    Ia = _capsule_axis_moment(L, r)
    # sliding: the slip v - w r falls at mu g (1 + m r^2 / I_a) and sticks at slip_eps
    v_f = v0 / (1.0 + Ia / (r * r))
    eps = sim.tolerances["slip_eps"]
    assert t_stick == pytest.approx((v0 - eps) / (mu * G * (1 + r * r / Ia)), rel=1e-9)
    s = res.sample([0.5, 1.0])
    assert s["velocity"][:, 0, 1] == pytest.approx([v_f, v_f], rel=1e-8)
    assert np.max(np.abs(s["position"][:, 0] @ n - r)) < 1e-9 * r
    assert res.energy([0.0, 1.0])[1] < res.energy([0.0, 1.0])[0]


def test_capsule_at_rest_across_a_slope_rolls_down():
    """Laid on a slope with its axis level (across the fall line), at rest: it rolls down
    with ``a = g sin(theta) / (1 + I_a / (m r^2))`` (friction mu = 0.5 > the rolling need)."""
    theta, L, r = 0.2, 0.3, 0.03
    sim, n, h = _slope(theta, "capsule", (0.0, 0.0, 0.0), 0.5)
    res = sim.run(0.5)
    assert res.status == "done"
    es = _down(theta)
    v = res.sample([0.1, 0.5])["velocity"][:, 0]
    a = (v[1] - v[0]) @ es / 0.4
    assert a == pytest.approx(G * math.sin(theta) / (1 + _capsule_axis_moment(L, r) / (r * r)),
                              rel=1e-8)
    assert abs(v[1][0]) < 1e-9 * np.linalg.norm(v[1])      # straight down, axis level
