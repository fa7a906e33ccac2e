"""The compiled event loop of the exact 2D event-driven stepper (DESIGN §6, issue 3).

Everything here is ``@njit(cache=True, _nrt=False)``: no reference counting, because the
kernels only index preallocated arrays and never allocate (nothing is allocated per
event). ``rbimpact.simulation`` packs a scene into the arrays below and calls
``run_loop`` (the first call initialises the run) until it returns ``RC_DONE`` or
``RC_MAX_EVENTS`` (``RC_BUFFER_FULL``: the Python side doubles the event/segment buffers
and calls again; the loop resumes exactly where it stopped). Negative return codes are
errors (``ERR_*``), with details in ``err``.

Scene arrays (constant during a run)
------------------------------------
``bint`` int64[nb, 3]      shape kind (``SH_*``), first vertex row in ``verts``, vertex count
``bflt`` float64[nb, 5]    mass (kg), moment of inertia (kg m^2), rounding radius (m; a
                           disk's radius, a capsule's radius, 0 for polygons), ellipse a, b (m)
``verts`` float64[nv, 2]   body-frame contact points (a disk and an ellipse have one, (0, 0))
``planes`` float64[np, 3]  ``(nx, ny, d)``: half-plane ``n . q >= d`` is free space
``grav`` float64[2]        gravity (m/s^2)
``law_ids`` int64[nl], ``law_par`` float64[nl, N_PARAMS]: the law table
``bp_law`` int64[nb, np]   law row of each body-plane contact
``pairs`` int64[npr, 3]    disk-disk pairs ``(a, b, law row)``
``tolf``, ``toli``         tolerances (``TF_*``, ``TI_*`` slots)

Dynamic state (kept between calls)
----------------------------------
``st`` float64[nb, 9] state rows at ``tref`` (see ``flight2d``); ``pm`` int64[nb, 4]
persistent contact (mode ``PM_*``, plane, face vertex 0, face vertex 1); ``tz``/``zp``
pending accumulation (Zeno) point and its plane; ``ttr`` next persistent-mode transition;
``bp_t``/``bp_off`` next impact time of each body-plane pair / pair disabled after a
perforating impact; ``pr_t``/``pr_off`` the same for disk pairs; ``glob[0]`` the current
time; ``cnt`` = (events logged, segments logged, consecutive events at one instant).

Output buffers
--------------
Events: ``ev_t`` (s), ``ev_i`` (kind ``EV_*``, a, b, mode, cluster size) and ``ev_f``
(point xy, normal xy, v_i (N, T), v_f (N, T), P (N, T), dE). ``b`` is a body index or
``-1 - plane`` for a plane. Segments: ``seg_t``, ``seg_b``, ``seg_s``: body ``seg_b`` moves
from ``seg_t`` with state row ``seg_s`` (exact piecewise-quadratic trajectories).

Accumulation (Zeno)
-------------------
After an impact on a plane pushing the body, when the energy of its motion normal to the
plane (and, not for a disk, of its rotation) plus its height above its rest falls below
``m zeno_speed^2 / 2``, the run jumps to the accumulation time ``t_inf`` and snaps the body
onto its rest there (event "contact"). The rest is the face least inclined to the plane
at the lowest corner; the accumulation is accepted only if it is consistent: the centre
of mass is over that face and the snap does not lift it (``SNAP_RTOL``), else the impacts
are stepped on. From the last impact to ``t_inf`` the body's reported trajectory (and
every other candidate event) is its held motion (``_held_into``: at the height of the
last impact, no normal velocity, tangential motion the exact free flight), so it never
dips below the plane; ``st`` keeps the free-flight row, so that the "contact" event
reports the accumulated impulse ``m v (1 + e) / (1 - e)`` and the energy removed. An
impact of another contact before ``t_inf`` cancels the jump: the body continues from its
held state (the unfinished normal energy, below the threshold, is dropped).
"""
import math

from numba import float64, int64, njit

# Explicit signatures for helpers called with literal constants, so that Numba compiles
# each of them once (not once per combination of literal arguments).
_A1 = float64[::1]
_A2 = float64[:, ::1]
_I1 = int64[::1]
_I2 = int64[:, ::1]
_f = float64
_i = int64

from .cache_guard import guard

# flush stale compiled callers before any kernel module below is imported (cache_guard)
guard(__name__, __file__)

from . import evbuf
from .common import P_E, P_MU
from .dispatch import resolve_2d
from .flight2d import fly_into, fly_row
from .toi2d import (FEAT_ELLIPSE, FEAT_VERTEX, TOI_MISSED, TOI_NOT_CONVERGED,
                    disk_disk_toi, ellipse_support, feature_gap, plane_feature_toi)

INF = math.inf

# shape kinds
SH_DISK = 0
SH_POLY = 1
SH_ELLIPSE = 2

# persistent modes (pm[:, 0])
PM_FLIGHT = 0
PM_SLIDE = 1
PM_ROLL = 2
PM_REST = 3

# event kinds (ev_i[:, 0]); a persistent mode m is logged as kind m + 1
EV_IMPACT = 0
EV_CONTACT = 1
EV_SLIDE = 2
EV_ROLL = 3
EV_REST = 4
EV_RELEASE = 5
EVENT_KINDS = ("impact", "contact", "slide", "roll", "rest", "release")

# policies
POL_SIMULTANEOUS = 0
POL_SEQUENTIAL = 1

# tolerance slots
TF_REST_LENGTH = 0
TF_ZENO_SPEED = 1      # < 0: derived, sqrt(2 |g_n| rest_length)
TF_GAP_TOL = 2
TF_TOI_RTOL = 3
TF_TOI_ATOL = 4
TF_SIMUL_TIME = 5
TF_SIMUL_TOL = 6
TF_SEQ_VTOL = 7
TF_T_END = 8
TF_SIMUL_GAP = 9
N_TF = 10
TI_TOI_MAXIT = 0
TI_SIMUL_MAXIT = 1
TI_SEQ_MAXSTEPS = 2
TI_STALL = 3
TI_POLICY = 4
TI_MAX_EVENTS = 5
N_TI = 6

# return codes
RC_DONE = 0
RC_MAX_EVENTS = 1
RC_BUFFER_FULL = 2
ERR_NO_SOLUTION = -1
ERR_NONFINITE = -2
ERR_MISSED = -3
ERR_TOI = -4
ERR_CHATTER = -5
ERR_SEQ = -6
ERR_PGS = -7
ERR_TIPPING = -8
ERR_ELLIPSE_SLIDE = -9
ERR_STALL = -10
ERR_TOO_MANY = -11
ERR_JOINT_E = -12

MAXC = 16            # contacts resolved at one instant (per call of the impact step)
#: accumulation onto a rest is accepted only if the snap lifts the centre of mass by at
#: most SNAP_RTOL times the rest height (dimensionless round-off allowance), i.e. if
#: E_ex >= -m |g_n| SNAP_RTOL h_rest: a rest above the body would create energy
SNAP_RTOL = 1e-12
N_CF = 13            # columns of the contact workspace c_f
N_CI = 6             # columns of the contact workspace c_i

# c_i columns
CI_TYPE = 0          # 0: body-plane, 1: disk-disk
CI_A = 1
CI_B = 2             # plane index or body index
CI_FEAT = 3          # vertex row in verts
CI_LAW = 4
CI_OFF = 5           # perforated during a sequential resolution
# c_f columns
CF_NX, CF_NY, CF_PX, CF_PY, CF_RAX, CF_RAY, CF_RBX, CF_RBY = 0, 1, 2, 3, 4, 5, 6, 7
CF_VIN, CF_VIT, CF_PN, CF_PT, CF_VCMN = 8, 9, 10, 11, 12


def event_margin(toli, nb):
    """Free event rows the loop needs before it handles one more instant (evbuf)."""
    return int(evbuf.event_margin.py_func(int(toli[TI_SEQ_MAXSTEPS]), MAXC, nb))


def segment_margin(nb):
    """Free segment rows the loop needs before it handles one more instant (evbuf)."""
    return int(evbuf.segment_margin.py_func(MAXC, nb))


# ------------------------------------------------------------------ small helpers


