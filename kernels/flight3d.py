"""Exact 3D motion between events: quadratic translation, torque-free rotation.

A body's state is a float64[19] row valid from a reference time (s):

====  =========  ================================================================
cols  name       meaning
====  =========  ================================================================
0:3   x          centre of mass (m)
3:7   q          orientation, unit quaternion (w, x, y, z): body -> world
7:10  v          velocity of the centre of mass (m/s)
10:13 w          angular velocity in the **world** frame (rad/s)
13:16 a          constant linear acceleration (m/s^2): gravity in flight
16:19 al         constant angular acceleration (rad/s^2), world frame: zero in flight
====  =========  ================================================================

Translation is exact: ``x(s) = x + v s + a s^2/2``. Rotation, for the principal moments
``I = (I1, I2, I3)`` (kg m^2) about the body axes:

* **torque-free** (``al = 0``; free flight, rolling):

  - spherical inertia: ``w`` constant, ``q(s) = exp(w s / 2) q``;
  - axisymmetric inertia (two equal moments ``A``, the third ``C`` about body axis ``e``):
    regular precession, exact (Goldstein, *Classical Mechanics*, sec. 5.6; Landau &
    Lifshitz, *Mechanics*, sec. 33): ``q(s) = exp(L^ |L| s / 2A) q exp(e sigma s / 2)`` with
    ``L`` the (constant) angular momentum, ``sigma = L.e (1/C - 1/A)`` the body-frame spin
    of ``w`` about ``e``, and ``w(s) = L/A + sigma e(s)``;
  - general inertia: Euler's equations ``I dw_b/ds = (I w_b) x w_b`` and
    ``dq/ds = q (0, w_b) / 2`` (``w_b`` the body-frame angular velocity) integrated by the
    embedded Runge-Kutta pair of Dormand & Prince, RK5(4)7M (Hairer, Norsett & Wanner,
    *Solving ODEs I*, II.5), with error control: a step is accepted when every
    component of the local error estimate is within ``rot_tol`` (quaternion components,
    dimensionless) or ``rot_tol * |w(0)|`` (rad/s). The quaternion is renormalised after
    every step; between steps the solver's 4th-order continuous extension is used. The
    step sequence depends only on the segment's initial state and ``rot_tol``, so the
    same trajectory is reproduced wherever it is evaluated.

* **constant angular acceleration** (``al != 0``: a sphere sliding in persistent contact):
  ``w(s) = w + al s``; when ``w x al = 0`` the axis is fixed and
  ``q(s) = exp((w s + al s^2/2) / 2) q`` exactly, otherwise ``dq/ds = (0, w(s)) q / 2`` is
  integrated as above.

Every function is ``@njit(cache=True)``; ``pose_at`` allocates nothing.
"""
import math

from numba import njit

from .dopri5 import (C2, C3, C4, C5, arg2, arg3, arg4, arg5, arg6, dense_eval, dense_store,
                     error_estimate, reject_factor, solution, step_factor)

N_STATE = 19
SX, SQ, SV, SW, SA, SAL = 0, 3, 7, 10, 13, 16

# rotation kinds of a body (inertia)
ROT_SPHERICAL = 0
ROT_AXISYM = 1
ROT_GENERAL = 2

# integrator workspace layout (float64[N_WS], one row per body)
WS_MODE = 0        # 0: closed form (no integration), 1: Euler equations, 2: q with w(s) linear
WS_TOL = 1
WS_I = 2           # 2:5 principal moments
WS_WSCALE = 5      # |w(0)| (rad/s): scale of the angular-velocity error
WS_AL = 6          # 6:9 angular acceleration (mode 2)
WS_W0 = 9          # 9:12 initial world angular velocity (mode 2)
WS_S0 = 12         # start of the current step (s)
WS_H = 13          # length of the current step (s); 0: no step taken yet
WS_HNEXT = 14      # proposed next step (s)
WS_YSTART = 15     # 15:22 state at s = 0 (q, w_b)
WS_Y = 22          # 22:29 state at the start of the current step
WS_RC = 29         # 29:64 dense-output coefficients, 5 x 7
WS_K = 64          # 64:113 stages k1..k7, 7 x 7
WS_YT = 113        # 113:120 stage argument
WS_Y1 = 120        # 120:127 end-of-step state
WS_NSTEP = 127     # steps taken (accepted + rejected)
WS_MAXSTEP = 128   # step limit
N_WS = 129

