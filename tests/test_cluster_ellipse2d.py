"""Ellipses in 2D clusters (``cluster2d``'s curved feature, ``CC_AEA``; issue 16 item 2).

The kernel replaces an ellipse by its osculating circle at the contact at every state
(``cluster2d.feature_circles``). Checked here against independent computations:

* the gap, its first two time derivatives, the slip and its rate of every row kind with an
  ellipse (on a plane, on a face, on a capsule side, on a vertex, on an ellipse) against
  finite differences of the exact gap, written from scratch: the support function for a
  plane or a face, and for two curved bodies the maximum over the axis of the separation
  ``n . (cA - cB) - sqrt(n^T M_A n) - sqrt(n^T M_B n)`` (scipy's bounded scalar search);
* an ellipse rocking on a floor without slipping against scipy's integration of its
  one-degree-of-freedom Lagrangian (``(I + m (h^2 + h'^2)) th'' + m h' (h + h'') th'^2 +
  m g h' = 0``, h the height of the centre), and sliding without friction (``(I + m h'^2)
  th'' + m h' h'' th'^2 + m g h' = 0``, the horizontal velocity constant);
* an ellipse with equal semi-axes rolling off a fixed cylinder (and a cylinder given as an
  ellipse): the closed-form lift-off angle ``cos phi = 4/7`` of ``test_cluster2d``;
* the rows that ``cluster2d_rows`` builds for an ellipse touching a box, a capsule, a disk
  and an ellipse: one row, gap 0 and the pair frame's normal (``pair2d.frame_rel``).
"""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

from rbimpact.kernels import cluster2d as C
from rbimpact.kernels import cluster2d_rows as R
from rbimpact.kernels.pair2d import frame_rel
from rbimpact.kernels.pair2d_shape import SH_DISK, SH_ELLIPSE, SH_POLY
from test_cluster2d import G, Cluster, body, contact, rot


def ellipse_row(kind, A, B=-1, ea=0.3, eb=0.12, **kw):
    r = contact(kind, A, B, **kw)
    r[C.CC_AEA] = ea
    r[C.CC_AEB] = eb
    return r


def _mat(a, b, th):
    c, s = math.cos(th), math.sin(th)
    Rm = np.array([[c, -s], [s, c]])
    return Rm @ np.diag([a * a, b * b]) @ Rm.T


def _support(M, c, u):
    """The point of the ellipse x^T M^-1 x = 1 centred at c with outward normal u."""
    return c + M @ u / math.sqrt(u @ M @ u)


def exact_gap_and_slip(row, st):
    """Gap and slip of an ellipse row for body states st[i] = (x, y, a, vx, vy, w), from
    the support function (module docstring); also returns the contact point and normal."""
    kind = int(row[C.CC_KIND])
    A = int(row[C.CC_A])
    B = int(row[C.CC_B])
    xa = np.array(st[A][:2])
    MA = _mat(row[C.CC_AEA], row[C.CC_AEB], st[A][2])
    if kind == C.KIND_PLANE:
        n = row[[C.CC_NX, C.CC_NY]]
        p = _support(MA, xa, -n)
        g = n @ p - row[C.CC_D]
    else:
        xb = np.array(st[B][:2])
        if kind == C.KIND_FACE:
            n = rot(st[B][2], row[[C.CC_NX, C.CC_NY]])
            fb = xb + rot(st[B][2], row[[C.CC_PBX, C.CC_PBY]])
            p = _support(MA, xa, -n)
            g = n @ (p - fb) - row[C.CC_RB]
        else:
            if row[C.CC_BEA] > 0.0:
                MB = _mat(row[C.CC_BEA], row[C.CC_BEB], st[B][2])
                cb = xb
            else:
                MB = row[C.CC_RB] ** 2 * np.eye(2)
                cb = xb + rot(st[B][2], row[[C.CC_PBX, C.CC_PBY]])

            def sep(psi):
                u = np.array([math.cos(psi), math.sin(psi)])
                return -(u @ (xa - cb) - math.sqrt(u @ MA @ u) - math.sqrt(u @ MB @ u))

            def dsep(psi):     # d sigma / d psi
                u = np.array([math.cos(psi), math.sin(psi)])
                v = np.array([-u[1], u[0]])
                hb = math.sqrt(u @ MB @ u)
                return (v @ (xa - cb) - (v @ MA @ u) / math.sqrt(u @ MA @ u)
                        - ((v @ MB @ u) / hb if hb > 0.0 else 0.0))
            d = xa - cb
            p0 = math.atan2(d[1], d[0])
            res = minimize_scalar(sep, bounds=(p0 - 1.2, p0 + 1.2), method="bounded",
                                  options={"xatol": 1e-10, "maxiter": 500})
            # the maximum's argument to round-off: the root of sigma' (Brent's maximum is
            # flat to sqrt(eps) only)
            psi = brentq(dsep, res.x - 1e-4, res.x + 1e-4, xtol=1e-16, rtol=1e-15)
            n = np.array([math.cos(psi), math.sin(psi)])
            g = -sep(psi)
            p = _support(MA, xa, -n)
    t = np.array([n[1], -n[0]])

    def vel(i):
        r = p - np.array(st[i][:2])
        return np.array(st[i][3:5]) + st[i][5] * np.array([-r[1], r[0]])
    dv = vel(A) - (vel(B) if kind != C.KIND_PLANE else 0.0)
    return g, t @ dv, p, n


