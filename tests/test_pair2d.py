"""2D body-body pair kinds (kernels/pair2d*.py, issue 16 item 1): gap, normal, witness points
and features against a brute-force distance (dense sampling of both boundaries, then a
local refinement with scipy.optimize), time of impact against a scan and bisection of the
gap along the exact flight, grazing and fast-spinning throws, invariance (translation by
1 km, rotation of the scene, swapping the bodies), and the input checks.

Conventions (DESIGN §3): ``n`` from B into A, ``pA - pB = g n``, ``g' < 0`` approaching."""
import math
import zlib

import numpy as np
import pytest
from numba import njit
from scipy.optimize import minimize_scalar

from rbimpact import shapes
from rbimpact.kernels.flight2d import ALPHA, ANGLE, AX, AY, OMEGA, VX, VY, X, Y, fly_into
from rbimpact.kernels.pair2d import (FE_A_KIND, FE_B_KIND, FR_GAP, FR_NX, FR_NY, FR_PAX,
                                     FR_PAY, FR_PBX, FR_PBY, FR_RATE, N_FE, N_FR,
                                     PAIR_TABLE, PK_NONE, pair_frame, pair_kind)
from rbimpact.kernels.pair2d_shape import (FT_CURVE, FT_EDGE, FT_VERTEX, SH_DISK,
                                           SH_ELLIPSE, SH_POLY)
from rbimpact.kernels.pair2d_shape import body_reach
from rbimpact.kernels.pair2d_toi import (AX_A, AX_B, AX_WORLD, axis_bound, closing_speed_bound,
                                        pair_toi, safe_step)
from rbimpact.kernels.toi2d import TOI_MISSED, TOI_OK
from rbimpact.pair2d_input import body_geometry, pose, shape_geometry

EPS = np.finfo(float).eps
RTOL, ATOL, GAP_TOL, MAXIT = 1e-14, 1e-15, 1e-9, 100000
GRAVITY = -9.81
SHAPES = ("disk", "polygon", "capsule", "ellipse")
PAIRS = [(a, b) for i, a in enumerate(SHAPES) for b in SHAPES[i:]]


def seed(pair):
    """A fixed seed per pair of shapes (``hash`` of strings changes between runs)."""
    return zlib.crc32("-".join(pair).encode())


# ---- random bodies -----------------------------------------------------------------------

def random_body(rng, name):
    """A random body of roughly unit size as ``(geometry, size)``; ``size`` the largest
    distance of its boundary from its centre (m)."""
    if name == "disk":
        shape = shapes.Disk(rng.uniform(0.2, 1.0))
    elif name == "polygon":
        if rng.random() < 0.3:
            shape = shapes.Box(rng.uniform(0.3, 2.0), rng.uniform(0.3, 2.0))
        else:
            n = int(rng.integers(3, 9))
            ang = np.sort(rng.uniform(0, 2 * np.pi, n))
            while np.min(np.diff(np.r_[ang, ang[0] + 2 * np.pi])) < 0.2 or \
                    np.max(np.diff(np.r_[ang, ang[0] + 2 * np.pi])) > 2.8:
                ang = np.sort(rng.uniform(0, 2 * np.pi, n))
            rad = rng.uniform(0.4, 1.0) * np.array([1.0, rng.uniform(0.5, 1.0)])
            shape = shapes.Polygon(np.c_[rad[0] * np.cos(ang), rad[1] * np.sin(ang)])
    elif name == "capsule":
        shape = shapes.Rod(rng.uniform(0.5, 2.0), rng.uniform(0.05, 0.5))
    else:
        a = rng.uniform(0.3, 1.5)
        shape = shapes.Ellipse(a, a / rng.uniform(1.05, 10.0))
        if rng.random() < 0.5:
            shape = shapes.Ellipse(shape.b, shape.a)
    geo = shape_geometry(shape)
    return geo, shape.bounding_radius


def kargs(geo, st):
    kind, rad, ea, eb, V = geo
    return (kind, rad, ea, eb, V, 0, V.shape[0], st)


def frame(geoA, stA, geoB, stB):
    fr = np.zeros(N_FR)
    fe = np.zeros(N_FE, np.int64)
    pair_frame(*kargs(geoA, stA), *kargs(geoB, stB), fr, fe)
    return fr, fe


# ---- independent geometry: boundary parametrisation, inside test, boundary distance ------

