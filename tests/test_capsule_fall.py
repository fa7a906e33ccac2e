"""A thin capsule landing plastically on one end and falling over (3D stepper, integrated
contact of one cap on the floor).

``Capsule(1.0, 0.02)`` (length 1 m between the cap centres, radius 0.02 m, 1 kg), tilted
by 0.3-1.0 rad about a horizontal axis, dropped from a centre height of 0.5 m onto the
floor, Kane & Levinson e = 0, mu = 1. The lower cap lands plastically and sticks (it rolls
on the floor without slipping: event "pivot"); the capsule falls over; its friction force
reaches the cone and the end starts to slip forward (event "slide"); the upper cap lands
and the capsule comes to rest lying on the floor.

mu = 1 is below this capsule's Painleve threshold (about 4/3, as for the uniform rod), so
a consistent stick/slip/lift-off state always exists. The run used to stop at the slip
onset with "no consistent stick/slip/lift-off state": ``stepper3d._pv_slide`` scans
the slip directions from the onset direction phi0, whose root it then missed (a zero at the
bracket's start bisected away from it; the closing angle phi0 + 2 pi re-evaluated with the
other sign by round-off). The sticking and sliding phases are checked here against an
independent planar solve (scipy ``solve_ivp``) of the capsule with a rolling, then sliding,
hemispherical end.
"""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rbimpact import Law
from rbimpact.scene3d import Scene3D
from rbimpact.shapes3d import Capsule
from rbimpact.simulation3d import Simulation3D

LENGTH = 1.0        # m, between the cap centres
RADIUS = 0.02       # m
MASS = 1.0          # kg
G = 9.81            # m/s^2
MU = 1.0
Z0 = 0.5            # m, initial centre height
H = 0.5 * LENGTH    # m, centre of mass to cap centre
T_END = 3.0         # s
E_SCALE = MASS * G * Z0     # J, the scene's energy scale
I_T = Capsule(LENGTH, RADIUS).inertia(MASS)[0]   # kg m^2, about a transverse axis

TILTS = (0.3, 0.65, 1.0)
POLICIES = ("simultaneous", "sequential")
#: tilt axes in the floor plane: the y axis (a planar fall in the x-z plane, where the
#: onset's scan function is exactly zero: these runs failed before the fix) and an oblique
#: one (zero up to round-off, whose sign happened to let these runs pass before the fix)
AXES = (0.0, 0.61)


def scene(tilt, axis_angle=0.0):
    """The capsule (axis along body z) tilted by ``tilt`` (rad) about the horizontal axis
    at ``axis_angle`` (rad) from the y axis, centre at height Z0, at rest."""
    ax = (math.sin(axis_angle), math.cos(axis_angle), 0.0)
    s = math.sin(0.5 * tilt)
    sc = Scene3D(gravity=(0.0, 0.0, -G))
    sc.add_floor()
    sc.add_body(Capsule(LENGTH, RADIUS), MASS, (0.0, 0.0, Z0),
                orientation=(math.cos(0.5 * tilt), s * ax[0], s * ax[1], s * ax[2]))
    return sc


_RUNS = {}


def run(tilt, policy="simultaneous", axis_angle=0.0):
    key = (tilt, policy, axis_angle)
    if key not in _RUNS:
        sim = Simulation3D(scene(tilt, axis_angle), Law("kane_levinson", e=0.0, mu=MU),
                           policy=policy)
        _RUNS[key] = (sim, sim.run(T_END))
    return _RUNS[key]


def body_axis(q):
    """World direction of the body z axis (the capsule's axis) for quaternions (..., 4)."""
    w, x, y, z = np.moveaxis(np.asarray(q), -1, 0)
    return np.stack([2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)], -1)


def test_mu_is_below_the_painleve_threshold():
    """The sliding end has a consistent force for every angle: mu = 1 is below the
    capsule's Painleve threshold ``min W_NN / |W_NT|`` (contact point RADIUS below the cap
    centre, tests/test_painleve.py), about 4/3 as for the uniform rod (Stewart 2000)."""
    th = np.linspace(1e-3, 0.5 * math.pi - 1e-3, 20001)      # axis angle from vertical
    rx = -H * np.sin(th)
    rz = -H * np.cos(th) - RADIUS
    w_nn = 1.0 / MASS + rx * rx / I_T
    w_nt = np.abs(rx * rz) / I_T
    mu_p = (w_nn / w_nt).min()
    assert 1.25 < mu_p < 1.4
    assert MU < mu_p


