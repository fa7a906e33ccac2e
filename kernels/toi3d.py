"""Time of impact in 3D: the earliest root with g' < 0 of smooth gap functions g(s).

Contact features (DESIGN §6, issue 5) are body-frame points ``p`` carrying a radius ``r``:
a sphere is its centre with its radius, a box its eight corners (``r = 0``), a capsule the
centres of its two end caps with the capsule radius. Against a static half-space
``{y : n . y >= d}`` (``n`` the unit normal into the free side):
``g(s) = n . (x(s) + R(s) p) - r - d``, ``g'(s) = n . (v(s) + w(s) x R(s) p)``.
Sphere against sphere: ``g(s) = |x_A(s) - x_B(s)| - r_A - r_B``.

Method (the 3D counterpart of ``toi2d``). All the features of one body against all the
planes are searched in one sweep. When nothing rotates (or the body is a sphere) every
gap is an exact quadratic and its roots are taken in closed form. Otherwise conservative
advancement: with ``M_k >= |g_k''|`` on the whole window, ``g_k(s + h) >= g_k(s) + g_k'(s) h
- M_k h^2 / 2``, so stepping by the smallest first zero of these lower bounds (over every
feature and plane) never passes the first root of any gap, grazing roots included; near a
transversal root the steps are Newton steps from the safe side (quadratic convergence).
The sweep stops when the step falls below ``atol + rtol |t0 + s|``.

Bound: ``|g_k''| <= |n . a| + |p_k| (w_max^2 + al_max)`` with ``w_max``, ``al_max`` bounds of
``|w|`` and ``|dw/ds|`` on the window (``flight3d.rotation_bounds``; exact constants for
spherical and axisymmetric inertia, from the conserved energy for general inertia, times
``1 + GENERAL_BOUND_SLACK`` to cover the integrator's own error).

Tangent basis (DESIGN §3), deterministic and right-handed (``t1 x t2 = n``):
``t1 = (y^ x n) / |y^ x n|`` when ``|n_y| <= BASIS_SWITCH``, else ``t1 = (n x x^)/|n x x^|``;
``t2 = n x t1``. A floor ``n = z^`` has ``t1 = x^, t2 = y^``, and for a normal in the x-z
plane ``(n_x, 0, n_z)`` it is ``t1 = (n_z, 0, -n_x)``: the 2D basis ``t = (n_y, -n_x)`` of
the x-z plane, so motion in that plane reproduces the 2D stepper component for component.
"""
import math

from numba import njit

from .cache_guard import guard

# flush stale compiled callers before any kernel module below is imported (cache_guard)
guard(__name__, __file__)

from .decisions import TOUCH_RTOL, touching_accel, touching_rate, touching_speed
from .flight3d import RK_OK, ROT_GENERAL, ROT_SPHERICAL, pose_at, qrot, qrot_inv, rotation_bounds
from .toi2d import TOI_MISSED, TOI_NOT_CONVERGED, TOI_OK, _safe_step, \
    centres_quadratic_toi, quadratic_descending_root, window_step

INF = math.inf
BASIS_SWITCH = 0.9            # |n_y| above which t1 is built from x^ instead of y^ (-)
GENERAL_BOUND_SLACK = 1e-6    # relative slack on the |g''| bound of integrated rotation (-)
TOI_ROT_FAILED = 3            # the rotation integrator hit its step limit


@njit(cache=True, inline="always")
def tangent_basis(nx, ny, nz):
    """Deterministic right-handed tangent basis (t1, t2) of the unit normal n (see the
    module docstring). Returns six floats."""
    if abs(ny) <= BASIS_SWITCH:
        # y x n = (nz, 0, -nx)
        ax = nz
        ay = 0.0
        az = -nx
    else:
        # n x x = (0, nz, -ny)
        ax = 0.0
        ay = nz
        az = -ny
    k = 1.0 / math.sqrt(ax * ax + ay * ay + az * az)
    ax *= k
    ay *= k
    az *= k
    bx = ny * az - nz * ay
    by = nz * ax - nx * az
    bz = nx * ay - ny * ax
    return ax, ay, az, bx, by, bz