def boundary(geo, st, t):
    """World points of the boundary at parameters ``t`` (array, period 1)."""
    kind, rad, ea, eb, V = geo
    t = np.mod(np.asarray(t, float), 1.0)
    if kind == SH_DISK:
        p = np.c_[rad * np.cos(2 * np.pi * t), rad * np.sin(2 * np.pi * t)] + V[0]
    elif kind == SH_ELLIPSE:
        p = np.c_[ea * np.cos(2 * np.pi * t), eb * np.sin(2 * np.pi * t)]
    elif V.shape[0] >= 3:                         # polygon, by perimeter
        E = np.roll(V, -1, axis=0) - V
        L = np.hypot(E[:, 0], E[:, 1])
        cum = np.r_[0.0, np.cumsum(L)] / L.sum()
        i = np.clip(np.searchsorted(cum, t, side="right") - 1, 0, len(V) - 1)
        u = (t - cum[i]) / (cum[i + 1] - cum[i])
        p = V[i] + u[:, None] * E[i]
    else:                                         # capsule along body x, by arc length
        half = 0.5 * np.hypot(*(V[1] - V[0]))
        L, r = 2 * half, rad
        per = 2 * L + 2 * np.pi * r
        s = t * per
        p = np.empty((len(s), 2))
        m1 = s < L
        p[m1] = np.c_[-half + s[m1], -r + 0 * s[m1]]
        m2 = (s >= L) & (s < L + np.pi * r)
        a2 = -np.pi / 2 + (s[m2] - L) / r
        p[m2] = np.c_[half + r * np.cos(a2), r * np.sin(a2)]
        m3 = (s >= L + np.pi * r) & (s < 2 * L + np.pi * r)
        p[m3] = np.c_[half - (s[m3] - L - np.pi * r), r + 0 * s[m3]]
        m4 = s >= 2 * L + np.pi * r
        a4 = np.pi / 2 + (s[m4] - 2 * L - np.pi * r) / r
        p[m4] = np.c_[-half + r * np.cos(a4), r * np.sin(a4)]
    c, s_ = math.cos(st[ANGLE]), math.sin(st[ANGLE])
    return np.c_[st[X] + c * p[:, 0] - s_ * p[:, 1], st[Y] + s_ * p[:, 0] + c * p[:, 1]]


def to_body(geo, st, p):
    c, s = math.cos(st[ANGLE]), math.sin(st[ANGLE])
    d = np.atleast_2d(p) - [st[X], st[Y]]
    return np.c_[c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]]


def seg_dist(q, a, b):
    e = b - a
    u = np.clip(((q - a) @ e) / (e @ e), 0.0, 1.0)
    return np.hypot(*(q - a - u[:, None] * e).T)


def boundary_distance(geo, st, p):
    """Distance (m) of world points ``p`` from the body's boundary (first order for the
    ellipse: |F| / |grad F| of its implicit function), and whether they are inside."""
    kind, rad, ea, eb, V = geo
    q = to_body(geo, st, p)
    if kind == SH_ELLIPSE:
        F = (q[:, 0] / ea) ** 2 + (q[:, 1] / eb) ** 2 - 1.0
        G = 2 * np.hypot(q[:, 0] / ea ** 2, q[:, 1] / eb ** 2)
        return np.abs(F) / G, F < 0
    if V.shape[0] == 1:
        d = np.hypot(*(q - V[0]).T)
        return np.abs(d - rad), d < rad
    if V.shape[0] == 2:
        d = seg_dist(q, V[0], V[1])
        return np.abs(d - rad), d < rad
    d = np.min([seg_dist(q, V[i], V[(i + 1) % len(V)]) for i in range(len(V))], axis=0)
    E = np.roll(V, -1, axis=0) - V
    cr = np.min([E[i, 0] * (q[:, 1] - V[i, 1]) - E[i, 1] * (q[:, 0] - V[i, 0])
                 for i in range(len(V))], axis=0)
    return d, cr > 0


N_SAMPLE = 256      # samples of each boundary
ZOOM_GRID = 11      # grid of one round of the zoomed search of a point's nearest boundary point
ZOOM_SHRINK = 3.0   # window shrink per round


@njit(cache=True)
def _bpoint(kind, rad, ea, eb, V, x, y, th, t):
    """Boundary point at parameter ``t`` (period 1), as ``boundary`` (scalar, compiled)."""
    t = t - math.floor(t)
    if kind == SH_DISK:
        px = V[0, 0] + rad * math.cos(2 * math.pi * t)
        py = V[0, 1] + rad * math.sin(2 * math.pi * t)
    elif kind == SH_ELLIPSE:
        px = ea * math.cos(2 * math.pi * t)
        py = eb * math.sin(2 * math.pi * t)
    elif V.shape[0] >= 3:
        n = V.shape[0]
        tot = 0.0
        for i in range(n):
            tot += math.hypot(V[(i + 1) % n, 0] - V[i, 0], V[(i + 1) % n, 1] - V[i, 1])
        s = t * tot
        px = V[0, 0]
        py = V[0, 1]
        for i in range(n):
            ex = V[(i + 1) % n, 0] - V[i, 0]
            ey = V[(i + 1) % n, 1] - V[i, 1]
            L = math.hypot(ex, ey)
            if s <= L or i == n - 1:
                u = min(s / L, 1.0)
                px = V[i, 0] + u * ex
                py = V[i, 1] + u * ey
                break
            s -= L
    else:
        half = 0.5 * math.hypot(V[1, 0] - V[0, 0], V[1, 1] - V[0, 1])
        L = 2 * half
        r = rad
        s = t * (2 * L + 2 * math.pi * r)
        if s < L:
            px, py = -half + s, -r
        elif s < L + math.pi * r:
            a = -math.pi / 2 + (s - L) / r
            px, py = half + r * math.cos(a), r * math.sin(a)
        elif s < 2 * L + math.pi * r:
            px, py = half - (s - L - math.pi * r), r
        else:
            a = math.pi / 2 + (s - 2 * L - math.pi * r) / r
            px, py = -half + r * math.cos(a), r * math.sin(a)
    c = math.cos(th)
    sn = math.sin(th)
    return x + c * px - sn * py, y + sn * px + c * py


