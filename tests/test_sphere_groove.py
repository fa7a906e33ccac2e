"""A sphere held by two planes (issue 13: "a disk or sphere held by two or more planes"):
rolling along a V-groove, sliding along it without friction, resting in it, and slipping
on both planes when friction cannot make it roll (then sticking into rolling).

References: rolling on both contacts, ``v = u e`` along the groove axis and ``w = (u /
rho) d`` with ``rho = r cos(gamma / 2)`` (``gamma`` the angle between the normals), so
``a = g.e / (1 + I / (m rho^2))`` (the classical ball in a V-groove: the contact forces do
no work); without friction ``a = g.e``. The friction needed to roll is computed here
independently: the contact forces solving Newton-Euler by least squares, plus the squeeze
along the line through the contact points that moves nothing, scanned for the smallest
friction coefficient that puts both forces in their cones.
"""
import math

import numpy as np
import pytest

from rbimpact import Law, Scene3D, Simulation, SimulationError, Sphere
from rbimpact.kernels import evbuf
from rbimpact.kernels import stepper3d as k
from rbimpact.kernels.codes import PM_WEDGED
from rbimpact.kernels.common import P_MU

G = 9.81


def _rot_x(v, a):
    c, s = math.cos(a), math.sin(a)
    return np.array([v[0], c * v[1] - s * v[2], s * v[1] + c * v[2]])


def _groove(beta, tilt, mu, r=0.05, e=0.3, start=(0.02, 0.0, 0.2), v0=(0.1, 0.3, 0.0),
            w0=(1.0, 2.0, 3.0), law="kane_levinson", end_wall=None):
    """A V-groove along y (half-angle beta between each normal and the vertical), tilted
    by ``tilt`` about x (its axis descending toward -y), and a sphere dropped into it."""
    n1 = _rot_x((math.sin(beta), 0.0, math.cos(beta)), tilt)
    n2 = _rot_x((-math.sin(beta), 0.0, math.cos(beta)), tilt)
    scene = Scene3D(gravity=(0.0, 0.0, -G))
    scene.add_plane((0.0, 0.0, 0.0), tuple(n1))
    scene.add_plane((0.0, 0.0, 0.0), tuple(n2))
    if end_wall is not None:
        scene.add_plane((0.0, end_wall, 0.0), (0.0, -1.0, 0.0))
    scene.add_body(Sphere(r), mass=1.0, position=start, velocity=v0, angular_velocity=w0)
    return Simulation(scene, Law(law, e=e, mu=mu)), n1, n2


def _wedged_at(res):
    ev = res.events
    idx = np.nonzero((ev["kind"] == "contact") & (ev["mode"] == PM_WEDGED))[0]
    return float(ev["t"][idx[-1]]) if len(idx) else None


def _check_rolling(res, n1, n2, r, t0, t1, slip_free=True):
    ts = np.linspace(t0, t1, 7)
    s = res.sample(ts)
    x, v, w = s["position"][:, 0], s["velocity"][:, 0], s["angular_velocity"][:, 0]
    V = np.max(np.linalg.norm(v, axis=1)) + math.sqrt(G * r)
    for n in (n1, n2):
        assert np.max(np.abs(x @ n - r)) < 1e-9 * r          # touching both planes
        assert np.max(np.abs(v @ n)) < 1e-12 * V               # moving along the groove
        if slip_free:
            slip = v + np.cross(w, -r * n)
            assert np.max(np.linalg.norm(slip, axis=1)) < 1e-12 * V
    E = res.energy(ts)
    assert np.max(np.abs(E - E[0])) < 1e-12 * (abs(E[0]) + G * r)     # no work, no loss
    return ts, v


@pytest.mark.parametrize("beta, tilt", [(0.5, 0.0), (0.5, 0.2), (0.8, 0.15), (0.3, -0.1)])
def test_sphere_rolls_along_a_groove(beta, tilt):
    r = 0.05
    sim, n1, n2 = _groove(beta, tilt, mu=0.6, r=r)
    res = sim.run(3.0)
    assert res.status == "done"
    t_w = _wedged_at(res)
    assert t_w is not None, list(res.events["kind"][-10:])
    assert res.events["t"][-1] == t_w or res.events["kind"][-1] == "rest"
    ts, v = _check_rolling(res, n1, n2, r, t_w + 1e-6, 3.0)
    axis = np.cross(n1, n2)
    axis /= np.linalg.norm(axis)
    gamma = math.acos(float(n1 @ n2))
    rho = r * math.cos(gamma / 2.0)
    a_ref = G * float(np.array([0.0, 0.0, -1.0]) @ axis) / (1.0 + 0.4 * r * r / rho ** 2)
    a = (v[-1] - v[0]) @ axis / (ts[-1] - ts[0])
    assert a == pytest.approx(a_ref, rel=1e-12, abs=1e-12 * G)