@njit(cache=True, inline="always")
def _round_off_rate_time(pose, rk, I1, I2, I3, nx, ny, nz, rx, ry, rz, gd, thr, wmax, almax,
                         slack):
    """A time (s) over which the rate ``gd`` (m/s, ``gd >= -thr``) of a feature point at
    arm ``r = R p`` touching a plane ``n`` stays above ``-thr``: the root of
    ``gd + g2 h - M3 h^2 / 2 = -thr`` with the point's own gap acceleration ``g2`` (m/s^2:
    ``n . (a + al x r + w x (w x r))``, ``al`` the row's prescribed angular acceleration or
    the torque-free ``I^-1 ((I w) x w)``) and ``M3 = |p| (wmax^3 + 3 almax wmax + (2 imax /
    imin + 1) wmax almax)`` (times ``slack``), a bound of the gap's third derivative
    (``|d al / ds| <= (2 imax / imin + 1) |w| |al|`` from Euler's equations). 0 when the point
    is pushed into the plane (``g2`` below its round-off, ``decisions.touching_accel``): the
    caller keeps its ``toi_atol`` steps there. The 3D counterpart of
    ``toi2d._round_off_rate_time``: a box released from a pivot starts at a third-order
    tangency, where ``toi_atol`` steps never reach the separation (3:3522406362)."""
    wx, wy, wz = pose[10], pose[11], pose[12]
    alx, aly, alz = pose[16], pose[17], pose[18]
    if alx == 0.0 and aly == 0.0 and alz == 0.0 and rk != ROT_SPHERICAL:
        q0, q1, q2, q3 = pose[3], pose[4], pose[5], pose[6]
        bx, by, bz = qrot_inv(q0, q1, q2, q3, wx, wy, wz)
        alx, aly, alz = qrot(q0, q1, q2, q3, (I2 - I3) * by * bz / I1,
                             (I3 - I1) * bz * bx / I2, (I1 - I2) * bx * by / I3)
    wr = wx * rx + wy * ry + wz * rz
    w2 = wx * wx + wy * wy + wz * wz
    nr = nx * rx + ny * ry + nz * rz
    g2 = (nx * pose[13] + ny * pose[14] + nz * pose[15]
          + nx * (aly * rz - alz * ry) + ny * (alz * rx - alx * rz) + nz * (alx * ry - aly * rx)
          + (nx * wx + ny * wy + nz * wz) * wr - nr * w2)
    reach = math.sqrt(rx * rx + ry * ry + rz * rz)
    al = math.sqrt(alx * alx + aly * aly + alz * alz)
    lin = math.sqrt(pose[13] ** 2 + pose[14] ** 2 + pose[15] ** 2)
    if touching_accel(g2, lin + al * reach, math.sqrt(w2), reach) < 0.0:
        return 0.0
    imin = min(I1, min(I2, I3))
    imax = max(I1, max(I2, I3))
    M3 = reach * slack * (wmax * wmax * wmax + 3.0 * almax * wmax
                          + (2.0 * imax / imin + 1.0) * wmax * almax)
    if M3 > 0.0:
        return (g2 + math.sqrt(g2 * g2 + 2.0 * M3 * (thr + gd))) / M3
    if g2 < 0.0:
        return (thr + gd) / -g2
    return INF