@njit(cache=True)
def _nearest(kind, rad, ea, eb, V, x, y, th, qx, qy):
    """Distance of the point ``q`` from the boundary: the best of ``N_SAMPLE`` samples, then
    a zoomed grid search around it down to 1e-16 in the parameter. Returns ``(d, t)``."""
    best = math.inf
    tb = 0.0
    for k in range(N_SAMPLE):
        t = (k + 0.5) / N_SAMPLE
        px, py = _bpoint(kind, rad, ea, eb, V, x, y, th, t)
        d = math.hypot(px - qx, py - qy)
        if d < best:
            best = d
            tb = t
    w = 2.0 / N_SAMPLE
    while w > 1e-16:
        t0 = tb
        for k in range(ZOOM_GRID):
            t = t0 + w * (2.0 * k / (ZOOM_GRID - 1) - 1.0)
            px, py = _bpoint(kind, rad, ea, eb, V, x, y, th, t)
            d = math.hypot(px - qx, py - qy)
            if d < best:
                best = d
                tb = t
        w /= ZOOM_SHRINK
    return best, tb


@njit(cache=True)
def _closest_pair(kA, rA, eaA, ebA, VA, xA, yA, thA, kB, rB, eaB, ebB, VB, xB, yB, thB):
    """``min_tA F(tA)``, ``F`` the distance of A's boundary point ``tA`` from B's boundary
    (``_nearest``): best of ``N_SAMPLE`` samples, then the same zoomed grid search in
    ``tA``. Returns ``(d, tA, tB)``."""
    best = math.inf
    ta = tb = 0.0
    for k in range(N_SAMPLE):
        t = (k + 0.5) / N_SAMPLE
        px, py = _bpoint(kA, rA, eaA, ebA, VA, xA, yA, thA, t)
        d, u = _nearest(kB, rB, eaB, ebB, VB, xB, yB, thB, px, py)
        if d < best:
            best, ta, tb = d, t, u
    w = 2.0 / N_SAMPLE
    while w > 1e-16:
        t0 = ta
        for k in range(ZOOM_GRID):
            t = t0 + w * (2.0 * k / (ZOOM_GRID - 1) - 1.0)
            px, py = _bpoint(kA, rA, eaA, ebA, VA, xA, yA, thA, t)
            d, u = _nearest(kB, rB, eaB, ebB, VB, xB, yB, thB, px, py)
            if d < best:
                best, ta, tb = d, t, u
        w /= ZOOM_SHRINK
    return best, ta, tb


def brute_force(geoA, stA, geoB, stB):
    """Distance of the boundaries, independent of the kernels: dense sampling of both
    boundaries and a zoomed grid search on the two boundary parameters (``_closest_pair``,
    robust at corners where the distance has a kink), then a final bounded Brent search
    (scipy) in A's parameter about the result. Returns ``(d, pA, pB)``, or None when the
    bodies overlap (a sample of one inside the other)."""
    t = (np.arange(N_SAMPLE) + 0.5) / N_SAMPLE
    if boundary_distance(geoB, stB, boundary(geoA, stA, t))[1].any() or \
            boundary_distance(geoA, stA, boundary(geoB, stB, t))[1].any():
        return None
    kA, rA, eaA, ebA, VA = geoA
    kB, rB, eaB, ebB, VB = geoB
    d, ta, tb = _closest_pair(kA, rA, eaA, ebA, VA, stA[X], stA[Y], stA[ANGLE],
                              kB, rB, eaB, ebB, VB, stB[X], stB[Y], stB[ANGLE])

    def F(x):
        px, py = _bpoint(kA, rA, eaA, ebA, VA, stA[X], stA[Y], stA[ANGLE], ta + x)
        return _nearest(kB, rB, eaB, ebB, VB, stB[X], stB[Y], stB[ANGLE], px, py)

    r = minimize_scalar(lambda x: F(x)[0], bounds=(-1e-13, 1e-13), method="bounded",
                        options=dict(xatol=1e-18))
    if r.fun < d:
        ta = ta + r.x
        d, tb = F(r.x)
    pA = np.array(_bpoint(kA, rA, eaA, ebA, VA, stA[X], stA[Y], stA[ANGLE], ta))
    pB = np.array(_bpoint(kB, rB, eaB, ebB, VB, stB[X], stB[Y], stB[ANGLE], tb))
    return d, pA, pB


def random_pose_pair(rng, geoA, sizeA, geoB, sizeB):
    stB = pose([rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-np.pi, np.pi)])
    u = rng.uniform(0, 2 * np.pi)
    dist = (sizeA + sizeB) * rng.uniform(0.35, 1.2)
    stA = pose([stB[X] + dist * math.cos(u), stB[Y] + dist * math.sin(u),
                rng.uniform(-np.pi, np.pi)])
    return stA, stB


# ---- 1. gap, normal, witness points and features against the brute force -----------------

N_POSES = 100           # separated poses per pair of shapes (plus as many near contact)


