"""The Painleve paradox and the impact without collision (issue 13 item 4).

A uniform rod (length 2 l, mass m, I = m l^2 / 3) whose lower end slides on a rough floor
at an angle theta from the horizontal, the lower end leading: the normal acceleration of
the end under a normal force lam is ``b + (W_NN - mu W_NT s) lam`` with
``W_NN = (1 + 3 cos^2 theta) / m`` and ``|W_NT| = 3 sin theta cos theta / m``, so no
consistent contact force exists once

    mu > mu_P(theta) = (1 + 3 cos^2 theta) / (3 sin theta cos theta)

(Painleve 1895; the minimum 4/3 at tan theta = 2; e.g. Stewart, SIAM Review 42 (2000) 3,
section 3.2). ``painleve="error"`` refuses exactly there; ``painleve="impact"`` (the
default) resolves it by an impact without collision: Darboux-Keller's integration in the
normal impulse from v_N = 0 (Genot & Brogliato 1999), checked here against its closed form
for the rod.
"""
import math

import numpy as np
import pytest

from rbimpact import Capsule, Law, Rod, Scene2D, Scene3D, Simulation
from rbimpact.errors import SimulationError

L_HALF = 0.5
MASS = 2.0
G = 9.81


def mu_p(theta):
    """Painleve's threshold of the uniform rod (closed form, module docstring)."""
    c, s = math.cos(theta), math.sin(theta)
    return (1.0 + 3.0 * c * c) / (3.0 * s * c)


def rod_scene(theta, vx, drop=0.0):
    """Rod tilted by theta (centre right of and above its lower end), lower end ``drop``
    (m) above the floor (0: on it, the persistent contact starts at t = 0), sliding at vx
    (m/s; negative: the lower end leads)."""
    scene = Scene2D(gravity=(0.0, -G))
    scene.add_floor(0.0)
    y = L_HALF * math.sin(theta) + drop
    scene.add_body(Rod(2 * L_HALF), MASS, (0.0, y), angle=theta, velocity=(vx, 0.0))
    return scene


def first_persistent(theta, mu, painleve, vx=-1.0, drop=0.0):
    sim = Simulation(rod_scene(theta, vx, drop), Law("kane_levinson", e=0.0, mu=mu),
                     painleve=painleve)
    try:
        res = sim.run(0.05)
    except SimulationError as exc:
        res = exc.result
    return res


@pytest.mark.parametrize("theta", [math.atan(2.0), 0.5, 1.0])
def test_refusal_exactly_above_the_threshold(theta):
    """painleve="error": the rod sliding on its leading lower end is refused ("painleve")
    for mu 1 % above mu_P(theta), and slides in integrated contact 1 % below it."""
    above = first_persistent(theta, 1.01 * mu_p(theta), "error")
    assert above.status == "painleve"
    below = first_persistent(theta, 0.99 * mu_p(theta), "error")
    assert below.status == "done"
    kinds = list(below.events["kind"])
    assert "pivot" in kinds
    pivot = below.events[kinds.index("pivot")]
    assert pivot["mode"] == 1                   # sliding (no jam)


def test_landing_jam_is_the_law_s_own():
    """Landing from above (1e-9 m) instead: the impact itself meets the jam in impulse
    space and Kane & Levinson's law stops the slip (mode stick): no Painleve state at
    all, for mu above or below the threshold."""
    res = first_persistent(0.5, 1.5 * mu_p(0.5), "error", drop=1e-9)
    assert res.status == "done"
    assert res.events[0]["kind"] == "impact" and res.events[0]["mode"] == 1


def test_trailing_end_never_jams():
    """The same rod sliding the other way (its lower end trailing): friction turns it off
    the floor, no threshold: integrated sliding even for mu = 100."""
    res = first_persistent(0.5, 100.0, "error", vx=1.0)
    assert res.status != "painleve"
    assert "painleve" not in list(res.events["kind"])