RK_OK = 0
RK_TOO_MANY_STEPS = 1

# Dormand-Prince RK5(4)7M: tableau, dense output and step control in kernels/dopri5.py
# first step: the rotation angle of one step is FIRST_ANGLE * rot_tol^(1/5) (rad)
FIRST_ANGLE = 0.5


# ------------------------------------------------------------------ quaternion algebra


@njit(cache=True, inline="always")
def qmul(a0, a1, a2, a3, b0, b1, b2, b3):
    """Hamilton product a b of quaternions (w, x, y, z)."""
    return (a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
            a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
            a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
            a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0)


@njit(cache=True, inline="always")
def qrot(q0, q1, q2, q3, x, y, z):
    """R(q) p: rotate the body-frame vector p by the unit quaternion q."""
    # t = 2 q_v x p ; p' = p + q0 t + q_v x t
    tx = 2.0 * (q2 * z - q3 * y)
    ty = 2.0 * (q3 * x - q1 * z)
    tz = 2.0 * (q1 * y - q2 * x)
    return (x + q0 * tx + q2 * tz - q3 * ty,
            y + q0 * ty + q3 * tx - q1 * tz,
            z + q0 * tz + q1 * ty - q2 * tx)


@njit(cache=True, inline="always")
def qrot_inv(q0, q1, q2, q3, x, y, z):
    """R(q)^T p: a world vector in the body frame."""
    return qrot(q0, -q1, -q2, -q3, x, y, z)


@njit(cache=True, inline="always")
def qexp(wx, wy, wz, s):
    """exp of the rotation by angle |w| s about w: (cos(|w|s/2), sin(|w|s/2) w/|w|)."""
    n = math.sqrt(wx * wx + wy * wy + wz * wz)
    if n == 0.0:
        return 1.0, 0.0, 0.0, 0.0
    h = 0.5 * n * s
    k = math.sin(h) / n
    return math.cos(h), wx * k, wy * k, wz * k


@njit(cache=True, inline="always")
def qnormalize(q0, q1, q2, q3):
    n = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    return q0 / n, q1 / n, q2 / n, q3 / n