A_BODY = body(0.1, 0.45, 0.4, 0.3, -0.7, 1.3, m=1.2, I=0.3)
B_BODY = body(-0.2, 0.05, 0.3, -0.5, 0.2, -2.1, m=0.7, I=0.1)

KIND_CASES = {
    "ellipse-plane": ([A_BODY], ellipse_row(C.KIND_PLANE, 0, n=(-math.sin(0.3), math.cos(0.3)),
                                            d=0.1)),
    "ellipse-face": ([A_BODY, B_BODY], ellipse_row(C.KIND_FACE, 0, 1, pb=(0.1, 0.2),
                                                   n=(math.sin(0.2), math.cos(0.2)))),
    "ellipse-capsule side": ([A_BODY, B_BODY], ellipse_row(C.KIND_FACE, 0, 1, pb=(0.1, 0.2),
                                                           rb=0.05, n=(0.0, 1.0))),
    "ellipse-vertex": ([A_BODY, B_BODY], ellipse_row(C.KIND_ROUND, 0, 1, pb=(0.1, 0.02),
                                                     rb=0.0)),
    "ellipse-round vertex": ([A_BODY, B_BODY], ellipse_row(C.KIND_ROUND, 0, 1, pb=(0.1, 0.02),
                                                           rb=0.08)),
    "ellipse-ellipse": ([A_BODY, B_BODY], ellipse_row(C.KIND_ROUND, 0, 1)),
}
KIND_CASES["ellipse-ellipse"][1][C.CC_BEA] = 0.2
KIND_CASES["ellipse-ellipse"][1][C.CC_BEB] = 0.07