def darboux_keller_rod(theta, mu, vT, e, radius=0.0):
    """Closed-form impact without collision of the rod's lower end (v_N = 0, slip vT,
    Poisson's e): slide along -mu s until the slip stops, then stick (if |W_TN| <= mu
    W_TT), v_N back to 0 at the compression end p_c; P_N = (1 + e) p_c. Returns
    (P_N, P_T) in the floor frame (n = +y, t = (n_y, -n_x) = +x); ``radius``: a capsule's
    (its contact point lies that much below the end)."""
    m, I = MASS, MASS * L_HALF ** 2 / 3.0
    rx, ry = -L_HALF * math.cos(theta), -L_HALF * math.sin(theta) - radius   # arm
    nx, ny, tx, ty = 0.0, 1.0, 1.0, 0.0
    cn = rx * ny - ry * nx
    ct = rx * ty - ry * tx
    wnn, wnt, wtt = 1 / m + cn * cn / I, cn * ct / I, 1 / m + ct * ct / I
    s = math.copysign(1.0, vT)
    kN = wnn - mu * s * wnt                     # < 0: the jam
    kT = wnt - mu * s * wtt
    assert kN < 0 and s * kT < 0                # v_N falls, the slip decelerates
    p1 = -vT / kT                               # the slip stops
    vN1 = kN * p1
    assert abs(wnt) <= mu * wtt                 # then it sticks
    kstick = (wnn * wtt - wnt * wnt) / wtt
    pc = p1 - vN1 / kstick                      # v_N back to 0: end of compression
    pf = (1.0 + e) * pc
    PT = -mu * s * p1 - wnt / wtt * (pf - p1)
    return pf, PT


@pytest.mark.parametrize("e", [0.0, 0.5])
def test_impact_without_collision_against_closed_form(e):
    """painleve="impact" (default): the jam is an impulsive transition at the landing,
    event "painleve", with the impulse of the closed-form Darboux-Keller integration (to
    1e-9 relative), P_N > 0, energy not created, the end leaving the floor (v_N >= 0)."""
    theta = 0.5
    mu = 1.5 * mu_p(theta)
    sim = Simulation(rod_scene(theta, -1.0), Law("kane_levinson", e=e, mu=mu))
    res = sim.run(0.05)
    ev = res.events
    iwc = ev[ev["kind"] == "painleve"]
    assert len(iwc) >= 1
    first = iwc[0]
    vT = first["v_i"][1]
    assert first["v_i"][0] == 0.0 and vT < 0.0
    PN, PT = darboux_keller_rod(theta, mu, vT, e)
    assert first["P"][0] == pytest.approx(PN, rel=1e-9)
    assert first["P"][1] == pytest.approx(PT, rel=1e-9, abs=1e-12 * abs(PN))
    assert first["P"][0] > 0.0
    assert first["dE"] <= 1e-12 * MASS * G * L_HALF
    assert first["v_f"][0] >= -1e-14          # leaves (or stays) at v_N = 0 to round-off
    if e > 0:
        assert first["v_f"][0] > 0.0            # it flies off
    # no energy created over the whole run
    t = np.linspace(0.0, res.t_end, 400)
    E = np.asarray(res.energy(t))
    assert np.max(np.diff(E)) <= 1e-12 * MASS * G * L_HALF


def test_painleve_option_is_checked():
    with pytest.raises(ValueError, match="painleve must be one of 'error', 'impact'"):
        Simulation(rod_scene(0.5, -1.0), Law("kane_levinson", e=0.0, mu=1.0),
                   painleve="ignore")


RADIUS_3D = 1e-3


def capsule_scene(theta, vx):
    """The rod in 3D: a thin capsule (radius 1e-3 m, the rod's moments of inertia) in the
    x-z plane, tilted by theta, its lower cap on the floor, sliding at vx along x."""
    scene = Scene3D(gravity=(0.0, 0.0, -G))
    scene.add_floor(0.0)
    phi = 0.5 * math.pi - theta             # body z axis -> (cos theta, 0, sin theta)
    q = (math.cos(0.5 * phi), 0.0, math.sin(0.5 * phi), 0.0)
    I = MASS * L_HALF ** 2 / 3.0
    scene.add_body(Capsule(2 * L_HALF, RADIUS_3D), MASS,
                   (0.0, 0.0, L_HALF * math.sin(theta) + RADIUS_3D), orientation=q,
                   velocity=(vx, 0.0, 0.0), inertia=(I, I, 1e-3 * I))
    return scene


def run3d(theta, mu, painleve, e=0.0, vx=-1.0):
    sim = Simulation(capsule_scene(theta, vx), Law("kane_levinson", e=e, mu=mu),
                     painleve=painleve)
    try:
        return sim.run(0.02)
    except SimulationError as exc:
        return exc.result


@pytest.mark.parametrize("theta", [math.atan(2.0), 0.8])
def test_3d_refusal_at_the_threshold(theta):
    """3D, painleve="error": refused 1 % above the rod's threshold (with the cap radius
    in the arm), not 1 % below."""
    c, s_ = math.cos(theta), math.sin(theta)
    # mu_P with the contact point RADIUS_3D below the cap centre: W_NN / |W_NT|
    rx, rz = -L_HALF * c, -L_HALF * s_ - RADIUS_3D
    I = MASS * L_HALF ** 2 / 3.0
    mup = (1.0 / MASS + rx * rx / I) / (abs(rx * rz) / I)
    assert run3d(theta, 1.01 * mup, "error").status == "painleve"
    assert run3d(theta, 0.99 * mup, "error").status == "done"