@njit(cache=True)
def rotmat(q, R):
    """Write the rotation matrix of the unit quaternion q (float64[4]) into R (3x3)."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    R[0, 0] = 1.0 - 2.0 * (y * y + z * z)
    R[0, 1] = 2.0 * (x * y - w * z)
    R[0, 2] = 2.0 * (x * z + w * y)
    R[1, 0] = 2.0 * (x * y + w * z)
    R[1, 1] = 1.0 - 2.0 * (x * x + z * z)
    R[1, 2] = 2.0 * (y * z - w * x)
    R[2, 0] = 2.0 * (x * z - w * y)
    R[2, 1] = 2.0 * (y * z + w * x)
    R[2, 2] = 1.0 - 2.0 * (x * x + y * y)


# ------------------------------------------------------------------ closed forms


@njit(cache=True)
def precession(q0, q1, q2, q3, wx, wy, wz, I1, I2, I3, rk, axis, s, out):
    """Closed-form torque-free rotation (spherical or axisymmetric inertia).

    ``q``: orientation at s = 0; ``w``: world angular velocity at s = 0 (rad/s);
    ``I1, I2, I3`` principal moments (kg m^2); ``rk`` ``ROT_SPHERICAL`` or ``ROT_AXISYM``
    with ``axis`` (0, 1, 2) the body symmetry axis. Writes ``q(s)`` to ``out[3:7]`` and
    ``w(s)`` to ``out[10:13]``.
    """
    if rk == ROT_SPHERICAL or (wx == 0.0 and wy == 0.0 and wz == 0.0):
        e0, e1, e2, e3 = qexp(wx, wy, wz, s)
        a0, a1, a2, a3 = qmul(e0, e1, e2, e3, q0, q1, q2, q3)
        a0, a1, a2, a3 = qnormalize(a0, a1, a2, a3)
        out[3] = a0
        out[4] = a1
        out[5] = a2
        out[6] = a3
        out[10] = wx
        out[11] = wy
        out[12] = wz
        return
    # body frame
    bx, by, bz = qrot_inv(q0, q1, q2, q3, wx, wy, wz)
    if axis == 0:
        A = I2
        C = I1
        L3 = I1 * bx
    elif axis == 1:
        A = I1
        C = I2
        L3 = I2 * by
    else:
        A = I1
        C = I3
        L3 = I3 * bz
    Lbx = I1 * bx
    Lby = I2 * by
    Lbz = I3 * bz
    Lx, Ly, Lz = qrot(q0, q1, q2, q3, Lbx, Lby, Lbz)
    sig = L3 * (1.0 / C - 1.0 / A)
    # body-frame spin about the symmetry axis, world-frame precession about L
    ex = 1.0 if axis == 0 else 0.0
    ey = 1.0 if axis == 1 else 0.0
    ez = 1.0 if axis == 2 else 0.0
    s0, s1, s2, s3 = qexp(ex * sig, ey * sig, ez * sig, s)
    p0, p1, p2, p3 = qexp(Lx / A, Ly / A, Lz / A, s)
    a0, a1, a2, a3 = qmul(q0, q1, q2, q3, s0, s1, s2, s3)
    a0, a1, a2, a3 = qmul(p0, p1, p2, p3, a0, a1, a2, a3)
    a0, a1, a2, a3 = qnormalize(a0, a1, a2, a3)
    out[3] = a0
    out[4] = a1
    out[5] = a2
    out[6] = a3
    ux, uy, uz = qrot(a0, a1, a2, a3, ex, ey, ez)
    out[10] = Lx / A + sig * ux
    out[11] = Ly / A + sig * uy
    out[12] = Lz / A + sig * uz


@njit(cache=True)
def rotation_bounds(st, I1, I2, I3, rk, axis, S):
    """Bounds over ``[0, S]`` (s) of ``|w|`` (rad/s) and ``|dw/ds|`` (rad/s^2) for the
    rotation of state row ``st``; used to bound the second derivative of gap functions."""
    wx, wy, wz = st[10], st[11], st[12]
    w2 = wx * wx + wy * wy + wz * wz
    alx, aly, alz = st[16], st[17], st[18]
    al2 = alx * alx + aly * aly + alz * alz
    if al2 > 0.0:
        a = math.sqrt(al2)
        return math.sqrt(w2) + a * S, a
    if w2 == 0.0 or rk == ROT_SPHERICAL:
        return math.sqrt(w2), 0.0
    bx, by, bz = qrot_inv(st[3], st[4], st[5], st[6], wx, wy, wz)
    if rk == ROT_AXISYM:
        # |w| is constant; dw/ds = sigma w x e, |w x e| = |w| sin(angle)
        if axis == 0:
            A, C, we = I2, I1, bx
        elif axis == 1:
            A, C, we = I1, I2, by
        else:
            A, C, we = I1, I3, bz
        sig = C * we * (1.0 / C - 1.0 / A)
        wperp = math.sqrt(max(w2 - we * we, 0.0))
        return math.sqrt(w2), abs(sig) * wperp
    T2 = I1 * bx * bx + I2 * by * by + I3 * bz * bz     # twice the rotational energy
    imin = min(I1, min(I2, I3))
    imax = max(I1, max(I2, I3))
    wmax2 = T2 / imin
    # |dw_b/ds|^2 <= ((imax - imin)/imin)^2 ((w2 w3)^2 + (w3 w1)^2 + (w1 w2)^2)
    #             <= ((imax - imin)/imin)^2 |w|^4 / 3
    return math.sqrt(wmax2), (imax - imin) / imin * wmax2 / math.sqrt(3.0)


# ------------------------------------------------------------------ Runge-Kutta


@njit(cache=True, inline="always")
def _rhs(ws, s, y, off, k, koff):
    """Right-hand side at (s, y[off:off+7]) into k[koff:koff+7]."""
    q0 = y[off]
    q1 = y[off + 1]
    q2 = y[off + 2]
    q3 = y[off + 3]
    if ws[WS_MODE] == 1.0:
        w1 = y[off + 4]
        w2 = y[off + 5]
        w3 = y[off + 6]
        I1 = ws[WS_I]
        I2 = ws[WS_I + 1]
        I3 = ws[WS_I + 2]
        # dq/ds = q (0, w_b) / 2
        d0, d1, d2, d3 = qmul(q0, q1, q2, q3, 0.0, w1, w2, w3)
        k[koff + 4] = (I2 - I3) * w2 * w3 / I1
        k[koff + 5] = (I3 - I1) * w3 * w1 / I2
        k[koff + 6] = (I1 - I2) * w1 * w2 / I3
    else:
        wx = ws[WS_W0] + ws[WS_AL] * s
        wy = ws[WS_W0 + 1] + ws[WS_AL + 1] * s
        wz = ws[WS_W0 + 2] + ws[WS_AL + 2] * s
        # dq/ds = (0, w) q / 2
        d0, d1, d2, d3 = qmul(0.0, wx, wy, wz, q0, q1, q2, q3)
        k[koff + 4] = 0.0
        k[koff + 5] = 0.0
        k[koff + 6] = 0.0
    k[koff] = 0.5 * d0
    k[koff + 1] = 0.5 * d1
    k[koff + 2] = 0.5 * d2
    k[koff + 3] = 0.5 * d3


@njit(cache=True)
def rk_start(ws, mode, q, wb, I1, I2, I3, al, w0, tol, max_steps):
    """Initialise the integrator workspace ``ws`` (float64[N_WS]) for one segment.

    ``mode`` 1: Euler equations from quaternion ``q`` (float64[4]) and body angular
    velocity ``wb`` (float64[3]); mode 2: quaternion only, world angular velocity
    ``w0 + al s``. ``tol``: ``rot_tol`` (dimensionless); ``max_steps``: step limit.
    """
    ws[WS_MODE] = mode
    ws[WS_TOL] = tol
    ws[WS_I] = I1
    ws[WS_I + 1] = I2
    ws[WS_I + 2] = I3
    for j in range(3):
        ws[WS_AL + j] = al[j]
        ws[WS_W0 + j] = w0[j]
    for j in range(4):
        ws[WS_YSTART + j] = q[j]
    for j in range(3):
        ws[WS_YSTART + 4 + j] = wb[j] if mode == 1 else 0.0
    if mode == 1:
        wsc = math.sqrt(wb[0] * wb[0] + wb[1] * wb[1] + wb[2] * wb[2])
    else:
        wsc = math.sqrt(w0[0] * w0[0] + w0[1] * w0[1] + w0[2] * w0[2])
        a = math.sqrt(al[0] * al[0] + al[1] * al[1] + al[2] * al[2])
        wsc = max(wsc, math.sqrt(a))
    ws[WS_WSCALE] = wsc
    ws[WS_MAXSTEP] = max_steps
    _rk_reset(ws)


@njit(cache=True)
def _rk_reset(ws):
    for j in range(7):
        ws[WS_Y + j] = ws[WS_YSTART + j]
    ws[WS_S0] = 0.0
    ws[WS_H] = 0.0
    ws[WS_NSTEP] = 0.0
    wsc = ws[WS_WSCALE]
    if wsc > 0.0:
        ws[WS_HNEXT] = FIRST_ANGLE * ws[WS_TOL] ** 0.2 / wsc
    else:
        ws[WS_HNEXT] = math.inf


@njit(cache=True)
def _rk_step(ws):
    """Take one accepted step from (WS_S0 + WS_H, y1) -- or from the start when no step
    has been taken -- storing the new step's dense output. Returns RK_OK or an error."""
    if ws[WS_H] > 0.0:
        # the previous step's end becomes the new start (renormalised quaternion)
        q0, q1, q2, q3 = qnormalize(ws[WS_Y1], ws[WS_Y1 + 1], ws[WS_Y1 + 2], ws[WS_Y1 + 3])
        ws[WS_Y] = q0
        ws[WS_Y + 1] = q1
        ws[WS_Y + 2] = q2
        ws[WS_Y + 3] = q3
        for j in range(4, 7):
            ws[WS_Y + j] = ws[WS_Y1 + j]
        ws[WS_S0] = ws[WS_S0] + ws[WS_H]
    s0 = ws[WS_S0]
    h = ws[WS_HNEXT]
    tol = ws[WS_TOL]
    wsc = ws[WS_WSCALE]
    if not (h < math.inf):
        # nothing rotates: one infinite constant step
        for j in range(7):
            ws[WS_Y1 + j] = ws[WS_Y + j]
            ws[WS_RC + j] = ws[WS_Y + j]
            for r in range(1, 5):
                ws[WS_RC + 7 * r + j] = 0.0
        ws[WS_H] = math.inf
        return RK_OK
    K = WS_K
    n = 7
    _rhs(ws, s0, ws, WS_Y, ws, K)
    while True:
        ws[WS_NSTEP] += 1.0
        if ws[WS_NSTEP] > ws[WS_MAXSTEP]:
            return RK_TOO_MANY_STEPS
        arg2(ws, n, WS_Y, K, WS_YT, h)
        _rhs(ws, s0 + C2 * h, ws, WS_YT, ws, K + 7)
        arg3(ws, n, WS_Y, K, WS_YT, h)
        _rhs(ws, s0 + C3 * h, ws, WS_YT, ws, K + 14)
        arg4(ws, n, WS_Y, K, WS_YT, h)
        _rhs(ws, s0 + C4 * h, ws, WS_YT, ws, K + 21)
        arg5(ws, n, WS_Y, K, WS_YT, h)
        _rhs(ws, s0 + C5 * h, ws, WS_YT, ws, K + 28)
        arg6(ws, n, WS_Y, K, WS_YT, h)
        _rhs(ws, s0 + h, ws, WS_YT, ws, K + 35)
        solution(ws, n, WS_Y, K, WS_Y1, h)
        _rhs(ws, s0 + h, ws, WS_Y1, ws, K + 42)
        err = 0.0
        for j in range(7):
            ej = error_estimate(ws, n, K, h, j)
            sc = tol if j < 4 else tol * wsc
            if sc > 0.0:
                r = abs(ej) / sc
                if r > err:
                    err = r
        if err <= 1.0:
            dense_store(ws, n, WS_Y, WS_Y1, K, WS_RC, h)
            ws[WS_H] = h
            ws[WS_HNEXT] = h * step_factor(err)
            return RK_OK
        h = h * reject_factor(err)