@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_gap_normal_witness_against_brute_force(pair):
    rng = np.random.default_rng(seed(pair))
    worst = dict(gap=0.0, normal=0.0, on_boundary=0.0, witness=0.0)
    done = 0
    while done < N_POSES:
        geoA, sA = random_body(rng, pair[0])
        geoB, sB = random_body(rng, pair[1])
        if rng.random() < 0.5:
            geoA, sA, geoB, sB = geoB, sB, geoA, sA
        stA, stB = random_pose_pair(rng, geoA, sA, geoB, sB)
        bf = brute_force(geoA, stA, geoB, stB)
        if bf is None or bf[0] < 1e-3:
            continue
        for near in (False, True):
            if near:    # move A along the normal to a gap of 1e-9 .. 1e-3 of the size
                fr, _ = frame(geoA, stA, geoB, stB)
                target = 10 ** rng.uniform(-9, -3) * max(sA, sB)
                stA = stA.copy()
                stA[X] += (target - fr[FR_GAP]) * fr[FR_NX]
                stA[Y] += (target - fr[FR_GAP]) * fr[FR_NY]
                bf = brute_force(geoA, stA, geoB, stB)
                assert bf is not None
            d, bA, bB = bf
            size = max(sA, sB)
            fr, fe = frame(geoA, stA, geoB, stB)
            g = fr[FR_GAP]
            n = fr[[FR_NX, FR_NY]]
            pA = fr[[FR_PAX, FR_PAY]]
            pB = fr[[FR_PBX, FR_PBY]]
            worst["gap"] = max(worst["gap"], abs(g - d) / size)
            # the normal: unit, along pA - pB, and along the brute-force closest pair
            assert abs(np.hypot(*n) - 1.0) < 1e-14
            worst["witness"] = max(worst["witness"], np.hypot(*(pA - pB - g * n)) / size)
            c = bA - bB
            worst["normal"] = max(worst["normal"], abs(n[0] * c[1] - n[1] * c[0]) / size)
            assert n @ c > 0.0
            on = max(boundary_distance(geoA, stA, pA[None])[0][0],
                     boundary_distance(geoB, stB, pB[None])[0][0]) / size
            worst["on_boundary"] = max(worst["on_boundary"], on)
            # features: an ellipse reports its curve, a polygon a vertex or an edge
            for kind, f in ((geoA[0], fe[FE_A_KIND]), (geoB[0], fe[FE_B_KIND])):
                if kind == SH_ELLIPSE:
                    assert f == FT_CURVE
                elif kind == SH_DISK:
                    assert f == FT_VERTEX
                else:
                    assert f in (FT_VERTEX, FT_EDGE)
            done += 1
    print(f"{pair}: {done} poses, worst {worst}")
    assert worst["gap"] < 1e-9
    assert worst["witness"] < 1e-12
    assert worst["on_boundary"] < 1e-12
    assert worst["normal"] < 1e-6


# ---- 2. gap rate -------------------------------------------------------------------------

def test_gap_rate_is_the_derivative_of_the_gap():
    """``g'`` of the frame against a central difference of the gap along the exact flight."""
    rng = np.random.default_rng(5)
    worst = 0.0
    for pair in PAIRS:
        k = 0
        while k < 20:
            geoA, sA = random_body(rng, pair[0])
            geoB, sB = random_body(rng, pair[1])
            stA, stB = random_pose_pair(rng, geoA, sA, geoB, sB)
            stA[VX:OMEGA + 1] = rng.normal(size=3)
            stB[VX:OMEGA + 1] = rng.normal(size=3)
            stA[AY] = stB[AY] = GRAVITY
            fr, _ = frame(geoA, stA, geoB, stB)
            if fr[FR_GAP] < 1e-2:
                continue
            h = 1e-5
            gp = gap_at(geoA, stA, geoB, stB, h)
            gm = gap_at(geoA, stA, geoB, stB, -h)
            fd = (gp - gm) / (2 * h)
            worst = max(worst, abs(fd - fr[FR_RATE]) / (1 + abs(fr[FR_RATE])))
            k += 1
    assert worst < 1e-6


def gap_at(geoA, stA, geoB, stB, s):
    a = np.empty(9)
    b = np.empty(9)
    fly_into(stA, s, a)
    fly_into(stB, s, b)
    return frame(geoA, a, geoB, b)[0][FR_GAP]


# ---- 3. time of impact against a scan and bisection of the gap along the exact flight -----

@njit(cache=True)
def _gap(kA, rA, eaA, ebA, VA, stA, kB, rB, eaB, ebB, VB, stB, s, a, b, fr, fe):
    fly_into(stA, s, a)
    fly_into(stB, s, b)
    return pair_frame(kA, rA, eaA, ebA, VA, 0, VA.shape[0], a, kB, rB, eaB, ebB, VB, 0,
                      VB.shape[0], b, fr, fe)