@njit((_A1, _I2, _A2, _I1, _f, _i, _i, _i, _i, _i, _f, _f, _f, _f, _f, _f, _f, _f, _f, _f,
       _f), cache=True, _nrt=False)
def _log(ev_t, ev_i, ev_f, cnt, t, kind, a, b, mode, cluster, px, py, nx, ny, viN, viT,
         vfN, vfT, PN, PT, dE):
    k = cnt[0]
    ev_t[k] = t
    ev_i[k, 0] = kind
    ev_i[k, 1] = a
    ev_i[k, 2] = b
    ev_i[k, 3] = mode
    ev_i[k, 4] = cluster
    ev_f[k, 0] = px
    ev_f[k, 1] = py
    ev_f[k, 2] = nx
    ev_f[k, 3] = ny
    ev_f[k, 4] = viN
    ev_f[k, 5] = viT
    ev_f[k, 6] = vfN
    ev_f[k, 7] = vfT
    ev_f[k, 8] = PN
    ev_f[k, 9] = PT
    ev_f[k, 10] = dE
    cnt[0] = k + 1


@njit(cache=True, _nrt=False, inline="always")
def _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i):
    k = cnt[1]
    seg_t[k] = tref[i]
    seg_b[k] = i
    for j in range(9):
        seg_s[k, j] = st[i, j]
    cnt[1] = k + 1


@njit(cache=True, _nrt=False, inline="always")
def _push_row(seg_t, seg_b, seg_s, cnt, row, t, i):
    k = cnt[1]
    seg_t[k] = t
    seg_b[k] = i
    for j in range(9):
        seg_s[k, j] = row[j]
    cnt[1] = k + 1


@njit(cache=True, _nrt=False)
def _held_into(src, kind, nx, ny, out):
    """The motion of a body during a pending accumulation (Zeno) jump on the plane with
    normal n: ``out`` = the state row ``src`` with its normal velocity and normal
    acceleration removed, and (not for a disk) its rotation stopped. From the last impact
    to the accumulation time the body then stays at the height of that impact while its
    tangential motion is the exact free flight (the bounces of the accumulation do not
    change it); the reported trajectory never dips below the plane. ``src`` may be
    ``out``. The stepper keeps the true free-flight row in ``st`` (so that the "contact"
    event at the accumulation time reports the accumulated impulse and the energy
    removed) and uses this row for the trajectory and for the other candidate events."""
    for j in range(9):
        out[j] = src[j]
    vN = nx * out[3] + ny * out[4]
    out[3] -= vN * nx
    out[4] -= vN * ny
    aN = nx * out[6] + ny * out[7]
    out[6] -= aN * nx
    out[7] -= aN * ny
    if kind != SH_DISK:
        out[5] = 0.0
        out[8] = 0.0


@njit((_A1, _f, _i, _i, _f, _f, _f, _f, _f), cache=True, _nrt=False)
def _set_err(err, t, a, b, px, py, x1, x2, x3):
    err[0] = t
    err[1] = a
    err[2] = b
    err[3] = px
    err[4] = py
    err[5] = x1
    err[6] = x2
    err[7] = x3


@njit(cache=True, _nrt=False, inline="always")
def _point_vel(st, i, rx, ry):
    return st[i, 3] - st[i, 5] * ry, st[i, 4] + st[i, 5] * rx


@njit(cache=True, _nrt=False, inline="always")
def _w_body(m, inertia, rx, ry, nx, ny):
    tx = ny
    ty = -nx
    cn = rx * ny - ry * nx
    ct = rx * ty - ry * tx
    im = 1.0 / m
    iI = 1.0 / inertia
    return im + cn * cn * iI, cn * ct * iI, im + ct * ct * iI


@njit(cache=True, _nrt=False)
def _energy(st, bflt, grav, i):
    m = bflt[i, 0]
    return (0.5 * m * (st[i, 3] * st[i, 3] + st[i, 4] * st[i, 4])
            + 0.5 * bflt[i, 1] * st[i, 5] * st[i, 5]
            - m * (grav[0] * st[i, 0] + grav[1] * st[i, 1]))


@njit(cache=True, _nrt=False, inline="always")
def _vz2(tolf, gabs):
    """Squared accumulation speed (m^2/s^2) for a normal acceleration magnitude gabs."""
    z = tolf[TF_ZENO_SPEED]
    if z >= 0.0:
        return z * z
    return 2.0 * gabs * tolf[TF_REST_LENGTH]


@njit(cache=True, _nrt=False, inline="always")
def _finite(st, i):
    for j in range(9):
        if not math.isfinite(st[i, j]):
            return False
    return True


# ------------------------------------------------------------------ contact geometry


@njit(cache=True, _nrt=False)
def _plane_contact(st, i, bint, bflt, verts, feat, nx, ny):
    """Contact point and arm (point minus centre of mass) of feature ``feat`` of body i
    against a plane with normal n, at the body's current state."""
    if bint[i, 0] == SH_DISK:
        rad = bflt[i, 2]
        return st[i, 0] - rad * nx, st[i, 1] - rad * ny, -rad * nx, -rad * ny
    c = math.cos(st[i, 2])
    s = math.sin(st[i, 2])
    if bint[i, 0] == SH_ELLIPSE:
        ea = bflt[i, 3]
        eb = bflt[i, 4]
        nbx = c * nx + s * ny
        nby = -s * nx + c * ny
        hh = math.sqrt(ea * ea * nbx * nbx + eb * eb * nby * nby)
        sbx = -ea * ea * nbx / hh
        sby = -eb * eb * nby / hh
        rx = c * sbx - s * sby
        ry = s * sbx + c * sby
    else:
        px = verts[feat, 0]
        py = verts[feat, 1]
        rad = bflt[i, 2]
        rx = c * px - s * py - rad * nx
        ry = s * px + c * py - rad * ny
    return st[i, 0] + rx, st[i, 1] + ry, rx, ry


@njit(cache=True, _nrt=False, inline="always")
def _contact_velocity(st, c_i, c_f, c):
    nx = c_f[c, CF_NX]
    ny = c_f[c, CF_NY]
    a = c_i[c, CI_A]
    ux, uy = _point_vel(st, a, c_f[c, CF_RAX], c_f[c, CF_RAY])
    if c_i[c, CI_TYPE] == 1:
        wx, wy = _point_vel(st, c_i[c, CI_B], c_f[c, CF_RBX], c_f[c, CF_RBY])
        ux -= wx
        uy -= wy
    return ux * nx + uy * ny, ux * ny - uy * nx


@njit(cache=True, _nrt=False, inline="always")
def _contact_W(bflt, c_i, c_f, c, W2):
    nx = c_f[c, CF_NX]
    ny = c_f[c, CF_NY]
    a = c_i[c, CI_A]
    wnn, wnt, wtt = _w_body(bflt[a, 0], bflt[a, 1], c_f[c, CF_RAX], c_f[c, CF_RAY], nx, ny)
    if c_i[c, CI_TYPE] == 1:
        b = c_i[c, CI_B]
        bnn, bnt, btt = _w_body(bflt[b, 0], bflt[b, 1], c_f[c, CF_RBX], c_f[c, CF_RBY],
                                nx, ny)
        wnn += bnn
        wnt += bnt
        wtt += btt
    W2[0, 0] = wnn
    W2[0, 1] = wnt
    W2[1, 0] = wnt
    W2[1, 1] = wtt


@njit(cache=True, _nrt=False, inline="always")
def _apply(st, bflt, c_i, c_f, c, PN, PT):
    nx = c_f[c, CF_NX]
    ny = c_f[c, CF_NY]
    jx = PN * nx + PT * ny
    jy = PN * ny - PT * nx
    a = c_i[c, CI_A]
    m = bflt[a, 0]
    st[a, 3] += jx / m
    st[a, 4] += jy / m
    st[a, 5] += (c_f[c, CF_RAX] * jy - c_f[c, CF_RAY] * jx) / bflt[a, 1]
    if c_i[c, CI_TYPE] == 1:
        b = c_i[c, CI_B]
        m = bflt[b, 0]
        st[b, 3] -= jx / m
        st[b, 4] -= jy / m
        st[b, 5] -= (c_f[c, CF_RBX] * jy - c_f[c, CF_RBY] * jx) / bflt[b, 1]