def test_frictionless_sphere_slides_along_a_groove():
    r = 0.05
    sim, n1, n2 = _groove(0.5, 0.2, mu=0.0, r=r)
    res = sim.run(3.0)
    assert res.status == "done"
    t_w = _wedged_at(res)
    assert t_w is not None
    ts, v = _check_rolling(res, n1, n2, r, t_w + 1e-6, 3.0, slip_free=False)
    axis = np.cross(n1, n2)
    axis /= np.linalg.norm(axis)
    a = (v[-1] - v[0]) @ axis / (ts[-1] - ts[0])
    assert a == pytest.approx(-G * axis[2], rel=1e-12)
    w = res.sample(ts)["angular_velocity"][:, 0]
    assert np.max(np.abs(w - w[0])) == 0.0        # no friction, no torque


def test_sphere_slides_back_from_an_end_wall_and_stays_in_the_groove():
    """A level frictionless groove closed by a wall: the sphere sliding along it hits the
    wall, bounces back and is held by the groove again (``_reevaluate``); no plane is ever
    entered, energy only lost."""
    r = 0.05
    sim, n1, n2 = _groove(0.6, 0.0, mu=0.0, r=r, e=0.5, end_wall=0.6, v0=(0.05, 1.0, 0.0))
    res = sim.run(4.0)
    assert res.status == "done"
    ev = res.events
    wall = np.nonzero((ev["kind"] == "impact") & (ev["b"] == -3))[0]
    assert len(wall) >= 1
    assert _wedged_at(res) > ev["t"][wall[0]]
    ts = np.linspace(0.0, 4.0, 4001)
    s = res.sample(ts)
    for pl in sim.scene.planes:
        n = np.asarray(pl.normal, float)
        gap = (s["position"][:, 0] - np.asarray(pl.point, float)) @ n - r
        assert gap.min() > -1e-9 * r
    E = res.energy(ts)
    assert np.all(np.diff(E) <= 1e-12 * E[0])
    # after the last event it rolls back along -y at a constant speed
    v_end = res.sample([3.9, 4.0])["velocity"][:, 0]
    assert v_end[0, 1] < 0.0 and v_end[0] == pytest.approx(v_end[1], abs=1e-15)


def test_too_little_friction_to_roll_in_a_tilted_groove_slides_at_the_closed_form_rate():
    """mu = 0.02 is below the friction a rolling sphere needs in this tilted groove: it
    slips on both planes (integrated contact on two planes, ``stepper3d._groove_slide``;
    the run used to stop here). By symmetry both contacts slip along the axis e with
    N = m |g_perp| / (2 cos beta) each, so the centre accelerates at the constant
    ``g.e - 2 mu N / m`` (closed form) while the slip keeps growing (no stick event)."""
    beta, tilt, mu, r, drop = 0.5, 0.2, 0.02, 0.05, 1e-9
    n1 = _rot_x((math.sin(beta), 0.0, math.cos(beta)), tilt)
    n2 = _rot_x((-math.sin(beta), 0.0, math.cos(beta)), tilt)
    scene = Scene3D(gravity=(0.0, 0.0, -G))
    scene.add_plane((0.0, 0.0, 0.0), tuple(n1))
    scene.add_plane((0.0, 0.0, 0.0), tuple(n2))
    bis = (n1 + n2) / np.linalg.norm(n1 + n2)
    scene.add_body(Sphere(r), 1.0, tuple(bis * (r + drop) / (bis @ n1)))
    sim = Simulation(scene, Law("kane_levinson", e=0.3, mu=mu))
    res = sim.run(1.0)
    assert res.status == "done"
    ev = res.events
    piv = np.nonzero((ev["kind"] == "pivot") & (ev["mode"] == 2))[0]
    assert len(piv) >= 1
    t0 = float(ev["t"][piv[-1]])
    assert not np.any(ev["t"] > t0)                 # slides on both to the end
    e = np.cross(n1, n2)
    e /= np.linalg.norm(e)
    g = np.array([0.0, 0.0, -G])
    g_perp = g - (g @ e) * e
    N = np.linalg.norm(g_perp) / (2.0 * math.cos(beta))           # per unit mass
    t = np.linspace(t0, 1.0, 9)
    v = res.sample(t)["velocity"][:, 0]
    a_ref = g @ e - 2.0 * mu * N * np.sign(v[-1] @ e)
    assert np.diff(v @ e) / np.diff(t) == pytest.approx(np.full(8, a_ref), rel=1e-8)
    for n in (n1, n2):
        assert np.max(np.abs(v @ n)) < 1e-9 * math.sqrt(G * r)