@pytest.mark.parametrize("axis_angle", AXES)
@pytest.mark.parametrize("policy", POLICIES)
@pytest.mark.parametrize("tilt", TILTS)
def test_capsule_falls_over_and_comes_to_rest(tilt, policy, axis_angle):
    """The run ends 'done': the end sticks, then slips, the capsule lands flat and rests;
    no point below the floor by more than gap_tol; the energy (rotation integrated by the
    result's sampler) never rises by more than 1e-9 of m g z0; it ends lying at rest."""
    sim, res = run(tilt, policy, axis_angle)
    assert res.status == "done"
    kinds = list(res.events["kind"])
    assert "painleve" not in kinds
    ip, isl = kinds.index("pivot"), kinds.index("slide")
    assert kinds[0] == "impact" and ip < isl
    assert kinds[-1] == "rest"
    ev_t = res.events["t"]
    t = np.unique(np.concatenate([np.linspace(0.0, T_END, 3001), ev_t,
                                  np.linspace(ev_t[isl] - 1e-3, ev_t[isl] + 1e-3, 41)]))
    s = res.sample(t)
    pos = s["position"][:, 0]
    a = body_axis(s["orientation"][:, 0])
    low = np.minimum(pos[:, 2] - H * a[:, 2], pos[:, 2] + H * a[:, 2]) - RADIUS
    assert low.min() >= -sim.tolerances["gap_tol"]
    e = res.energy(t)
    assert np.diff(e).max() <= 1e-9 * E_SCALE
    assert e[-1] < e[0]
    # at rest lying on the floor: centre at RADIUS, axis horizontal
    assert abs(pos[-1, 2] - RADIUS) <= sim.tolerances["gap_tol"]
    assert abs(a[-1, 2]) <= 1e-9
    assert np.abs(s["velocity"][-1, 0]).max() == 0.0
    assert np.abs(s["angular_velocity"][-1, 0]).max() == 0.0
    np.testing.assert_allclose(e[-1], MASS * G * RADIUS, rtol=0, atol=1e-9 * E_SCALE)


# ------------------------------------------------------------ the independent planar solve
# theta: angle of the axis (lower cap centre -> centre of mass) from the vertical, in the
# plane of the fall; the lower cap centre stays at height RADIUS; its contact point is
# RADIUS below it, arm r = (-H sin th - ..., -H cos th - RADIUS) from the centre of mass.


def stick_accel(th, om):
    """The cap rolling without slipping (sticking contact point): the cap centre moves by
    RADIUS dtheta, so x_c = RADIUS th + H sin th, z_c = RADIUS + H cos th (one degree of
    freedom, Lagrange). Returns (theta'', friction force F (N, along the fall), normal
    force N (N))."""
    s, c = math.sin(th), math.cos(th)
    M = MASS * (RADIUS ** 2 + 2 * RADIUS * H * c + H * H) + I_T
    al = (MASS * G * H * s + MASS * RADIUS * H * s * om * om) / M
    F = MASS * ((RADIUS + H * c) * al - H * s * om * om)
    N = MASS * G - MASS * H * (c * om * om + s * al)
    return al, F, N


def slide_rhs(t, y):
    """The end sliding (Coulomb, mu MU) with the cap centre at height RADIUS: state
    (x_c, th, vx_c, om); the normal force from the vertical constraint."""
    xc, th, vx, om = y
    s, c = math.sin(th), math.cos(th)
    vp = vx - om * (H * c + RADIUS)         # slip velocity of the contact point along x
    sg = 1.0 if vp >= 0.0 else -1.0
    k = (H * c + RADIUS) * MU * sg + H * s  # torque about y per unit normal force (m)
    N = (MASS * G - MASS * H * c * om * om) / (1.0 + MASS * H * s * k / I_T)
    return [vx, om, -MU * N * sg / MASS, N * k / I_T]