@njit(cache=True, _nrt=False)
def _gap_accel(st, bint, bflt, c_i, c_f, c, verts, grav):
    """Second time derivative (m/s^2) of the contact's gap in free flight, now."""
    nx = c_f[c, CF_NX]
    ny = c_f[c, CF_NY]
    a = c_i[c, CI_A]
    if c_i[c, CI_TYPE] == 1:
        b = c_i[c, CI_B]
        dvx = st[a, 3] - st[b, 3]
        dvy = st[a, 4] - st[b, 4]
        vt = dvx * ny - dvy * nx
        dist = bflt[a, 2] + bflt[b, 2]
        return nx * (st[a, 6] - st[b, 6]) + ny * (st[a, 7] - st[b, 7]) + vt * vt / dist
    gn = nx * st[a, 6] + ny * st[a, 7]
    w = st[a, 5]
    if bint[a, 0] == SH_ELLIPSE:
        ea = bflt[a, 3]
        eb = bflt[a, 4]
        c = math.cos(st[a, 2])
        s = math.sin(st[a, 2])
        nbx = c * nx + s * ny
        nby = -s * nx + c * ny
        hh, dh = ellipse_support(st[a, 2], ea, eb, nx, ny)
        d2h = (ea * ea - eb * eb) * (nby * nby - nbx * nbx) / hh - dh * dh / hh
        return gn - d2h * w * w
    rad = bflt[a, 2]
    np_ = nx * c_f[c, CF_RAX] + ny * c_f[c, CF_RAY] + rad   # n . R p
    return gn - w * w * np_


# ------------------------------------------------------------------ candidates


@njit(cache=True, _nrt=False, inline="always")
def _recompute_planes(i, t_now, st, tref, bint, bflt, verts, planes, pm, tz, zp, bp_t,
                      bp_off, tolf, toli, tmp, err):
    """Next impact time of body i (state at t_now) against every plane (during a pending
    accumulation jump: of its held motion, see ``_held_into``; ``tmp[0]`` scratch)."""
    S = tolf[TF_T_END] - t_now
    kind = FEAT_ELLIPSE if bint[i, 0] == SH_ELLIPSE else FEAT_VERTEX
    v0 = bint[i, 1]
    nv = bint[i, 2]
    rad = bflt[i, 2]
    ea = bflt[i, 3]
    eb = bflt[i, 4]
    row = st[i]
    if tz[i] < INF:
        _held_into(st[i], bint[i, 0], planes[zp[i], 0], planes[zp[i], 1], tmp[0])
        row = tmp[0]
    for p in range(planes.shape[0]):
        if (bp_off[i, p] != 0 or (pm[i, 0] != PM_FLIGHT and pm[i, 1] == p)
                or (tz[i] < INF and zp[i] == p)):
            bp_t[i, p] = INF
            continue
        nx = planes[p, 0]
        ny = planes[p, 1]
        d = planes[p, 2]
        best = INF
        for k in range(nv):
            s, code = plane_feature_toi(kind, row, verts[v0 + k, 0], verts[v0 + k, 1], rad,
                                        ea, eb, nx, ny, d, t_now, S, tolf[TF_TOI_RTOL],
                                        tolf[TF_TOI_ATOL], tolf[TF_GAP_TOL],
                                        toli[TI_TOI_MAXIT])
            if code == TOI_MISSED:
                _set_err(err, t_now, i, -1 - p, st[i, 0], st[i, 1], k, 0.0, 0.0)
                return ERR_MISSED
            if code == TOI_NOT_CONVERGED:
                _set_err(err, t_now, i, -1 - p, st[i, 0], st[i, 1], k, s, 0.0)
                return ERR_TOI
            if s < best:
                best = s
        bp_t[i, p] = t_now + best
    return 0


@njit(cache=True, _nrt=False)
def _recompute_pair(q, t_now, st, tref, bint, bflt, planes, pairs, tz, zp, pr_t, pr_off,
                    tolf, toli, tmp, err):
    if pr_off[q] != 0:
        pr_t[q] = INF
        return 0
    a = pairs[q, 0]
    b = pairs[q, 1]
    # a disk in a pending accumulation jump moves with its held motion
    for j in range(2):
        i = a if j == 0 else b
        if tz[i] < INF:
            _held_into(st[i], bint[i, 0], planes[zp[i], 0], planes[zp[i], 1], tmp[j])
            fly_into(tmp[j], t_now - tref[i], tmp[j])
        else:
            fly_into(st[i], t_now - tref[i], tmp[j])
    R = bflt[a, 2] + bflt[b, 2]
    s, code = disk_disk_toi(tmp[0, 0] - tmp[1, 0], tmp[0, 1] - tmp[1, 1],
                            tmp[0, 3] - tmp[1, 3], tmp[0, 4] - tmp[1, 4],
                            tmp[0, 6] - tmp[1, 6], tmp[0, 7] - tmp[1, 7], R, t_now,
                            tolf[TF_T_END] - t_now, tolf[TF_TOI_RTOL], tolf[TF_TOI_ATOL],
                            tolf[TF_GAP_TOL], toli[TI_TOI_MAXIT])
    if code == TOI_MISSED:
        _set_err(err, t_now, a, b, tmp[0, 0], tmp[0, 1], 0.0, 0.0, 0.0)
        return ERR_MISSED
    if code == TOI_NOT_CONVERGED:
        _set_err(err, t_now, a, b, tmp[0, 0], tmp[0, 1], 0.0, s, 0.0)
        return ERR_TOI
    pr_t[q] = t_now + s
    return 0


@njit(cache=True, _nrt=False, inline="always")
def _recompute_marked(t_now, st, tref, bint, bflt, verts, planes, pairs, pm, tz, zp, bp_t,
                      bp_off, pr_t, pr_off, tolf, toli, bmark, tmp, err):
    """Recompute the candidates of every marked body (state at t_now) and of its pairs."""
    for i in range(st.shape[0]):
        if bmark[i] == 0:
            continue
        rc = _recompute_planes(i, t_now, st, tref, bint, bflt, verts, planes, pm, tz, zp,
                               bp_t, bp_off, tolf, toli, tmp, err)
        if rc < 0:
            return rc
    for q in range(pairs.shape[0]):
        if bmark[pairs[q, 0]] != 0 or bmark[pairs[q, 1]] != 0:
            rc = _recompute_pair(q, t_now, st, tref, bint, bflt, planes, pairs, tz, zp, pr_t,
                                 pr_off, tolf, toli, tmp, err)
            if rc < 0:
                return rc
    return 0


# ------------------------------------------------------------------ persistent contact