@njit(cache=True)
def _reference_root(kA, rA, eaA, ebA, VA, stA, kB, rB, eaB, ebB, VB, stB, S, N):
    """First root of the gap in ``[0, S]`` (inf if none): the gap on ``N + 1`` grid points;
    at the first sign change, or where a discrete local minimum dips below zero after a
    golden-section search of its minimum, bisection to a width of 1e-16 s."""
    a = np.empty(9)
    b = np.empty(9)
    fr = np.empty(N_FR)
    fe = np.empty(N_FE, np.int64)
    g0 = _gap(kA, rA, eaA, ebA, VA, stA, kB, rB, eaB, ebB, VB, stB, 0.0, a, b, fr, fe)
    if g0 <= 0.0:
        return 0.0
    gm2 = math.inf
    gm1 = g0
    for i in range(1, N + 1):
        t = S * i / N
        g = _gap(kA, rA, eaA, ebA, VA, stA, kB, rB, eaB, ebB, VB, stB, t, a, b, fr, fe)
        lo = -1.0
        hi = -1.0
        if g <= 0.0:
            lo = S * (i - 1) / N
            hi = t
        elif i >= 2 and gm1 < gm2 and gm1 <= g:     # local minimum at i - 1: look inside
            x0 = S * (i - 2) / N
            x1 = t
            gr = 0.5 * (math.sqrt(5.0) - 1.0)
            for _ in range(100):
                c = x1 - gr * (x1 - x0)
                d = x0 + gr * (x1 - x0)
                gc = _gap(kA, rA, eaA, ebA, VA, stA, kB, rB, eaB, ebB, VB, stB, c, a, b, fr, fe)
                gd = _gap(kA, rA, eaA, ebA, VA, stA, kB, rB, eaB, ebB, VB, stB, d, a, b, fr, fe)
                if gc <= 0.0:
                    x1 = c
                    break
                if gc < gd:
                    x1 = d
                else:
                    x0 = c
            gx = _gap(kA, rA, eaA, ebA, VA, stA, kB, rB, eaB, ebB, VB, stB, x1, a, b, fr, fe)
            if gx <= 0.0:
                lo = S * (i - 2) / N
                hi = x1
        if hi >= 0.0:
            for _ in range(200):
                mid = 0.5 * (lo + hi)
                if hi - lo <= 1e-16 or mid <= lo or mid >= hi:
                    break
                gmid = _gap(kA, rA, eaA, ebA, VA, stA, kB, rB, eaB, ebB, VB, stB, mid, a, b,
                            fr, fe)
                if gmid > 0.0:
                    lo = mid
                else:
                    hi = mid
            return hi
        gm2 = gm1
        gm1 = g
    return math.inf


def toi(geoA, stA, geoB, stB, S):
    return pair_toi(*kargs(geoA, stA), *kargs(geoB, stB), 0.0, S, RTOL, ATOL, GAP_TOL, MAXIT)


def reference(geoA, stA, geoB, stB, S):
    spin = (abs(stA[OMEGA]) + abs(stB[OMEGA])) * S
    N = int(min(4000, 400 + 8 * spin))
    return _reference_root(geoA[0], geoA[1], geoA[2], geoA[3], geoA[4], stA,
                           geoB[0], geoB[1], geoB[2], geoB[3], geoB[4], stB, S, N)


def random_throw(rng, pair, spin_max):
    """Two bodies of the pair in flight (gravity on both, or B fixed), A thrown at B with
    a random impact parameter, spins up to ``spin_max * |v| / size``; gap > 0 at s = 0."""
    while True:
        geoA, sA = random_body(rng, pair[0])
        geoB, sB = random_body(rng, pair[1])
        if rng.random() < 0.5:
            geoA, sA, geoB, sB = geoB, sB, geoA, sA
        fixed = rng.random() < 0.3
        stB = pose([rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-np.pi, np.pi)])
        u = rng.uniform(0, 2 * np.pi)
        D = (sA + sB) * rng.uniform(1.2, 3.0)
        stA = pose([stB[X] + D * math.cos(u), stB[Y] + D * math.sin(u),
                    rng.uniform(-np.pi, np.pi)])
        v = rng.uniform(0.5, 5.0)
        aim = np.array([stB[X], stB[Y]]) + rng.uniform(-1, 1) * (sA + sB) * np.array(
            [-math.sin(u), math.cos(u)])
        dirn = aim - stA[:2]
        vB = np.zeros(2) if fixed else rng.normal(size=2)
        stA[VX:VY + 1] = vB + v * dirn / np.hypot(*dirn)
        stB[VX:VY + 1] = vB
        ratio = spin_max * rng.random() ** 2
        stA[OMEGA] = rng.uniform(-1, 1) * ratio * v / sA
        stB[OMEGA] = 0.0 if fixed else rng.uniform(-1, 1) * ratio * v / sB
        stA[AY] = GRAVITY
        stB[AY] = 0.0 if fixed else GRAVITY
        if frame(geoA, stA, geoB, stB)[0][FR_GAP] > 1e-3:
            return geoA, stA, geoB, stB, 2.0 * D / v


def genuine_root(geoA, stA, geoB, stB, s):
    """The gap is zero (to 1e-12 m) and closing at ``s``: a root the scan did not see."""
    fr, _ = frame(*_flown(geoA, stA, geoB, stB, s))
    return abs(fr[FR_GAP]) < 1e-12 and fr[FR_RATE] < 0.0


def _flown(geoA, stA, geoB, stB, s):
    a = np.empty(9)
    b = np.empty(9)
    fly_into(stA, s, a)
    fly_into(stB, s, b)
    return geoA, a, geoB, b


N_THROWS = 500


@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_toi_never_misses_and_matches_bisection(pair):
    """500 random throws per pair of shapes, spins up to omega size / |v| = 100: the time of
    impact equals the first root of a scan-and-bisection of the exact motion to 1e-12 s;
    an earlier time is accepted only where the gap is zero and closing (a root the scan
    did not resolve); a later or missing one is a missed impact."""
    rng = np.random.default_rng(1000 + seed(pair))
    hits = earlier = 0
    worst = 0.0
    for i in range(N_THROWS):
        geoA, stA, geoB, stB, S = random_throw(rng, pair, 100.0 if i % 2 else 2.0)
        s, code = toi(geoA, stA, geoB, stB, S)
        assert code == TOI_OK
        r = reference(geoA, stA, geoB, stB, S)
        if math.isinf(r):
            if not math.isinf(s):
                assert genuine_root(geoA, stA, geoB, stB, s)
                earlier += 1
            continue
        hits += 1
        assert s <= r + 1e-12, f"missed impact: toi {s!r}, reference {r!r}"
        if s < r - 1e-12:
            assert genuine_root(geoA, stA, geoB, stB, s)
            earlier += 1
        else:
            worst = max(worst, abs(s - r))
    print(f"{pair}: {N_THROWS} throws, {hits} impacts, {earlier} earlier roots found only "
          f"by the toi, worst |toi - bisection| {worst:.2e} s")
    assert hits > N_THROWS // 5
    assert worst <= 1e-12


