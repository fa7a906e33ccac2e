"""kernels/cluster3d.py: persistent contact between several spheres in 3D.

Closed forms (a sphere rolling off a fixed sphere: lift-off at cos phi = (10/17) cos phi0,
frictionless (2/3) cos phi0; the stick -> slip angle against a brentq root of the
rolling forces), an independent scipy integration of a sphere on a free sphere on a
frictionless floor, energy and momentum, rest of a pyramid with its minimum-norm split,
g'' and dc/dt against finite differences, the input checks, the asymmetric groove
sticking on a split inside the cones where a closed-form squeeze along the chord exists
(and slipping where none does), and rest found right after a backspin sphere's slip stop.
"""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from rbimpact.kernels import cluster3d as C

G = 9.81


# ------------------------------------------------------------------ helpers


def sphere(x, r, v=(0.0, 0.0, 0.0), w=(0.0, 0.0, 0.0), m=1.0, I=None, fixed=False):
    b = np.zeros(C.N_CB)
    b[C.CB_X:C.CB_X + 3] = x
    b[C.CB_QW] = 1.0
    b[C.CB_VX:C.CB_VX + 3] = v
    b[C.CB_WX:C.CB_WX + 3] = w
    b[C.CB_M] = m
    b[C.CB_I] = 0.4 * m * r * r if I is None else I
    b[C.CB_R] = r
    b[C.CB_FIXED] = 1.0 if fixed else 0.0
    return b


def contact(A, B=-1, n=(0.0, 0.0, 1.0), d=0.0, mu=0.0, mode=C.MODE_STICK):
    c = np.zeros(C.N_CC)
    c[C.CC_KIND] = C.KIND_PLANE if B < 0 else C.KIND_SPHERE
    c[C.CC_A] = A
    c[C.CC_B] = B
    if B < 0:
        c[C.CC_NX:C.CC_NX + 3] = n
        c[C.CC_D] = d
    c[C.CC_MU] = mu
    c[C.CC_MODE] = mode
    return c


class Cluster:
    """Tables and work arrays of one cluster (Python convenience for the tests)."""

    def __init__(self, bodies, contacts, cands=(), g=(0.0, 0.0, -G), L=1.0):
        self.b = np.array(bodies, dtype=np.float64)
        self.c = np.array(contacts, dtype=np.float64).reshape(-1, C.N_CC)
        self.nk = self.c.shape[0]
        self.cand = np.array(cands, dtype=np.float64).reshape(-1, C.N_CC)
        self.nc = self.cand.shape[0]
        if self.nc == 0:
            self.cand = np.zeros((1, C.N_CC))
        self.g = tuple(float(x) for x in g)
        self.L = L
        self.w = np.zeros(C.work_size(self.b.shape[0], self.nc))
        self.la = np.zeros(C.N_LA)
        C.validate_cluster3d(self.b, self.c, self.nk, self.cand, self.nc, L)

    def advance(self, t0, t1, rec=None):
        """cluster_advance; ``rec``: (seg_t, seg_b, seg_s, cnt) to record into."""
        if rec is None:
            rec = (np.zeros(0), np.zeros(0, np.int64), np.zeros((0, C.N_ROW)),
                   np.zeros(2, np.int64))
        ids = np.arange(self.b.shape[0], dtype=np.int64)
        return C.cluster_advance(self.b, self.c, self.nk, self.cand, self.nc, *self.g, self.L,
                                 t0, t1, self.w, self.la, *rec, ids)

    def select(self):
        return C.cluster_select_modes(self.b, self.c, self.nk, *self.g, self.L, self.w,
                                      self.la)

    def after(self, ev, k):
        return C.cluster_after_event(self.b, self.c, self.nk, ev, k, *self.g, self.L, self.w,
                                     self.la)

    def forces(self):
        acc = np.zeros((self.b.shape[0], 6))
        st = C.cluster_forces(self.b, self.c, self.nk, *self.g, self.L, self.w, self.la, acc)
        return st, acc

    def energy(self):
        return C.cluster_energy(self.b, *self.g)


def rotation(seed):
    """A random proper rotation matrix."""
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def ball_on_fixed(phi0, mu, R=1.0, r=0.3, rot=None):
    """A solid sphere (radius r) at rest on a fixed sphere (radius R) at the polar angle
    phi0 from the top; ``rot``: the whole scene rotated (gravity with it)."""
    Rm = np.eye(3) if rot is None else rot
    up = Rm @ np.array([0.0, 0.0, 1.0])
    ex = Rm @ np.array([1.0, 0.0, 0.0])
    rho = R + r
    xa = rho * (math.cos(phi0) * up + math.sin(phi0) * ex)
    cl = Cluster([sphere(xa, r), sphere(np.zeros(3), R, fixed=True)],
                 [contact(0, 1, mu=mu)], g=-G * up, L=R + r)
    return cl, up


def polar(cl, up):
    """Polar angle of the ball's centre seen from the fixed sphere's centre."""
    d = cl.b[0, C.CB_X:C.CB_X + 3] - cl.b[1, C.CB_X:C.CB_X + 3]
    return math.acos(np.dot(d, up) / np.linalg.norm(d))