@njit(cache=True, _nrt=False)
def _rest_config(i, p, st, bint, bflt, verts, planes, grav):
    """Nearest resting configuration of body i on plane p.

    Returns (stable, face0, face1, h_rest, dangle, E_excess): the face (polygon vertex rows,
    -1 for a disk or an ellipse), the height (m) of the centre of mass above the plane at
    rest, the rotation (rad) onto that rest, and the energy (J) of the motion normal to the
    plane and of the rotation (not for a disk) plus the potential energy above that rest.
    """
    nx = planes[p, 0]
    ny = planes[p, 1]
    d = planes[p, 2]
    g = abs(nx * grav[0] + ny * grav[1])
    m = bflt[i, 0]
    inertia = bflt[i, 1]
    rad = bflt[i, 2]
    vN = nx * st[i, 3] + ny * st[i, 4]
    w = st[i, 5]
    hc = nx * st[i, 0] + ny * st[i, 1] - d
    kind = bint[i, 0]
    if kind == SH_DISK:
        return True, -1, -1, rad, 0.0, 0.5 * m * vN * vN + m * g * max(hc - rad, 0.0)
    c = math.cos(st[i, 2])
    s = math.sin(st[i, 2])
    erot = 0.5 * m * vN * vN + 0.5 * inertia * w * w
    if kind == SH_ELLIPSE:
        ea = bflt[i, 3]
        eb = bflt[i, 4]
        hf = min(ea, eb)
        dth = 0.0
        if ea != eb:
            if ea > eb:
                ex = -s
                ey = c
            else:
                ex = c
                ey = s
            phi = math.atan2(ex * ny - ey * nx, ex * nx + ey * ny)
            if phi > 0.5 * math.pi:
                phi -= math.pi
            elif phi < -0.5 * math.pi:
                phi += math.pi
            dth = phi
        return True, -1, -1, hf, dth, erot + m * g * (hc - hf)
    v0 = bint[i, 1]
    nv = bint[i, 2]
    k0 = 0
    gmin = INF
    for k in range(nv):
        wx = c * verts[v0 + k, 0] - s * verts[v0 + k, 1]
        wy = s * verts[v0 + k, 0] + c * verts[v0 + k, 1]
        gk = nx * wx + ny * wy
        if gk < gmin:
            gmin = gk
            k0 = k
    if nv == 2:
        f0 = k0
        f1 = 1 - k0
    else:
        # of the two faces at the lowest corner, the one least inclined to the plane
        # (its outward normal closest to -n): the smaller rise per unit length (not the
        # lower neighbour: a short steep face can end lower than a long flat one)
        kp = (k0 - 1) % nv
        kn = (k0 + 1) % nv
        gp = (nx * (c * verts[v0 + kp, 0] - s * verts[v0 + kp, 1])
              + ny * (s * verts[v0 + kp, 0] + c * verts[v0 + kp, 1]))
        gq = (nx * (c * verts[v0 + kn, 0] - s * verts[v0 + kn, 1])
              + ny * (s * verts[v0 + kn, 0] + c * verts[v0 + kn, 1]))
        lp = math.hypot(verts[v0 + kp, 0] - verts[v0 + k0, 0],
                        verts[v0 + kp, 1] - verts[v0 + k0, 1])
        lq = math.hypot(verts[v0 + kn, 0] - verts[v0 + k0, 0],
                        verts[v0 + kn, 1] - verts[v0 + k0, 1])
        if (gq - gmin) * lp <= (gp - gmin) * lq:
            f0 = k0
            f1 = kn
        else:
            f0 = kp
            f1 = k0
    a0x = c * verts[v0 + f0, 0] - s * verts[v0 + f0, 1]
    a0y = s * verts[v0 + f0, 0] + c * verts[v0 + f0, 1]
    a1x = c * verts[v0 + f1, 0] - s * verts[v0 + f1, 1]
    a1y = s * verts[v0 + f1, 0] + c * verts[v0 + f1, 1]
    ex = a1x - a0x
    ey = a1y - a0y
    L2 = ex * ex + ey * ey
    L = math.sqrt(L2)
    ux = ey / L
    uy = -ex / L
    if nv == 2 and ux * nx + uy * ny > 0.0:
        ux = -ux
        uy = -uy
    lam = -(a0x * ex + a0y * ey) / L2
    stable = lam > 1e-9 and lam < 1.0 - 1e-9
    hf = ux * a0x + uy * a0y + rad
    dth = math.atan2(-ux * ny + uy * nx, -(ux * nx + uy * ny))
    return stable, f0, f1, hf, dth, erot + m * g * (hc - hf)


@njit(cache=True, _nrt=False)
def _persist_setup(i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, ttr,
                   tolf, err):
    """Choose the persistent mode of body i on plane p (normal velocity already zero) and
    set its constant accelerations and next transition time. Returns 0, 1 (the plane does
    not push: release) or an error code."""
    nx = planes[p, 0]
    ny = planes[p, 1]
    tx = ny
    ty = -nx
    gn = nx * grav[0] + ny * grav[1]
    gt = tx * grav[0] + ty * grav[1]
    ttr[i] = INF
    if not gn < 0.0:
        return 1
    m = bflt[i, 0]
    inertia = bflt[i, 1]
    rad = bflt[i, 2]
    mu = law_par[bp_law[i, p], P_MU]
    N = -m * gn
    vT = tx * st[i, 3] + ty * st[i, 4]
    w = st[i, 5]
    kind = bint[i, 0]
    al = 0.0
    aT = 0.0
    mode = PM_REST
    if kind == SH_DISK:
        vc = vT + w * rad
        kinv = 1.0 / m + rad * rad / inertia
        sig = 0.0
        if vc == 0.0:
            F = -gt / kinv
            if abs(F) <= mu * N:
                aT = gt + F / m
                al = rad * F / inertia
                mode = PM_REST if (gt == 0.0 and vT == 0.0 and w == 0.0) else PM_ROLL
            else:
                sig = 1.0 if gt > 0.0 else -1.0
        else:
            sig = 1.0 if vc > 0.0 else -1.0
        if sig != 0.0:
            F = -sig * mu * N
            aT = gt + F / m
            al = rad * F / inertia
            mode = PM_SLIDE
            k = gt + F * kinv
            if vc != 0.0 and sig * k < 0.0:
                ttr[i] = t - vc / k
    elif kind == SH_POLY:
        if vT == 0.0:
            if abs(gt) <= -mu * gn:
                mode = PM_REST
                FT = -m * gt
                aT = 0.0
            else:
                sig = 1.0 if gt > 0.0 else -1.0
                FT = -sig * mu * N
                aT = gt + FT / m
                mode = PM_SLIDE
        else:
            sig = 1.0 if vT > 0.0 else -1.0
            FT = -sig * mu * N
            aT = gt + FT / m
            mode = PM_SLIDE
            if sig * aT < 0.0:
                ttr[i] = t - vT / aT
        # no tipping: both face contacts must carry a non-negative normal force
        c = math.cos(st[i, 2])
        s = math.sin(st[i, 2])
        v0 = bint[i, 1]
        f0 = v0 + pm[i, 2]
        f1 = v0 + pm[i, 3]
        r0x = c * verts[f0, 0] - s * verts[f0, 1] - rad * nx
        r0y = s * verts[f0, 0] + c * verts[f0, 1] - rad * ny
        r1x = c * verts[f1, 0] - s * verts[f1, 1] - rad * nx
        r1y = s * verts[f1, 0] + c * verts[f1, 1] - rad * ny
        xi0 = tx * r0x + ty * r0y
        xi1 = tx * r1x + ty * r1y
        h = -(nx * r0x + ny * r0y)
        N1 = (-h * FT - xi0 * N) / (xi1 - xi0)
        N0 = N - N1
        if N0 < -1e-12 * N or N1 < -1e-12 * N:
            _set_err(err, t, i, -1 - p, st[i, 0], st[i, 1], FT, N0, N1)
            return ERR_TIPPING
    else:
        if mu == 0.0:
            aT = gt
            mode = PM_REST if (vT == 0.0 and gt == 0.0) else PM_SLIDE
        else:
            vz = math.sqrt(_vz2(tolf, -gn))
            if abs(vT) <= vz and abs(gt) <= -mu * gn:
                st[i, 3] = 0.0
                st[i, 4] = 0.0
                aT = 0.0
                mode = PM_REST
            else:
                _set_err(err, t, i, -1 - p, st[i, 0], st[i, 1], vT, gt, mu)
                return ERR_ELLIPSE_SLIDE
    st[i, 6] = aT * tx
    st[i, 7] = aT * ty
    st[i, 8] = al
    pm[i, 0] = mode
    pm[i, 1] = p
    return 0


@njit(cache=True, _nrt=False)
def _release(i, t, st, planes, grav, pm, ttr, ev_t, ev_i, ev_f, cnt):
    p = pm[i, 1]
    nx = planes[p, 0]
    ny = planes[p, 1]
    hc = nx * st[i, 0] + ny * st[i, 1] - planes[p, 2]
    vN = nx * st[i, 3] + ny * st[i, 4]
    vT = ny * st[i, 3] - nx * st[i, 4]
    pm[i, 0] = PM_FLIGHT
    st[i, 6] = grav[0]
    st[i, 7] = grav[1]
    st[i, 8] = 0.0
    ttr[i] = INF
    _log(ev_t, ev_i, ev_f, cnt, t, EV_RELEASE, i, -1 - p, 0, 0, st[i, 0] - hc * nx,
         st[i, 1] - hc * ny, nx, ny, vN, vT, vN, vT, 0.0, 0.0, 0.0)