@njit(cache=True)
def body_planes_toi(st, rk, axis, I1, I2, I3, ws, feats, f0, nf, rad, planes, skip, t0, S,
                    rtol, atol, gap_tol, maxit, rot_tol, rot_max, pose):
    """Earliest impact of a body's features with any plane in ``[0, S]`` (s after ``t0``).

    ``st`` float64[19]: the body's state row at ``t0`` (its segment start, ``s = 0``);
    ``rk, axis, I1..I3``: its rotation kind and principal moments; ``ws``: its integrator
    workspace; ``feats[f0:f0+nf]``: body-frame feature points with radius ``rad``;
    ``planes`` float64[np, 4] ``(n, d)``; ``skip`` int64[np]: planes to ignore (non-zero);
    ``pose`` float64[19] scratch. Returns ``(s, plane, feature, code)``; ``s = inf`` if no
    impact in the window.
    """
    npl = planes.shape[0]
    best = INF
    bp = -1
    bk = -1
    wmax, almax = rotation_bounds(st, I1, I2, I3, rk, axis, S)
    rot = (wmax > 0.0 or almax > 0.0)
    if rot:
        rot = False
        for k in range(nf):
            if feats[f0 + k, 0] != 0.0 or feats[f0 + k, 1] != 0.0 or feats[f0 + k, 2] != 0.0:
                rot = True
    if not rot:
        # exact quadratics: the rotating part of every gap is constant
        for p in range(npl):
            if skip[p] != 0:
                continue
            nx = planes[p, 0]
            ny = planes[p, 1]
            nz = planes[p, 2]
            na = nx * st[13] + ny * st[14] + nz * st[15]
            g1 = nx * st[7] + ny * st[8] + nz * st[9]
            gc = nx * st[0] + ny * st[1] + nz * st[2] - planes[p, 3] - rad
            for k in range(nf):
                px = feats[f0 + k, 0]
                py = feats[f0 + k, 1]
                pz = feats[f0 + k, 2]
                # R p with R from q
                wx, wy, wz = _rotp(st, px, py, pz)
                g0 = gc + nx * wx + ny * wy + nz * wz
                gd0 = g1
                if g0 <= 0.0:
                    # touching: a rate at the round-off of the speed is zero (TOUCH_RTOL;
                    # its scale decisions.touching_speed)
                    gd0 = touching_rate(g1, touching_speed(
                        math.sqrt(st[7] ** 2 + st[8] ** 2 + st[9] ** 2),
                        math.sqrt(st[13] ** 2 + st[14] ** 2 + st[15] ** 2),
                        math.sqrt(px * px + py * py + pz * pz) + rad))
                s, code = quadratic_descending_root(g0, gd0, na, S, gap_tol)
                if code == TOI_MISSED:
                    return 0.0, p, k, TOI_MISSED
                if s < best:
                    best = s
                    bp = p
                    bk = k
        return best, bp, bk, TOI_OK
    slack = 1.0 + (GENERAL_BOUND_SLACK if rk == ROT_GENERAL else 0.0)
    wb = (wmax * wmax + almax) * slack
    s = 0.0
    for it in range(maxit):
        rc = pose_at(st, rk, axis, I1, I2, I3, ws, s, rot_tol, rot_max, pose)
        if rc != RK_OK:
            return s, -1, -1, TOI_ROT_FAILED
        hmin = INF
        hp = -1
        hk = -1
        hgd = 0.0
        for p in range(npl):
            if skip[p] != 0:
                continue
            nx = planes[p, 0]
            ny = planes[p, 1]
            nz = planes[p, 2]
            na = abs(nx * pose[13] + ny * pose[14] + nz * pose[15])
            gc = nx * pose[0] + ny * pose[1] + nz * pose[2] - planes[p, 3] - rad
            gv = nx * pose[7] + ny * pose[8] + nz * pose[9]
            for k in range(nf):
                px = feats[f0 + k, 0]
                py = feats[f0 + k, 1]
                pz = feats[f0 + k, 2]
                rx, ry, rz = _rotp(pose, px, py, pz)
                g = gc + nx * rx + ny * ry + nz * rz
                # w x r
                ux = pose[11] * rz - pose[12] * ry
                uy = pose[12] * rx - pose[10] * rz
                uz = pose[10] * ry - pose[11] * rx
                gd = gv + nx * ux + ny * uy + nz * uz
                if g <= 0.0:
                    if g < -gap_tol:
                        return s, p, k, TOI_MISSED
                    # a rate at the round-off of the point's speed is zero (TOUCH_RTOL;
                    # its scale decisions.touching_speed)
                    scale = touching_speed(
                        math.sqrt(pose[7] ** 2 + pose[8] ** 2 + pose[9] ** 2)
                        + math.sqrt(ux * ux + uy * uy + uz * uz),
                        math.sqrt(pose[13] ** 2 + pose[14] ** 2 + pose[15] ** 2),
                        math.sqrt(px * px + py * py + pz * pz) + rad)
                    thr = TOUCH_RTOL * scale
                    gd0 = gd
                    gd = touching_rate(gd, scale)
                    if gd < 0.0:
                        return s, p, k, TOI_OK
                    g = 0.0
                    if thr > 0.0:
                        # touching (or inside by at most gap_tol) at a rate above -thr, not
                        # pushed into the plane: no impact while the rate stays above -thr
                        # (a separating rate too: from a gap at -7.8e-13 m, safe steps from
                        # a gap of 0 crept by 2 g' / M = 1.8e-13 s); the gap sinks at most
                        # thr h meanwhile, kept within gap_tol / 2
                        h = _round_off_rate_time(pose, rk, I1, I2, I3, nx, ny, nz, rx, ry, rz,
                                                 gd0, thr, wmax, almax, slack)
                        if h > 0.0:
                            h = min(h, 0.5 * gap_tol / thr)
                            if h < hmin:
                                hmin = h
                                hp = p
                                hk = k
                                hgd = 0.0
                            continue
                M = na + math.sqrt(px * px + py * py + pz * pz) * wb
                h = _safe_step(g, gd, M)
                if h < hmin:
                    hmin = h
                    hp = p
                    hk = k
                    hgd = gd
        if hp < 0:
            return INF, -1, -1, TOI_OK
        tol = atol + rtol * abs(t0 + s)
        if hmin <= tol:
            if hgd < 0.0:
                r = s + hmin
                if r <= S:
                    return r, hp, hk, TOI_OK
                return INF, -1, -1, TOI_OK
            hmin = tol  # tangency (grazing without crossing): step past it
        s += hmin
        if s > S:
            return INF, -1, -1, TOI_OK
    return s, -1, -1, TOI_NOT_CONVERGED


