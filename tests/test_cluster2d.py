"""kernels/cluster2d.py: persistent contact between several 2D bodies (issue 16 item 2).

Closed forms (a disk rolling off a cylinder: lift-off at cos phi = 4/7, frictionless 2/3;
a stack of boxes at rest; blocks on an incline), an independent scipy integration of the
constrained Newton-Euler equations with Lagrange multipliers, energy, projection drift,
each contact kind's g'' against finite differences of the exact gap, and the status codes.
"""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rbimpact.kernels import cluster2d as C

G = 9.81


# ------------------------------------------------------------------ helpers


def body(x, y, a=0.0, vx=0.0, vy=0.0, w=0.0, m=1.0, I=1.0, fixed=False):
    r = np.zeros(C.N_CB)
    r[[C.CB_X, C.CB_Y, C.CB_ANGLE, C.CB_VX, C.CB_VY, C.CB_OMEGA]] = x, y, a, vx, vy, w
    r[C.CB_M] = m
    r[C.CB_I] = I
    r[C.CB_FIXED] = 1.0 if fixed else 0.0
    return r


def contact(kind, A, B=-1, pa=(0.0, 0.0), ra=0.0, pb=(0.0, 0.0), rb=0.0, n=(0.0, 1.0), d=0.0,
            mu=0.0, mode=C.MODE_STICK, a_cone=(-math.inf, math.inf),
            b_range=(-math.inf, math.inf)):
    r = np.zeros(C.N_CC)
    r[C.CC_ALO], r[C.CC_AHI] = a_cone
    r[C.CC_BLO], r[C.CC_BHI] = b_range
    r[C.CC_KIND] = kind
    r[C.CC_A] = A
    r[C.CC_B] = B
    r[C.CC_PAX], r[C.CC_PAY] = pa
    r[C.CC_RA] = ra
    r[C.CC_PBX], r[C.CC_PBY] = pb
    r[C.CC_RB] = rb
    r[C.CC_NX], r[C.CC_NY] = n
    r[C.CC_D] = d
    r[C.CC_MU] = mu
    r[C.CC_MODE] = mode
    return r


class Cluster:
    """Tables and work arrays of one cluster (Python convenience for the tests)."""

    def __init__(self, bodies, contacts, cands=(), g=(0.0, -G), L=1.0):
        self.b = np.array(bodies, dtype=np.float64)
        self.c = np.array(contacts, dtype=np.float64).reshape(-1, C.N_CC)
        self.nk = self.c.shape[0]
        self.cand = np.array(cands, dtype=np.float64).reshape(-1, C.N_CC)
        if self.cand.shape[0] == 0:
            self.cand = np.zeros((1, C.N_CC))
            self.nc = 0
        else:
            self.nc = self.cand.shape[0]
        self.g = g
        self.L = L
        C.validate_cluster(self.b, self.c, self.nk, self.cand, self.nc, L)
        self.w = np.zeros(C.work_size(self.b.shape[0], self.nc))
        self.la = np.zeros(C.N_LA)
        self.acc = np.zeros((self.b.shape[0], 3))

    def forces(self):
        return C.cluster_forces(self.b, self.c, self.nk, self.g[0], self.g[1], self.L, self.w,
                                self.la, self.acc)

    def select(self):
        return C.cluster_select_modes(self.b, self.c, self.nk, self.g[0], self.g[1], self.L,
                                      self.w, self.la)

    def project(self):
        return C.cluster_project(self.b, self.c, self.nk, self.g[0], self.g[1], self.L, self.w,
                                 self.la)

    def advance(self, t0, t1, rec=None):
        """rec: (seg_t, seg_b, seg_s, cnt) to record pieces (ids = body rows)."""
        if rec is None:
            rec = (np.zeros(0), np.zeros(0, np.int64), np.zeros((0, 9)), np.zeros(3, np.int64))
        ids = np.arange(self.b.shape[0], dtype=np.int64)
        return C.cluster_advance(self.b, self.c, self.nk, self.cand, self.nc, self.g[0],
                                 self.g[1], self.L, t0, t1, self.w, self.la, *rec, ids)

    def after_event(self, ev, k):
        return C.cluster_after_event(self.b, self.c, self.nk, ev, k, self.g[0], self.g[1],
                                     self.L, self.w, self.la)

    def energy(self):
        return C.cluster_energy(self.b, self.g[0], self.g[1])

    def rates(self, k, table=None):
        out = np.zeros(7)
        C.cluster_rates(self.b, self.c if table is None else table, k, self.acc, self.w, out)
        return out


def rot(a, p):
    c, s = math.cos(a), math.sin(a)
    return np.array([c * p[0] - s * p[1], s * p[0] + c * p[1]])


# ------------------------------------------------------------------ 6. g'' of each kind


def _exact_gap_and_slip(row, st):
    """Independent gap and slip of contact row ``row`` for body states st[i] = (x, y, a, vx,
    vy, w): the geometry written from scratch (module docstring of cluster2d, DESIGN §3)."""
    kind = int(row[C.CC_KIND])
    A = int(row[C.CC_A])
    B = int(row[C.CC_B])
    xa = np.array(st[A][:2])
    ca = xa + rot(st[A][2], row[[C.CC_PAX, C.CC_PAY]])
    rA = row[C.CC_RA]
    if kind == C.KIND_PLANE:
        n = row[[C.CC_NX, C.CC_NY]]
        g = n @ ca - row[C.CC_D] - rA
    else:
        xb = np.array(st[B][:2])
        pb = xb + rot(st[B][2], row[[C.CC_PBX, C.CC_PBY]])
        if kind == C.KIND_ROUND:
            dd = ca - pb
            n = dd / np.linalg.norm(dd)
            g = np.linalg.norm(dd) - rA - row[C.CC_RB]
        else:
            n = rot(st[B][2], row[[C.CC_NX, C.CC_NY]])
            g = n @ (ca - pb) - rA - row[C.CC_RB]
    p = ca - rA * n
    t = np.array([n[1], -n[0]])

    def vel(i):
        x = np.array(st[i][:2])
        r = p - x
        return np.array(st[i][3:5]) + st[i][5] * np.array([-r[1], r[0]])
    dv = vel(A) - (vel(B) if kind != C.KIND_PLANE else 0.0)
    _exact_gap_and_slip.frame = (n, t, p)
    return g, t @ dv


KIND_CASES = {
    # (bodies, contact): generic positions, velocities, features with and without radius
    "round-round": ([body(0.1, 0.9, 0.4, 0.3, -0.7, 1.3, m=1.2, I=0.3),
                     body(-0.2, 0.05, -0.6, -0.5, 0.2, -2.1, m=0.7, I=0.1)],
                    contact(C.KIND_ROUND, 0, 1, pa=(0.05, -0.1), ra=0.3, pb=(0.1, 0.02), rb=0.25)),
    "vertex-face": ([body(0.1, 0.9, 0.4, 0.3, -0.7, 1.3, m=1.2, I=0.3),
                     body(-0.2, 0.05, 0.3, -0.5, 0.2, -2.1, m=0.7, I=0.1)],
                    contact(C.KIND_FACE, 0, 1, pa=(-0.2, -0.3), ra=0.0, pb=(0.1, 0.2),
                            rb=0.0, n=(math.sin(0.2), math.cos(0.2)))),
    "round-capsule side": ([body(0.1, 0.9, 0.4, 0.3, -0.7, 1.3, m=1.2, I=0.3),
                            body(-0.2, 0.05, 0.3, -0.5, 0.2, -2.1, m=0.7, I=0.1)],
                           contact(C.KIND_FACE, 0, 1, pa=(-0.2, -0.3), ra=0.15, pb=(0.1, 0.2),
                                   rb=0.1, n=(0.0, 1.0))),
    "round-plane": ([body(0.1, 0.9, 0.4, 0.3, -0.7, 1.3, m=1.2, I=0.3)],
                    contact(C.KIND_PLANE, 0, -1, pa=(0.2, -0.1), ra=0.2,
                            n=(-math.sin(0.3), math.cos(0.3)), d=0.1)),
}


@pytest.mark.parametrize("name", list(KIND_CASES))
def test_gap_second_derivative_against_finite_differences(name):
    """g, g', g'' and vT, dvT/dt of each kind against finite differences of the exact gap
    and slip along a motion with constant (arbitrary) accelerations."""
    bodies, row = KIND_CASES[name]
    cl = Cluster(bodies, [row], g=(0.0, 0.0))
    rng = np.random.default_rng(7)
    cl.acc[:] = rng.normal(size=cl.acc.shape)
    out = cl.rates(0)

    def state(t):
        st = []
        for i in range(cl.b.shape[0]):
            q = cl.b[i, :3] + cl.b[i, 3:6] * t + 0.5 * cl.acc[i] * t * t
            v = cl.b[i, 3:6] + cl.acc[i] * t
            st.append(np.concatenate([q, v]))
        return st
    h = 1e-3
    vals = np.array([_exact_gap_and_slip(row, state(k * h)) for k in (-2, -1, 0, 1, 2)])
    g0 = vals[2, 0]
    d1 = (vals[0] - 8 * vals[1] + 8 * vals[3] - vals[4]) / (12 * h)      # O(h^4)
    d2 = (-vals[0] + 16 * vals[1] - 30 * vals[2] + 16 * vals[3] - vals[4]) / (12 * h * h)
    assert out[0] == pytest.approx(g0, abs=1e-14)
    assert out[1] == pytest.approx(d1[0], abs=1e-9)
    assert out[2] == pytest.approx(d2[0], abs=1e-6)
    assert out[3] == pytest.approx(vals[2, 1], abs=1e-14)
    assert out[4] == pytest.approx(d1[1], abs=1e-9)
    assert abs(out[2]) > 0.1 and abs(out[4]) > 0.1      # not trivially zero


