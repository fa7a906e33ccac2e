"""Time of impact in 2D: the earliest root with g' < 0 of a smooth gap function g(s).

Contact features (DESIGN §6, issue 3) and their gap functions, for a body whose state row
``st = (x, y, angle, vx, vy, omega, ax, ay, alpha)`` holds at ``s = 0`` (see ``flight2d``),
against a static half-plane ``{q : n . q >= d}`` (``n`` the unit normal into the free side):

* ``FEAT_VERTEX``: a body-frame point ``p`` carrying a radius ``r`` (a disk is its centre
  with its radius; a polygon's corner has ``r = 0``; a rod's ends carry the capsule radius):
  ``g(s) = n . (x(s) + R(angle(s)) p) - r - d``;
* ``FEAT_ELLIPSE``: semi-axes ``a`` (body x) and ``b`` (body y):
  ``g(s) = n . x(s) - sqrt(a^2 (n . e1)^2 + b^2 (n . e2)^2) - d``, ``e1, e2`` the body axes.

Disk against disk: ``g(s) = |x_A(s) - x_B(s)| - r_A - r_B``.

Method. When the gap is an exact quadratic (no rotation, or the point is the centre of
mass; two disks with equal accelerations) its roots are taken in closed form with the
cancellation-free quadratic formula. Otherwise conservative advancement: with a bound
``M >= |g''|`` over the search window, ``g(s + h) >= g(s) + g'(s) h - M h^2 / 2``, so stepping
to the first zero of that lower bound never passes the first root of ``g`` (grazing roots
included); near a transversal root the steps converge quadratically (the step is a Newton
step from the safe side). The iteration stops when the step is below
``atol + rtol * |t0 + s|`` (s); the root is then within about that of the true one.

Bounds used: vertex ``|d^2/ds^2 n.R p| <= |p| (omega_max^2 + |alpha|)``; ellipse support
``h(angle)``: ``|h''| <= |a^2 - b^2| / min(a, b)`` and ``|h'| <= max(a, b)``; two disks
with relative acceleration ``da``: ``|g''| <= (|dv| + |da| H)^2 / (r_A + r_B) + |da|`` over a
window of length ``H`` (valid up to the first root, where the distance is >= r_A + r_B).

Touching (``g <= 0`` within ``gap_tol``) at the search's start: the feature approaches only
when its normal rate is below ``-decisions.TOUCH_RTOL`` times the speed the rate is computed
from: the centre's speed plus ``|omega|`` times the feature's reach, and at least
``sqrt(|a| reach)``, ``decisions.touching_speed``; a rate at that speed's round-off is
zero, never read for its sign. The same holds inside a plane feature's search: wherever the
gap is at or below 0, an impact is a rate below ``-thr`` (``thr = TOUCH_RTOL`` times that
speed), and a feature touching at a rate within ``thr`` is stepped over by the time its
rate needs to fall below ``-thr`` (``_round_off_rate_time``; for a vertex from its own g''
and the bound ``|p| (omega_max^3 + 3 |alpha| omega_max)`` of its third derivative), sinking
at most ``gap_tol / 2`` meanwhile, unless it is pushed into the plane (g'' below its
round-off, ``decisions.touching_accel``): then it meets the plane one step on.

Return convention: ``(s, code)`` with ``s`` the root (``inf`` if none in ``[0, S]``) and
``code`` one of ``TOI_OK``, ``TOI_MISSED`` (the gap is already below ``-gap_tol``: an event
was missed or the body started inside), ``TOI_NOT_CONVERGED`` (iteration limit).
"""
import math

from numba import njit

from .decisions import TOUCH_RTOL, touching_accel, touching_rate, touching_speed

FEAT_VERTEX = 0
FEAT_ELLIPSE = 1

TOI_OK = 0
TOI_MISSED = 1
TOI_NOT_CONVERGED = 2

INF = math.inf