@njit(cache=True)
def rk_eval(ws, s, out):
    """State at ``s`` (s >= 0) of the integrated segment: q(s) into ``out[3:7]`` and, in
    mode 1, the **body-frame** angular velocity into ``out[10:13]`` (mode 2: zeros). Steps forward
    as needed (restarting from s = 0 when s lies before the current step). Returns RK_OK
    or RK_TOO_MANY_STEPS."""
    if s < ws[WS_S0]:
        _rk_reset(ws)
    while ws[WS_H] == 0.0 or s > ws[WS_S0] + ws[WS_H]:
        rc = _rk_step(ws)
        if rc != RK_OK:
            return rc
    h = ws[WS_H]
    th = (s - ws[WS_S0]) / h if h < math.inf else 0.0
    for j in range(7):
        out[3 + j if j < 4 else 6 + j] = dense_eval(ws, 7, WS_RC, th, j)
    q0, q1, q2, q3 = qnormalize(out[3], out[4], out[5], out[6])
    out[3] = q0
    out[4] = q1
    out[5] = q2
    out[6] = q3
    return RK_OK


# ------------------------------------------------------------------ the pose at any time


@njit(cache=True)
def pose_at(st, rk, axis, I1, I2, I3, ws, s, rot_tol, rot_max_steps, out):
    """Pose of a body ``s`` seconds after its state row ``st`` (float64[19]) into ``out``
    (float64[19], same layout). ``rk``/``axis``: rotation kind and symmetry axis of the
    principal moments ``I1, I2, I3``; ``ws``: the body's integrator workspace
    (``ws[WS_MODE] < 0`` marks it uninitialised for this segment; it is set up here when
    the rotation needs integration). Returns RK_OK or RK_TOO_MANY_STEPS."""
    h = 0.5 * s * s
    for j in range(3):
        out[j] = st[j] + st[7 + j] * s + st[13 + j] * h
        out[7 + j] = st[7 + j] + st[13 + j] * s
        out[13 + j] = st[13 + j]
        out[16 + j] = st[16 + j]
    wx, wy, wz = st[10], st[11], st[12]
    alx, aly, alz = st[16], st[17], st[18]
    if alx == 0.0 and aly == 0.0 and alz == 0.0:
        if (wx == 0.0 and wy == 0.0 and wz == 0.0) or s == 0.0:
            for j in range(4):
                out[3 + j] = st[3 + j]
            out[10] = wx
            out[11] = wy
            out[12] = wz
            return RK_OK
        if rk != ROT_GENERAL:
            precession(st[3], st[4], st[5], st[6], wx, wy, wz, I1, I2, I3, rk, axis, s, out)
            return RK_OK
        if ws[WS_MODE] < 0.0:
            bx, by, bz = qrot_inv(st[3], st[4], st[5], st[6], wx, wy, wz)
            _start_general(ws, st, bx, by, bz, I1, I2, I3, rot_tol, rot_max_steps)
        rc = rk_eval(ws, s, out)
        if rc != RK_OK:
            return rc
        ux, uy, uz = qrot(out[3], out[4], out[5], out[6], out[10], out[11], out[12])
        out[10] = ux
        out[11] = uy
        out[12] = uz
        return RK_OK
    out[10] = wx + alx * s
    out[11] = wy + aly * s
    out[12] = wz + alz * s
    cx = wy * alz - wz * aly
    cy = wz * alx - wx * alz
    cz = wx * aly - wy * alx
    if cx == 0.0 and cy == 0.0 and cz == 0.0:
        # fixed axis: rotation vector w s + al s^2 / 2
        e0, e1, e2, e3 = qexp(wx * s + alx * h, wy * s + aly * h, wz * s + alz * h, 1.0)
        a0, a1, a2, a3 = qmul(e0, e1, e2, e3, st[3], st[4], st[5], st[6])
        a0, a1, a2, a3 = qnormalize(a0, a1, a2, a3)
        out[3] = a0
        out[4] = a1
        out[5] = a2
        out[6] = a3
        return RK_OK
    if ws[WS_MODE] < 0.0:
        _start_linear(ws, st, I1, I2, I3, rot_tol, rot_max_steps)
    w10 = out[10]
    w11 = out[11]
    w12 = out[12]
    rc = rk_eval(ws, s, out)
    out[10] = w10
    out[11] = w11
    out[12] = w12
    return rc


