"""kernels/cluster3d.py: persistent contact between several spheres in 3D.

Closed forms (a sphere rolling off a fixed sphere: lift-off at cos phi = (10/17) cos phi0,
frictionless (2/3) cos phi0; the stick -> slip angle against a brentq root of the
rolling forces), an independent scipy integration of a sphere on a free sphere on a
frictionless floor, energy and momentum, rest of a pyramid with its minimum-norm split,
g'' and dc/dt against finite differences, and the input checks.
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

    def advance(self, t0, t1):
        return C.cluster_advance(self.b, self.c, self.nk, self.cand, self.nc, *self.g, self.L,
                                 t0, t1, self.w, self.la)

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