@pytest.mark.parametrize("name", list(KIND_CASES))
def test_ellipse_rates_against_finite_differences(name):
    """g, g', g'' and vT, dvT/dt of each row kind with an ellipse, against finite
    differences of the exact gap and slip along a motion with constant (arbitrary)
    accelerations; the common-normal iteration starts 0.05 rad off."""
    bodies, row = KIND_CASES[name]
    row = row.copy()
    st0 = [b[:6] for b in bodies]
    _, _, _, n0 = exact_gap_and_slip(row, st0)
    row[C.CC_PSI] = math.atan2(n0[1], n0[0]) + 0.05
    cl = Cluster(bodies, [row], g=(0.0, 0.0))
    cl.acc[:] = np.random.default_rng(7).normal(size=cl.acc.shape)
    out = cl.rates(0)

    def state(t):
        return [np.concatenate([cl.b[i, :3] + cl.b[i, 3:6] * t + 0.5 * cl.acc[i] * t * t,
                                cl.b[i, 3:6] + cl.acc[i] * t]) for i in range(cl.b.shape[0])]
    h = 2e-4
    vals = np.array([exact_gap_and_slip(row, state(k * h))[:2] for k in (-2, -1, 0, 1, 2)])
    d1 = (vals[0] - 8 * vals[1] + 8 * vals[3] - vals[4]) / (12 * h)      # O(h^4)
    d2 = (-vals[0] + 16 * vals[1] - 30 * vals[2] + 16 * vals[3] - vals[4]) / (12 * h * h)
    assert out[0] == pytest.approx(vals[2, 0], abs=1e-13)
    assert out[1] == pytest.approx(d1[0], abs=1e-9)
    assert out[2] == pytest.approx(d2[0], abs=1e-6)
    assert out[3] == pytest.approx(vals[2, 1], abs=1e-12)
    assert out[4] == pytest.approx(d1[1], abs=1e-8)
    assert np.allclose(out[5:7], n0, atol=1e-12)
    assert abs(out[2]) > 0.1 and abs(out[4]) > 0.1      # not trivially zero


# ------------------------------------------------------------------ rocking on a floor


def _h3(a, b, th):
    """Height of the centre of an ellipse (a on the body x axis) over a level floor, and
    its first two derivatives in the body angle."""
    s, c = math.sin(th), math.cos(th)
    h = math.sqrt(a * a * s * s + b * b * c * c)
    h1 = (a * a - b * b) * s * c / h
    h2 = ((a * a - b * b) * (c * c - s * s) - h1 * h1) / h
    return h, h1, h2


@pytest.mark.parametrize("rolling", [True, False], ids=["rolling", "frictionless"])
def test_ellipse_rocking_on_floor_against_lagrangian(rolling):
    a, b, m, I = 0.3, 0.2, 1.5, 0.04
    th0 = 0.5
    h0, _, _ = _h3(a, b, th0)
    M = _mat(a, b, th0)
    p = _support(M, np.zeros(2), np.array([0.0, -1.0]))      # contact point from the centre
    assert p[1] == pytest.approx(-h0, abs=1e-15)
    bd = body(0.0, h0, th0, 0.0, 0.0, 0.0, m=m, I=I)
    row = ellipse_row(C.KIND_PLANE, 0, ea=a, eb=b, n=(0.0, 1.0), d=0.0,
                      mu=math.inf if rolling else 0.0,
                      mode=C.MODE_STICK if rolling else C.MODE_SLIP_POS)
    cl = Cluster([bd], [row], L=2 * a)
    e0 = cl.energy()
    T = 1.5
    st, ev, k, t = cl.advance(0.0, T)
    assert st == C.CS_OK and ev == C.CE_NONE and t == T

    def rhs(_, y):
        th, w = y
        h, h1, h2 = _h3(a, b, th)
        if rolling:
            return [w, -(m * h1 * (h + h2) * w * w + m * G * h1) / (I + m * (h * h + h1 * h1))]
        return [w, -(m * h1 * h2 * w * w + m * G * h1) / (I + m * h1 * h1)]
    sol = solve_ivp(rhs, (0.0, T), [th0, 0.0], method="DOP853", rtol=1e-13, atol=1e-14)
    th, w = sol.y[:, -1]
    assert abs(cl.b[0, C.CB_ANGLE] - th) < 1e-8, cl.b[0, C.CB_ANGLE] - th
    assert abs(cl.b[0, C.CB_OMEGA] - w) < 1e-7
    assert abs(cl.b[0, C.CB_Y] - _h3(a, b, th)[0]) < 1e-12       # on the floor
    assert abs(cl.energy() - e0) < 1e-10 * m * G * a
    if not rolling:
        assert abs(cl.b[0, C.CB_VX]) < 1e-12                      # no horizontal force
    assert abs(th - th0) > 0.1       # it rocked


# ------------------------------------------------------------------ a circle given as an ellipse