# ---- the entry rule itself, against an independent force computation -------------------

def _needed_mu(n1, n2, r, m=1.0, g=(0.0, 0.0, -G)):
    """Smallest friction coefficient for which a sphere can roll along the groove:
    Newton-Euler contact forces (lstsq) plus the squeeze, scanned."""
    g = np.asarray(g, float)
    e = np.cross(n1, n2)
    e /= np.linalg.norm(e)
    d = (n1 - n2) / np.linalg.norm(n1 - n2)
    rho = r * np.linalg.norm(n1 + n2) / 2.0
    inertia = 0.4 * m * r * r
    acc = m * (g @ e) / (m + inertia / rho ** 2)
    # unknowns f1, f2: f1 + f2 = m a e - m g;  -r n1 x f1 - r n2 x f2 = I (acc / rho) d
    def cross_mat(a):
        return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    A = np.block([[np.eye(3), np.eye(3)], [-r * cross_mat(n1), -r * cross_mat(n2)]])
    b = np.concatenate([m * acc * e - m * g, inertia * acc / rho * d])
    f, *_ = np.linalg.lstsq(A, b, rcond=None)
    assert np.allclose(A @ f, b, atol=1e-12 * m * G)

    def need(s):
        worst = 0.0
        for fk, nk in ((f[:3] + s * d, n1), (f[3:] - s * d, n2)):
            N = fk @ nk
            if N <= 0.0:
                return np.inf
            worst = max(worst, np.linalg.norm(fk - N * nk) / N)
        return worst
    S = np.linspace(-50.0, 50.0, 20001) * m * G
    vals = np.array([need(s) for s in S])
    j = int(np.argmin(vals))
    from scipy.optimize import minimize_scalar
    lo, hi = S[max(j - 1, 0)], S[min(j + 1, len(S) - 1)]
    best = minimize_scalar(need, bounds=(lo, hi), method="bounded",
                           options={"xatol": 1e-12 * m * G})
    return min(best.fun, vals[j])


def _enter(n1, n2, r, mu, u=0.3, spin=(0.4, -0.2, 0.1)):
    """Call the kernel rule on a sphere touching both planes, rolling at speed u plus a
    small extra spin; returns (rc, state row, pm row, events logged)."""
    e = np.cross(n1, n2)
    e /= np.linalg.norm(e)
    d = (n1 - n2) / np.linalg.norm(n1 - n2)
    rho = r * np.linalg.norm(n1 + n2) / 2.0
    planes = np.array([[*n1, 0.0], [*n2, 0.0]])
    bis = (n1 + n2) / np.linalg.norm(n1 + n2)
    st = np.zeros((1, 19))
    st[0, k.SX:k.SX + 3] = bis * (r / (bis @ n1))
    st[0, k.SQ] = 1.0
    st[0, k.SV:k.SV + 3] = u * e
    st[0, k.SW:k.SW + 3] = u / rho * d + 1e-4 * np.asarray(spin)
    bflt = np.zeros((1, 8))
    bflt[0, k.B_MASS] = 1.0
    bflt[0, k.B_I1:k.B_I1 + 3] = 0.4 * r * r
    bflt[0, k.B_RADIUS] = r
    law_par = np.zeros((1, 5))
    law_par[0, P_MU] = mu
    bp_law = np.zeros((1, 2), np.int64)
    pm = np.zeros((1, 4), np.int64)
    ttr = np.full(1, np.inf)
    tolf = np.zeros(k.N_TF)
    tolf[k.TF_REST_LENGTH] = 1e-3
    tolf[k.TF_ZENO_SPEED] = -1.0
    ev_t, ev_i, ev_f = np.zeros(8), np.zeros((8, 5), np.int64), np.zeros((8, 19))
    cnt = np.zeros(evbuf.N_CNT, np.int64)
    c_f = np.zeros((k.MAXC, k.N_CF))
    err = np.zeros(k.N_ERR)
    rc = k._groove_enter(0, 0, 1, 0.0, st, bflt, planes, np.array([0.0, 0.0, -G]), law_par,
                         bp_law, pm, ttr, tolf, ev_t, ev_i, ev_f, cnt, c_f, k.MAXC - 1, err)
    return rc, st[0], pm[0], int(cnt[evbuf.CN_EVENTS]), e, d, rho