# ------------------------------------------------------------------ 1. disk off a cylinder


def disk_on_cylinder(mu, v0, R=1.0, r=0.5, m=1.0):
    """Disk (radius r, I = m r^2 / 2) on top of a fixed cylinder (radius R) with the
    tangential speed v0, rolling (mu > 0) or sliding (mu = 0)."""
    I = 0.5 * m * r * r
    w0 = -v0 / r if mu > 0.0 else 0.0        # rolling: v_p = v + w J (0, -r) = (v + w r, 0)
    bodies = [body(0.0, 0.0, m=1.0, I=1.0, fixed=True),
              body(0.0, R + r, 0.0, v0, 0.0, w0, m=m, I=I)]
    mode = C.MODE_STICK if mu > 0.0 else C.MODE_SLIP_POS
    ct = contact(C.KIND_ROUND, 1, 0, ra=r, rb=R, mu=mu, mode=mode)
    return Cluster(bodies, [ct], L=R + r)


@pytest.mark.parametrize("rolling", [True, False], ids=["rolling", "frictionless"])
def test_disk_leaves_cylinder_at_closed_form_angle(rolling):
    """Rolling (mu = inf): energy m g (R + r)(1 - cos phi) = (1/2)(m + I/r^2) v^2 - (1/2)
    (m + I/r^2) v0^2 with v = (R + r) dphi/dt and I/r^2 = m/2; the normal force
    m g cos phi - m v^2 / (R + r) vanishes at cos phi = 4/7 + (3/7) v0^2 / (g (R + r)).
    Frictionless: (1/2) m v^2 only: cos phi = 2/3 + v0^2 / (3 g (R + r))."""
    R, r = 1.0, 0.5
    v0 = 1e-3 * math.sqrt(G * (R + r))
    cl = disk_on_cylinder(math.inf if rolling else 0.0, v0, R, r)
    q = v0 * v0 / (G * (R + r))
    expect = 4.0 / 7.0 + 3.0 / 7.0 * q if rolling else 2.0 / 3.0 + q / 3.0
    e0 = cl.energy()
    st, ev, k, t = cl.advance(0.0, 30.0)
    assert st == C.CS_OK and ev == C.CE_LEAVE and k == 0
    cphi = cl.b[1, C.CB_Y] / (R + r)
    assert abs(cphi - expect) < 1e-8, cphi - expect
    assert abs(cl.energy() - e0) < 1e-10 * G * (R + r)
    assert abs(cl.c[0, C.CC_LAMN]) < 1e-7 * G
    # on the constraint: the gap and, rolling, the slip
    out = cl.rates(0)
    assert abs(out[0]) < 1e-12 * (R + r)
    if rolling:
        assert abs(out[3]) < 1e-12 * math.sqrt(G * (R + r))
    test_disk_leaves_cylinder_at_closed_form_angle.err = cphi - expect


# ------------------------------------------------------------------ 3. a stack at rest


def box_inertia(m, w, h):
    return m * (w * w + h * h) / 12.0


def test_stack_of_boxes_rests_with_the_weights_above():
    """Four boxes on a floor, each face contact two point-face contacts at the ends of the
    overlap (a narrower box's corners on the face below; a wider box's face on the corners
    below: the mirror, A the corners' body). Rest is detected, nothing moves, and each pair
    of normal forces is the statics of the weight above: N_a + N_b = W, N_a x_a + N_b x_b =
    W x_bar (x_bar the centre of mass of the boxes above)."""
    # (width, height, mass, x centre)
    spec = [(2.0, 0.5, 3.0, 0.0), (1.2, 0.4, 1.0, 0.3), (1.6, 0.3, 0.5, 0.1),
            (0.5, 0.6, 0.8, -0.2)]
    bodies, contacts, faces = [], [], []
    y = 0.0
    for i, (wd, h, m, x) in enumerate(spec):
        bodies.append(body(x, y + h / 2, m=m, I=box_inertia(m, wd, h)))
        y += h
    for i, (wd, h, m, x) in enumerate(spec):
        if i == 0:
            for sx in (-1, 1):
                contacts.append(contact(C.KIND_PLANE, 0, -1, pa=(sx * wd / 2, -h / 2),
                                        mu=0.6))
            faces.append([(x - wd / 2, 0), (x + wd / 2, 1)])
            continue
        wl, hl, ml, xl = spec[i - 1]
        pair = []
        for sx in (-1, 1):
            if wd <= wl:      # this box's bottom corners on the top face of the one below
                contacts.append(contact(C.KIND_FACE, i, i - 1, pa=(sx * wd / 2, -h / 2),
                                        pb=(0.0, hl / 2), n=(0.0, 1.0), mu=0.6))
                pair.append((x + sx * wd / 2, len(contacts) - 1))
            else:             # the lower box's top corners on this box's bottom face
                contacts.append(contact(C.KIND_FACE, i - 1, i, pa=(sx * wl / 2, hl / 2),
                                        pb=(0.0, -h / 2), n=(0.0, -1.0), mu=0.6))
                pair.append((xl + sx * wl / 2, len(contacts) - 1))
        faces.append(pair)
    # 8 contacts: the enumeration handles at most KSEL_MAX; rest is decided by the modes
    # given (all sticking), as the stepper would after an accumulation
    cl = Cluster(bodies, contacts, L=2.0)
    before = cl.b.copy()
    st, ev, k, t = cl.advance(0.0, 10.0)
    assert st == C.CS_REST and ev == C.CE_NONE and t == 0.0
    assert np.max(np.abs(cl.b - before)) <= 1e-12
    for i, pair in enumerate(faces):
        W = G * sum(s[2] for s in spec[i:])
        xbar = sum(s[2] * s[3] for s in spec[i:]) / sum(s[2] for s in spec[i:])
        (xa, ka), (xb, kb) = pair
        Nb = W * (xbar - xa) / (xb - xa)
        Na = W - Nb
        assert cl.c[ka, C.CC_LAMN] == pytest.approx(Na, rel=1e-12, abs=1e-12 * W)
        assert cl.c[kb, C.CC_LAMN] == pytest.approx(Nb, rel=1e-12, abs=1e-12 * W)
        assert abs(cl.c[ka, C.CC_LAMT]) < 1e-12 * W and abs(cl.c[kb, C.CC_LAMT]) < 1e-12 * W


def test_three_box_stack_mode_selection_finds_rest():
    """Three boxes (6 contacts, within KSEL_MAX): the enumeration picks all sticking."""
    spec = [(2.0, 0.5, 3.0, 0.0), (1.2, 0.4, 1.0, 0.3), (0.8, 0.3, 0.5, 0.1)]
    bodies, contacts = [], []
    y = 0.0
    for wd, h, m, x in spec:
        bodies.append(body(x, y + h / 2, m=m, I=box_inertia(m, wd, h)))
        y += h
    for sx in (-1, 1):
        contacts.append(contact(C.KIND_PLANE, 0, -1, pa=(sx * 1.0, -0.25), mu=0.5))
    for i in (1, 2):
        wd, h = spec[i][:2]
        for sx in (-1, 1):
            contacts.append(contact(C.KIND_FACE, i, i - 1, pa=(sx * wd / 2, -h / 2),
                                    pb=(0.0, spec[i - 1][1] / 2), n=(0.0, 1.0), mu=0.5))
    cl = Cluster(bodies, contacts, L=2.0)
    cl.c[:, C.CC_MODE] = C.MODE_LIFT
    assert cl.select() == C.CS_OK
    assert np.all(cl.c[:, C.CC_MODE] == C.MODE_STICK)
    st, ev, k, t = cl.advance(0.0, 10.0)
    assert st == C.CS_REST
    assert cl.c[0, C.CC_LAMN] + cl.c[1, C.CC_LAMN] == pytest.approx(4.5 * G, rel=1e-13)


def _box_column(n, w=0.4, h=0.2, m=1.0, mu_floor=0.6, mu=0.6, mu_top=None, v_top=0.0):
    """n equal boxes stacked on a floor, each resting on the one below by its two bottom
    corners (2 n contacts); the top one sliding at v_top along +x on friction mu_top."""
    bodies, contacts = [], []
    for i in range(n):
        bodies.append(body(0.0, h / 2 + i * h, vx=v_top if i == n - 1 else 0.0, m=m,
                           I=box_inertia(m, w, h)))
    for sx in (-1, 1):
        contacts.append(contact(C.KIND_PLANE, 0, -1, pa=(sx * w / 2, -h / 2), mu=mu_floor))
    for i in range(1, n):
        top = i == n - 1 and mu_top is not None
        for sx in (-1, 1):
            contacts.append(contact(C.KIND_FACE, i, i - 1, pa=(sx * w / 2, -h / 2),
                                    pb=(0.0, h / 2), n=(0.0, 1.0), mu=mu_top if top else mu,
                                    mode=C.MODE_SLIP_POS if top and v_top else C.MODE_STICK))
    return bodies, contacts