@pytest.mark.parametrize("which", ["A", "B", "both"])
def test_circle_as_ellipse_rolls_off_cylinder_at_closed_form_angle(which):
    """A disk (radius r, I = m r^2 / 2) rolling off a fixed cylinder (radius R): cos phi =
    4/7 + (3/7) v0^2 / (g (R + r)) (test_cluster2d), with the disk, the cylinder or both
    given as ellipses of equal semi-axes (the osculating-circle path of the kernel)."""
    R_, r, m = 1.0, 0.5, 1.0
    v0 = 1e-3 * math.sqrt(G * (R_ + r))
    bodies = [body(0.0, 0.0, m=1.0, I=1.0, fixed=True),
              body(0.0, R_ + r, 0.3, v0, 0.0, -v0 / r, m=m, I=0.5 * m * r * r)]
    ct = contact(C.KIND_ROUND, 1, 0, ra=r, rb=R_, mu=math.inf, mode=C.MODE_STICK)
    if which in ("A", "both"):
        ct[C.CC_AEA] = ct[C.CC_AEB] = r
    if which in ("B", "both"):
        ct[C.CC_BEA] = ct[C.CC_BEB] = R_
    ct[C.CC_PSI] = 0.5 * math.pi
    cl = Cluster(bodies, [ct], L=R_ + r)
    e0 = cl.energy()
    st, ev, k, t = cl.advance(0.0, 30.0)
    assert st == C.CS_OK and ev == C.CE_LEAVE and k == 0
    q = v0 * v0 / (G * (R_ + r))
    cphi = cl.b[1, C.CB_Y] / (R_ + r)
    assert abs(cphi - (4.0 / 7.0 + 3.0 / 7.0 * q)) < 1e-8
    assert abs(cl.energy() - e0) < 1e-10 * G * (R_ + r)


def test_ellipse_on_ellipse_keeps_contact_and_energy():
    """A frictionless ellipse sliding over a fixed ellipse under gravity until it leaves:
    energy kept, the gap 0 throughout (checked at the end against the separation maximum)."""
    bodies = [body(0.0, 0.0, 0.2, m=1.0, I=1.0, fixed=True),
              body(0.0, 0.0, -0.4, 0.05, 0.0, 0.3, m=0.8, I=0.01)]
    row = ellipse_row(C.KIND_ROUND, 1, 0, ea=0.25, eb=0.1, mode=C.MODE_SLIP_POS)
    row[C.CC_BEA], row[C.CC_BEB] = 0.6, 0.3
    # place the free ellipse on top, touching: its support along -n at the fixed one's
    # support along n, n = (sin 0.1, cos 0.1)
    n = np.array([math.sin(0.1), math.cos(0.1)])
    top = _support(_mat(0.6, 0.3, 0.2), np.zeros(2), n)
    low = _support(_mat(0.25, 0.1, -0.4), np.zeros(2), -n)
    bodies[1][:2] = top - low
    row[C.CC_PSI] = math.atan2(n[1], n[0])
    cl = Cluster(bodies, [row], L=1.0)
    assert abs(cl.rates(0)[0]) < 1e-15
    assert cl.project() == C.CS_OK      # the velocities onto dg/dt = 0
    assert abs(cl.rates(0)[1]) < 1e-15
    e0 = cl.energy()
    st, ev, k, t = cl.advance(0.0, 5.0)
    assert st == C.CS_OK and ev == C.CE_LEAVE and t > 0.05
    assert abs(cl.energy() - e0) < 1e-10 * G
    g, _, _, _ = exact_gap_and_slip(cl.c[0], [b[:6] for b in cl.b])
    assert abs(g) < 1e-11


# ------------------------------------------------------------------ rows from the shapes


def _state(x, y, a):
    s = np.zeros(9)
    s[:3] = x, y, a
    return s