# ------------------------------------------------------------------ 1. lift-off angles


@pytest.mark.parametrize("seed", [None, 7])
@pytest.mark.parametrize("mu,ratio", [(math.inf, 10.0 / 17.0), (0.0, 2.0 / 3.0)])
def test_rolls_off_fixed_sphere(seed, mu, ratio):
    phi0 = 1e-6
    cl, up = ball_on_fixed(phi0, mu, rot=None if seed is None else rotation(seed))
    st, ev, k, t = cl.advance(0.0, 100.0)
    assert (st, ev, k) == (C.CS_OK, C.CE_LEAVE, 0)
    phi = polar(cl, up)
    assert abs(math.cos(phi) - ratio * math.cos(phi0)) < 1e-9
    assert abs(cl.c[0, C.CC_LAMN]) < 1e-9 * G


# ------------------------------------------------------------------ 2. stick -> slip


def test_stick_slip_on_fixed_sphere_and_energy():
    """Rolling on a fixed sphere (I = 2/5 m r^2, from rest at phi0): tangential
    m rho phi'' = m g sin phi - F, spin I omega' = F r with r omega = rho phi' give
    F = (2/7) m g sin phi; energy (7/10) m rho^2 phi'^2 = m g rho (cos phi0 - cos phi) and
    the radial equation N = m g cos phi - m rho phi'^2 give N = m g (17 cos phi - 10 cos
    phi0) / 7. Slip starts at the first phi with F = mu N."""
    phi0, mu = 0.1, 0.5
    cl, up = ball_on_fixed(phi0, mu, rot=rotation(3))
    e0 = cl.energy()
    st, ev, k, t = cl.advance(0.0, 100.0)
    assert (st, ev, k) == (C.CS_OK, C.CE_SLIP, 0)
    phi_ref = brentq(lambda p: 2.0 * math.sin(p) - mu * (17.0 * math.cos(p)
                                                         - 10.0 * math.cos(phi0)), phi0, 1.0)
    assert abs(polar(cl, up) - phi_ref) < 1e-9
    # the forces at the event: on the cone, N as the closed form
    N = G * (17.0 * math.cos(phi_ref) - 10.0 * math.cos(phi0)) / 7.0
    assert abs(cl.c[0, C.CC_LAMN] - N) < 1e-9 * G
    assert abs(np.linalg.norm(cl.c[0, C.CC_TX:C.CC_TX + 3]) - mu * N) < 1e-9 * G
    assert abs(cl.energy() - e0) < 1e-10 * G
    # slip (opposite to the sticking force) until lift-off: energy never increases
    assert cl.after(ev, k) == C.CS_OK
    assert cl.c[0, C.CC_MODE] == C.MODE_SLIP
    e = cl.energy()
    t_end = None
    for i in range(400):
        st, ev, k, t = cl.advance(t, t + 0.01)
        assert st == C.CS_OK
        e1 = cl.energy()
        assert e1 <= e + 1e-12 * G
        e = e1
        if ev == C.CE_LEAVE:
            t_end = t
            break
        assert ev == C.CE_NONE
    assert t_end is not None and e < e0 - 1e-4 * G


# ------------------------------------------------------------------ 3. a sphere on a free sphere


def two_stack(phi0, mu_ab, mu_floor=0.0, r1=0.5, r2=0.3, m1=2.0, m2=1.0, spin=0.0, rot=None):
    """Sphere 0 (r2, m2) on sphere 1 (r1, m1) on the floor z >= 0, at the polar angle phi0
    in the x-z plane, from rest (``spin``: sphere 0 turning about the vertical); ``rot``:
    the whole scene (floor, gravity) rotated."""
    Rm = np.eye(3) if rot is None else rot
    rho = r1 + r2
    x1 = np.array([0.0, 0.0, r1])
    x0 = x1 + rho * np.array([math.sin(phi0), 0.0, math.cos(phi0)])
    up = Rm[:, 2]
    return Cluster([sphere(Rm @ x0, r2, m=m2, w=spin * up), sphere(Rm @ x1, r1, m=m1)],
                   [contact(0, 1, mu=mu_ab), contact(1, n=up, mu=mu_floor)], g=-G * up,
                   L=rho)