def test_five_box_stack_mode_selection_beyond_the_enumeration():
    """Five boxes (10 contacts, beyond KSEL_MAX): the local search's base combination, every
    contact sticking, is consistent; the stack rests with each face carrying the weight
    above, half on each corner."""
    bodies, contacts = _box_column(5)
    cl = Cluster(bodies, contacts, L=1.0)
    assert cl.nk > C.KSEL_MAX
    cl.c[:, C.CC_MODE] = C.MODE_LIFT
    assert cl.select() == C.CS_OK
    assert np.all(cl.c[:, C.CC_MODE] == C.MODE_STICK)
    st, ev, k, t = cl.advance(0.0, 10.0)
    assert st == C.CS_REST
    for i in range(5):
        W = G * (5 - i)
        assert cl.c[2 * i:2 * i + 2, C.CC_LAMN] == pytest.approx([W / 2, W / 2], rel=1e-12)


def test_top_box_of_a_five_box_stack_slides_to_a_stop():
    """The top box of five slides at v on friction mu_top = 0.2 (the others 0.6: they hold):
    it decelerates at mu_top g and sticks at v / (mu_top g) after v^2 / (2 mu_top g); at the
    stop (CE_STOP) both corners stick (they stop at the same instant: held sliding, the
    other's friction would push the stopping one's force onto its cone and reverse its
    slip) and the stack rests."""
    v, mut = 0.3, 0.2
    bodies, contacts = _box_column(5, mu_top=mut, v_top=v)
    cl = Cluster(bodies, contacts, L=1.0)
    st, ev, k, t = cl.advance(0.0, 10.0)
    assert (st, ev) == (C.CS_OK, C.CE_STOP) and k in (8, 9)
    ts = v / (mut * G)
    assert t == pytest.approx(ts, rel=1e-9)
    xs = v * v / (2 * mut * G)
    assert cl.b[4, C.CB_X] == pytest.approx(xs, rel=1e-9)
    assert np.abs(cl.b[:4, C.CB_X]).max() < 1e-12         # the boxes below held
    assert cl.after_event(ev, k) == C.CS_OK
    assert np.all(cl.c[:, C.CC_MODE] == C.MODE_STICK)
    st, ev, k, t = cl.advance(t, 10.0)
    assert st == C.CS_REST
    assert cl.b[4, C.CB_X] == pytest.approx(xs, rel=1e-9)


def _sliding_pair(layout, v, mu, mu_top):
    """Box 1 (0.2 m high) resting on box 0 (0.4 x 0.2 m) on a floor, both moving at v along
    +x. Contacts: box 0's bottom corners on the floor; then the two ends of the overlap:
    "narrow" (box 1 0.3 m wide) box 1's corners on box 0's face; "wide" (0.5 m, shifted
    -0.05 m) box 0's corners on box 1's face (normal down); "offset" (0.4 m, shifted 0.1 m)
    box 1's left corner on box 0 and box 0's right corner on box 1 (rows in both orders)."""
    h = 0.2
    w0 = 0.4
    w1, off = {"narrow": (0.3, 0.02), "wide": (0.5, -0.05), "offset": (0.4, 0.1)}[layout]
    bodies = [body(0.0, h / 2, vx=v, I=box_inertia(1.0, w0, h)),
              body(off, 1.5 * h, vx=v, I=box_inertia(1.0, w1, h))]
    contacts = [contact(C.KIND_PLANE, 0, -1, pa=(sx * w0 / 2, -h / 2), mu=mu) for sx in (-1, 1)]
    if layout == "narrow":
        contacts += [contact(C.KIND_FACE, 1, 0, pa=(sx * w1 / 2, -h / 2), pb=(0.0, h / 2),
                             n=(0.0, 1.0), mu=mu_top) for sx in (-1, 1)]
    elif layout == "wide":
        contacts += [contact(C.KIND_FACE, 0, 1, pa=(sx * w0 / 2, h / 2), pb=(0.0, -h / 2),
                             n=(0.0, -1.0), mu=mu_top) for sx in (-1, 1)]
    else:
        contacts += [contact(C.KIND_FACE, 1, 0, pa=(-w1 / 2, -h / 2), pb=(0.0, h / 2),
                             n=(0.0, 1.0), mu=mu_top),
                     contact(C.KIND_FACE, 0, 1, pa=(w0 / 2, h / 2), pb=(0.0, -h / 2),
                             n=(0.0, -1.0), mu=mu_top)]
    return Cluster(bodies, contacts, L=0.5)


@pytest.mark.parametrize("layout", ["narrow", "wide", "offset"])
def test_two_box_stack_slides_on_the_floor_to_a_stop(layout):
    """Two boxes, one on the other, sliding together on a rough floor (mu = 0.3; 0.4 between
    the boxes): the upper box sticks on the lower one, whose floor friction decelerates both
    at mu g, stopping after v / (mu g) and v^2 / (2 mu g) (closed form). The two ends of the boxes'
    face contact have the same tangential row: the minimum-norm split (equal halves) put the
    lightly loaded end outside its cone and no mode was found (the stepper refused the scene
    as Painleve); the split is now proportional to the cones (``_split_friction``): each end
    inside its cone, ``lam_T / lam_N`` equal."""
    v, mu, mu_top = 1.0, 0.3, 0.4
    cl = _sliding_pair(layout, v, mu, mu_top)
    cl.c[:, C.CC_MODE] = C.MODE_LIFT
    assert cl.select() == C.CS_OK
    assert list(cl.c[:, C.CC_MODE]) == [1, 1, 0, 0]
    ln = cl.c[2:, C.CC_LAMN]
    lt = cl.c[2:, C.CC_LAMT]
    assert np.all(ln > 0.1) and abs(ln[0] - ln[1]) > 0.1      # unequal loads
    assert np.all(np.abs(lt) < mu_top * ln)
    assert lt[0] / ln[0] == pytest.approx(lt[1] / ln[1], rel=1e-12)
    # box 1 decelerates at mu g: the x-force on it is lam_T in both row orders (t = (1, 0)
    # on box 1 as A; t = (-1, 0) on box 0 as A, the opposite force on box 1)
    assert np.sum(lt) == pytest.approx(-mu * G, rel=1e-12)
    st, ev, k, t = cl.advance(0.0, 10.0)
    assert (st, ev, k) == (C.CS_OK, C.CE_STOP, 0) or (st, ev, k) == (C.CS_OK, C.CE_STOP, 1)
    assert t == pytest.approx(v / (mu * G), rel=1e-9)
    x0 = {"narrow": 0.02, "wide": -0.05, "offset": 0.1}[layout]
    assert cl.b[0, C.CB_X] == pytest.approx(v * v / (2 * mu * G), rel=1e-9)
    assert cl.b[1, C.CB_X] - cl.b[0, C.CB_X] == pytest.approx(x0, abs=1e-12)
    assert cl.after_event(ev, k) == C.CS_OK
    assert np.all(cl.c[:, C.CC_MODE] == C.MODE_STICK)
    st, ev, k, t = cl.advance(t, 10.0)
    assert st == C.CS_REST


# ------------------------------------------------------------------ 4. blocks on an incline


def blocks_on_incline(th, mu1, mu2, m1=2.0, m2=1.0, w1=1.0, h1=0.3, w2=0.6, h2=0.2, u=0.1):
    """Block 0 (w1 x h1) on the plane through the origin inclined at th, block 1 (w2 x h2)
    on it, offset u along the incline; both at rest. Contacts: block 0's bottom corners on
    the plane (mu1), block 1's bottom corners on block 0's top face (mu2)."""
    n = np.array([-math.sin(th), math.cos(th)])
    tdir = np.array([math.cos(th), math.sin(th)])
    c0 = 2.0 * tdir + (h1 / 2) * n
    c1 = c0 + u * tdir + (h1 / 2 + h2 / 2) * n
    bodies = [body(*c0, a=th, m=m1, I=box_inertia(m1, w1, h1)),
              body(*c1, a=th, m=m2, I=box_inertia(m2, w2, h2))]
    contacts = [contact(C.KIND_PLANE, 0, -1, pa=(sx * w1 / 2, -h1 / 2), n=tuple(n), mu=mu1)
                for sx in (-1, 1)]
    contacts += [contact(C.KIND_FACE, 1, 0, pa=(sx * w2 / 2, -h2 / 2), pb=(0.0, h1 / 2),
                         n=(0.0, 1.0), mu=mu2) for sx in (-1, 1)]
    return Cluster(bodies, contacts, L=w1)


INCLINE_CASES = {
    # name: (theta, mu1, mu2, modes (plane, plane, face, face), a1, a2 along -t in g)
    "rest": (math.radians(20), 0.8, 0.8, [0, 0, 0, 0], 0.0, 0.0),
    "lower slides, upper sticks": (math.radians(20), 0.2, 0.8, [-1, -1, 0, 0], None, None),
    "both slide": (math.radians(30), 0.3, 0.1, [-1, -1, -1, -1], None, None),
    "upper slides on a sticking lower": (math.radians(30), 0.9, 0.1, [0, 0, -1, -1], 0.0, None),
}