@njit(cache=True)
def _start_general(ws, st, bx, by, bz, I1, I2, I3, tol, max_steps):
    ws[WS_MODE] = 1.0
    ws[WS_TOL] = tol
    ws[WS_I] = I1
    ws[WS_I + 1] = I2
    ws[WS_I + 2] = I3
    for j in range(3):
        ws[WS_AL + j] = 0.0
        ws[WS_W0 + j] = 0.0
    for j in range(4):
        ws[WS_YSTART + j] = st[3 + j]
    ws[WS_YSTART + 4] = bx
    ws[WS_YSTART + 5] = by
    ws[WS_YSTART + 6] = bz
    ws[WS_WSCALE] = math.sqrt(bx * bx + by * by + bz * bz)
    ws[WS_MAXSTEP] = max_steps
    _rk_reset(ws)


@njit(cache=True)
def _start_linear(ws, st, I1, I2, I3, tol, max_steps):
    ws[WS_MODE] = 2.0
    ws[WS_TOL] = tol
    ws[WS_I] = I1
    ws[WS_I + 1] = I2
    ws[WS_I + 2] = I3
    w2 = 0.0
    a2 = 0.0
    for j in range(3):
        ws[WS_AL + j] = st[16 + j]
        ws[WS_W0 + j] = st[10 + j]
        w2 += st[10 + j] * st[10 + j]
        a2 += st[16 + j] * st[16 + j]
    for j in range(4):
        ws[WS_YSTART + j] = st[3 + j]
    for j in range(3):
        ws[WS_YSTART + 4 + j] = 0.0
    ws[WS_WSCALE] = max(math.sqrt(w2), a2 ** 0.25)
    ws[WS_MAXSTEP] = max_steps
    _rk_reset(ws)