def stack_reference(phi0, r1=0.5, r2=0.3, m1=2.0, m2=1.0):
    """Lagrange's equations of the frictionless stack in (x1, phi): T = (m1 + m2) x1'^2 / 2
    + m2 rho cos(phi) x1' phi' + m2 rho^2 phi'^2 / 2, V = m2 g rho cos(phi):
    (m1 + m2) x1'' + m2 rho (cos phi phi'' - sin phi phi'^2) = 0,
    cos phi x1'' + rho phi'' = g sin phi; the contact force (Newton, the upper sphere's
    radial equation) N = m2 (g cos phi + x1'' sin phi - rho phi'^2)."""
    rho = r1 + r2

    def acc(y):
        x, p, xd, pd = y
        A = np.array([[m1 + m2, m2 * rho * math.cos(p)], [math.cos(p), rho]])
        b = np.array([m2 * rho * math.sin(p) * pd * pd, G * math.sin(p)])
        return np.linalg.solve(A, b)

    def rhs(t, y):
        a = acc(y)
        return [y[2], y[3], a[0], a[1]]

    def normal(t, y):
        a = acc(y)
        return m2 * (G * math.cos(y[1]) + a[0] * math.sin(y[1]) - rho * y[3] ** 2)

    normal.terminal = True
    normal.direction = -1
    return solve_ivp(rhs, (0.0, 20.0), [0.0, phi0, 0.0, 0.0], method="DOP853", rtol=1e-13,
                     atol=1e-14, dense_output=True, events=normal)


def stack_angle(cl, rot=None):
    Rm = np.eye(3) if rot is None else rot
    d = Rm.T @ (cl.b[0, C.CB_X:C.CB_X + 3] - cl.b[1, C.CB_X:C.CB_X + 3])
    return math.atan2(d[0], d[2])


@pytest.mark.parametrize("seed", [None, 11])
def test_sphere_on_free_sphere_against_lagrange(seed):
    rot = None if seed is None else rotation(seed)
    Rm = np.eye(3) if rot is None else rot
    phi0 = 0.3
    ref = stack_reference(phi0)
    t_leave = ref.t_events[0][0]
    cl = two_stack(phi0, 0.0, rot=rot)
    e0 = cl.energy()
    t = 0.0
    for tk in (0.25 * t_leave, 0.5 * t_leave, 0.75 * t_leave):
        st, ev, k, t = cl.advance(t, tk)
        assert (st, ev) == (C.CS_OK, C.CE_NONE) and t == tk
        y = ref.sol(tk)
        assert abs(stack_angle(cl, rot) - y[1]) < 1e-8 * abs(y[1])
        x1 = Rm.T @ cl.b[1, C.CB_X:C.CB_X + 3]
        assert abs(x1[0] - y[0]) < 1e-8 * 0.8
        assert abs(cl.energy() - e0) < 1e-10 * G * 0.8
        # the floor holds the lower sphere; nothing turns (frictionless)
        assert abs(x1[2] - 0.5) < 1e-13 and abs(x1[1]) < 1e-13
        assert np.all(np.abs(cl.b[:, C.CB_WX:C.CB_WX + 3]) < 1e-12)
    st, ev, k, t = cl.advance(t, 10.0)
    assert (st, ev, k) == (C.CS_OK, C.CE_LEAVE, 0)
    assert abs(t - t_leave) < 1e-8 * t_leave
    assert abs(stack_angle(cl, rot) - ref.y_events[0][0][1]) < 1e-8


# ------------------------------------------------------------------ 4. conservation


def test_rolling_stack_conserves_energy_and_horizontal_momentum():
    """The upper sphere rolls (mu = inf) on the lower one, which slides on a frictionless
    floor; the upper one also spins about the vertical, so the motion leaves the plane:
    no work is done (energy conserved), no horizontal force acts on the pair (linear
    momentum in the floor's plane conserved, here zero)."""
    cl = two_stack(0.2, math.inf, spin=3.0)
    assert C.cluster_project(cl.b, cl.c, cl.nk, *cl.g, cl.L, cl.w, cl.la) == C.CS_OK
    e0 = cl.energy()
    p0 = cl.b[0, C.CB_M] * cl.b[0, C.CB_VX:C.CB_VX + 2] + cl.b[1, C.CB_M] * cl.b[1, C.CB_VX:C.CB_VX + 2]
    t = 0.0
    emax = 0.0
    moved = 0.0
    for i in range(30):
        st, ev, k, t = cl.advance(t, t + 0.05)
        assert st == C.CS_OK
        emax = max(emax, abs(cl.energy() - e0))
        p = (cl.b[0, C.CB_M] * cl.b[0, C.CB_VX:C.CB_VX + 2]
             + cl.b[1, C.CB_M] * cl.b[1, C.CB_VX:C.CB_VX + 2])
        assert np.all(np.abs(p - p0) < 1e-10 * math.sqrt(G * 0.8))
        moved = max(moved, abs(cl.b[0, C.CB_X + 1] - cl.b[1, C.CB_X + 1]))
        if ev == C.CE_LEAVE:
            break
        assert ev == C.CE_NONE
    assert emax < 1e-10 * G * 0.8
    assert moved > 1e-3      # out of the x-z plane: a 3D motion
    q = cl.b[0, C.CB_QW:C.CB_QW + 4]
    assert abs(np.linalg.norm(q) - 1.0) < 1e-14


# ------------------------------------------------------------------ 5. rest