@njit(cache=True, inline="always")
def _rotp(row, px, py, pz):
    """R(q) p for the quaternion in row[3:7]."""
    q0 = row[3]
    q1 = row[4]
    q2 = row[5]
    q3 = row[6]
    tx = 2.0 * (q2 * pz - q3 * py)
    ty = 2.0 * (q3 * px - q1 * pz)
    tz = 2.0 * (q1 * py - q2 * px)
    return (px + q0 * tx + q2 * tz - q3 * ty,
            py + q0 * ty + q3 * tx - q1 * tz,
            pz + q0 * tz + q1 * ty - q2 * tx)


@njit(cache=True)
def sphere_sphere_toi(dx, dy, dz, dvx, dvy, dvz, dax, day, daz, R, t0, S, rtol, atol,
                      gap_tol, maxit):
    """Earliest ``s`` in ``[0, S]`` at which two spheres (radii summing to ``R``) touch while
    approaching, given their relative position, velocity and acceleration (A minus B) at
    ``t0``. Equal accelerations: exact quadratic. Returns ``(s, code)``."""
    dist = math.sqrt(dx * dx + dy * dy + dz * dz)
    g0 = dist - R
    if dax == 0.0 and day == 0.0 and daz == 0.0:
        return centres_quadratic_toi(g0, dist, R, 2.0 * (dx * dvx + dy * dvy + dz * dvz),
                                     dvx * dvx + dvy * dvy + dvz * dvz, S, gap_tol)
    da = math.sqrt(dax * dax + day * day + daz * daz)
    s = 0.0
    ex, ey, ez, ux, uy, uz = dx, dy, dz, dvx, dvy, dvz
    g = g0
    gd = (ex * ux + ey * uy + ez * uz) / dist
    if g <= 0.0:
        code = TOI_MISSED if g < -gap_tol else TOI_OK
        if gd < 0.0 or code == TOI_MISSED:
            return 0.0, code
        g = 0.0
    H = S
    for _ in range(maxit):
        s, H, done = window_step(s, g, gd, math.sqrt(ux * ux + uy * uy + uz * uz), da, R, H,
                                 S, t0, rtol, atol)
        if done:
            return s, TOI_OK
        hs = 0.5 * s * s
        ex = dx + dvx * s + dax * hs
        ey = dy + dvy * s + day * hs
        ez = dz + dvz * s + daz * hs
        ux = dvx + dax * s
        uy = dvy + day * s
        uz = dvz + daz * s
        dist = math.sqrt(ex * ex + ey * ey + ez * ez)
        g = dist - R
        gd = (ex * ux + ey * uy + ez * uz) / dist
        if g <= 0.0:
            if gd < 0.0:
                return s, TOI_OK
            g = 0.0
    return s, TOI_NOT_CONVERGED