@pytest.mark.parametrize("beta, tilt", [(0.5, 0.2), (0.3, 0.25), (0.9, 0.1), (0.6, -0.3)])
def test_groove_entry_needs_exactly_the_rolling_friction(beta, tilt):
    r = 0.05
    n1 = _rot_x((math.sin(beta), 0.0, math.cos(beta)), tilt)
    n2 = _rot_x((-math.sin(beta), 0.0, math.cos(beta)), tilt)
    mu_star = _needed_mu(n1, n2, r)
    assert 0.0 < mu_star < 5.0
    rc, st, pm, nev, e, d, rho = _enter(n1, n2, r, 1.001 * mu_star)
    assert rc == 0 and pm[0] == PM_WEDGED and nev >= 1
    # the momentum projection: linear + angular momentum along the rolling motion kept
    u = st[k.SV:k.SV + 3] @ e
    m, inertia = 1.0, 0.4 * r * r
    u_ref = (m * 0.3 + inertia * (0.3 / rho + 1e-4 * np.array([0.4, -0.2, 0.1]) @ d) / rho) \
        / (m + inertia / rho ** 2)
    assert u == pytest.approx(u_ref, rel=1e-14)
    for n in (n1, n2):
        slip = st[k.SV:k.SV + 3] + np.cross(st[k.SW:k.SW + 3], -r * n)
        assert np.linalg.norm(slip) < 1e-15
    a = st[k.SA:k.SA + 3] @ e
    assert a == pytest.approx(-G * e[2] / (1.0 + inertia / (m * rho ** 2)), rel=1e-13)
    rc, st2, pm2, nev2, *_ = _enter(n1, n2, r, 0.999 * mu_star)
    assert rc == k.GROOVE_SLIPS and pm2[0] == 0 and nev2 == 0     # left to _groove_slide


def test_sphere_thrown_along_a_level_groove_slips_then_rolls_at_the_closed_form_time():
    """A sphere (no spin) thrown at v0 along a level V-groove slips on both planes: per
    contact N = m g / (2 cos beta) and friction mu N along -e, so
    ``v' = -mu g / cos beta`` and the spin about the horizontal normal to the axis grows
    at ``r mu m g / I``: the common slip ``s = v - r w cos beta`` falls at
    ``mu g / cos beta + r^2 mu m g cos beta / I`` (closed form, constant). Both contacts
    stick when s reaches slip_eps, and the sphere rolls on at the closed-form speed."""
    beta, r, m, mu, v0, drop = 0.5, 0.05, 0.7, 0.3, 2.0, 1e-9
    scene = Scene3D(gravity=(0.0, 0.0, -G))
    scene.add_plane((0.0, 0.0, 0.0), (-math.sin(beta), 0.0, math.cos(beta)))
    scene.add_plane((0.0, 0.0, 0.0), (math.sin(beta), 0.0, math.cos(beta)))
    scene.add_body(Sphere(r), m, (0.0, 0.0, (r + drop) / math.cos(beta)),
                   velocity=(0.0, v0, 0.0))
    sim = Simulation(scene, Law("kane_levinson", e=0.0, mu=mu))
    res = sim.run(1.0)
    ev = res.events
    assert res.status == "done"
    assert list(ev["kind"]) == ["impact", "impact", "pivot", "stick", "contact"]
    assert ev["mode"][2] == 2 and ev["mode"][4] == PM_WEDGED
    tp = float(ev["t"][2])
    sp = res.sample([tp])
    vp, wp = sp["velocity"][0, 0], sp["angular_velocity"][0, 0]
    inertia = 0.4 * m * r * r
    rate = mu * G / math.cos(beta) + r * r * mu * m * G * math.cos(beta) / inertia
    s0 = vp[1] + r * math.cos(beta) * wp[0]      # w along -x turns the contacts back
    eps = sim.tolerances["slip_eps"]
    t_stick = tp + (s0 - eps) / rate
    assert float(ev["t"][3]) == pytest.approx(t_stick, rel=1e-10)
    v_star = vp[1] - mu * G / math.cos(beta) * (t_stick + eps / rate - tp)
    v_end = res.sample([0.99])["velocity"][0, 0]
    assert v_end[1] == pytest.approx(v_star, rel=1e-6)     # slip_eps removed at the stick