def pyramid(mu):
    r = 0.5
    side = 2.0 * r
    cen = np.array([0.0, 0.0, r])
    bodies = []
    for j in range(3):
        a = 2.0 * math.pi * j / 3.0
        bodies.append(sphere(cen + side / math.sqrt(3.0) * np.array([math.cos(a), math.sin(a),
                                                                      0.0]), r))
    bodies.append(sphere(cen + np.array([0.0, 0.0, side * math.sqrt(2.0 / 3.0)]), r))
    contacts = [contact(j, mu=mu) for j in range(3)]
    contacts += [contact(3, j, mu=mu) for j in range(3)]
    contacts += [contact(0, 1, mu=mu), contact(1, 2, mu=mu), contact(2, 0, mu=mu)]
    return Cluster(bodies, contacts, L=2.0)


def test_pyramid_at_rest_with_symmetric_split():
    cl = pyramid(0.5)
    st, ev, k, t = cl.advance(0.0, 1.0)
    assert (st, ev, t) == (C.CS_REST, C.CE_NONE, 0.0)
    lam = cl.c[:, C.CC_LAMN]
    T = np.linalg.norm(cl.c[:, C.CC_TX:C.CC_TX + 3], axis=1)
    # the floor carries the weight, evenly; the top sphere's three contacts share it evenly
    assert abs(lam[:3].sum() - 4.0 * G) < 1e-10 * G
    for grp in (slice(0, 3), slice(3, 6), slice(6, 9)):
        assert np.ptp(lam[grp]) < 1e-10 * G
        assert np.ptp(T[grp]) < 1e-10 * G
    assert np.all(lam[:6] > 0.0) and np.all(T <= 0.5 * lam + 1e-12)


def test_not_at_rest_without_friction():
    # the frictionless pyramid's lower spheres would need tension between them
    cl = pyramid(0.0)
    st, ev, k, t = cl.advance(0.0, 1.0)
    assert st == C.CS_INCONSISTENT
    # a sphere slightly off the top of a sphere on the floor rolls off
    cl = two_stack(1e-3, 0.0)
    st, ev, k, t = cl.advance(0.0, 0.1)
    assert (st, ev) == (C.CS_OK, C.CE_NONE) and stack_angle(cl) > 1e-3


# ------------------------------------------------------------------ kinematics, selection


@pytest.mark.parametrize("plane", [False, True])
def test_rates_against_finite_differences(plane):
    """g'' and the tangential part of dw/dt of the kernel against central differences of
    g and c along x(t) = x + v t + a t^2 / 2, omega(t) = omega + alpha t (a state with
    dg/dt = 0, where the tangential part of dc/dt is that of dw/dt)."""
    rng = np.random.default_rng(5)
    if plane:
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        cl = Cluster([sphere(0.4 * n + 0.1, 0.4, v=rng.normal(size=3), w=rng.normal(size=3))],
                     [contact(0, n=n, d=float(np.dot(n, 0.4 * n + 0.1)) - 0.4)])
    else:
        cl = Cluster([sphere(rng.normal(size=3) * 0.1, 0.3, v=rng.normal(size=3),
                             w=rng.normal(size=3)),
                      sphere(np.array([0.0, 0.0, -0.7]), 0.4, v=rng.normal(size=3),
                             w=rng.normal(size=3))], [contact(0, 1)])
    C.cluster_project(cl.b, cl.c, cl.nk, *cl.g, cl.L, cl.w, cl.la)
    acc = rng.normal(size=(cl.b.shape[0], 6))
    out = np.zeros(12)
    b0 = cl.b.copy()

    def at(s):
        b = b0.copy()
        b[:, 0:3] += b0[:, C.CB_VX:C.CB_VX + 3] * s + 0.5 * acc[:, 0:3] * s * s
        b[:, C.CB_VX:C.CB_VX + 3] += acc[:, 0:3] * s
        b[:, C.CB_WX:C.CB_WX + 3] += acc[:, 3:6] * s
        o = np.zeros(12)
        C.cluster_rates(b, cl.c, 0, acc, cl.w, cl.la, o)
        return o

    o0 = at(0.0)
    h = 1e-4
    op, om = at(h), at(-h)
    assert abs(o0[1]) < 1e-12
    gdd = (op[0] - 2.0 * o0[0] + om[0]) / h ** 2
    assert abs(gdd - o0[2]) < 1e-6 * (1.0 + abs(o0[2]))
    assert abs((op[0] - om[0]) / (2 * h) - o0[1]) < 1e-7
    n = o0[9:12]
    dc = (op[3:6] - om[3:6]) / (2 * h)
    dc -= np.dot(dc, n) * n
    assert np.all(np.abs(dc - o0[6:9]) < 1e-6 * (1.0 + np.abs(o0[6:9]).max()))


def test_select_modes_frictionless_off_top_and_rough_rolls():
    # rough: the selection keeps the ball rolling (stick); frictionless: active, no force T
    cl, up = ball_on_fixed(0.2, 1.0)
    cl.c[0, C.CC_MODE] = C.MODE_LIFT
    assert cl.select() == C.CS_OK
    assert cl.c[0, C.CC_MODE] == C.MODE_STICK and cl.c[0, C.CC_LAMN] > 0.0
    # too little friction at phi = 0.2 rad for rolling (needs mu >= 2 sin / (7 cos) = 0.058)
    cl, up = ball_on_fixed(0.2, 0.03)
    assert cl.select() == C.CS_OK
    assert cl.c[0, C.CC_MODE] == C.MODE_SLIP
    # a sphere held below a fixed sphere falls away: lift-off
    cl, up = ball_on_fixed(math.pi, 1.0)
    assert cl.select() == C.CS_OK
    assert cl.c[0, C.CC_MODE] == C.MODE_LIFT


