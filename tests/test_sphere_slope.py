"""A sphere sliding across a slope (issue 13: "sliding on a curved boundary", 3D): its slip
direction turns under gravity and friction, so the contact is integrated (pivot3d, one
contact at the sphere's centre) until the slip stops, and the sphere then rolls in closed
form.

Reference: the slip u of the contact point obeys ``du/dt = a e_s - k u/|u|`` with ``a = g
sin(theta)`` down the slope ``e_s`` and ``k = mu g cos(theta) (1 + m r^2 / I)``. With
``phi`` the angle from ``e_s`` to ``u`` and ``tau = tan(phi / 2)``, ``q = k / a``:
``|u| = (C / 2) tau^(q-1) (1 + tau^2)`` and ``t(tau) = t_0 + (C / 2a) [tau0^(q-1)/(q-1) +
tau0^(q+1)/(q+1) - tau^(q-1)/(q-1) - tau^(q+1)/(q+1)]`` with ``C = |u_0| sin(phi_0) /
tau_0^q`` (the classical sliding-puck-on-an-incline solution; for q > 1 the slip stops).
The trajectory is also checked against an independent integration of the Newton-Euler
equations with SciPy (solve_ivp, rtol 1e-12).
"""
import math

import numpy as np
import pytest

from rbimpact import Law, Scene3D, Simulation, Sphere

from _slope_helpers import slip_stop_time

G = 9.81


def _ramp(theta, r, v0, w0=(0.0, 0.0, 0.0), mu=0.3, law="kane_levinson"):
    """A sphere touching the plane through the origin tilted by theta about x (down-slope
    direction -y in the plane), started with velocity v0 and spin w0."""
    n = np.array([0.0, math.sin(theta), math.cos(theta)])
    scene = Scene3D(gravity=(0.0, 0.0, -G))
    scene.add_plane((0.0, 0.0, 0.0), tuple(n))
    scene.add_body(Sphere(r), mass=1.0, position=tuple(r * n), velocity=tuple(v0),
                   angular_velocity=tuple(w0))
    return Simulation(scene, Law(law, e=0.0, mu=mu)), n


def _frame(theta):
    n = np.array([0.0, math.sin(theta), math.cos(theta)])
    g = np.array([0.0, 0.0, -G])
    gt = g - (g @ n) * n
    es = gt / np.linalg.norm(gt)
    return n, es


def _stick_time(u0, theta, mu, eps):
    """Time at which the slip speed has fallen to ``eps`` (closed form above)."""
    n, es = _frame(theta)
    a = G * math.sin(theta)
    q = mu * G * math.cos(theta) * 3.5 / a
    return slip_stop_time(u0, es, a, q, eps), q


def _newton_euler(theta, r, mu, v0, w0, t_end):
    """SciPy reference: the sliding sphere (m = 1, I = 2/5 m r^2) until the slip stops."""
    from scipy.integrate import solve_ivp
    n, _ = _frame(theta)
    g = np.array([0.0, 0.0, -G])
    N = -(g @ n)                      # normal force per unit mass
    inv_i = 1.0 / (0.4 * r * r)
    arm = -r * n

    def slip(y):
        return y[3:6] + np.cross(y[6:9], arm)

    def f(t, y):
        u = slip(y)
        F = N * n - mu * N * u / np.linalg.norm(u)      # contact force per unit mass
        return np.concatenate([y[3:6], g + F, inv_i * np.cross(arm, F - N * n)])

    def stop(t, y):
        return np.linalg.norm(slip(y)) - 1e-6
    stop.terminal = True
    y0 = np.concatenate([r * n, v0, w0])
    return solve_ivp(f, (0.0, t_end), y0, rtol=1e-12, atol=1e-14, events=stop,
                     dense_output=True)


@pytest.mark.parametrize("theta, mu, v0", [
    (0.3, 0.3, (2.0, 0.0, 0.0)),                  # thrown straight across the slope
    (0.2, 0.5, (1.0, 0.4, -0.4 * math.tan(0.2))),  # across and up the slope
    (0.5, 0.4, (-0.7, -0.3, 0.3 * math.tan(0.5))),  # across and down
])
def test_slide_across_slope_stops_at_the_closed_form_time(theta, mu, v0):
    r = 0.1
    sim, n = _ramp(theta, r, v0, mu=mu)
    res = sim.run(1.5)
    assert res.status == "done"
    kinds = list(res.events["kind"])
    assert "pivot" in kinds and "stick" in kinds, kinds
    eps = sim.tolerances["slip_eps"]
    u0 = np.asarray(v0, float)          # no spin: the slip is the centre's velocity
    t_ref, q = _stick_time(u0, theta, mu, eps)
    assert q > 1.0
    t_stick = float(res.events["t"][kinds.index("stick")])
    assert t_stick == pytest.approx(t_ref, rel=1e-7, abs=1e-9)
    # then it rolls in closed form: acceleration 5/7 g sin(theta) down the slope
    assert kinds[kinds.index("stick") + 1] == "roll"
    _, es = _frame(theta)
    ts = np.array([t_stick + 0.2, t_stick + 0.7])
    v = res.sample(ts)["velocity"][:, 0]
    assert (v[1] - v[0]) @ es / 0.5 == pytest.approx(5.0 / 7.0 * G * math.sin(theta),
                                                     rel=1e-9)