@pytest.mark.parametrize("e", [0.0, 0.5])
def test_3d_impact_without_collision_against_closed_form(e):
    """3D, painleve="impact": event "painleve" whose impulse is the planar closed form
    (Routh's 3D integrator, default tolerance: 1e-8 relative), no energy created."""
    theta = 0.5
    mu = 1.5 * mu_p(theta)
    res = run3d(theta, mu, "impact", e=e)
    assert res.status == "done"
    ev = res.events
    iwc = ev[ev["kind"] == "painleve"]
    assert len(iwc) >= 1
    first = iwc[0]
    PN, PT = darboux_keller_rod(theta, mu, -1.0, e, radius=RADIUS_3D)
    assert first["P"][0] == pytest.approx(PN, rel=1e-8)
    assert math.hypot(first["P"][1], first["P"][2]) == pytest.approx(abs(PT), rel=1e-8)
    assert first["dE"] <= 1e-12 * MASS * G * L_HALF
    assert first["v_f"][0] >= -1e-14          # leaves (or stays) at v_N = 0 to round-off
    t = np.linspace(0.0, res.t_end, 200)
    E = np.asarray(res.energy(t))
    assert np.max(np.diff(E)) <= 1e-12 * MASS * G * L_HALF


def _random_jam_contact(rng):
    """A random SPD contact matrix W (1/kg: a = W_NN, w = W_TN, C = W_TT), mu and a slip x
    (m/s) whose coefficient A = a - mu w . u is small, positive and falling under Routh's
    sliding flow dx/dP = w - mu C u (3D: the slip direction swerves)."""
    from rbimpact.kernels.stepper3d import _jam_approach
    while True:
        M = rng.normal(size=(3, 3))
        W = M @ M.T + 0.1 * np.eye(3)
        a, w, C = W[0, 0], W[0, 1:], W[1:, 1:]
        mu = rng.uniform(1.0, 10.0)
        # directions where A = 0: w . u = a / mu
        wn = np.linalg.norm(w)
        if mu * wn <= a:
            continue
        phi_w = math.atan2(w[1], w[0])
        half = math.acos(a / (mu * wn))
        for sgn in (1.0, -1.0):
            # start just outside the arc A < 0, on the side the flow turns u into it
            phi = phi_w + sgn * (half + 1e-6)
            u = np.array([math.cos(phi), math.sin(phi)])
            x = rng.uniform(1e-3, 1.0) * u
            vn0 = _jam_approach(a, w[0], w[1], C[0, 0], C[0, 1], C[1, 1], mu, x[0], x[1])
            if vn0 <= 0.0:
                return a, w, C, mu, x, vn0


def test_3d_jam_approach_against_routh_sliding_flow():
    """``stepper3d._jam_approach``: the impulse P1 = -vn0 / A (N s) at which a sliding slip,
    turned by Routh's flow ``dx/dP = w - mu C x/|x|`` (integrated by scipy, rtol 1e-12),
    brings A = a - mu w . u to 0 agrees with the closed first-order form to second order
    (relative error below 1e-4 for a start 1e-6 rad outside the jam arc)."""
    from scipy.integrate import solve_ivp
    rng = np.random.default_rng(7)
    for _ in range(20):
        a, w, C, mu, x, vn0 = _random_jam_contact(rng)
        u = x / np.linalg.norm(x)
        A0 = a - mu * w @ u
        assert A0 > 0.0
        P1 = -vn0 / A0

        def flow(P, y):
            return w - mu * C @ (y / np.linalg.norm(y))

        def jam(P, y):
            return a - mu * w @ (y / np.linalg.norm(y))
        jam.terminal = True
        sol = solve_ivp(flow, (0.0, 1e3 * P1), x, events=jam, rtol=1e-12, atol=1e-15)
        assert sol.t_events[0].size == 1
        assert P1 == pytest.approx(sol.t_events[0][0], rel=1e-4)


def test_3d_jam_approach_refuses_what_is_not_a_jam():
    """NaN (no impact without collision) when A > 0 does not fall under the flow (a planar
    slide: the slip cannot swerve), and 0 when A <= 0 already (the jam is here)."""
    from rbimpact.kernels.stepper3d import _jam_approach
    # planar: w along x, C diagonal, slip along x: u does not turn, dA/dP = 0
    assert math.isnan(_jam_approach(1.0, 0.5, 0.0, 2.0, 0.0, 2.0, 1.0, -0.3, 0.0))
    # A = 1 - 3 * 0.5 < 0 already
    assert _jam_approach(1.0, 0.5, 0.0, 2.0, 0.0, 2.0, 3.0, 0.3, 0.0) == 0.0