def fall_angle(q, axis_angle):
    """Angle of the capsule's axis from the vertical, measured in the plane of the fall
    (tilting about the axis at axis_angle from y towards +x rotated by axis_angle)."""
    a = body_axis(q)
    hx = a[..., 0] * math.cos(axis_angle) - a[..., 1] * math.sin(axis_angle)
    return np.arctan2(hx, a[..., 2])


@pytest.mark.parametrize("axis_angle", AXES)
@pytest.mark.parametrize("tilt", TILTS)
def test_stick_then_slip_against_an_independent_solve(tilt, axis_angle):
    """From the state just after the landing ("pivot"), the end sticks until
    |F| = mu N (the independent solve, ``stick_accel``, locates that instant and angle:
    the run's "slide" event agrees to 1e-8 s and 1e-8 rad); the end then slides forward,
    along +x of the fall (the friction force pointed backwards), and the slide (state on
    a grid, and the instant the upper cap lands, the axis horizontal) agrees with
    ``slide_rhs`` to 1e-8."""
    sim, res = run(tilt, "simultaneous", axis_angle)
    ev = res.events
    kinds = list(ev["kind"])
    tp = ev["t"][kinds.index("pivot")]
    ts = ev["t"][kinds.index("slide")]
    later = (ev["kind"] == "impact") & (ev["t"] > ts)
    tl = ev["t"][later][0]
    ca, sa = math.cos(axis_angle), math.sin(axis_angle)
    # sticking phase
    s0 = res.sample([tp])
    th0 = float(fall_angle(s0["orientation"][0, 0], axis_angle))
    w = s0["angular_velocity"][0, 0]
    om0 = w[0] * sa + w[1] * ca              # about the tilt axis (sin, cos, 0)
    assert th0 == pytest.approx(tilt, abs=1e-9)

    def onset(t, y):
        al, F, N = stick_accel(y[0], y[1])
        return MU * N - abs(F)
    onset.terminal = True
    sol = solve_ivp(lambda t, y: [y[1], stick_accel(y[0], y[1])[0]], (tp, tp + 2.0),
                    [th0, om0], events=onset, rtol=1e-12, atol=1e-12)
    t_on, th_on = sol.t_events[0][0], sol.y_events[0][0][0]
    al, F, N = stick_accel(*sol.y_events[0][0])
    assert F < 0.0 < N                   # friction pulls backwards: the end slips forward
    assert ts == pytest.approx(t_on, abs=1e-8)
    s1 = res.sample([ts])
    assert float(fall_angle(s1["orientation"][0, 0], axis_angle)) == pytest.approx(
        th_on, abs=1e-8)
    # sliding phase
    tt = np.linspace(ts, tl, 200)[1:-1]
    s2 = res.sample(tt)
    p1 = s1["position"][0, 0]
    v1 = s1["velocity"][0, 0]
    w1 = s1["angular_velocity"][0, 0]
    y0 = [0.0, float(fall_angle(s1["orientation"][0, 0], axis_angle)),
          v1[0] * ca - v1[1] * sa, w1[0] * sa + w1[1] * ca]

    def flat(t, y):
        return y[1] - 0.5 * math.pi
    flat.terminal = True
    sol = solve_ivp(slide_rhs, (ts, ts + 2.0), y0, events=flat, rtol=1e-12, atol=1e-13,
                    dense_output=True)
    assert tl == pytest.approx(sol.t_events[0][0], abs=1e-8)
    ref = sol.sol(tt)
    pos = s2["position"][:, 0]
    xc = (pos[:, 0] - p1[0]) * ca - (pos[:, 1] - p1[1]) * sa
    th = fall_angle(s2["orientation"][:, 0], axis_angle)
    np.testing.assert_allclose(th, ref[1], rtol=0, atol=1e-8)
    np.testing.assert_allclose(xc, ref[0], rtol=0, atol=1e-8)
    np.testing.assert_allclose(pos[:, 2], RADIUS + H * np.cos(th), rtol=0, atol=1e-9)
    vel = s2["velocity"][:, 0]
    om = s2["angular_velocity"][:, 0, 0] * sa + s2["angular_velocity"][:, 0, 1] * ca
    slip = vel[:, 0] * ca - vel[:, 1] * sa - om * (H * np.cos(th) + RADIUS)
    assert slip.min() > 0.0              # forward, all the way to the landing