# ------------------------------------------------------------------ 6. bad input


def test_bad_input_raises():
    good = [sphere(np.array([0.0, 0.0, 0.5]), 0.5)]
    c = [contact(0)]
    with pytest.raises(ValueError, match="radius must be positive"):
        Cluster([sphere(np.zeros(3), -1.0)], c)
    with pytest.raises(ValueError, match="mass and moment"):
        Cluster([sphere(np.zeros(3), 1.0, m=0.0)], c)
    with pytest.raises(ValueError, match="unit vector"):
        Cluster(good, [contact(0, n=(0.0, 0.0, 2.0))])
    with pytest.raises(ValueError, match="mu must be >= 0"):
        Cluster(good, [contact(0, mu=-0.1)])
    with pytest.raises(ValueError, match="mu must be >= 0"):
        Cluster(good, [contact(0, mu=math.nan)])
    with pytest.raises(ValueError, match="out of range"):
        Cluster(good, [contact(0, 3)])
    with pytest.raises(ValueError, match="unit quaternion"):
        b = sphere(np.zeros(3), 1.0)
        b[C.CB_QW] = 2.0
        Cluster([b], c)
    with pytest.raises(ValueError, match="both sides fixed"):
        Cluster([sphere(np.zeros(3), 1.0, fixed=True)], c)
    with pytest.raises(ValueError, match="cannot slip"):
        Cluster(good, [contact(0, mu=math.inf, mode=C.MODE_SLIP)])


# ------------------------------------------------------------------ slip -> stick, a gap


def test_sliding_sphere_on_floor_stops_slipping_then_meets_a_wall():
    """A sphere sliding and spinning on the floor (any v0, omega0): the slip
    c = v + omega x (-r n) obeys dc/dt = -(1/m + r^2/I) mu m g c/|c| = -(7/2) mu g c/|c|,
    so it keeps its direction and falls linearly; the centre's acceleration is
    -mu g c0/|c0|. The kernel's stop fires at |c| = SLIP_EPS V; then it rolls at a
    constant velocity (energy conserved) into a wall candidate x <= X at a known time."""
    r, mu = 0.2, 0.3
    v0 = np.array([1.0, 0.4, 0.0])
    w0 = np.array([3.0, -5.0, 2.0])
    cl = Cluster([sphere((0.0, 0.0, r), r, v=v0, w=w0)], [contact(0, mu=mu, mode=C.MODE_SLIP)],
                 cands=[contact(0, n=(-1.0, 0.0, 0.0), d=-2.0)], L=r)
    n = np.array([0.0, 0.0, 1.0])
    c0 = v0 + np.cross(w0, -r * n)
    c0l = np.linalg.norm(c0)
    V = np.linalg.norm(v0) + np.linalg.norm(w0) * r + math.sqrt(G * r)
    t_stop = (c0l - C.SLIP_EPS * V) / (3.5 * mu * G)
    st, ev, k, t = cl.advance(0.0, 10.0)
    assert (st, ev, k) == (C.CS_OK, C.CE_STOP, 0)
    assert abs(t - t_stop) < 1e-12 * t_stop
    v_stop = v0 - mu * G * c0 / c0l * t_stop
    assert np.all(np.abs(cl.b[0, C.CB_VX:C.CB_VX + 3] - v_stop) < 1e-11)
    assert cl.after(ev, k) == C.CS_OK and cl.c[0, C.CC_MODE] == C.MODE_STICK
    x_stop = v0[0] * t_stop - 0.5 * mu * G * c0[0] / c0l * t_stop ** 2
    e1 = cl.energy()
    st, ev, k, t2 = cl.advance(t, 10.0)
    assert (st, ev, k) == (C.CS_OK, C.CE_GAP, 0)
    # rolling after the stop: the remaining slip SLIP_EPS V removed by the projection
    vr = cl.b[0, C.CB_VX]
    assert abs(t2 - t - (2.0 - r - x_stop) / vr) < 1e-9 * t2
    assert abs(cl.b[0, C.CB_X] - (2.0 - r)) < 1e-12
    assert abs(cl.energy() - e1) < 1e-8 * G * r


# ------------------------------------------------------------------ recording