@njit(cache=True, _nrt=False)
def _settle(i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, ttr, tolf,
            ev_t, ev_i, ev_f, cnt, err):
    """Snap body i (state at t) onto its rest on plane p and enter persistent contact.
    Returns 0, 1 (no stable rest: stays in flight) or an error code."""
    stable, f0, f1, hf, dth, eex = _rest_config(i, p, st, bint, bflt, verts, planes, grav)
    if not stable:
        return 1
    nx = planes[p, 0]
    ny = planes[p, 1]
    tx = ny
    ty = -nx
    m = bflt[i, 0]
    e0 = _energy(st, bflt, grav, i)
    hc = nx * st[i, 0] + ny * st[i, 1] - planes[p, 2]
    # contact-space velocity of the material point at the contact, before
    ux, uy = _point_vel(st, i, -hc * nx, -hc * ny)
    viN = ux * nx + uy * ny
    viT = ux * tx + uy * ty
    vx0 = st[i, 3]
    vy0 = st[i, 4]
    st[i, 2] += dth
    st[i, 0] += (hf - hc) * nx
    st[i, 1] += (hf - hc) * ny
    vN = nx * st[i, 3] + ny * st[i, 4]
    st[i, 3] -= vN * nx
    st[i, 4] -= vN * ny
    if bint[i, 0] != SH_DISK:
        st[i, 5] = 0.0
    pm[i, 2] = f0
    pm[i, 3] = f1
    rc = _persist_setup(i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
                        ttr, tolf, err)
    if rc < 0:
        return rc
    if rc == 1:
        return 1
    ux, uy = _point_vel(st, i, -hf * nx, -hf * ny)
    dvx = st[i, 3] - vx0
    dvy = st[i, 4] - vy0
    _log(ev_t, ev_i, ev_f, cnt, t, EV_CONTACT, i, -1 - p, pm[i, 0], 0,
         st[i, 0] - hf * nx, st[i, 1] - hf * ny, nx, ny, viN, viT, ux * nx + uy * ny,
         ux * tx + uy * ty, m * (dvx * nx + dvy * ny), m * (dvx * tx + dvy * ty),
         _energy(st, bflt, grav, i) - e0)
    return 0


@njit(cache=True, _nrt=False)
def _log_mode(i, t, st, bflt, planes, pm, ev_t, ev_i, ev_f, cnt, viN, viT):
    p = pm[i, 1]
    nx = planes[p, 0]
    ny = planes[p, 1]
    hc = nx * st[i, 0] + ny * st[i, 1] - planes[p, 2]
    ux, uy = _point_vel(st, i, -hc * nx, -hc * ny)
    _log(ev_t, ev_i, ev_f, cnt, t, pm[i, 0] + 1, i, -1 - p, pm[i, 0], 0,
         st[i, 0] - hc * nx, st[i, 1] - hc * ny, nx, ny, viN, viT, ux * nx + uy * ny,
         ux * ny - uy * nx, 0.0, 0.0, 0.0)


@njit(cache=True, _nrt=False)
def _transition(i, t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law, pm, ttr,
                tolf, ev_t, ev_i, ev_f, cnt, err):
    """Slip of a persistent contact stops at t: roll, rest or slide the other way."""
    fly_row(st, i, t - tref[i])
    tref[i] = t
    ttr[i] = INF
    p = pm[i, 1]
    nx = planes[p, 0]
    ny = planes[p, 1]
    hc = nx * st[i, 0] + ny * st[i, 1] - planes[p, 2]
    ux, uy = _point_vel(st, i, -hc * nx, -hc * ny)
    viN = ux * nx + uy * ny
    viT = ux * ny - uy * nx
    vT = ny * st[i, 3] - nx * st[i, 4]
    if bint[i, 0] == SH_DISK:
        st[i, 5] = -vT / bflt[i, 2]      # contact point velocity exactly zero
    else:
        st[i, 3] = 0.0
        st[i, 4] = 0.0
    rc = _persist_setup(i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
                        ttr, tolf, err)
    if rc < 0:
        return rc
    _log_mode(i, t, st, bflt, planes, pm, ev_t, ev_i, ev_f, cnt, viN, viT)
    return 0


@njit(cache=True, _nrt=False)
def _reevaluate(i, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm, ttr, tolf,
                ev_t, ev_i, ev_f, cnt, err):
    """A body in persistent contact received an impulse: keep the contact (zeroing the
    normal velocity, and the rotation of a non-disk) when that motion carries less energy
    than the accumulation threshold, else release it to free flight."""
    p = pm[i, 1]
    nx = planes[p, 0]
    ny = planes[p, 1]
    gn = nx * grav[0] + ny * grav[1]
    m = bflt[i, 0]
    vN = nx * st[i, 3] + ny * st[i, 4]
    ex = 0.5 * m * vN * vN
    if bint[i, 0] != SH_DISK:
        ex += 0.5 * bflt[i, 1] * st[i, 5] * st[i, 5]
    if gn < 0.0 and ex <= 0.5 * m * _vz2(tolf, -gn):
        hc = nx * st[i, 0] + ny * st[i, 1] - planes[p, 2]
        ux, uy = _point_vel(st, i, -hc * nx, -hc * ny)
        st[i, 3] -= vN * nx
        st[i, 4] -= vN * ny
        if bint[i, 0] != SH_DISK:
            st[i, 5] = 0.0
        old = pm[i, 0]
        rc = _persist_setup(i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law,
                            pm, ttr, tolf, err)
        if rc < 0:
            return rc
        if rc == 0:
            if pm[i, 0] != old:
                _log_mode(i, t, st, bflt, planes, pm, ev_t, ev_i, ev_f, cnt,
                          ux * nx + uy * ny, ux * ny - uy * nx)
            return 0
    _release(i, t, st, planes, grav, pm, ttr, ev_t, ev_i, ev_f, cnt)
    return 0


# ------------------------------------------------------------------ impact resolution


@njit(cache=True, inline="always", _nrt=False)
def _single(c, t, cluster, st, bflt, law_ids, law_par, c_i, c_f, v2, W2, P2, ev_t, ev_i,
            ev_f, cnt, err):
    """Resolve contact c with its pair law at its current velocity. Returns (rc, v_fN)."""
    viN, viT = _contact_velocity(st, c_i, c_f, c)
    v2[0] = viN
    v2[1] = viT
    _contact_W(bflt, c_i, c_f, c, W2)
    li = c_i[c, CI_LAW]
    mode = resolve_2d(law_ids[li], v2, W2, law_par[li], P2)
    if mode < 0:
        _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_PX], c_f[c, CF_PY], mode,
                 viN, viT)
        return ERR_NO_SOLUTION, 0.0
    PN = P2[0]
    PT = P2[1]
    _apply(st, bflt, c_i, c_f, c, PN, PT)
    vfN, vfT = _contact_velocity(st, c_i, c_f, c)
    c_f[c, CF_PN] += PN
    c_f[c, CF_PT] += PT
    _log(ev_t, ev_i, ev_f, cnt, t, EV_IMPACT, c_i[c, CI_A], _bcode(c_i, c), mode, cluster,
         c_f[c, CF_PX], c_f[c, CF_PY], c_f[c, CF_NX], c_f[c, CF_NY], viN, viT, vfN, vfT,
         PN, PT, 0.5 * (PN * (viN + vfN) + PT * (viT + vfT)))
    return 0, vfN


@njit(cache=True, _nrt=False, inline="always")
def _bcode(c_i, c):
    if c_i[c, CI_TYPE] == 0:
        return -1 - c_i[c, CI_B]
    return c_i[c, CI_B]