@pytest.mark.parametrize("theta, mu, v0, w0", [
    (0.3, 0.3, (2.0, 0.0, 0.0), (0.0, 0.0, 0.0)),
    (0.25, 0.35, (1.2, 0.5, -0.5 * math.tan(0.25)), (3.0, -4.0, 2.0)),    # spinning
])
def test_slide_across_slope_agrees_with_newton_euler(theta, mu, v0, w0):
    r = 0.1
    n, _ = _frame(theta)
    v0 = np.asarray(v0, float)
    w0 = np.asarray(w0, float)
    sim, _ = _ramp(theta, r, v0, w0, mu=mu)
    res = sim.run(0.6)
    ref = _newton_euler(theta, r, mu, v0, w0, 0.6)
    t_stop = ref.t_events[0][0] if len(ref.t_events[0]) else 0.6
    kinds = list(res.events["kind"])
    if "stick" in kinds:
        assert float(res.events["t"][kinds.index("stick")]) == pytest.approx(t_stop, rel=1e-8)
    ts = np.linspace(0.0, t_stop, 9)[1:-1]
    s = res.sample(ts)
    y = ref.sol(ts)
    L = r
    V = np.linalg.norm(v0) + r * np.linalg.norm(w0) + math.sqrt(G * r)
    assert np.max(np.abs(s["position"][:, 0] - y[0:3].T)) < 1e-9 * L
    assert np.max(np.abs(s["velocity"][:, 0] - y[3:6].T)) < 1e-9 * V
    assert np.max(np.abs(s["angular_velocity"][:, 0] - y[6:9].T)) < 1e-9 * V / L


def test_weak_friction_keeps_sliding_and_turns_down_the_slope():
    """q = k / a < 1: friction cannot stop the slip; its direction tends to the slope's."""
    theta, mu, r = 0.6, 0.05, 0.1
    sim, n = _ramp(theta, r, (1.5, 0.0, 0.0), mu=mu)
    res = sim.run(2.0)
    assert res.status == "done"
    assert "stick" not in list(res.events["kind"])
    _, es = _frame(theta)
    ts = np.linspace(0.0, 2.0, 201)
    s = res.sample(ts)
    E = res.energy(ts)
    assert np.all(np.diff(E) <= 1e-12 * abs(E[0]) + 1e-15)      # friction only dissipates
    height = s["position"][:, 0] @ n - r
    assert np.max(np.abs(height)) < 1e-9 * r
    u = s["velocity"][-1, 0] + np.cross(s["angular_velocity"][-1, 0], -r * n)
    assert u @ es / np.linalg.norm(u) > 0.99


def test_energy_never_grows_and_the_sphere_stays_on_the_plane():
    theta, mu, r = 0.3, 0.3, 0.05
    sim, n = _ramp(theta, r, (0.8, 0.3, -0.3 * math.tan(0.3)), (10.0, 5.0, -3.0), mu=mu)
    res = sim.run(1.0)
    ts = np.linspace(0.0, 1.0, 401)
    E = res.energy(ts)
    assert np.all(np.diff(E) <= 1e-9 * abs(E[0]))
    h = res.sample(ts)["position"][:, 0] @ n - r
    assert np.max(np.abs(h)) < 1e-9 * r


def test_sphere_on_a_level_floor_compiles_no_integrated_contact():
    """Compile only what a scene uses: a sphere on a floor square to gravity cannot slide
    across a slope, so the integrated-contact handlers are not in its loop."""
    from rbimpact import kernels  # noqa: F401
    from rbimpact.kernels import stepper3d as k
    scene = Scene3D(gravity=(0.0, 0.0, -G))
    scene.add_floor()
    scene.add_body(Sphere(0.1), mass=1.0, position=(0.0, 0.0, 0.5))
    sim = Simulation(scene, Law("kane_levinson", e=0.5, mu=0.3))
    pivot = k.scene_features(sim._bint, sim._planes, sim._grav, len(sim._pairs))[0]
    assert pivot is None
    sim2, _ = _ramp(0.3, 0.1, (1.0, 0.0, 0.0))
    assert k.scene_features(sim2._bint, sim2._planes, sim2._grav, len(sim2._pairs))[0]