def grazing_throw(rng, pair, spin_max):
    """Bodies touching at ``t_c`` with zero normal speed and a convex gap there (closest
    approach exactly zero), flown back to ``s = 0``: ``(geoA, stA, geoB, stB, t_c, n, size,
    tol)``, ``tol`` (s) the resolution of the double root at ``t_c``."""
    while True:
        geoA, sA = random_body(rng, pair[0])
        geoB, sB = random_body(rng, pair[1])
        if rng.random() < 0.5:
            geoA, sA, geoB, sB = geoB, sB, geoA, sA
        stA, stB = random_pose_pair(rng, geoA, sA, geoB, sB)
        fr, _ = frame(geoA, stA, geoB, stB)
        stA[X] -= fr[FR_GAP] * fr[FR_NX]
        stA[Y] -= fr[FR_GAP] * fr[FR_NY]
        v = rng.uniform(0.5, 3.0)
        stA[VX:VY + 1] = rng.normal(size=2) * v
        stB[VX:VY + 1] = rng.normal(size=2) * v
        ratio = spin_max * rng.random()
        stA[OMEGA] = rng.uniform(-1, 1) * ratio * v / sA
        stB[OMEGA] = rng.uniform(-1, 1) * ratio * v / sB
        stA[AY] = stB[AY] = GRAVITY
        fr, _ = frame(geoA, stA, geoB, stB)
        stA[VX] -= fr[FR_RATE] * fr[FR_NX]
        stA[VY] -= fr[FR_RATE] * fr[FR_NY]
        fr, _ = frame(geoA, stA, geoB, stB)
        size = max(sA, sB)
        h = 1e-3 * size / v
        gdd = (gap_at(geoA, stA, geoB, stB, h) + gap_at(geoA, stA, geoB, stB, -h)
               - 2.0 * fr[FR_GAP]) / h ** 2
        if abs(fr[FR_GAP]) > 1e-15 * size or abs(fr[FR_RATE]) > 1e-13 * v or \
                gdd < 1e-2 * v * v / size:
            continue
        tc = rng.uniform(0.05, 0.3) * size / v
        a = np.empty(9)
        b = np.empty(9)
        fly_into(stA, -tc, a)
        fly_into(stB, -tc, b)
        if frame(geoA, a, geoB, b)[0][FR_GAP] <= 1e-6 * size:
            continue
        # the double root at t_c is resolved to |g| ~ eps size: to ~sqrt(eps size / g'')
        tol = 10.0 * math.sqrt(8.0 * EPS * size / gdd)
        return geoA, a, geoB, b, tc, fr[[FR_NX, FR_NY]].copy(), size, tol


N_GRAZES = 30


@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_grazing_throws(pair):
    """Constructed grazes (closest approach exactly zero at ``t_c``, spins up to 100 |v| /
    size): the exact graze is found at ``t_c`` (a double root: to sqrt(eps)) or passed as
    a tangency, never reported early; shifted by ``1e-6`` of the size into the other body
    it is an impact matching the bisection to 1e-12 s; shifted out, no impact."""
    rng = np.random.default_rng(77 + seed(pair))
    worst = 0.0
    found = 0
    for i in range(N_GRAZES):
        geoA, stA, geoB, stB, tc, n, size, tol = grazing_throw(rng, pair,
                                                               100.0 if i % 2 else 1.0)
        S = 2.0 * tc
        r = reference(geoA, stA, geoB, stB, S)
        s, code = toi(geoA, stA, geoB, stB, S)
        assert code == TOI_OK
        if r < tc - tol:            # the bodies met earlier on the way in: an ordinary hit
            assert abs(s - r) <= 1e-12
            continue
        if abs(s - tc) <= tol:      # the tangency reported (zero normal speed)
            found += 1
        else:                       # passed: the next root after the graze
            t1 = tc + tol
            r2 = t1 + reference(*_flown(geoA, stA, geoB, stB, t1), S - t1)
            assert s <= r2 + 1e-12, "missed impact after a graze"
            assert math.isinf(s) or abs(s - r2) <= 1e-12
        for shift in (-1e-6 * size, 1e-6 * size):
            a = stA.copy()
            a[X] += shift * n[0]
            a[Y] += shift * n[1]
            r = reference(geoA, a, geoB, stB, S)
            s, code = toi(geoA, a, geoB, stB, S)
            assert code == TOI_OK
            if math.isinf(r):
                assert math.isinf(s) or genuine_root(geoA, a, geoB, stB, s)
            else:
                assert s <= r + 1e-12, "missed grazing impact"
                worst = max(worst, abs(s - r))
    print(f"{pair}: {N_GRAZES} grazes ({found} found at t_c), worst |toi - bisection| of the "
          f"near grazes {worst:.2e} s")
    assert worst <= 1e-12


# ---- 4. invariance -----------------------------------------------------------------------