@njit(cache=True, _nrt=False)
def _jblock(c, d, bflt, c_i, c_f):
    """2x2 block of the stacked Delassus matrix coupling contacts c and d."""
    w00 = 0.0
    w01 = 0.0
    w10 = 0.0
    w11 = 0.0
    ncx = c_f[c, CF_NX]
    ncy = c_f[c, CF_NY]
    ndx = c_f[d, CF_NX]
    ndy = c_f[d, CF_NY]
    for sc in range(2):
        if sc == 1 and c_i[c, CI_TYPE] == 0:
            continue
        jc = c_i[c, CI_A] if sc == 0 else c_i[c, CI_B]
        rcx = c_f[c, CF_RAX] if sc == 0 else c_f[c, CF_RBX]
        rcy = c_f[c, CF_RAY] if sc == 0 else c_f[c, CF_RBY]
        scs = 1.0 if sc == 0 else -1.0
        for sd in range(2):
            if sd == 1 and c_i[d, CI_TYPE] == 0:
                continue
            jd = c_i[d, CI_A] if sd == 0 else c_i[d, CI_B]
            if jd != jc:
                continue
            rdx = c_f[d, CF_RAX] if sd == 0 else c_f[d, CF_RBX]
            rdy = c_f[d, CF_RAY] if sd == 0 else c_f[d, CF_RBY]
            sds = 1.0 if sd == 0 else -1.0
            im = 1.0 / bflt[jc, 0]
            iI = 1.0 / bflt[jc, 1]
            sg = scs * sds
            # directions: c normal (ncx, ncy), c tangent (ncy, -ncx); same for d
            cnc = rcx * ncy - rcy * ncx
            ctc = rcx * (-ncx) - rcy * ncy
            cnd = rdx * ndy - rdy * ndx
            ctd = rdx * (-ndx) - rdy * ndy
            w00 += sg * ((ncx * ndx + ncy * ndy) * im + cnc * cnd * iI)
            w01 += sg * ((ncx * ndy - ncy * ndx) * im + cnc * ctd * iI)
            w10 += sg * ((ncy * ndx - ncx * ndy) * im + ctc * cnd * iI)
            w11 += sg * ((ncy * ndy + ncx * ndx) * im + ctc * ctd * iI)
    return w00, w01, w10, w11


@njit((_I1, _i, _f, _A2, _A2, _A2, _I2, _A2, _A2, _A1, _A1, _A1, _A1, _I1, _A1, _I2, _A2, _I1,
       _A1), cache=True, _nrt=False)
def _joint(members, K, t, st, bflt, law_par, c_i, c_f, Wb, Pb, vb, tb, tolf, toli, ev_t,
           ev_i, ev_f, cnt, err):
    """Simultaneous policy: Newton restitution + Coulomb friction solved jointly over the
    K contacts (projected Gauss-Seidel on the stacked Delassus matrix)."""
    for a in range(K):
        c = members[a]
        viN, viT = _contact_velocity(st, c_i, c_f, c)
        c_f[c, CF_VIN] = viN
        c_f[c, CF_VIT] = viT
        e = law_par[c_i[c, CI_LAW], P_E]
        if not (0.0 <= e <= 1.0):
            _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_PX], c_f[c, CF_PY], e,
                     0.0, 0.0)
            return ERR_JOINT_E
        vb[2 * a] = viN
        vb[2 * a + 1] = viT
        tb[2 * a] = -e * min(viN, 0.0)
        Pb[2 * a] = 0.0
        Pb[2 * a + 1] = 0.0
        for b in range(K):
            w00, w01, w10, w11 = _jblock(c, members[b], bflt, c_i, c_f)
            Wb[2 * a, 2 * b] = w00
            Wb[2 * a, 2 * b + 1] = w01
            Wb[2 * a + 1, 2 * b] = w10
            Wb[2 * a + 1, 2 * b + 1] = w11
    n2 = 2 * K
    vmax = 0.0
    for k in range(n2):
        vmax = max(vmax, abs(vb[k]))
    tol = tolf[TF_SIMUL_TOL] * vmax
    converged = False
    for it in range(toli[TI_SIMUL_MAXIT]):
        dmax = 0.0
        for a in range(K):
            mu = law_par[c_i[members[a], CI_LAW], P_MU]
            for r in range(2):
                idx = 2 * a + r
                if r == 0:
                    new = Pb[idx] - (vb[idx] - tb[idx]) / Wb[idx, idx]
                    if new < 0.0:
                        new = 0.0
                else:
                    lim = mu * Pb[idx - 1]
                    new = Pb[idx] - vb[idx] / Wb[idx, idx]
                    if new > lim:
                        new = lim
                    elif new < -lim:
                        new = -lim
                dp = new - Pb[idx]
                if dp != 0.0:
                    Pb[idx] = new
                    for k in range(n2):
                        vb[k] += Wb[k, idx] * dp
                    dv = abs(dp) * Wb[idx, idx]
                    if dv > dmax:
                        dmax = dv
        if dmax <= tol:
            converged = True
            break
    if not converged:
        c = members[0]
        _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_PX], c_f[c, CF_PY], K,
                 dmax, 0.0)
        return ERR_PGS
    for a in range(K):
        c = members[a]
        _apply(st, bflt, c_i, c_f, c, Pb[2 * a], Pb[2 * a + 1])
    for a in range(K):
        c = members[a]
        PN = Pb[2 * a]
        PT = Pb[2 * a + 1]
        viN = c_f[c, CF_VIN]
        viT = c_f[c, CF_VIT]
        c_f[c, CF_PN] += PN
        c_f[c, CF_PT] += PT
        if PN == 0.0 and viN >= 0.0:
            continue
        vfN, vfT = _contact_velocity(st, c_i, c_f, c)
        mu = law_par[c_i[c, CI_LAW], P_MU]
        if PN == 0.0:
            mode = 0
        elif abs(PT) < mu * PN * (1.0 - 1e-12):
            mode = 1
        else:
            mode = 2
        _log(ev_t, ev_i, ev_f, cnt, t, EV_IMPACT, c_i[c, CI_A], _bcode(c_i, c), mode, K,
             c_f[c, CF_PX], c_f[c, CF_PY], c_f[c, CF_NX], c_f[c, CF_NY], viN, viT, vfN, vfT,
             PN, PT, 0.5 * (PN * (viN + vfN) + PT * (viT + vfT)))
    return 0


@njit(cache=True, inline="always", _nrt=False)
def _sequential(members, K, vtol, t, st, bflt, law_ids, law_par, c_i, c_f, v2, W2, P2,
                toli, ev_t, ev_i, ev_f, cnt, err):
    """Sequential policy: repeatedly resolve, with its pair law, the contact that approaches
    fastest (ties: lowest contact index), until none approaches faster than vtol. A single
    contact goes through here too, with vtol = 0 (resolved once if it approaches)."""
    for step in range(toli[TI_SEQ_MAXSTEPS]):
        best = -1
        vbest = -vtol
        for a in range(K):
            c = members[a]
            if c_i[c, CI_OFF] != 0:
                continue
            vN, vT = _contact_velocity(st, c_i, c_f, c)
            if vN < vbest:
                vbest = vN
                best = c
        if best < 0:
            return 0
        rc, vfN = _single(best, t, K, st, bflt, law_ids, law_par, c_i, c_f, v2, W2, P2,
                          ev_t, ev_i, ev_f, cnt, err)
        if rc < 0:
            return rc
        if vfN < 0.0:
            c_i[best, CI_OFF] = 1
    c = members[0]
    _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_PX], c_f[c, CF_PY], K,
             toli[TI_SEQ_MAXSTEPS], 0.0)
    return ERR_SEQ


# ------------------------------------------------------------------ the event loop


@njit(cache=True, _nrt=False)
def _init(t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law, pm, ttr, tolf,
          ev_t, ev_i, ev_f, cnt, err):
    """Start of a run: settle the bodies that start at rest on a plane."""
    nb = st.shape[0]
    for i in range(nb):
        tref[i] = t
        st[i, 6] = grav[0]
        st[i, 7] = grav[1]
        st[i, 8] = 0.0
        if not _finite(st, i):
            _set_err(err, t, i, 0, st[i, 0], st[i, 1], 0.0, 0.0, 0.0)
            return ERR_NONFINITE
    for i in range(nb):
        for p in range(planes.shape[0]):
            if pm[i, 0] != PM_FLIGHT:
                break
            nx = planes[p, 0]
            ny = planes[p, 1]
            gn = nx * grav[0] + ny * grav[1]
            if not gn < 0.0:
                continue
            stable, f0, f1, hf, dth, eex = _rest_config(i, p, st, bint, bflt, verts, planes,
                                                        grav)
            hc = nx * st[i, 0] + ny * st[i, 1] - planes[p, 2]
            if not stable or hc - hf > tolf[TF_GAP_TOL]:
                continue
            if (eex < 0.5 * bflt[i, 0] * _vz2(tolf, -gn)
                    and eex >= -bflt[i, 0] * (-gn) * SNAP_RTOL * hf):
                rc = _settle(i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
                             ttr, tolf, ev_t, ev_i, ev_f, cnt, err)
                if rc < 0:
                    return rc
    return 0