def test_recorded_pieces_follow_the_integration():
    """The rolling, spinning stack recorded: per sphere, consecutive pieces evaluated at
    the next piece's start (``piece_state``) agree with it to the piece tolerances
    (centre and orientation PIECE_LTOL L, velocities PIECE_VTOL V), the last piece reaches
    the returned state, and the pieces' energy stays the run's."""
    cl = two_stack(0.2, math.inf, spin=3.0)
    C.cluster_project(cl.b, cl.c, cl.nk, *cl.g, cl.L, cl.w, cl.la)
    e0 = cl.energy()
    V = np.abs(cl.b[:, C.CB_VX:C.CB_VX + 3]).sum() + 3.0 * cl.L + math.sqrt(G * cl.L)
    m = 4000
    rec = (np.zeros(m), np.zeros(m, np.int64), np.zeros((m, C.N_ROW)), np.zeros(2, np.int64))
    st, ev, k, t = cl.advance(0.0, 0.3, rec)
    assert (st, ev) == (C.CS_OK, C.CE_NONE)
    seg_t, seg_b, seg_s, cnt = rec
    n = cnt[C.CNT_SEG]
    assert 10 < n < m and seg_t[0] == 0.0
    out = np.zeros(C.NS)
    for i in range(2):
        rows = np.flatnonzero(seg_b[:n] == i)
        assert np.all(np.diff(seg_t[rows]) > 0.0)
        ends = list(rows[1:]) + [None]
        for r, nx in zip(rows, ends):
            t1 = seg_t[nx] if nx is not None else t
            C.piece_state(seg_s[r], t1 - seg_t[r], out)
            ref = seg_s[nx, :C.NS] if nx is not None else cl.b[i, :C.NS]
            assert np.linalg.norm(out[0:3] - ref[0:3]) < 2 * C.PIECE_LTOL * cl.L
            dq = min(np.linalg.norm(out[3:7] - ref[3:7]), np.linalg.norm(out[3:7] + ref[3:7]))
            assert dq < 2 * C.PIECE_LTOL
            dv = np.linalg.norm(out[7:10] - ref[7:10]) + cl.L * np.linalg.norm(out[10:13]
                                                                               - ref[10:13])
            assert dv < 2 * C.PIECE_VTOL * V
        assert abs(np.linalg.norm(seg_s[rows, 3:7], axis=1) - 1.0).max() < 1e-14
    e = [sum(0.5 * cl.b[i, C.CB_M] * seg_s[r, 7:10] @ seg_s[r, 7:10]
             + 0.5 * cl.b[i, C.CB_I] * seg_s[r, 10:13] @ seg_s[r, 10:13]
             + cl.b[i, C.CB_M] * G * seg_s[r, 2] for i, r in enumerate(pair))
         for pair in zip(np.flatnonzero(seg_b[:n] == 0), np.flatnonzero(seg_b[:n] == 1))]
    assert np.max(np.abs(np.array(e) - e0)) < 1e-9 * G * cl.L


def test_rough_stack_sticks_slips_and_leaves():
    """Sphere on sphere (mu = 0.2), spinning about the vertical, the lower one on a
    frictionless floor: it rolls, slips (cluster_after_event: slip, the floor contact
    kept), then leaves; energy never increases (conserved while rolling), horizontal
    momentum is conserved throughout, and after the top sphere leaves the floor carries
    the lower sphere's weight alone."""
    cl = two_stack(0.15, 0.2, spin=2.0)
    C.cluster_project(cl.b, cl.c, cl.nk, *cl.g, cl.L, cl.w, cl.la)
    assert cl.select() == C.CS_OK and list(cl.c[:, C.CC_MODE]) == [C.MODE_STICK] * 2
    e0 = e = cl.energy()
    mom = lambda: (cl.b[0, C.CB_M] * cl.b[0, C.CB_VX:C.CB_VX + 2]
                   + cl.b[1, C.CB_M] * cl.b[1, C.CB_VX:C.CB_VX + 2])
    p0 = mom()
    t = 0.0
    events = []
    for i in range(100):
        st, ev, k, t = cl.advance(t, t + 0.05)
        assert st == C.CS_OK
        e1 = cl.energy()
        assert e1 <= e + 1e-12 * G
        if not events:
            assert abs(e1 - e0) < 1e-10 * G
        e = e1
        assert np.all(np.abs(mom() - p0) < 1e-12)
        if ev != C.CE_NONE:
            events.append((ev, k))
            if ev == C.CE_LEAVE:
                break
            assert cl.after(ev, k) == C.CS_OK
            assert list(cl.c[:, C.CC_MODE]) == [C.MODE_SLIP, C.MODE_STICK]
    assert events == [(C.CE_SLIP, 0), (C.CE_LEAVE, 0)]
    assert e < e0 - 1e-3
    assert cl.after(C.CE_LEAVE, 0) == C.CS_OK
    assert cl.c[0, C.CC_MODE] == C.MODE_LIFT
    assert abs(cl.c[1, C.CC_LAMN] - 2.0 * G) < 1e-10 * G