def hitting_throws(pair, count, rng):
    out = []
    while len(out) < count:
        geoA, stA, geoB, stB, S = random_throw(rng, pair, 100.0 if len(out) % 2 else 2.0)
        s, _ = toi(geoA, stA, geoB, stB, S)
        if math.isfinite(s):
            fr, _ = frame(*_flown(geoA, stA, geoB, stB, s))
            out.append((geoA, stA, geoB, stB, S, s, abs(fr[FR_RATE])))
    return out


def rotated(st, phi):
    c, s = math.cos(phi), math.sin(phi)
    out = st.copy()
    for i, j in ((X, Y), (VX, VY), (AX, AY)):
        out[i] = c * st[i] - s * st[j]
        out[j] = s * st[i] + c * st[j]
    out[ANGLE] += phi
    return out


@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_invariance_translation_rotation_swap(pair):
    """Translating both bodies by 1 km, or rotating the scene, moves the time of impact by
    round-off of the scene's size over the normal speed; swapping A and B leaves it and
    flips the normal (witness points exchanged)."""
    rng = np.random.default_rng(5000 + seed(pair))
    worst = dict(translate=0.0, rotate=0.0, swap=0.0)
    for geoA, stA, geoB, stB, S, s, vn in hitting_throws(pair, 30, rng):
        # 1 km away
        off = 1000.0 * np.array([math.cos(1.0), math.sin(1.0)])
        a, b = stA.copy(), stB.copy()
        a[X:Y + 1] += off
        b[X:Y + 1] += off
        s1, code = toi(geoA, a, geoB, b, S)
        assert code == TOI_OK
        err = abs(s1 - s) * vn / (EPS * 1000.0)        # in units of eps * 1 km / v_n
        worst["translate"] = max(worst["translate"], err)
        # the whole scene turned about the origin (gravity with it)
        phi = rng.uniform(-np.pi, np.pi)
        s2, _ = toi(geoA, rotated(stA, phi), geoB, rotated(stB, phi), S)
        L = 10.0
        worst["rotate"] = max(worst["rotate"], abs(s2 - s) * vn / (EPS * L))
        # A and B exchanged
        s3, _ = toi(geoB, stB, geoA, stA, S)
        worst["swap"] = max(worst["swap"], abs(s3 - s) * vn / (EPS * L))
        fr, _ = frame(*_flown(geoA, stA, geoB, stB, s))
        fr2, _ = frame(*_flown(geoB, stB, geoA, stA, s))
        assert abs(fr2[FR_GAP] - fr[FR_GAP]) < 1e-14
        assert np.allclose(fr2[[FR_NX, FR_NY]], -fr[[FR_NX, FR_NY]], atol=1e-12)
        assert np.allclose(fr2[[FR_PAX, FR_PAY]], fr[[FR_PBX, FR_PBY]], atol=1e-12)
        assert abs(fr2[FR_RATE] - fr[FR_RATE]) < 1e-12 * (1 + vn)
    print(f"{pair}: worst changes in units of eps L / v_n: {worst}")
    assert worst["translate"] < 64 and worst["rotate"] < 64 and worst["swap"] < 64


# ---- 5. overlap, dispatcher table, input checks -------------------------------------------

@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_overlap_depth(pair):
    """Overlapping bodies: ``g < 0``; moving A by ``-g n`` leaves them touching (exactly for
    disks, capsules and polygons: the minimum translation; for an ellipse a lower estimate
    of the signed distance, so the move separates them by at most a small fraction)."""
    rng = np.random.default_rng(9000 + seed(pair))
    k = 0
    while k < 40:
        geoA, sA = random_body(rng, pair[0])
        geoB, sB = random_body(rng, pair[1])
        stA, stB = random_pose_pair(rng, geoA, sA, geoB, sB)
        fr, _ = frame(geoA, stA, geoB, stB)
        if fr[FR_GAP] <= 0.0:       # start from touching bodies (exact frame)
            continue
        depth = rng.uniform(1e-6, 3e-3)     # m: below half the thinnest body (0.06 m)
        stA[X] -= (fr[FR_GAP] + depth) * fr[FR_NX]
        stA[Y] -= (fr[FR_GAP] + depth) * fr[FR_NY]
        fr, _ = frame(geoA, stA, geoB, stB)
        assert fr[FR_GAP] < 0.0
        a = stA.copy()
        a[X] -= fr[FR_GAP] * fr[FR_NX]
        a[Y] -= fr[FR_GAP] * fr[FR_NY]
        after = frame(geoA, a, geoB, stB)[0][FR_GAP]
        if SH_ELLIPSE in (geoA[0], geoB[0]):
            assert -1e-12 < after < 0.05 * abs(fr[FR_GAP]) + 1e-12
        else:
            assert abs(after) < 1e-12
        k += 1


def test_dispatcher_table():
    """Every pair of shape kinds has one pair kind, and the shape kinds are the stepper's."""
    assert (SH_DISK, SH_POLY, SH_ELLIPSE) == (shapes._SH_DISK, shapes._SH_POLY,
                                              shapes._SH_ELLIPSE)
    keys = [(a, b) for a, b, _, _ in PAIR_TABLE]
    assert len(keys) == len(set(keys)) == 9
    for a in (SH_DISK, SH_POLY, SH_ELLIPSE):
        for b in (SH_DISK, SH_POLY, SH_ELLIPSE):
            assert pair_kind(a, b)[0] != PK_NONE
    assert pair_kind(3, 0)[0] == PK_NONE
    s, _ = pair_toi(7, 0.0, 0.0, 0.0, np.zeros((1, 2)), 0, 1, np.zeros(9),
                    0, 1.0, 0.0, 0.0, np.zeros((1, 2)), 0, 1, np.zeros(9),
                    0.0, 1.0, RTOL, ATOL, GAP_TOL, MAXIT)
    assert math.isnan(s)