@njit(cache=True)
def sample_segments3d(seg_t, seg_s, start, stop, rk, axis, I1, I2, I3, rot_tol,
                      rot_max_steps, times, order, out, col, ws, pose):
    """Evaluate one body's piecewise motion at ``times[order]`` (``order`` sorts them).

    ``seg_t[start:stop]`` are the body's segment start times (non-decreasing), ``seg_s``
    the state rows. Results go to ``out[k, col, :]`` (float64[n_times, n_bodies, 13]:
    x, q, v, w). ``ws`` (float64[N_WS]) and ``pose`` (float64[19]) are scratch. Each
    integrated segment is re-integrated from its start with the same steps as in the run.
    Returns RK_OK or RK_TOO_MANY_STEPS.
    """
    n = stop - start
    cur = -1
    for kk in range(times.shape[0]):
        k = order[kk]
        t = times[k]
        lo = 0
        hi = n - 1
        if seg_t[start] > t:
            j = 0
        else:
            while lo < hi:
                mid = (lo + hi + 1) // 2
                if seg_t[start + mid] <= t:
                    lo = mid
                else:
                    hi = mid - 1
            j = lo
        r = start + j
        if r != cur:
            ws[WS_MODE] = -1.0
            cur = r
        rc = pose_at(seg_s[r], rk, axis, I1, I2, I3, ws, t - seg_t[r], rot_tol,
                     rot_max_steps, pose)
        if rc != RK_OK:
            return rc
        for m in range(13):
            out[k, col, m] = pose[m]
    return RK_OK


@njit(cache=True)
def world_inertia_inv(q, I1, I2, I3, R, Iinv):
    """Iinv = R diag(1/I) R^T (kg^-1 m^-2) for orientation q; R is scratch (3x3)."""
    rotmat(q, R)
    for a in range(3):
        for b in range(3):
            Iinv[a, b] = R[a, 0] * R[b, 0] / I1 + R[a, 1] * R[b, 1] / I2 + \
                R[a, 2] * R[b, 2] / I3