@njit(cache=True, _nrt=False, inline="always")
def _gather(t, st, tref, bint, bflt, verts, planes, bp_law, pairs, tolf, toli, tz, zp, bp_t,
            pr_t, c_i, c_f, bmark, err):
    """Gather the contacts touching in [t, t + simul_time] (and closing corners within
    simul_gap), bring their bodies to t and build their contact frames. Returns the number
    of contacts or an error code."""
    nb = st.shape[0]
    npl = planes.shape[0]
    npr = pairs.shape[0]
    # ---- impacts: gather every contact touching within [t, t + simul_time]
    tw = t + tolf[TF_SIMUL_TIME]
    nc = 0
    for i in range(nb):
        for p in range(npl):
            if bp_t[i, p] > tw:
                continue
            bmark[i] = 1
            kind = FEAT_ELLIPSE if bint[i, 0] == SH_ELLIPSE else FEAT_VERTEX
            v0 = bint[i, 1]
            nv = bint[i, 2]
            for k in range(nv):
                if nv > 1:
                    s, code = plane_feature_toi(
                        kind, st[i], verts[v0 + k, 0], verts[v0 + k, 1], bflt[i, 2],
                        bflt[i, 3], bflt[i, 4], planes[p, 0], planes[p, 1], planes[p, 2],
                        tref[i], tw - tref[i], tolf[TF_TOI_RTOL], tolf[TF_TOI_ATOL],
                        tolf[TF_GAP_TOL], toli[TI_TOI_MAXIT])
                    if not (tref[i] + s <= tw):
                        g, gd = feature_gap(kind, st[i], verts[v0 + k, 0],
                                            verts[v0 + k, 1], bflt[i, 2], bflt[i, 3],
                                            bflt[i, 4], planes[p, 0], planes[p, 1],
                                            planes[p, 2], t - tref[i])
                        if not (g <= tolf[TF_SIMUL_GAP] and gd < 0.0):
                            continue
                if nc >= MAXC:
                    _set_err(err, t, i, -1 - p, st[i, 0], st[i, 1], MAXC, 0.0, 0.0)
                    return ERR_TOO_MANY
                c_i[nc, CI_TYPE] = 0
                c_i[nc, CI_A] = i
                c_i[nc, CI_B] = p
                c_i[nc, CI_FEAT] = v0 + k
                c_i[nc, CI_LAW] = bp_law[i, p]
                c_i[nc, CI_OFF] = 0
                nc += 1
    for q in range(npr):
        if pr_t[q] > tw:
            continue
        if nc >= MAXC:
            _set_err(err, t, pairs[q, 0], pairs[q, 1], 0.0, 0.0, MAXC, 0.0, 0.0)
            return ERR_TOO_MANY
        bmark[pairs[q, 0]] = 1
        bmark[pairs[q, 1]] = 1
        c_i[nc, CI_TYPE] = 1
        c_i[nc, CI_A] = pairs[q, 0]
        c_i[nc, CI_B] = pairs[q, 1]
        c_i[nc, CI_FEAT] = -1
        c_i[nc, CI_LAW] = pairs[q, 2]
        c_i[nc, CI_OFF] = 0
        nc += 1
    # bring the bodies involved to t; a pending accumulation point is cancelled: the body
    # continues from its held motion (on the plane, normal velocity zero; the normal
    # energy of the unfinished accumulation, below the accumulation threshold
    # m zeno_speed^2 / 2, is dropped without an event)
    for i in range(nb):
        if bmark[i] != 0:
            if tz[i] < INF:
                _held_into(st[i], bint[i, 0], planes[zp[i], 0], planes[zp[i], 1], st[i])
                tz[i] = INF
            fly_row(st, i, t - tref[i])
            tref[i] = t
    # contact frames
    for c in range(nc):
        a = c_i[c, CI_A]
        if c_i[c, CI_TYPE] == 0:
            p = c_i[c, CI_B]
            nx = planes[p, 0]
            ny = planes[p, 1]
            px, py, rx, ry = _plane_contact(st, a, bint, bflt, verts, c_i[c, CI_FEAT],
                                            nx, ny)
            c_f[c, CF_RBX] = 0.0
            c_f[c, CF_RBY] = 0.0
        else:
            b = c_i[c, CI_B]
            dx = st[a, 0] - st[b, 0]
            dy = st[a, 1] - st[b, 1]
            dist = math.sqrt(dx * dx + dy * dy)
            nx = dx / dist
            ny = dy / dist
            rb = bflt[b, 2]
            px = st[b, 0] + rb * nx
            py = st[b, 1] + rb * ny
            rx = -bflt[a, 2] * nx
            ry = -bflt[a, 2] * ny
            c_f[c, CF_RBX] = rb * nx
            c_f[c, CF_RBY] = rb * ny
        c_f[c, CF_NX] = nx
        c_f[c, CF_NY] = ny
        c_f[c, CF_PX] = px
        c_f[c, CF_PY] = py
        c_f[c, CF_RAX] = rx
        c_f[c, CF_RAY] = ry
        c_f[c, CF_PN] = 0.0
        c_f[c, CF_PT] = 0.0
        c_f[c, CF_VCMN] = nx * st[a, 3] + ny * st[a, 4]
    return nc


@njit(cache=True, _nrt=False, inline="always")
def _resolve(nc, t, st, bflt, law_ids, law_par, c_i, c_f, Wb, Pb, vb, tb, comp, v2, W2, P2,
             tolf, toli, ev_t, ev_i, ev_f, cnt, err):
    """Group the gathered contacts into clusters sharing a body and resolve each one."""
    policy = toli[TI_POLICY]
    # clusters: contacts sharing a body
    for c in range(nc):
        comp[c] = c
    changed = True
    while changed:
        changed = False
        for c in range(nc):
            for d in range(c + 1, nc):
                if comp[c] == comp[d]:
                    continue
                share = c_i[c, CI_A] == c_i[d, CI_A]
                if c_i[d, CI_TYPE] == 1 and c_i[c, CI_A] == c_i[d, CI_B]:
                    share = True
                if c_i[c, CI_TYPE] == 1 and (c_i[c, CI_B] == c_i[d, CI_A] or (
                        c_i[d, CI_TYPE] == 1 and c_i[c, CI_B] == c_i[d, CI_B])):
                    share = True
                if share:
                    lo = min(comp[c], comp[d])
                    comp[c] = lo
                    comp[d] = lo
                    changed = True
    for root in range(nc):
        K = 0
        for c in range(nc):
            if comp[c] == root:
                K += 1
        if K == 0:
            continue
        # members of this cluster, in contact order, stored in the tail of comp
        k = 0
        for c in range(nc):
            if comp[c] == root:
                comp[MAXC + k] = c
                k += 1
        members = comp[MAXC:MAXC + K]
        if K > 1 and policy == POL_SIMULTANEOUS:
            rc = _joint(members, K, t, st, bflt, law_par, c_i, c_f, Wb, Pb, vb, tb, tolf,
                        toli, ev_t, ev_i, ev_f, cnt, err)
            if rc < 0:
                return rc
        else:
            vtol = tolf[TF_SEQ_VTOL] if K > 1 else 0.0
            rc = _sequential(members, K, vtol, t, st, bflt, law_ids, law_par, c_i, c_f,
                             v2, W2, P2, toli, ev_t, ev_i, ev_f, cnt, err)
            if rc < 0:
                return rc
    return 0