def test_overlapping_start_is_a_missed_event():
    geo = body_geometry(SH_POLY, vertices=[(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)])
    s, code = toi(geo, pose([0.0, 0.9, 0.0]), geo, pose([0.0, 0.0, 0.0]), 1.0)
    assert (s, code) == (0.0, TOI_MISSED)


@pytest.mark.parametrize("bad", [
    dict(kind=SH_POLY, vertices=[(0, 0), (1, 0), (0.2, 0.2), (0, 1)]),      # reflex corner
    dict(kind=SH_POLY, vertices=[(0, 0), (1, 0), (1, 1), (0, 1), (1, 0.5)]),  # not convex
    dict(kind=SH_POLY, vertices=[(0, 0), (0, 0), (1, 1)]),                 # repeated
    dict(kind=SH_POLY, vertices=[(0, 0)], radius=0.5),                     # a disk
    dict(kind=SH_POLY, vertices=[(0, 0), (1, 0)], radius=-0.1),            # negative radius
    dict(kind=SH_DISK, radius=0.0),                                        # zero radius
    dict(kind=SH_DISK, radius=float("nan")),
    dict(kind=SH_ELLIPSE, a=1.0, b=0.0),                                   # zero semi-axis
    dict(kind=SH_POLY, vertices=[(0, 0), (1, float("nan")), (0, 1)]),
    dict(kind=5, radius=1.0),                                              # unknown kind
])
def test_bad_body_raises(bad):
    with pytest.raises(ValueError):
        body_geometry(**bad)


@pytest.mark.parametrize("bad", [[0.0, float("nan"), 0.0], [0.0, 1.0], [0, 0, float("inf")],
                                 "abc", [0.0] * 9 + [1.0]])
def test_bad_pose_raises(bad):
    with pytest.raises(ValueError):
        pose(bad)


def test_clockwise_polygon_is_stored_counter_clockwise():
    sq = [(0, 0), (0, 1), (1, 1), (1, 0)]
    V = body_geometry(SH_POLY, vertices=sq)[4]
    E = np.roll(V, -1, axis=0) - V
    En = np.roll(E, -1, axis=0)
    assert np.all(E[:, 0] * En[:, 1] - E[:, 1] * En[:, 0] > 0)


# ---- 6. the bounds themselves, and accelerated rotation ----------------------------------

@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_lower_bounds_hold_on_the_exact_motion(pair):
    """From random states (angular accelerations included), the step of each axis mode
    (``safe_step`` with ``axis_bound`` over the window) leaves the exact gap positive on a
    fine grid of the step, and Mirtich's ``g(s) >= g(0) - V s`` holds."""
    rng = np.random.default_rng(3000 + seed(pair))
    for i in range(40):
        geoA, stA, geoB, stB, S = random_throw(rng, pair, 100.0 if i % 2 else 2.0)
        stA[ALPHA] = rng.normal() * 10.0
        stB[ALPHA] = rng.normal() * 10.0
        stB[AX] = rng.normal()
        fr, _ = frame(geoA, stA, geoB, stB)
        KA = body_reach(*kargs(geoA, stA)[:7])
        KB = body_reach(*kargs(geoB, stB)[:7])
        g0 = fr[FR_GAP]
        for mode in (AX_WORLD, AX_A, AX_B):
            M = axis_bound(mode, stA, stB, 0.0, S, KA[0], KA[1], KB[0], KB[1])
            h = safe_step(mode, *kargs(geoA, stA), *kargs(geoB, stB), 0.0, fr[FR_NX],
                          fr[FR_NY], M)
            for s in np.linspace(0.0, min(h, S), 200)[1:]:
                assert gap_at(geoA, stA, geoB, stB, s) > -1e-12
        V = closing_speed_bound(stA, stB, KA[0] + geoA[1], KB[0] + geoB[1], S)
        for s in np.linspace(0.0, S, 50)[1:]:
            assert gap_at(geoA, stA, geoB, stB, s) >= g0 - V * s - 1e-12


@pytest.mark.parametrize("pair", PAIRS, ids=["-".join(p) for p in PAIRS])
def test_toi_with_angular_and_unequal_accelerations(pair):
    """State rows of persistent contact (constant alpha, unequal accelerations): the time
    of impact still equals the scan and bisection to 1e-12 s and misses nothing."""
    rng = np.random.default_rng(4000 + seed(pair))
    worst = 0.0
    for i in range(60):
        geoA, stA, geoB, stB, S = random_throw(rng, pair, 20.0)
        stA[ALPHA] = rng.normal() * 20.0
        stB[ALPHA] = rng.normal() * 20.0
        stA[AX] = rng.normal() * 5.0
        s, code = toi(geoA, stA, geoB, stB, S)
        assert code == TOI_OK
        r = reference(geoA, stA, geoB, stB, S)
        assert s <= r + 1e-12, "missed impact"
        if s < r - 1e-12:
            assert genuine_root(geoA, stA, geoB, stB, s)
        elif math.isfinite(r):
            worst = max(worst, abs(s - r))
    assert worst <= 1e-12