@pytest.mark.parametrize("name", list(INCLINE_CASES))
def test_two_blocks_on_incline_coulomb_closed_form(name):
    """The two-block Coulomb problem from rest: which contacts stick or slip, and the
    accelerations along the incline against the closed forms (m1 = 2, m2 = 1):
    lower slides, upper sticks: a = g (sin th - mu1 cos th) for both; both slide:
    a2 = g (sin th - mu2 cos th), m1 a1 = m1 g sin th + mu2 m2 g cos th - mu1 (m1 + m2)
    g cos th; upper slides alone: a2 as before, a1 = 0. Rest: the friction and normal
    forces on the plane balance the total weight."""
    th, mu1, mu2, modes, a1, a2 = INCLINE_CASES[name]
    m1, m2 = 2.0, 1.0
    cl = blocks_on_incline(th, mu1, mu2, m1, m2)
    cl.c[:, C.CC_MODE] = C.MODE_LIFT
    assert cl.select() == C.CS_OK
    assert list(cl.c[:, C.CC_MODE]) == modes
    s, c = math.sin(th), math.cos(th)
    if name == "lower slides, upper sticks":
        a1 = a2 = G * (s - mu1 * c)
    elif name == "both slide":
        a2 = G * (s - mu2 * c)
        a1 = (m1 * G * s + mu2 * m2 * G * c - mu1 * (m1 + m2) * G * c) / m1
    elif name == "upper slides on a sticking lower":
        a2 = G * (s - mu2 * c)
    assert cl.forces() == C.CS_OK
    down = -np.array([c, s])
    for i, a in ((0, a1), (1, a2)):
        np.testing.assert_allclose(cl.acc[i, :2], a * down, atol=1e-12 * G)
        assert abs(cl.acc[i, 2]) < 1e-12 * G
    N = cl.c[:2, C.CC_LAMN].sum()
    F = cl.c[:2, C.CC_LAMT].sum()
    assert N == pytest.approx((m1 + m2) * G * c, rel=1e-12)
    # Newton along the incline for the whole: (m1 + m2) g sin th + F = -(m1 a1 + m2 a2)... in
    # the t direction (up the incline): F - (m1 + m2) g s = -(m1 a1 + m2 a2)
    assert F - (m1 + m2) * G * s == pytest.approx(-(m1 * a1 + m2 * a2), abs=1e-12 * G)
    st, ev, k, t = cl.advance(0.0, 0.2)
    if name == "rest":
        assert st == C.CS_REST
    else:
        assert st == C.CS_OK and ev == C.CE_NONE
        # constant accelerations: the displacement along the incline is a t^2 / 2
        x0 = blocks_on_incline(th, mu1, mu2, m1, m2).b
        for i, a in ((0, a1), (1, a2)):
            np.testing.assert_allclose(cl.b[i, :2] - x0[i, :2], 0.5 * a * 0.04 * down,
                                       atol=1e-11)


# ------------------------------------------------------------------ 2. against scipy


R1, R2, M1, M2 = 1.0, 0.5, 2.0, 0.5


def two_disks(phi0=0.3, mu_floor=0.6, mu_disks=0.3, w2=0.0):
    """Disk 0 (R1, M1) on the floor, disk 1 (R2, M2) on it at phi0 from the vertical, at rest
    (disk 1 spinning at w2). Contacts: floor-disk 0, disk 0-disk 1 (A = the upper disk)."""
    c1 = np.array([0.0, R1]) + (R1 + R2) * np.array([math.sin(phi0), math.cos(phi0)])
    bodies = [body(0.0, R1, m=M1, I=0.5 * M1 * R1 * R1),
              body(*c1, w=w2, m=M2, I=0.5 * M2 * R2 * R2)]
    contacts = [contact(C.KIND_PLANE, 0, -1, ra=R1, mu=mu_floor),
                contact(C.KIND_ROUND, 1, 0, ra=R2, rb=R1, mu=mu_disks)]
    return Cluster(bodies, contacts, L=2 * (R1 + R2))


def _ref_rows(q):
    """Velocity-level constraint rows (normal, tangential) of the two-disk scene at the
    configuration q = (x0, y0, a0, x1, y1, a1), written independently of the kernel:
    floor: g = y0 - R1, vT = vx0 + R1 w0; disks: n = (c1 - c0)/|c1 - c0|, t = (n_y, -n_x),
    g = |c1 - c0| - R1 - R2, vT = t . (v1 - v0) + R2 w1 + R1 w0. Complex-safe."""
    dx = q[3] - q[0]
    dy = q[4] - q[1]
    dist = np.sqrt(dx * dx + dy * dy)
    nx, ny = dx / dist, dy / dist
    tx, ty = ny, -nx
    z = 0.0 * dist
    floorN = np.array([z, 1 + z, z, z, z, z])
    floorT = np.array([1 + z, z, R1 + z, z, z, z])
    diskN = np.array([-nx, -ny, z, nx, ny, z])
    diskT = np.array([-tx, -ty, R1 + z, tx, ty, R2 + z])
    return [(floorN, floorT), (diskN, diskT)]


def reference_solution(y0, modes, mus, t_end):
    """solve_ivp (DOP853, rtol 1e-12) of M q'' = F + sum (G lam) with the constraint
    accelerations Phi q'' + (dPhi/dt) q' = 0, (dPhi/dt) q' by complex-step differentiation
    along q' (exact to round-off): the constrained Newton-Euler equations with Lagrange
    multipliers. Terminal events: lam_N = 0, cone margin, slip stop."""
    minv = np.array([1 / M1, 1 / M1, 1 / (0.5 * M1 * R1 * R1),
                     1 / M2, 1 / M2, 1 / (0.5 * M2 * R2 * R2)])
    Fg = np.array([0.0, -G, 0.0, 0.0, -G, 0.0]) / minv

    def solve(y):
        q, v = y[:6], y[6:]
        hc = 1e-30
        rows = _ref_rows(q)
        rows_c = _ref_rows(q + 1j * hc * v)
        eqs, cols, gam = [], [], []
        for k, ((rN, rT), (cN, cT)) in enumerate(zip(rows, rows_c)):
            eqs.append(rN)
            gam.append((cN.imag / hc) @ v)
            if modes[k] == C.MODE_STICK:
                cols.append(rN)
                eqs.append(rT)
                gam.append((cT.imag / hc) @ v)
                cols.append(rT)
            else:
                cols.append(rN - mus[k] * modes[k] * rT)
        Phi = np.array(eqs).real
        Gc = np.array(cols).real.T
        n = len(eqs)
        K = np.zeros((6 + n, 6 + n))
        K[:6, :6] = np.diag(1 / minv)
        K[:6, 6:] = -Gc
        K[6:, :6] = Phi
        rhs = np.concatenate([Fg, -np.array(gam)])
        sol = np.linalg.solve(K, rhs)
        qdd, lam = sol[:6], sol[6:]
        out = []
        i = 0
        for k in range(2):
            ln = lam[i]
            i += 1
            if modes[k] == C.MODE_STICK:
                lt = lam[i]
                i += 1
            else:
                lt = -mus[k] * modes[k] * ln
            vt = (rows[k][1].real @ v)
            out.append((ln, lt, vt))
        return qdd, out

    def f(t, y):
        qdd, _ = solve(y)
        return np.concatenate([y[6:], qdd])

    events = []
    for k in range(2):
        def ev_lam(t, y, k=k):
            return solve(y)[1][k][0]

        def ev_slip(t, y, k=k):
            ln, lt, vt = solve(y)[1][k]
            return mus[k] * ln - abs(lt) if modes[k] == C.MODE_STICK else modes[k] * vt
        ev_lam.terminal = ev_slip.terminal = True
        ev_lam.direction = ev_slip.direction = -1
        events += [ev_lam, ev_slip]
    return solve_ivp(f, (0.0, t_end), y0, method="DOP853", rtol=1e-12, atol=1e-14,
                     dense_output=True, events=events), solve