def groove(mu):
    """A sphere at rest in an asymmetric V groove (two fixed planes at 0.5 and 0.8 rad
    from the horizontal), gravity tilted along the groove and a little across it."""
    r = 0.3
    n1 = np.array([math.sin(0.5), 0.0, math.cos(0.5)])
    n2 = np.array([-math.sin(0.8), 0.0, math.cos(0.8)])
    gdir = np.array([0.1, math.sin(0.3), -math.cos(0.3)])
    gdir /= np.linalg.norm(gdir)
    return Cluster([sphere(np.zeros(3), r)], [contact(0, n=n1, d=-r, mu=mu),
                                              contact(0, n=n2, d=-r, mu=mu)], g=G * gdir, L=r)


def test_groove_slip_directions_follow_coulomb():
    """Both contacts start to slip from rest (mu = 0.05): the selection turns each start
    direction (first opposite to its all-stick force, which is not the answer here) until
    its slip accelerates along it, s || dc/dt; with mu = 2 the sphere rolls (both stick)
    with the forces in their cones; the motion afterwards dissipates energy."""
    cl = groove(0.05)
    assert cl.select() == C.CS_OK
    assert list(cl.c[:, C.CC_MODE]) == [C.MODE_SLIP, C.MODE_SLIP]
    st, acc = cl.forces()
    assert st == C.CS_OK
    out = np.zeros(12)
    for k in range(2):
        C.cluster_rates(cl.b, cl.c, k, acc, cl.w, cl.la, out)
        s = cl.c[k, C.CC_SX:C.CC_SX + 3]
        a = out[6:9]
        assert np.dot(s, a) > 0.1 * G
        assert np.linalg.norm(np.cross(s, a)) < 1e-10 * np.linalg.norm(a)
        assert abs(np.linalg.norm(cl.c[k, C.CC_TX:C.CC_TX + 3])
                   - 0.05 * cl.c[k, C.CC_LAMN]) < 1e-12 * G
    e0 = cl.energy()
    st, ev, k, t = cl.advance(0.0, 0.2)
    assert (st, ev) == (C.CS_OK, C.CE_NONE) and cl.energy() < e0 - 1e-3
    cl = groove(2.0)
    assert cl.select() == C.CS_OK
    assert list(cl.c[:, C.CC_MODE]) == [C.MODE_STICK, C.MODE_STICK]
    T = np.linalg.norm(cl.c[:, C.CC_TX:C.CC_TX + 3], axis=1)
    assert np.all(T < 2.0 * cl.c[:, C.CC_LAMN]) and np.all(cl.c[:, C.CC_LAMN] > 0.0)


def groove_squeeze(mu, r=0.3, m=1.0):
    """Closed form of the asymmetric ``groove`` rolling from rest with both contacts
    sticking: the sphere turns about the chord p1 p2 (both contact points at rest), so
    ``alpha = ((x - p1) x m g) . e / (I + m h^2)`` (e along the chord, h the centre's distance
    to it); the contact forces are then known up to a squeeze s along the chord
    (``F1 + s d, F2 - s d``, d = (p2 - p1) / |p2 - p1|: no net force or moment). Each cone
    ``|T_k(s)| <= mu lam_k(s)``, ``lam_k(s) >= 0`` is a quadratic inequality in s: its
    interval (empty: None). Returns the two intervals, the particular split and d, and
    the centre's acceleration."""
    n1 = np.array([math.sin(0.5), 0.0, math.cos(0.5)])
    n2 = np.array([-math.sin(0.8), 0.0, math.cos(0.8)])
    gdir = np.array([0.1, math.sin(0.3), -math.cos(0.3)])
    g = G * gdir / np.linalg.norm(gdir)
    I = 0.4 * m * r * r
    p1, p2 = -r * n1, -r * n2
    e = (p1 - p2) / np.linalg.norm(p1 - p2)
    h = -p1 - np.dot(-p1, e) * e
    alpha = np.dot(np.cross(-p1, m * g), e) / (I + m * np.dot(h, h))
    a = alpha * np.cross(e, -p1)
    # one split: the forces along the normals and the chord's normal plane (lstsq, rank 5)
    sk = lambda v: np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    Am = np.block([[np.eye(3), np.eye(3)], [sk(p1), sk(p2)]])
    F = np.linalg.lstsq(Am, np.concatenate([m * a - m * g, I * alpha * e]), rcond=None)[0]
    d = (p2 - p1) / np.linalg.norm(p2 - p1)
    ivs = []
    for Fk, nk, sg in ((F[:3], n1, 1.0), (F[3:], n2, -1.0)):
        a0, a1 = np.dot(Fk, nk), sg * np.dot(d, nk)
        c0, c1 = Fk - a0 * nk, sg * (d - np.dot(d, nk) * nk)
        qa = mu * mu * a1 * a1 - np.dot(c1, c1)
        qb = 2.0 * (mu * mu * a0 * a1 - np.dot(c0, c1))
        qc = mu * mu * a0 * a0 - np.dot(c0, c0)
        disc = qb * qb - 4.0 * qa * qc
        assert qa < 0.0          # the chord is outside both cones at these mu
        if disc <= 0.0:
            ivs.append(None)
            continue
        lo, hi = sorted(((-qb - math.sqrt(disc)) / (2 * qa), (-qb + math.sqrt(disc)) / (2 * qa)))
        sn = -a0 / a1            # lam_k = 0: the cone's two nappes; keep lam_k >= 0
        lo, hi = (max(lo, sn), hi) if a1 > 0.0 else (lo, min(hi, sn))
        ivs.append((lo, hi) if lo < hi else None)
    return ivs, F, d, a