@njit(cache=True, _nrt=False)
def quadratic_descending_root(g0, g1, g2, S, gap_tol):
    """Earliest ``s`` in ``[0, S]`` with ``g(s) = g0 + g1 s + g2 s^2 / 2 = 0`` and ``g'(s) < 0``.

    ``g0 <= 0`` with ``g1 < 0`` (or ``g1 = 0 < -g2``) is an impact now (``s = 0``). A gap
    below ``-gap_tol`` reports ``TOI_MISSED``. Returns ``(s, code)``.
    """
    if g0 <= 0.0:
        code = TOI_MISSED if g0 < -gap_tol else TOI_OK
        if g1 < 0.0 or (g1 == 0.0 and g2 < 0.0):
            return 0.0, code
        if g2 < 0.0:
            disc = g1 * g1 - 2.0 * g0 * g2
            if disc < 0.0:
                return INF, code
            s = (g1 + math.sqrt(disc)) / (-g2)
            return (s if s <= S else INF), code
        return INF, code
    a = 0.5 * g2
    b = g1
    c = g0
    if a == 0.0:
        if b < 0.0:
            s = -c / b
            return (s if s <= S else INF), TOI_OK
        return INF, TOI_OK
    disc = b * b - 4.0 * a * c
    if disc <= 0.0:
        return INF, TOI_OK
    sq = math.sqrt(disc)
    q = -0.5 * (b + math.copysign(sq, b))
    best = INF
    r1 = q / a
    r2 = c / q
    if r1 >= 0.0 and 2.0 * a * r1 + b < 0.0 and r1 < best:
        best = r1
    if r2 >= 0.0 and 2.0 * a * r2 + b < 0.0 and r2 < best:
        best = r2
    return (best if best <= S else INF), TOI_OK


@njit(cache=True, _nrt=False, inline="always")
def _safe_step(g, gd, M):
    """First zero h >= 0 of g + gd h - M h^2/2 (g >= 0), cancellation-free; inf if none."""
    if M > 0.0:
        root = math.sqrt(gd * gd + 2.0 * M * g)
        if gd <= 0.0:
            den = root - gd
            return 2.0 * g / den if den > 0.0 else 0.0
        return (gd + root) / M
    if gd < 0.0:
        return -g / gd
    return INF


@njit(cache=True, _nrt=False, inline="always")
def centres_quadratic_toi(g0, dist, R, b, a, S, gap_tol):
    """Closed-form earliest touching ``s`` in ``[0, S]`` of two round bodies (disks or
    spheres, radii summing to ``R``) with equal accelerations: ``|d + u s|^2 = R^2`` with
    ``g0 = |d| - R``, ``dist = |d|``, ``b = 2 d . u``, ``a = |u|^2``; cancellation-free.
    Returns ``(s, code)`` (shared by ``disk_disk_toi`` and ``toi3d.sphere_sphere_toi``).
    Touching (``g0 <= 0``), the bodies approach only when the normal rate ``b / (2 |d|)`` is
    below ``-decisions.TOUCH_RTOL`` times the relative speed ``sqrt(a)``: a rate at its
    round-off (an impact resolved to ``v_N = 0``) is zero, and then the gap grows
    (``g'' = |u|^2 / |d| >= 0``): no impact, whatever the sign of that round-off."""
    if g0 <= 0.0:
        code = TOI_MISSED if g0 < -gap_tol else TOI_OK
        if touching_rate(0.5 * b / dist, math.sqrt(a)) < 0.0 or code == TOI_MISSED:
            return 0.0, code
        return INF, code
    if b >= 0.0:
        return INF, TOI_OK
    c = g0 * (dist + R)
    disc = b * b - 4.0 * a * c
    if disc <= 0.0:
        return INF, TOI_OK
    q = -0.5 * (b - math.sqrt(disc))
    s = c / q
    return (s if s <= S else INF), TOI_OK


@njit(cache=True, _nrt=False, inline="always")
def window_step(s, g, gd, dvn, da, R, H, S, t0, rtol, atol):
    """One step of the windowed conservative advancement of two round bodies (radii
    summing to ``R``, relative speed ``dvn`` and acceleration magnitude ``da`` at ``s``,
    gap ``g >= 0`` and rate ``gd``): bound ``|g''| <= (dvn + da H)^2 / R + da`` over the
    window ``H`` (clipped to ``S``), step to the first zero of the lower bound. Returns
    ``(s, H, done)``: ``done`` 1 with ``s`` the root (``inf``: none in ``[0, S]``), 0 to
    evaluate the gap at the new ``s`` and step again (shared by ``disk_disk_toi`` and
    ``toi3d.sphere_sphere_toi``)."""
    Hw = min(H, S - s)
    M = (dvn + da * Hw) ** 2 / R + da
    h = _safe_step(g, gd, M)
    tol = atol + rtol * abs(t0 + s)
    if h >= Hw:
        h = Hw
        H = 2.0 * H
    else:
        if h <= tol:
            if gd < 0.0:
                r = s + h
                return (r if r <= S else INF), H, 1
            h = tol
        H = 4.0 * h
    s += h
    if s >= S:
        return INF, H, 1
    return s, H, 0