def test_disk_on_disk_on_floor_matches_scipy_lagrange_multipliers():
    """A disk on a free disk on a rough floor, from rest: the kernel's modes are consistent
    for the reference too; the trajectories agree to 1e-8 L (positions) and 1e-8 V
    (velocities) until the first event, and the event (kind, contact, time) agrees."""
    cl = two_disks()
    cl.c[:, C.CC_MODE] = C.MODE_LIFT
    assert cl.select() == C.CS_OK
    modes = list(cl.c[:, C.CC_MODE])
    assert modes == [C.MODE_STICK, C.MODE_STICK]        # both roll at first
    mus = list(cl.c[:, C.CC_MU])
    y0 = np.concatenate([cl.b[:, :3].ravel(), cl.b[:, 3:6].ravel()])
    sol, solve = reference_solution(y0, modes, mus, 10.0)
    # the reference's forces at the start: consistent with the modes
    for k, (ln, lt, vt) in enumerate(solve(y0)[1]):
        assert ln > 0 and abs(lt) < mus[k] * ln
        assert ln == pytest.approx(cl.c[k, C.CC_LAMN], rel=1e-12)
        assert lt == pytest.approx(cl.c[k, C.CC_LAMT], rel=1e-12, abs=1e-12 * G)
    assert sol.status == 1                    # a terminal event
    iev = [i for i, te in enumerate(sol.t_events) if len(te)][0]
    t_ref = sol.t_events[iev][0]
    L, V = cl.L, math.sqrt(G * cl.L)
    t = 0.0
    worst = 0.0
    for tk in np.linspace(0.0, t_ref, 9)[1:-1]:
        st, ev, k, t = cl.advance(t, tk)
        assert st == C.CS_OK and ev == C.CE_NONE and t == tk
        yr = sol.sol(tk)
        dq = np.abs(cl.b[:, :3].ravel() - yr[:6]) * np.array([1, 1, L] * 2)
        dv = np.abs(cl.b[:, 3:6].ravel() - yr[6:]) * np.array([1, 1, L] * 2)
        worst = max(worst, dq.max() / L, dv.max() / V)
    st, ev, k, t = cl.advance(t, 10.0)
    assert st == C.CS_OK
    assert (ev, k) == ((C.CE_LEAVE, iev // 2) if iev % 2 == 0 else (C.CE_SLIP, iev // 2))
    assert abs(t - t_ref) < 1e-8 * t_ref, t - t_ref
    yr = sol.y_events[iev][0]
    worst = max(worst, np.abs(cl.b[:, :3].ravel() - yr[:6]).max() / L)
    assert worst < 1e-8, worst
    test_disk_on_disk_on_floor_matches_scipy_lagrange_multipliers.figures = (worst, t - t_ref,
                                                                            t_ref, ev, k)


def test_disk_on_disk_second_phase_slip_matches_scipy_and_dissipates():
    """After the first event (the disks' contact reaches its cone), the mode selection
    makes it slip; that phase against the reference too (slip force column JN - mu sig
    JT), to its own first event; energy decreases (friction works -mu lam_N |vT|)."""
    cl = two_disks()
    cl.c[:, C.CC_MODE] = C.MODE_LIFT
    assert cl.select() == C.CS_OK
    st, ev, k, t1 = cl.advance(0.0, 10.0)
    assert (st, ev, k) == (C.CS_OK, C.CE_SLIP, 1)
    # the enumeration, blind to the trend, keeps the force on its cone sticking; the
    # transition after the event follows the trend
    assert cl.select() == C.CS_OK and cl.c[1, C.CC_MODE] == C.MODE_STICK
    assert cl.after_event(ev, k) == C.CS_OK
    modes = list(cl.c[:, C.CC_MODE])
    assert modes[0] == C.MODE_STICK and modes[1] in (C.MODE_SLIP_POS, C.MODE_SLIP_NEG)
    mus = list(cl.c[:, C.CC_MU])
    y0 = np.concatenate([cl.b[:, :3].ravel(), cl.b[:, 3:6].ravel()])
    sol, solve = reference_solution(y0, modes, mus, 10.0)
    iev = [i for i, te in enumerate(sol.t_events) if len(te)][0]
    t_ref = sol.t_events[iev][0]
    L, V = cl.L, math.sqrt(G * cl.L)
    t = 0.0
    worst = 0.0
    E = [cl.energy()]
    for tk in np.linspace(0.0, t_ref, 9)[1:-1]:
        st, ev, k, t = cl.advance(t1 + t, t1 + tk)
        t -= t1
        assert st == C.CS_OK and ev == C.CE_NONE
        yr = sol.sol(tk)
        worst = max(worst, np.abs(cl.b[:, :3].ravel() - yr[:6]).max() / L,
                    np.abs(cl.b[:, 3:6].ravel() - yr[6:]).max() / V)
        E.append(cl.energy())
    st, ev, k, t = cl.advance(t1 + t, t1 + 10.0)
    E.append(cl.energy())
    kind = C.CE_LEAVE if iev % 2 == 0 else C.CE_STOP
    assert (st, ev, k) == (C.CS_OK, kind, iev // 2)
    assert abs(t - t1 - t_ref) < 1e-8 * t_ref
    assert worst < 1e-8, worst
    dE = np.diff(E)
    assert np.all(dE < 1e-12 * abs(E[0])) and E[-1] < E[0] - 1e-3
    test_disk_on_disk_second_phase_slip_matches_scipy_and_dissipates.figures = (
        worst, t - t1 - t_ref, t_ref, ev, k, E[0] - E[-1])


# ------------------------------------------------------------------ 5. energy, drift


RC, BW, BH = 1.0, 1.0, 0.4        # cylinder radius, box width and height


def box_on_cylinder(w0, mu, cands=None):
    """A box (BW x BH, m = 1) balanced on a fixed cylinder (radius RC), turning at w0 with
    its contact point at rest (rolling): the cylinder's centre (A, radius RC) against the
    box's bottom face (B), whose extent is [-BW/2, BW/2] from its middle. Candidates:
    ``cands`` (default: the box's bottom corners reaching the cylinder)."""
    I = box_inertia(1.0, BW, BH)
    bodies = [body(0.0, 0.0, fixed=True),
              body(0.0, RC + BH / 2, 0.0, -w0 * BH / 2, 0.0, w0, m=1.0, I=I)]
    mode = C.MODE_STICK if mu > 0 else C.MODE_SLIP_POS
    ct = contact(C.KIND_FACE, 0, 1, ra=RC, pb=(0.0, -BH / 2), n=(0.0, -1.0), mu=mu, mode=mode,
                 b_range=(-BW / 2, BW / 2))
    if cands is None:
        cands = [contact(C.KIND_ROUND, 1, 0, pa=(sx * BW / 2, -BH / 2), rb=RC)
                 for sx in (-1, 1)]
    return Cluster(bodies, [ct], cands, L=BW)


def test_rocking_box_conserves_energy_and_holds_constraints_for_10_s():
    """Rolling (mu = inf) rocking of a box on a cylinder (stable: BH/2 < RC) for 10 s:
    energy constant to 1e-10 of m g L, the gap, its rate and the slip at round-off after
    every call (projection), no candidate reached, and the small-oscillation period
    2 pi sqrt((rho^2 + c^2) / (g (R - c))) (c = BH/2, rho^2 = I/m; kinetic energy
    (I + m c^2) w^2 / 2 about the contact point, potential m g (R - c) theta^2 / 2)."""
    w0 = 0.5
    cl = box_on_cylinder(w0, math.inf)
    E0 = cl.energy()
    t = 0.0
    worst_e = worst_g = 0.0
    for tk in np.arange(1.0, 10.5, 1.0):
        st, ev, k, t = cl.advance(t, tk)
        assert st == C.CS_OK and ev == C.CE_NONE
        worst_e = max(worst_e, abs(cl.energy() - E0))
        out = cl.rates(0)
        worst_g = max(worst_g, abs(out[0]) / cl.L, abs(out[1]) / math.sqrt(G * cl.L),
                      abs(out[3]) / math.sqrt(G * cl.L))
    assert worst_e < 1e-10 * G * cl.L, worst_e
    assert worst_g < 1e-12, worst_g
    # the period of small oscillations from the zero crossings of w
    cl = box_on_cylinder(0.02, math.inf)
    ts, ws = [0.0], [0.02]
    t = 0.0
    for tk in np.arange(0.01, 2.0, 0.01):
        st, ev, k, t = cl.advance(t, tk)
        ts.append(t)
        ws.append(cl.b[1, C.CB_OMEGA])
    ts, ws = np.array(ts), np.array(ws)
    i = np.nonzero(np.sign(ws[1:]) != np.sign(ws[:-1]))[0]
    tz = ts[i] - ws[i] * (ts[i + 1] - ts[i]) / (ws[i + 1] - ws[i])
    c = BH / 2
    period = 2 * math.pi * math.sqrt((box_inertia(1.0, BW, BH) + c * c) / (G * (RC - c)))
    assert np.mean(np.diff(tz)) * 2 == pytest.approx(period, rel=1e-4)
    test_rocking_box_conserves_energy_and_holds_constraints_for_10_s.figures = (
        worst_e / (G * cl.L), worst_g, np.mean(np.diff(tz)) * 2 / period - 1)


def test_frictionless_box_on_cylinder_conserves_energy():
    """The same box without friction slides as it rocks: energy constant to 1e-10 m g L
    over the phase (5 s or its first event), constraints at round-off."""
    cl = box_on_cylinder(0.5, 0.0)
    E0 = cl.energy()
    t = 0.0
    worst = 0.0
    for tk in np.arange(0.5, 5.01, 0.5):
        st, ev, k, t = cl.advance(t, tk)
        assert st == C.CS_OK
        worst = max(worst, abs(cl.energy() - E0))
        out = cl.rates(0)
        assert abs(out[0]) < 1e-12 * cl.L and abs(out[1]) < 1e-12 * math.sqrt(G * cl.L)
        if ev != C.CE_NONE:
            break
    assert worst < 1e-10 * G * cl.L, worst
    test_frictionless_box_on_cylinder_conserves_energy.figures = (worst / (G * cl.L), t, ev)


# ------------------------------------------------------------------ impacts, feature ends


def test_candidate_gaps_end_the_phase_at_the_impact():
    """Candidates of both kinds: a fixed peg (round-round: the box's top corner, radius 0,
    against a fixed disk) placed on the path of a rocking box's top corner, and a wall
    (feature-plane) in the way of a disk rolling off a cylinder: CE_GAP with the
    candidate's index, its gap at the event within 1e-12 L of 0 (located on the open
    side; the projection of the event state moves it by round-off) and closing."""
    free = box_on_cylinder(3.0, math.inf, cands=[])
    free.advance(0.0, 0.2)
    corner = free.b[1, :2] + rot(free.b[1, C.CB_ANGLE], (BW / 2, BH / 2))
    b = np.vstack([box_on_cylinder(3.0, math.inf, cands=[]).b,
                   body(*(corner + (0.05, 0.0)), fixed=True)])
    cl0 = box_on_cylinder(3.0, math.inf, cands=[])
    peg = contact(C.KIND_ROUND, 1, 2, pa=(BW / 2, BH / 2), rb=0.06)
    cl = Cluster(b, cl0.c, [contact(C.KIND_PLANE, 1, -1, n=(0.0, 1.0), d=-5.0), peg], L=BW)
    st, ev, k, t = cl.advance(0.0, 5.0)
    assert (st, ev, k) == (C.CS_OK, C.CE_GAP, 1) and 0.0 < t < 0.2
    out = cl.rates(1, cl.cand)
    assert abs(out[0]) < 1e-12 * cl.L and out[1] < 0.0
    R, r = 1.0, 0.5
    cl = disk_on_cylinder(math.inf, 1e-2)
    wall = contact(C.KIND_PLANE, 1, -1, ra=r, n=(-1.0, 0.0), d=-1.2)   # x <= 1.2
    cl = Cluster(cl.b, cl.c, [wall], L=R + r)
    st, ev, k, t = cl.advance(0.0, 30.0)
    assert (st, ev, k) == (C.CS_OK, C.CE_GAP, 0)
    out = cl.rates(0, cl.cand)
    assert abs(out[0]) < 1e-12 * cl.L and out[1] < 0.0
    assert cl.b[1, C.CB_X] == pytest.approx(1.2 - r, abs=1e-12)


def test_face_end_and_vertex_cone_end_the_phase():
    """CE_FEATURE: the rolling box swung past the end of its face (the contact point at s =
    +-BW/2 to 1e-12 L: the stepper continues on the corner, round-round), and a disk
    rolling over a fixed square's corner (round-round, the corner's normal cone [0, pi/2],
    gravity along the cone's bisector into the corner: it would leave at 55 degrees from
    the bisector, past the cone's 45) with its normal on the cone's bound to 1e-12."""
    cl = box_on_cylinder(4.5, math.inf, cands=[])
    st, ev, k, t = cl.advance(0.0, 5.0)
    assert (st, ev) == (C.CS_OK, C.CE_FEATURE) and k in (C.FR_BLO, C.FR_BHI)
    # the contact point: on the cylinder along -n from its centre
    n = cl.rates(0)[5:7]
    p = -RC * n
    f = cl.b[1, :2] + rot(cl.b[1, C.CB_ANGLE], (0.0, -BH / 2))
    s = n[1] * (p[0] - f[0]) - n[0] * (p[1] - f[1])
    assert abs(abs(s) - BW / 2) < 1e-12 * BW and np.sign(s) == (1 if k == C.FR_BHI else -1)
    r = 0.3
    gdir = -np.array([1.0, 1.0]) / math.sqrt(2)
    v0 = 1e-2
    tdir = np.array([1.0, -1.0]) / math.sqrt(2)     # t = (n_y, -n_x) of n = -gdir
    c0 = -r * gdir
    w0 = -v0 / r                                     # rolling on a point: v + w J(-r n) = 0
    bodies = [body(0.0, 0.0, fixed=True),
              body(*c0, vx=v0 * tdir[0], vy=v0 * tdir[1], w=w0, m=1.0, I=0.5 * r * r)]
    ct = contact(C.KIND_ROUND, 1, 0, ra=r, mu=math.inf, b_range=(0.0, math.pi / 2))
    cl = Cluster(bodies, [ct], g=tuple(G * gdir), L=r)
    st, ev, k, t = cl.advance(0.0, 30.0)
    assert (st, ev, k) == (C.CS_OK, C.CE_FEATURE, C.FR_BLO)
    n = cl.rates(0)[5:7]
    assert abs(n[1]) < 1e-12 and n[0] > 0.0 and cl.c[0, C.CC_LAMN] > 0.0


# ------------------------------------------------------------------ 7. status codes, input


def rod_on_floor(sig, mu, th=math.radians(45)):
    """A thin rod (L = 1, m = 1, I = 1/12) at th with its lower end on the floor, sliding
    along sig t; DESIGN §5: W = [[2.5, -1.5], [-1.5, 2.5]] at 45 degrees, so sliding with
    W_NN - mu sig W_NT = 2.5 + 1.5 mu sig <= 0 is Painleve's paradox (mu >= 5/3)."""
    c, s = math.cos(th), math.sin(th)
    b = body(0.5 * c, 0.5 * s, th, vx=sig * 1.0, m=1.0, I=1.0 / 12)
    ct = contact(C.KIND_PLANE, 0, -1, pa=(-0.5, 0.0), mu=mu,
                 mode=C.MODE_SLIP_POS if sig > 0 else C.MODE_SLIP_NEG)
    return Cluster([b], [ct], L=1.0)


def test_painleve_and_no_mode_status():
    """The rod sliding towards its lower end's side with mu = 2 (> 5/3) has no consistent
    force (CS_PAINLEVE), and the mode selection finds no mode (CS_NO_MODE: slip is
    Painleve, lift-off accelerates the end into the floor); the other direction, or
    mu = 1, is consistent. Never NaN."""
    assert rod_on_floor(-1, 2.0).forces() == C.CS_PAINLEVE
    assert rod_on_floor(+1, 2.0).forces() == C.CS_OK
    assert rod_on_floor(-1, 1.0).forces() == C.CS_OK
    cl = rod_on_floor(-1, 2.0)
    assert cl.select() == C.CS_NO_MODE
    cl = rod_on_floor(-1, 2.0)
    st, ev, k, t = cl.advance(0.0, 1.0)
    assert st == C.CS_PAINLEVE and np.all(np.isfinite(cl.b))
    cl = rod_on_floor(-1, 1.0)
    assert cl.select() == C.CS_OK and cl.c[0, C.CC_MODE] == C.MODE_SLIP_NEG


def test_contradictory_constraints_are_singular_not_nan():
    """Two fixed bodies (a support moving along another) held in round-round contact:
    the gap's g'' = |v_T|^2 / |D| cannot be cancelled by any force: CS_SINGULAR."""
    b = [body(0.0, 0.0, vx=1.0, fixed=True), body(0.0, 2.0, fixed=True), body(5.0, 5.0)]
    ct = contact(C.KIND_ROUND, 1, 0, ra=1.0, rb=1.0, mu=0.0)
    cl = Cluster.__new__(Cluster)                     # skip validation: both sides fixed
    cl.b, cl.c, cl.nk = np.array(b), ct.reshape(1, -1), 1
    cl.cand, cl.nc, cl.g, cl.L = np.zeros((1, C.N_CC)), 0, (0.0, -G), 1.0
    cl.w = np.zeros(C.work_size(3, 0))
    cl.la = np.zeros(C.N_LA)
    cl.acc = np.zeros((3, 3))
    assert cl.forces() == C.CS_SINGULAR
    with pytest.raises(ValueError, match="both sides fixed"):
        C.validate_cluster(cl.b, cl.c, 1)
    # too many contacts for the kernel
    many = np.repeat(ct.reshape(1, -1), C.KMAX + 1, axis=0)
    assert C.cluster_forces(cl.b, many, C.KMAX + 1, 0.0, -G, 1.0, cl.w, cl.la,
                            cl.acc) == C.CS_TOO_MANY_CONTACTS


@pytest.mark.parametrize("change,msg", [
    (lambda b, c: c.__setitem__((0, C.CC_A), 5), "out of range"),
    (lambda b, c: c.__setitem__((0, C.CC_B), 1), "out of range or equal"),
    (lambda b, c: c.__setitem__((0, C.CC_NX), 0.5), "unit vector"),
    (lambda b, c: c.__setitem__((0, C.CC_MU), -0.1), "mu must be"),
    (lambda b, c: c.__setitem__((0, C.CC_MODE), 7), "unknown mode"),
    (lambda b, c: c.__setitem__((0, C.CC_KIND), 9), "unknown kind"),
    (lambda b, c: b.__setitem__((1, C.CB_M), 0.0), "positive"),
    (lambda b, c: b.__setitem__((1, C.CB_X), math.nan), "non-finite"),
])
def test_validate_cluster_names_the_problem(change, msg):
    bodies = np.array([body(0.0, 0.0, fixed=True), body(0.0, 1.0)])
    c = contact(C.KIND_FACE, 1, 0, pb=(0.0, 0.5), n=(0.0, 1.0)).reshape(1, -1)
    C.validate_cluster(bodies, c, 1)
    change(bodies, c)
    with pytest.raises(ValueError, match=msg):
        C.validate_cluster(bodies, c, 1)


def test_eccentric_disk_rocks_without_friction_for_20_s():
    """A disk (radius 0.5) whose centre of mass lies 0.15 below its geometric centre rocks on
    a frictionless floor (the round feature at pa = (0, 0.15) in the body frame): one long
    frictionless phase of 20 s, energy constant to 1e-10 m g L, the horizontal momentum
    (no horizontal force) to round-off, the gap and its rate at round-off after
    projection; the rolling version (mu = inf) conserves energy too."""
    for mu, mode in ((0.0, C.MODE_SLIP_POS), (math.inf, C.MODE_STICK)):
        r, e = 0.5, 0.15
        th0 = 0.0
        w0 = 2.0
        # the contact point (below the geometric centre) at rest for rolling, any v for mu = 0
        vx = -w0 * (r - e) if mu > 0 else 0.3
        b = body(0.0, r - e, th0, vx, 0.0, w0, m=1.0, I=0.2)
        ct = contact(C.KIND_PLANE, 0, -1, pa=(0.0, e), ra=r, mu=mu, mode=mode)
        cl = Cluster([b], [ct], L=2 * r)
        st = cl.project()
        E0 = cl.energy()
        px0 = cl.b[0, C.CB_VX]
        t = 0.0
        worst_e = worst_g = worst_p = 0.0
        for tk in np.arange(2.0, 20.01, 2.0):
            st, ev, k, t = cl.advance(t, tk)
            assert st == C.CS_OK and ev == C.CE_NONE, (st, ev)
            worst_e = max(worst_e, abs(cl.energy() - E0))
            out = cl.rates(0)
            worst_g = max(worst_g, abs(out[0]) / cl.L, abs(out[1]) / math.sqrt(G * cl.L))
            worst_p = max(worst_p, abs(cl.b[0, C.CB_VX] - px0))
        assert worst_e < 1e-10 * G * cl.L, worst_e
        assert worst_g < 1e-12, worst_g
        if mu == 0.0:
            assert worst_p < 1e-12 * math.sqrt(G * cl.L), worst_p
        assert abs(cl.b[0, C.CB_ANGLE]) < 1.5      # it rocks, it does not roll away


def test_overhanging_box_is_not_at_rest_and_pivots():
    """A box whose centre of mass overhangs the box below: the selection lifts the inner
    corner and keeps the edge corner (sticking), rest is not claimed, and the box turns
    about the edge corner: its angular acceleration m g d / (I + m |r|^2) (d the overhang,
    r the corner's arm) at the start, the corner fixed."""
    lower = body(0.0, 0.25, m=3.0, I=box_inertia(3.0, 1.0, 0.5), fixed=True)
    m, wd, h, x = 1.0, 0.6, 0.2, 0.65        # centre 0.15 beyond the lower's edge at 0.5
    upper = body(x, 0.6, m=m, I=box_inertia(m, wd, h))
    # the overlap's ends: the upper box's inner corner on the lower's top face, and the
    # lower box's edge corner (A) on the upper box's bottom face (B)
    cts = [contact(C.KIND_FACE, 1, 0, pa=(-wd / 2, -h / 2), pb=(0.0, 0.25), n=(0.0, 1.0),
                   mu=0.8, b_range=(-0.5, 0.5)),
           contact(C.KIND_FACE, 0, 1, pa=(0.5, 0.25), pb=(0.0, -h / 2), n=(0.0, -1.0),
                   mu=0.8, b_range=(-wd / 2, wd / 2))]
    cl = Cluster([lower, upper], cts, L=1.0)
    assert cl.select() == C.CS_OK
    assert list(cl.c[:, C.CC_MODE]) == [C.MODE_LIFT, C.MODE_STICK]
    assert cl.forces() == C.CS_OK
    d = x - 0.5
    r2 = d * d + (h / 2) ** 2
    assert cl.acc[1, 2] == pytest.approx(-m * G * d / (box_inertia(m, wd, h) + m * r2),
                                         rel=1e-12)
    st, ev, k, t = cl.advance(0.0, 0.05)
    assert st == C.CS_OK
    corner = cl.b[1, :2] + rot(cl.b[1, C.CB_ANGLE], (-wd / 2, -h / 2))
    # the edge corner of the lower box stays the pivot: the upper's face point there is at
    # rest (stick) and in contact
    out = cl.rates(1)
    assert abs(out[0]) < 1e-12 and abs(out[3]) < 1e-12
    assert corner[1] > 0.5 + 1e-3          # the inner corner has lifted


def test_random_clusters_newton_euler_and_constraints():
    """Random three-body clusters (a fixed body, contacts of every kind in random modes,
    random positions and velocities, gaps not zero): the kernel's forces and accelerations
    satisfy Newton-Euler for every body with the forces applied at the contact points
    (geometry recomputed independently), and along the motion with those accelerations the
    exact gaps have g'' = 0 and the sticking slips dvT/dt = 0 (finite differences)."""
    rng = np.random.default_rng(11)
    checked = 0
    for trial in range(60):
        bodies = [body(*rng.normal(size=6), m=rng.uniform(0.5, 2), I=rng.uniform(0.05, 0.5))
                  for _ in range(3)]
        bodies[2][C.CB_FIXED] = 1.0
        rows = []
        for k in range(4):
            kind = rng.integers(3)
            a, b = rng.choice(3, size=2, replace=False)
            if a == 2 and (kind == C.KIND_PLANE or b == 2):
                a, b = b, a
            if kind == C.KIND_PLANE:
                a = rng.integers(2)
            mode = rng.choice([C.MODE_STICK, C.MODE_SLIP_POS, C.MODE_SLIP_NEG])
            ang = rng.uniform(-math.pi, math.pi)
            rows.append(contact(kind, a, -1 if kind == C.KIND_PLANE else b,
                                pa=tuple(rng.normal(scale=0.3, size=2)),
                                ra=rng.uniform(0, 0.3), pb=tuple(rng.normal(scale=0.3, size=2)),
                                rb=rng.uniform(0, 0.3), n=(math.cos(ang), math.sin(ang)),
                                d=rng.normal(), mu=rng.uniform(0, 0.5), mode=mode))
        cl = Cluster(bodies, rows, L=1.0)
        st = cl.forces()
        assert st in (C.CS_OK, C.CS_PAINLEVE, C.CS_SINGULAR)
        if st != C.CS_OK:
            continue
        assert np.all(np.isfinite(cl.acc)) and np.all(np.isfinite(cl.c[:, C.CC_LAMN]))
        F = np.zeros((3, 3))
        st0 = [cl.b[i, :6] for i in range(3)]
        for k, r in enumerate(cl.c):
            _exact_gap_and_slip(r, st0)
            n, t, p = _exact_gap_and_slip.frame
            f = cl.c[k, C.CC_LAMN] * n + cl.c[k, C.CC_LAMT] * t
            for i, sgn in ((int(r[C.CC_A]), 1.0), (int(r[C.CC_B]), -1.0)):
                if i < 0:
                    continue
                arm = p - cl.b[i, :2]
                F[i] += sgn * np.array([f[0], f[1], arm[0] * f[1] - arm[1] * f[0]])
            if r[C.CC_MODE] != C.MODE_STICK:
                assert cl.c[k, C.CC_LAMT] == pytest.approx(
                    -r[C.CC_MU] * r[C.CC_MODE] * cl.c[k, C.CC_LAMN], rel=1e-12, abs=1e-12)
        scale = 1.0 + np.abs(F).max() + G
        for i in range(2):
            m, I = cl.b[i, C.CB_M], cl.b[i, C.CB_I]
            res = np.array([m * cl.acc[i, 0], m * (cl.acc[i, 1] + G), I * cl.acc[i, 2]]) - F[i]
            assert np.abs(res).max() < 1e-9 * scale, res
        assert np.all(cl.acc[2] == 0.0)

        def state(tt):
            return [np.concatenate([cl.b[i, :3] + cl.b[i, 3:6] * tt + 0.5 * cl.acc[i] * tt * tt,
                                    cl.b[i, 3:6] + cl.acc[i] * tt]) for i in range(3)]
        h = 1e-3
        for k, r in enumerate(cl.c):
            vals = np.array([_exact_gap_and_slip(r, state(j * h)) for j in (-2, -1, 0, 1, 2)])
            d1 = (vals[0] - 8 * vals[1] + 8 * vals[3] - vals[4]) / (12 * h)
            d2 = (-vals[0] + 16 * vals[1] - 30 * vals[2] + 16 * vals[3] - vals[4]) / (12 * h * h)
            assert abs(d2[0]) < 1e-5 * scale, (k, d2[0])
            if r[C.CC_MODE] == C.MODE_STICK and r[C.CC_MU] > 0:
                assert abs(d1[1]) < 1e-7 * scale, (k, d1[1])
        checked += 1
    assert checked >= 20


# ------------------------------------------------------------------ recorded pieces


def test_recorded_pieces_follow_the_integrated_motion():
    """The rocking box and the two disks recorded as velocity-interpolating quadratic
    pieces (one row per free body and piece; the fixed cylinder has none), in calls of at
    most PIECE_BUDGET rows: sampled anywhere, the pieces keep the energy within a few
    PIECE_ETOL M V^2 (plus the integration's own error), the contact gaps within a few
    PIECE_LTOL L, and they join continuously."""
    from rbimpact.kernels.flight2d import sample_segments
    for make, t_end in ((lambda: box_on_cylinder(0.5, math.inf), 0.5),
                        (lambda: two_disks(), 0.6)):
        cl = make()
        if cl.b.shape[0] == 2 and cl.b[0, C.CB_FIXED] == 0.0:
            cl.c[:, C.CC_MODE] = C.MODE_LIFT
            assert cl.select() == C.CS_OK
        E0 = cl.energy()
        nfree = int(np.sum(cl.b[:, C.CB_FIXED] == 0.0))
        V = max(np.hypot(cl.b[i, 3], cl.b[i, 4]) + abs(cl.b[i, 5]) * cl.L
                for i in range(cl.b.shape[0])) + math.sqrt(G * cl.L)
        Mf = sum(cl.b[i, C.CB_M] for i in range(cl.b.shape[0]) if cl.b[i, C.CB_FIXED] == 0)
        cap = 200_000
        rec = (np.zeros(cap), np.zeros(cap, np.int64), np.zeros((cap, 9)), np.zeros(3, np.int64))
        t, calls = 0.0, 0
        while t < t_end:
            before = rec[3][C.CNT_SEG]
            t_before = t
            st, ev, k, t = cl.advance(t, t_end, rec)
            assert st == C.CS_OK and ev == C.CE_NONE and t > t_before
            assert rec[3][C.CNT_SEG] - before <= C.PIECE_BUDGET
            calls += 1
        nseg = rec[3][C.CNT_SEG]
        seg_t, seg_b, seg_s = rec[0][:nseg], rec[1][:nseg], rec[2][:nseg]
        assert calls > 1 and seg_t[0] == 0.0 and np.all(np.diff(seg_t) >= 0.0)
        assert set(seg_b) == {i for i in range(cl.b.shape[0]) if cl.b[i, C.CB_FIXED] == 0}
        assert nseg % nfree == 0
        times = np.linspace(0.0, t_end, 2001)[:-1]
        nb = cl.b.shape[0]
        out = [np.zeros((times.size, nb)) for _ in range(6)]
        for i in set(seg_b):
            idx = np.nonzero(seg_b == i)[0]
            # each body's rows are contiguous in time: sample them through a compact copy
            sample_segments(seg_t[idx].copy(), seg_s[idx].copy(), 0, idx.size, times, *out, i)
        worst_e = worst_g = 0.0
        probe = make()
        probe.c[:, C.CC_MODE] = cl.c[:, C.CC_MODE]
        for j in range(times.size):
            for i in range(nb):
                if probe.b[i, C.CB_FIXED] == 0.0:
                    probe.b[i, :6] = [o[j, i] for o in out]
            worst_e = max(worst_e, abs(probe.energy() - E0))
            for k in range(probe.nk):
                worst_g = max(worst_g, abs(probe.rates(k)[0]))
        assert worst_e < 5 * C.PIECE_ETOL * Mf * V * V + 1e-11, worst_e
        assert worst_g < 5 * C.PIECE_LTOL * cl.L, worst_g
        # joins: each piece's end is the next one's start
        for i in set(seg_b):
            idx = np.nonzero(seg_b == i)[0]
            for a, b in zip(idx[:-1], idx[1:]):
                h = seg_t[b] - seg_t[a]
                r = seg_s[a]
                end = r[:3] + r[3:6] * h + 0.5 * r[6:9] * h * h
                assert np.abs(end[:2] - seg_s[b, :2]).max() < 5 * C.PIECE_LTOL * cl.L
                assert np.abs(r[3:6] + r[6:9] * h - seg_s[b, 3:6]).max() < 5 * C.PIECE_VTOL * V
        test_recorded_pieces_follow_the_integrated_motion.figures = getattr(
            test_recorded_pieces_follow_the_integrated_motion, "figures", []) + [
            (nseg, calls, worst_e / (Mf * V * V), worst_g / cl.L)]


# ------------------------------------------------------------------ modes after an event
# Found by the drop campaign (2:2298760360, two disks rolling side by side on the floor,
# mu = 1): when the larger disk's floor slip stopped, cluster_after_event changed only that
# contact's mode; the forces of the new modes pulled at the other two contacts (lam_N
# -1.27 N and -1.37 N), their leave events, armed below a start that was already
# negative, never fired, and the friction of the pulling contacts drove the slip: the
# energy grew from 0.007 J to 235 J while the run ended 'done'.

R_BIG, R_SMALL = 0.009853301382100181, 0.0070184221435927435
M_BIG, M_SMALL = 0.04805832237231507, 0.010202370037936838


def side_by_side(vx, w0, w1, mu, r0=R_BIG, r1=R_SMALL, m0=M_BIG, m1=M_SMALL,
                 modes=(C.MODE_SLIP_POS,) * 3):
    """Disk 0 (r0) and disk 1 (r1, to its right) on the floor y = 0, touching; common
    velocity vx, spins w0, w1. Contacts: disk-disk (A = disk 0), floor-disk 0, floor-disk 1."""
    x1 = math.sqrt((r0 + r1) ** 2 - (r0 - r1) ** 2)
    bodies = [body(0.0, r0, vx=vx, w=w0, m=m0, I=0.5 * m0 * r0 * r0),
              body(x1, r1, vx=vx, w=w1, m=m1, I=0.5 * m1 * r1 * r1)]
    contacts = [contact(C.KIND_ROUND, 0, 1, ra=r0, rb=r1, mu=mu, mode=modes[0]),
                contact(C.KIND_PLANE, 0, -1, ra=r0, mu=mu, mode=modes[1]),
                contact(C.KIND_PLANE, 1, -1, ra=r1, mu=mu, mode=modes[2])]
    return Cluster(bodies, contacts, L=2 * (r0 + r1))


def _modes_consistent(cl, tol=1e-9):
    """Independent check of the forces written by the kernel for the modes in the table:
    no pulling normal force, sticking forces in their cones, friction against the slip."""
    F = sum(cl.b[i, C.CB_M] for i in range(cl.b.shape[0])) * G
    for k in range(cl.nk):
        mode = cl.c[k, C.CC_MODE]
        if mode == C.MODE_LIFT:
            continue
        ln, lt, mu = cl.c[k, C.CC_LAMN], cl.c[k, C.CC_LAMT], cl.c[k, C.CC_MU]
        if ln < -tol * F:
            return f"contact {k} pulls: lam_N = {ln:.3g} N"
        if mode == C.MODE_STICK and abs(lt) > mu * ln + tol * F:
            return f"contact {k} sticks outside its cone: {lt:.3g} vs mu lam_N {mu * ln:.3g}"
        if mode in (C.MODE_SLIP_POS, C.MODE_SLIP_NEG) and mu > 0.0:
            vt = cl.rates(k)[3]
            if mode * vt < -1e-9 * (abs(cl.b[:, C.CB_VX]).max() + 1e-3):
                return f"contact {k} slides against its slip vT = {vt:.3g} m/s"
    return None


def test_jammed_disks_after_a_stop_are_refused_not_driven():
    """The campaign scene's cluster: disk 0's floor slip stops (CE_STOP at its floor
    contact). With disk 0 rolling, no mode of the two other contacts is consistent: the
    disks wedge (pushing disk 1 harder presses it into the floor and its friction, mu = 1,
    grows faster than the push: a Painleve-type jam): cluster_after_event says CS_NO_MODE.
    The modes the old rule left (0 slides, 1 sticks, 2 slides) pull, and cluster_advance
    refuses them (CS_INCONSISTENT) without moving anything."""
    cl = side_by_side(0.219642456, -20.7370094, 10.2302977, 1.0)
    assert cl.project() == C.CS_OK and cl.select() == C.CS_OK
    modes = cl.c[:, C.CC_MODE].copy()
    assert list(modes) == [C.MODE_SLIP_NEG, C.MODE_SLIP_POS, C.MODE_SLIP_POS]
    e0 = cl.energy()
    st, ev, k, t = cl.advance(0.0, 1.0)
    assert (st, ev, k) == (C.CS_OK, C.CE_STOP, 1)
    assert 5e-4 < t < 6e-4                          # the slip 0.0153 m/s stops
    assert cl.energy() <= e0 + 1e-12 * e0           # sliding friction only dissipates
    saved = (cl.b.copy(), cl.c.copy())
    assert cl.after_event(ev, k) == C.CS_NO_MODE
    assert cl.select() == C.CS_NO_MODE
    # the old rule: contact 1 sticks, the others keep sliding; the forces pull
    cl.b[:], cl.c[:] = saved
    cl.c[1, C.CC_MODE] = C.MODE_STICK
    assert cl.forces() == C.CS_OK
    assert cl.c[0, C.CC_LAMN] < -1.0 and cl.c[2, C.CC_LAMN] < -1.0
    b0, e1 = cl.b.copy(), cl.energy()
    st, ev, k, t2 = cl.advance(t, t + 1.0)
    assert st == C.CS_INCONSISTENT and t2 == t
    assert np.allclose(cl.b[:, :6], b0[:, :6], rtol=0.0, atol=1e-12)
    assert abs(cl.energy() - e1) <= 1e-12 * e1


@pytest.mark.parametrize("seed", range(40))
def test_random_side_by_side_and_stacked_disks_modes_after_events(seed):
    """Campaign axis for the event rule: random two-disk clusters (side by side on the
    floor, or one disk on the other), random radii, masses, spins and mu, run from event to
    event: after every mode event the new modes are consistent (checked from the written
    forces and the kinematics, independently of the kernel's own test) or CS_NO_MODE; no
    pass starts inconsistent; the energy never rises beyond the integration tolerance."""
    rng = np.random.default_rng(seed)
    r0, r1 = rng.uniform(0.005, 0.05, 2)
    m0, m1 = rng.uniform(0.01, 1.0, 2)
    mu = rng.choice([0.1, 0.3, 1.0, 3.0])
    V = 0.5
    if seed % 2 == 0:
        cl = side_by_side(rng.uniform(-V, V), *rng.uniform(-V, V, 2) / min(r0, r1), mu,
                          r0, r1, m0, m1)
    else:
        phi = rng.uniform(-0.6, 0.6)
        c1 = np.array([0.0, r0]) + (r0 + r1) * np.array([math.sin(phi), math.cos(phi)])
        cl = Cluster([body(0.0, r0, vx=rng.uniform(-V, V), w=rng.uniform(-V, V) / r0, m=m0,
                           I=0.5 * m0 * r0 * r0),
                      body(*c1, w=rng.uniform(-V, V) / r1, m=m1, I=0.5 * m1 * r1 * r1)],
                     [contact(C.KIND_PLANE, 0, -1, ra=r0, mu=mu, mode=C.MODE_SLIP_POS),
                      contact(C.KIND_ROUND, 1, 0, ra=r1, rb=r0, mu=mu, mode=C.MODE_SLIP_POS)],
                     L=2 * (r0 + r1))
    assert cl.project() == C.CS_OK
    if cl.select() != C.CS_OK:
        return                                      # a jam at the start (named refusal)
    assert _modes_consistent(cl) is None
    escale = (m0 + m1) * (V * V + G * (r0 + r1))
    e_prev, t = cl.energy(), 0.0
    for n_ev in range(30):
        st, ev, k, t = cl.advance(t, 0.5)
        assert st in (C.CS_OK, C.CS_REST), st
        e = cl.energy()
        assert e <= e_prev + 1e-9 * escale, (n_ev, e - e_prev)
        e_prev = e
        if st == C.CS_REST or ev not in (C.CE_LEAVE, C.CE_SLIP, C.CE_STOP):
            break
        st = cl.after_event(ev, k)
        assert st in (C.CS_OK, C.CS_NO_MODE), st
        if st == C.CS_NO_MODE:
            break
        assert _modes_consistent(cl) is None
        if np.any(cl.c[:cl.nk, C.CC_MODE] == C.MODE_LIFT):
            break                                   # the stepper moves it to the candidates