@njit(cache=True, _nrt=False)
def _after_impacts(nc, t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law, pairs,
                   pm, tz, zp, ttr, bp_off, pr_off, tolf, c_i, c_f, bmark, ev_t, ev_i, ev_f,
                   seg_t, seg_b, seg_s, cnt, tmp, err):
    """After the impacts of an instant: disable perforated pairs, re-evaluate persistent
    contacts, schedule accumulation points, detect single-point chatter, log segments."""
    nb = st.shape[0]
    npr = pairs.shape[0]
    # perforating impacts disable their pair for good
    for c in range(nc):
        if c_i[c, CI_OFF] == 0:
            continue
        if c_i[c, CI_TYPE] == 0:
            bp_off[c_i[c, CI_A], c_i[c, CI_B]] = 1
        else:
            for q in range(npr):
                if ((pairs[q, 0] == c_i[c, CI_A] and pairs[q, 1] == c_i[c, CI_B])
                        or (pairs[q, 1] == c_i[c, CI_A] and pairs[q, 0] == c_i[c, CI_B])):
                    pr_off[q] = 1
    # persistent contacts, accumulation (Zeno) points, chatter
    for i in range(nb):
        if bmark[i] == 0:
            continue
        if pm[i, 0] != PM_FLIGHT:
            rc = _reevaluate(i, t, st, bint, bflt, verts, planes, grav, law_par, bp_law,
                             pm, ttr, tolf, ev_t, ev_i, ev_f, cnt, err)
            if rc < 0:
                return rc
            continue
        settled = False
        for c in range(nc):
            if c_i[c, CI_TYPE] != 0 or c_i[c, CI_A] != i:
                continue
            p = c_i[c, CI_B]
            if bp_off[i, p] != 0:
                continue
            nx = planes[p, 0]
            ny = planes[p, 1]
            gn = nx * grav[0] + ny * grav[1]
            if not gn < 0.0:
                continue
            stable, f0, f1, hf, dth, eex = _rest_config(i, p, st, bint, bflt, verts,
                                                        planes, grav)
            # accumulation on that rest only when consistent: the centre of mass is over
            # the face (stable), the motion left is below the threshold, and the snap
            # onto the face does not lift the body (create energy)
            if not (stable and eex < 0.5 * bflt[i, 0] * _vz2(tolf, -gn)
                    and eex >= -bflt[i, 0] * (-gn) * SNAP_RTOL * hf):
                continue
            after = nx * st[i, 3] + ny * st[i, 4]
            before = c_f[c, CF_VCMN]
            dt = 0.0
            if after > 0.0:
                dt = 2.0 * after / (-gn)
                if before < 0.0:
                    ek = -after / before
                    if ek < 1.0:
                        dt = dt / (1.0 - ek)
            tz[i] = t + dt
            zp[i] = p
            settled = True
            break
        if not settled:
            for c in range(nc):
                if c_i[c, CI_A] != i and not (c_i[c, CI_TYPE] == 1 and c_i[c, CI_B] == i):
                    continue
                if c_i[c, CI_OFF] != 0:
                    continue
                vN, vT = _contact_velocity(st, c_i, c_f, c)
                acc = _gap_accel(st, bint, bflt, c_i, c_f, c, verts, grav)
                if vN >= 0.0 and acc < 0.0 and vN * vN < _vz2(tolf, -acc):
                    _set_err(err, t, c_i[c, CI_A], _bcode(c_i, c), c_f[c, CF_PX],
                             c_f[c, CF_PY], vN, acc, 0.0)
                    return ERR_CHATTER
    for i in range(nb):
        if bmark[i] == 0:
            continue
        if not _finite(st, i):
            _set_err(err, t, i, 0, st[i, 0], st[i, 1], 0.0, 0.0, 0.0)
            return ERR_NONFINITE
        if tz[i] < INF:
            # accumulation jump pending: the trajectory holds the body on the plane
            _held_into(st[i], bint[i, 0], planes[zp[i], 0], planes[zp[i], 1], tmp[0])
            _push_row(seg_t, seg_b, seg_s, cnt, tmp[0], tref[i], i)
        else:
            _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i)
    return 0


@njit(cache=True, _nrt=False)
def run_loop(bint, bflt, verts, planes, grav, law_ids, law_par, bp_law, pairs, tolf, toli,
             st, tref, pm, tz, zp, ttr, bp_t, bp_off, pr_t, pr_off, glob, cnt, ev_t, ev_i,
             ev_f, seg_t, seg_b, seg_s, c_i, c_f, Wb, Pb, vb, tb, comp, bmark, v2, W2, P2,
             tmp, err):
    """Advance from glob[0] to tolf[TF_T_END]; see the module docstring for the contract.
    The first call (cnt[3] == 0) initialises the run at glob[0]."""
    nb = st.shape[0]
    npl = planes.shape[0]
    npr = pairs.shape[0]
    t_end = tolf[TF_T_END]
    max_events = toli[TI_MAX_EVENTS]
    margin_e = evbuf.event_margin(toli[TI_SEQ_MAXSTEPS], MAXC, nb)
    margin_s = evbuf.segment_margin(MAXC, nb)
    cap_e = ev_t.shape[0]
    cap_s = seg_t.shape[0]
    # the candidates of the bodies marked at an instant are recomputed at the top of the
    # next pass (one call site, inlined: the per-impact path makes no large calls)
    pend = False
    while True:
        if pend:
            pend = False
            rc = _recompute_marked(glob[0], st, tref, bint, bflt, verts, planes, pairs, pm, tz,
                                   zp, bp_t, bp_off, pr_t, pr_off, tolf, toli, bmark, tmp,
                                   err)
            if rc < 0:
                return rc
        t_now = glob[0]
        if cnt[3] == 0:
            # ---- start of the run
            if not evbuf.has_room(cnt, margin_e, margin_s + nb, cap_e, cap_s):
                return RC_BUFFER_FULL
            rc = _init(t_now, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law, pm,
                       ttr, tolf, ev_t, ev_i, ev_f, cnt, err)
            if rc < 0:
                return rc
            cnt[3] = 1
            for i in range(nb):
                bmark[i] = 1
                _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i)
            pend = True
            continue
        tmin = INF
        for i in range(nb):
            if tz[i] < tmin:
                tmin = tz[i]
            if ttr[i] < tmin:
                tmin = ttr[i]
            for p in range(npl):
                if bp_t[i, p] < tmin:
                    tmin = bp_t[i, p]
        for q in range(npr):
            if pr_t[q] < tmin:
                tmin = pr_t[q]
        if tmin > t_end:
            glob[0] = t_end
            return RC_DONE
        if cnt[0] >= max_events:
            return RC_MAX_EVENTS
        if not evbuf.has_room(cnt, margin_e, margin_s, cap_e, cap_s):
            return RC_BUFFER_FULL
        if tmin <= t_now:
            tmin = t_now
            cnt[2] += 1
            if cnt[2] > toli[TI_STALL]:
                _set_err(err, t_now, -1, 0, 0.0, 0.0, cnt[2], 0.0, 0.0)
                return ERR_STALL
        else:
            cnt[2] = 0
        t = tmin
        glob[0] = t
        for i in range(nb):
            bmark[i] = 0

        # ---- scheduled switches: accumulation points and the end of slip
        did = False
        for i in range(nb):
            if tz[i] <= t:
                p = zp[i]
                tz[i] = INF
                fly_row(st, i, t - tref[i])
                tref[i] = t
                rc = _settle(i, p, t, st, bint, bflt, verts, planes, grav, law_par, bp_law,
                             pm, ttr, tolf, ev_t, ev_i, ev_f, cnt, err)
                if rc < 0:
                    return rc
            elif ttr[i] <= t:
                rc = _transition(i, t, st, tref, bint, bflt, verts, planes, grav, law_par,
                                 bp_law, pm, ttr, tolf, ev_t, ev_i, ev_f, cnt, err)
                if rc < 0:
                    return rc
            else:
                continue
            did = True
            bmark[i] = 1
            if not _finite(st, i):
                _set_err(err, t, i, 0, st[i, 0], st[i, 1], 0.0, 0.0, 0.0)
                return ERR_NONFINITE
            _push_seg(seg_t, seg_b, seg_s, cnt, st, tref, i)
        if did:
            pend = True
            continue

        nc = _gather(t, st, tref, bint, bflt, verts, planes, bp_law, pairs, tolf, toli, tz,
                     zp, bp_t, pr_t, c_i, c_f, bmark, err)
        if nc < 0:
            return nc
        rc = _resolve(nc, t, st, bflt, law_ids, law_par, c_i, c_f, Wb, Pb, vb, tb, comp, v2,
                      W2, P2, tolf, toli, ev_t, ev_i, ev_f, cnt, err)
        if rc < 0:
            return rc
        rc = _after_impacts(nc, t, st, tref, bint, bflt, verts, planes, grav, law_par, bp_law,
                            pairs, pm, tz, zp, ttr, bp_off, pr_off, tolf, c_i, c_f, bmark,
                            ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, cnt, tmp, err)
        if rc < 0:
            return rc
        pend = True