@njit(cache=True, _nrt=False, inline="always")
def _touching_scale(st, arm, reach):
    """The speed scale (m/s) of a touching feature's rate (``decisions.touching_speed``):
    the centre's speed plus ``|omega|`` times the feature's ``arm`` (m: the bound K1 of the
    rotating part of its gap), at least ``sqrt(|a| reach)`` (``reach`` m)."""
    return touching_speed(math.hypot(st[3], st[4]) + abs(st[5]) * arm,
                          math.hypot(st[6], st[7]), reach)


@njit(cache=True, _nrt=False, inline="always")
def vertex_gap(st, px, py, rad, nx, ny, d, s):
    """Gap (m) and its rate (m/s) at ``s`` of the point ``p`` (radius ``rad``) of a body."""
    h = 0.5 * s * s
    x = st[0] + st[3] * s + st[6] * h
    y = st[1] + st[4] * s + st[7] * h
    th = st[2] + st[5] * s + st[8] * h
    vx = st[3] + st[6] * s
    vy = st[4] + st[7] * s
    w = st[5] + st[8] * s
    if px == 0.0 and py == 0.0:
        return (nx * x + ny * y - d) - rad, nx * vx + ny * vy
    c = math.cos(th)
    sn = math.sin(th)
    wx = c * px - sn * py
    wy = sn * px + c * py
    g = (nx * x + ny * y - d) + (nx * wx + ny * wy) - rad
    gd = nx * vx + ny * vy + w * (ny * wx - nx * wy)
    return g, gd


@njit(cache=True, _nrt=False, inline="always")
def ellipse_support(th, ea, eb, nx, ny):
    """Support distance ``h`` (m) of the ellipse along ``-n`` and ``dh/dangle`` (m/rad)."""
    c = math.cos(th)
    sn = math.sin(th)
    nbx = c * nx + sn * ny
    nby = -sn * nx + c * ny
    hh = math.sqrt(ea * ea * nbx * nbx + eb * eb * nby * nby)
    dh = (ea * ea - eb * eb) * nbx * nby / hh
    return hh, dh


@njit(cache=True, _nrt=False, inline="always")
def ellipse_gap(st, ea, eb, nx, ny, d, s):
    h = 0.5 * s * s
    x = st[0] + st[3] * s + st[6] * h
    y = st[1] + st[4] * s + st[7] * h
    th = st[2] + st[5] * s + st[8] * h
    vx = st[3] + st[6] * s
    vy = st[4] + st[7] * s
    w = st[5] + st[8] * s
    hh, dh = ellipse_support(th, ea, eb, nx, ny)
    return (nx * x + ny * y - d) - hh, nx * vx + ny * vy - w * dh


@njit(cache=True, _nrt=False, inline="always")
def feature_gap(kind, st, px, py, rad, ea, eb, nx, ny, d, s):
    if kind == FEAT_VERTEX:
        return vertex_gap(st, px, py, rad, nx, ny, d, s)
    return ellipse_gap(st, ea, eb, nx, ny, d, s)