@pytest.mark.parametrize("mu", [0.5, 0.2])
def test_groove_redundant_stick_split_inside_cones(mu):
    """At mu = 0.5 and 0.2 the minimum-norm split leaves a cone but a squeeze along the
    chord puts both forces inside theirs (closed form: the two intervals of s intersect):
    the selection sticks both contacts with such a split, and the sphere rolls down the
    groove (no event) at the closed-form acceleration, conserving energy."""
    ivs, F, d, a = groove_squeeze(mu)
    lo, hi = max(ivs[0][0], ivs[1][0]), min(ivs[0][1], ivs[1][1])
    assert lo < hi and lo > 0.0      # a split exists, and it is not the min-norm one (s > 0)
    cl = groove(mu)
    assert cl.select() == C.CS_OK
    assert list(cl.c[:, C.CC_MODE]) == [C.MODE_STICK, C.MODE_STICK]
    f = [cl.c[k, C.CC_LAMN] * cl.c[k, C.CC_NX:C.CC_NX + 3] + cl.c[k, C.CC_TX:C.CC_TX + 3]
         for k in range(2)]
    # the same net force and moment as the closed form, a squeeze inside the interval
    assert np.linalg.norm(f[0] + f[1] - F[:3] - F[3:]) < 1e-10 * G
    s = np.dot(f[0] - F[:3], d)
    assert np.linalg.norm(f[0] - F[:3] - s * d) < 1e-9 * G
    assert np.linalg.norm(f[1] - F[3:] + s * d) < 1e-9 * G
    assert lo - 1e-9 * G <= s <= hi + 1e-9 * G
    T = np.linalg.norm(cl.c[:, C.CC_TX:C.CC_TX + 3], axis=1)
    assert np.all(T <= mu * cl.c[:, C.CC_LAMN] + 1e-10 * G)
    st, acc = cl.forces()
    assert st == C.CS_OK and np.linalg.norm(acc[0, :3] - a) < 1e-10 * G
    e0 = cl.energy()
    t1 = 0.2
    st, ev, k, t = cl.advance(0.0, t1)
    assert (st, ev) == (C.CS_OK, C.CE_NONE)
    assert np.linalg.norm(cl.b[0, C.CB_X:C.CB_X + 3] - 0.5 * a * t1 * t1) < 1e-9
    assert abs(cl.energy() - e0) < 1e-9 * G * 0.3


def test_groove_without_split_slips():
    """At mu = 0.1 no squeeze puts the second contact's force in its cone (closed form:
    its interval is empty): the selection does not stick both contacts."""
    ivs, F, d, a = groove_squeeze(0.1)
    assert ivs[1] is None
    cl = groove(0.1)
    st = cl.select()
    assert st in (C.CS_OK, C.CS_NO_MODE)
    assert list(cl.c[:, C.CC_MODE]) != [C.MODE_STICK, C.MODE_STICK]
    if st == C.CS_OK:
        assert cl.c[1, C.CC_MODE] != C.MODE_STICK


def test_backspin_stops_at_rest_after_the_slip_stop():
    """Rest is reached in finite time only at a slip stop (module docstring, "Rest"): a
    sphere with backspin ``omega0 = v0 / (0.4 r)`` has zero angular momentum about its
    contact point, which friction keeps; v and r omega fall to zero together. The stop
    fires (CE_STOP at the closed-form time), the stick projection removes the remaining
    slip keeping that momentum (zero): the next call finds the rest."""
    r, mu, v0 = 0.2, 0.3, 0.7
    w0 = v0 / (0.4 * r)
    cl = Cluster([sphere((0.0, 0.0, r), r, v=(v0, 0.0, 0.0), w=(0.0, -w0, 0.0))],
                 [contact(0, mu=mu, mode=C.MODE_SLIP)], L=r)
    c0 = v0 + r * w0
    V = v0 + w0 * r + math.sqrt(G * r)
    t_stop = (c0 - C.SLIP_EPS * V) / (3.5 * mu * G)
    st, ev, k, t = cl.advance(0.0, 10.0)
    assert (st, ev, k) == (C.CS_OK, C.CE_STOP, 0)
    assert abs(t - t_stop) < 1e-12 * t_stop
    assert cl.after(ev, k) == C.CS_OK and cl.c[0, C.CC_MODE] == C.MODE_STICK
    st, ev, k, t2 = cl.advance(t, 10.0)
    assert (st, ev, t2) == (C.CS_REST, C.CE_NONE, t)
    vr = (np.linalg.norm(cl.b[0, C.CB_VX:C.CB_VX + 3])
          + r * np.linalg.norm(cl.b[0, C.CB_WX:C.CB_WX + 3]))
    assert vr <= C.REST_VTOL * math.sqrt(G * r)