OTHERS = {
    "box": (SH_POLY, 0.0, 0.0, 0.0, np.array([(-0.3, -0.1), (0.3, -0.1), (0.3, 0.1),
                                              (-0.3, 0.1)], float)),
    "capsule": (SH_POLY, 0.07, 0.0, 0.0, np.array([(-0.25, 0.0), (0.25, 0.0)], float)),
    "disk": (SH_DISK, 0.15, 0.0, 0.0, np.zeros((1, 2))),
    "ellipse": (SH_ELLIPSE, 0.0, 0.2, 0.08, np.zeros((1, 2))),
}


@pytest.mark.parametrize("other", list(OTHERS))
@pytest.mark.parametrize("pose", range(6))
def test_ellipse_rows_touch_with_the_pair_normal(other, pose):
    """An ellipse placed touching another shape at a random pose: ``ellipse_rows`` writes
    one row whose kinematics (cluster_rates) give gap 0 and the pair frame's normal."""
    rng = np.random.default_rng(100 + pose)
    ea, eb = 0.3, 0.12
    kB, rB, eaB, ebB, VB = OTHERS[other]
    thA, thB = rng.uniform(-math.pi, math.pi, 2)
    stB = _state(0.0, 0.0, thB)
    u = rng.normal(size=2)
    u /= np.linalg.norm(u)
    VA = np.zeros((1, 2))
    V = np.vstack([VA, VB])
    # slide A in along -u until it touches (bisection on the pair frame's gap)

    def gap(s):
        return frame_rel(SH_ELLIPSE, 0.0, ea, eb, V, 0, 1, thA, kB, rB, eaB, ebB, V, 1,
                         VB.shape[0], -s * u[0], -s * u[1], thB)
    lo, hi = 0.0, 3.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if gap(mid)[0] > 0.0:
            hi = mid
        else:
            lo = mid
    s = hi
    g, nx, ny = gap(s)[:3]
    assert 0.0 <= g < 1e-12
    stA = _state(s * u[0], s * u[1], thA)
    act = np.zeros((2, C.N_CC))
    na, nc = R.ellipse_rows(ea, eb, 0, V, 1, VB.shape[0], rB, eaB, ebB, stB, 1, nx, ny, 1e-9,
                            0.3, act)
    assert (na, nc) == (1, 0)
    bodies = np.array([body(*stA[:3]), body(*stB[:3])])
    w = np.zeros(C.work_size(2, 0))
    out = np.zeros(7)
    C.cluster_rates(bodies, act, 0, np.zeros((2, 3)), w, out)
    assert abs(out[0]) < 1e-11
    assert np.allclose(out[5:7], (nx, ny), atol=1e-7)


# ------------------------------------------------------------------ in the stepper


def _rocking_scene(mu, th0=0.5, a=0.3, b=0.2, H=0.1, M=10.0):
    """A box (2 m x H, mass M) on the floor and an ellipse (a x b, 1 kg) touching its top
    face at the angle th0, at rest (e = 0, friction mu everywhere)."""
    from rbimpact import Box, Ellipse, Law, Scene2D

    sc = Scene2D(gravity=(0.0, -G))
    floor = sc.add_floor()
    sc.add_body(Box(2.0, H), M, (0.0, H / 2))
    sc.add_body(Ellipse(a, b), 1.0, (0.0, H + _h3(a, b, th0)[0]), angle=th0)
    law = Law("kane_levinson", e=0.0, mu=mu)
    return sc, law, {floor: law}