@njit(cache=True, _nrt=False, inline="always")
def _round_off_rate_time(kind, st, px, py, nx, ny, s, gd, thr, M, K1, wmax):
    """A time (s) over which the rate ``gd`` (m/s, ``|gd| <= thr``) of a feature touching
    at ``s`` stays above ``-thr``: ``(thr + gd) / M``, ``M`` the bound of ``|g''|``; for a
    vertex also the root of ``gd + g''(s) h - M3 h^2 / 2 = -thr`` with its own ``g''(s)``
    and ``M3 = K1 (wmax^3 + 3 |alpha| wmax)``, a bound of ``|g'''|`` (``g = n.x - d + n.R p
    - rad``, x and the angle quadratic in s): a vertex touching at a third-order tangency
    (a rod pivoting on its end, ``g'' = 0``) has a rate that falls as ``s^2``, not ``M s``.
    0 when the vertex is pushed into the plane (``g''`` below its round-off,
    ``decisions.touching_accel``): it meets the plane now."""
    h = (thr + gd) / M if M > 0.0 else INF
    if kind != FEAT_VERTEX:
        return h
    th = st[2] + st[5] * s + 0.5 * st[8] * s * s
    w = st[5] + st[8] * s
    c = math.cos(th)
    sn = math.sin(th)
    nr = nx * (c * px - sn * py) + ny * (sn * px + c * py)       # n . R p
    njr = -nx * (sn * px + c * py) + ny * (c * px - sn * py)     # n . J R p
    g2 = nx * st[6] + ny * st[7] + st[8] * njr - w * w * nr
    if touching_accel(g2, math.hypot(st[6], st[7]) + abs(st[8]) * K1, w, K1) < 0.0:
        return 0.0      # pushed into the plane: an impact now
    M3 = K1 * (wmax * wmax * wmax + 3.0 * abs(st[8]) * wmax)
    if M3 > 0.0:
        h3 = (g2 + math.sqrt(g2 * g2 + 2.0 * M3 * (thr + gd))) / M3
    elif g2 < 0.0:
        h3 = (thr + gd) / -g2
    else:
        h3 = INF
    return max(h, h3)


@njit(cache=True, _nrt=False)
def plane_feature_toi(kind, st, px, py, rad, ea, eb, nx, ny, d, t0, S, rtol, atol, gap_tol,
                      maxit):
    """Earliest impact ``s`` in ``[0, S]`` (s after ``t0``) of one feature with a plane.

    ``st`` float64[9] is the body state at ``t0``; see the module docstring.
    Returns ``(s, code)``.
    """
    na = nx * st[6] + ny * st[7]
    if kind == FEAT_VERTEX:
        K1 = math.sqrt(px * px + py * py)
        K2 = K1
    else:
        K1 = max(ea, eb)
        K2 = abs(ea * ea - eb * eb) / min(ea, eb)
    rot = K2 > 0.0 and (st[5] != 0.0 or st[8] != 0.0)
    if not rot:
        # exact quadratic: the rotating part of the gap is constant
        g0, g1 = feature_gap(kind, st, px, py, rad, ea, eb, nx, ny, d, 0.0)
        if g0 <= 0.0:
            # touching: a rate at the round-off of the speed is zero (TOUCH_RTOL)
            g1 = touching_rate(g1, _touching_scale(st, K1, max(K1, rad)))
        return quadratic_descending_root(g0, g1, na, S, gap_tol)
    wmax = abs(st[5]) + abs(st[8]) * S
    M = abs(na) + K2 * wmax * wmax + K1 * abs(st[8])
    scale = _touching_scale(st, K1, max(K1, rad))
    s = 0.0
    g, gd = feature_gap(kind, st, px, py, rad, ea, eb, nx, ny, d, s)
    if g <= 0.0:
        code = TOI_MISSED if g < -gap_tol else TOI_OK
        # touching: a rate at the round-off of its speed scale is zero
        # (decisions.TOUCH_RTOL): a plastic impact leaves -1.1e-16 m/s at a vertex of a
        # body spinning at 19 rad/s, and an impulse that small no longer changes the
        # state: 2:2574756275 stalled on it
        gd = touching_rate(gd, scale)
        if gd < 0.0 or code == TOI_MISSED:
            return 0.0, code
        g = 0.0
    else:
        # the feature lies within K1 of the centre, so g(s) >= n.x(s) - d - rad - K1, an
        # exact quadratic: no root of g before the first root of that bound (closed form)
        c0 = nx * st[0] + ny * st[1] - d - rad - K1 - gap_tol
        if c0 > 0.0:
            s0, _ = quadratic_descending_root(c0, nx * st[3] + ny * st[4], na, S, gap_tol)
            if not s0 <= S:
                return INF, TOI_OK
            if s0 > 0.0:
                s = s0
                g, gd = feature_gap(kind, st, px, py, rad, ea, eb, nx, ny, d, s)
                if g <= 0.0:
                    if gd < 0.0:
                        return s, TOI_OK
                    g = 0.0
    thr = TOUCH_RTOL * scale
    for _ in range(maxit):
        tol = atol + rtol * abs(t0 + s)
        if g == 0.0 and abs(gd) <= thr and thr > 0.0:
            # touching at a round-off rate (an impact is a rate below -thr): |g''| <= M
            # keeps the rate above -thr for (thr + gd) / M, over which the gap sinks at
            # most thr h, kept within gap_tol / 2. A capsule flat on a wall that gravity
            # does not push, sliding at a round-off spin, stepped tol at a time and never
            # ended (2:441169314). A vertex pushed into the plane (its g'' below round-off)
            # meets it one step on, as before
            h = _round_off_rate_time(kind, st, px, py, nx, ny, s, gd, thr, M, K1, wmax)
            if h == 0.0:
                r = s + tol
                return (r if r <= S else INF), TOI_OK
            h = max(tol, min(h, 0.5 * gap_tol / thr))
        else:
            h = _safe_step(g, gd, M)
            if h <= tol:
                if gd < 0.0:
                    r = s + h
                    return (r if r <= S else INF), TOI_OK
                h = tol  # tangency (grazing without crossing): step past it
        s += h
        if s > S:
            return INF, TOI_OK
        g, gd = feature_gap(kind, st, px, py, rad, ea, eb, nx, ny, d, s)
        if g <= 0.0:
            if touching_rate(gd, scale) < 0.0:
                return s, TOI_OK
            g = 0.0
    return s, TOI_NOT_CONVERGED


@njit(cache=True, _nrt=False)
def disk_plane_toi(st, rad, nx, ny, d, S, gap_tol):
    """Earliest impact ``s`` in ``[0, S]`` (s) of a disk of radius ``rad`` (m; state row
    ``st`` of its centre) with the plane ``(n, d)``: its gap is an exact quadratic (closed
    form), the same arithmetic as ``plane_feature_toi`` for ``FEAT_VERTEX`` with ``p = 0``
    (the loops compiled for disks only call this, not the general search). Returns
    ``(s, code)``."""
    g0, g1 = vertex_gap(st, 0.0, 0.0, rad, nx, ny, d, 0.0)
    if g0 <= 0.0:
        # touching: a rate at the round-off of the centre's speed is zero (TOUCH_RTOL)
        g1 = touching_rate(g1, _touching_scale(st, 0.0, rad))
    return quadratic_descending_root(g0, g1, nx * st[6] + ny * st[7], S, gap_tol)


@njit(cache=True, _nrt=False)
def disk_disk_toi(dx, dy, dvx, dvy, dax, day, R, t0, S, rtol, atol, gap_tol, maxit):
    """Earliest ``s`` in ``[0, S]`` at which two disks (radii summing to ``R``) touch while
    approaching, given their relative position, velocity and acceleration (A minus B) at
    ``t0``. Equal accelerations (both in free flight): exact quadratic. Returns ``(s, code)``.
    """
    dist = math.sqrt(dx * dx + dy * dy)
    g0 = dist - R
    if dax == 0.0 and day == 0.0:
        return centres_quadratic_toi(g0, dist, R, 2.0 * (dx * dvx + dy * dvy),
                                     dvx * dvx + dvy * dvy, S, gap_tol)
    # conservative advancement on g(s) = |dx(s)| - R with a windowed bound on |g''|
    da = math.sqrt(dax * dax + day * day)
    s = 0.0
    ex, ey, ux, uy = dx, dy, dvx, dvy
    g = g0
    gd = (ex * ux + ey * uy) / dist
    if g <= 0.0:
        code = TOI_MISSED if g < -gap_tol else TOI_OK
        if gd < 0.0 or code == TOI_MISSED:
            return 0.0, code
        g = 0.0
    H = S
    for _ in range(maxit):
        s, H, done = window_step(s, g, gd, math.sqrt(ux * ux + uy * uy), da, R, H, S, t0,
                                 rtol, atol)
        if done:
            return s, TOI_OK
        hs = 0.5 * s * s
        ex = dx + dvx * s + dax * hs
        ey = dy + dvy * s + day * hs
        ux = dvx + dax * s
        uy = dvy + day * s
        dist = math.sqrt(ex * ex + ey * ey)
        g = dist - R
        gd = (ex * ux + ey * uy) / dist
        if g <= 0.0:
            if gd < 0.0:
                return s, TOI_OK
            g = 0.0
    return s, TOI_NOT_CONVERGED