def test_ellipse_rocks_on_a_box_in_the_stepper():
    """The ellipse placed on a resting box enters a cluster with it (the ellipse on the
    box's face, the box's corners on the floor, rough): the box stays at rest and the
    ellipse rocks as on a fixed floor, the Lagrangian of the rolling test above."""
    from rbimpact import Ellipse, Simulation

    a, b, th0 = 0.3, 0.2, 0.5
    sc, law, planes = _rocking_scene(5.0, th0, a, b)
    res = Simulation(sc, law, planes).run(1.5)
    assert res.status == "done"
    assert "contact" in set(res.events["kind"])
    ts = np.array([0.5, 1.0, 1.5])
    s = res.sample(ts)
    I = Ellipse(a, b).moment(1.0)

    def rhs(_, y):
        th, w = y
        h, h1, h2 = _h3(a, b, th)
        return [w, -(h1 * (h + h2) * w * w + G * h1) / (I + h * h + h1 * h1)]
    sol = solve_ivp(rhs, (0.0, 1.5), [th0, 0.0], method="DOP853", rtol=1e-13, atol=1e-14,
                    dense_output=True)
    assert np.abs(s["angle"][:, 1] - sol.sol(ts)[0]).max() < 1e-9
    assert np.abs(s["x"][:, 0]).max() < 1e-12 and np.abs(s["y"][:, 0] - 0.05).max() < 1e-12


def test_frictionless_ellipse_on_a_box_on_a_frictionless_floor():
    """Without friction anywhere the face pushes the ellipse only upwards: its centre stays
    on the vertical, the box stays at rest, the energy stays (the ellipse starts touching at
    rest: no impact dissipates), and the angle follows the frictionless Lagrangian."""
    from rbimpact import Ellipse, Simulation

    a, b, th0 = 0.3, 0.2, 0.5
    sc, law, planes = _rocking_scene(0.0, th0, a, b)
    sim = Simulation(sc, law, planes)
    res = sim.run(2.0)
    assert res.status == "done"
    ts = np.linspace(0.0, 2.0, 41)
    s = res.sample(ts)
    m = np.array([10.0, 1.0])
    E = ((0.5 * (s["vx"] ** 2 + s["vy"] ** 2) + G * s["y"]) @ m
         + 0.5 * s["omega"] ** 2 @ np.array(sim._moments))
    assert np.abs(E - E[0]).max() < 1e-9 * E[0]
    assert np.abs(s["x"]).max() < 1e-12 and np.abs(s["y"][:, 0] - 0.05).max() < 1e-12
    h = np.array([_h3(a, b, th)[0] for th in s["angle"][:, 1]])
    assert np.abs(s["y"][:, 1] - 0.1 - h).max() < 1e-10
    I = Ellipse(a, b).moment(1.0)

    def rhs(_, y):
        th, w = y
        h, h1, h2 = _h3(a, b, th)
        return [w, -(h1 * h2 * w * w + G * h1) / (I + h1 * h1)]
    sol = solve_ivp(rhs, (0.0, 2.0), [th0, 0.0], method="DOP853", rtol=1e-13, atol=1e-14,
                    dense_output=True)
    assert np.abs(s["angle"][:, 1] - sol.sol(ts)[0]).max() < 1e-9


#: two-body campaign scenes (``rbimpact stability --scenes 2000 --dim 2 --bodies 2``, seed
#: 0) with an ellipse that stopped with the refusal of persistent body-body contact before
#: session 25, one per kind of pair; and two that now end with the named Painleve refusal
#: (mu = 10, Chatterjee & Ruina)
ELLIPSE_PAIR_SEEDS = [3412079874, 2334183247, 2510467182, 3161546553, 1993083410, 522625139]
ELLIPSE_PAIR_REFUSED = [3456656600, 2966532034]


@pytest.mark.parametrize("seed", ELLIPSE_PAIR_SEEDS)
def test_campaign_ellipse_pair_scenes_pass(seed):
    from rbimpact.campaign import run_drop
    row = run_drop(2, seed, bodies=2)
    assert "ellipse" in row.shape
    assert row.verdict == "OK", row.note
    assert row.penetration <= row.pen_tol
    assert row.impacts >= 1


@pytest.mark.parametrize("seed", ELLIPSE_PAIR_REFUSED)
def test_campaign_ellipse_pair_scenes_refused_by_name(seed):
    from rbimpact.campaign import run_drop
    row = run_drop(2, seed, bodies=2)
    assert row.status == "SimulationError"
    assert "no consistent stick/slip/lift-off mode" in row.note, row.note
    assert row.penetration <= row.pen_tol
