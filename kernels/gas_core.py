"""Event-driven dynamics of many disks (2D) or spheres (3D) in a box: the generic loop,
compiled by ``gas_entries`` once per dimension ``D``, law and sleep option (compile-time
constants of the loop).

Model. ``n`` equal round bodies (radius ``r`` m, mass ``m`` kg, central inertia ``I``
kg m^2; smooth bodies are given ``1/I = 0``: they never spin) in the box
``[0, L_0] x ... x [0, L_{D-1}]`` whose faces are static planes, with optional uniform
gravity ``g`` (m/s^2) along minus the last axis (2D: -y, 3D: -z). Between impacts every
body flies exactly: ``x(t) = x + u s + a s^2 / 2``, ``s = t - t_local``.

Events (one pending event per body, ``scheduler`` calendar queue; the body's key is the
earliest of three candidates kept in its row of ``bt``):

* pair impact: earliest predicted impact with a neighbour (``BEST_T``, partner
  ``BEST_P`` and the partner's collision counter ``BEST_C`` at prediction time). The
  relative motion of two bodies is linear even under gravity (same acceleration), so the
  time of impact is the smaller root of ``|dr + dv s|^2 = (2r)^2`` with ``dr . dv < 0``,
  taken in the cancellation-free form ``s = c / (-b + sqrt(b^2 - a c))``. Against a
  sleeping body (static) the relative motion is a parabola: ``sleeper_toi``, below;
* wall impact (``WALL_T``): exit of the centre from ``[r, L - r]`` on an axis, a linear
  or quadratic root (``_exit``, cancellation-free forms);
* cell crossing (``CROSS_T``): exit from the body's cell of the cell list (cells of side
  ``>= 2 r (1 + CELL_MARGIN)``, so every partner of an impact is in the 3^D block around
  the body's cell).

Validation on pop: a predicted pair impact whose partner's counter changed is stale; the
body's predictions are recomputed (full scan of the 3^D block) and it is queued again.
A cell crossing moves the body to its new cell and scans only the newly adjacent cells
(the far layer of the 3^D block) unless the body's pair prediction went stale, in which
case the whole block is rescanned. Bodies are advanced lazily: only the bodies of an
impact are moved to the impact time (``TL`` is each body's local time); everybody else
is evaluated "virtually" at the current time when needed.

Impacts. Every impact (pair or wall) is resolved by the chosen law's scalar kernel in
contact space (DESIGN §3): ``n`` from B into A (pair: ``A = i``, ``B = j``,
``n = (x_i - x_j) / |x_i - x_j|``; wall: A is the body, ``n`` the wall's inward normal),
tangent basis 2D ``t = (n_y, -n_x)``, 3D any right-handed orthonormal ``(t1, t2)``
(``W`` is isotropic in the tangent plane for round bodies, so the law does not depend on
the choice). ``v`` is the velocity of A's contact point minus B's: with the arms
``r_A = -r n`` and ``r_B = r n``, ``v = dv - r (w_A + w_B) x n``; 2D (spin ``w`` about
z) ``v_T = dv . t + r (w_A + w_B)``. ``W = k diag(1/m, 1/m + r^2/I[, 1/m + r^2/I])``
with ``k = 2`` for a pair and ``1`` for a wall. The impulse ``P`` acts on A (``-P`` on
B): ``dv_A = P/m``, ``dw_A = dw_B = -r (n x P) / I`` (2D ``r P_T / I``).
The normal velocity handed to the law is ``(dr . dv) / |dr|`` (pair) so that its sign is
the sign of the quantity that predicted the impact: a grazing impact is never re-predicted
at the same instant with a "separating" velocity.

Inelastic collapse (option ``collapse``): ``COLLAPSE_NONE`` applies the law as given;
``COLLAPSE_TC`` is the TC model of Luding & McNamara ("How to handle the inelastic
collapse of a dissipative hard-sphere gas with the TC model", Granular Matter 1:113, 1998):
an impact of a body whose previous impact (pair or wall) happened less than ``tc``
seconds earlier is resolved by the same law with ``e = 1, mu = 0`` (no dissipation), so
the number of impacts per unit time stays finite. As a last guard, ``STALL_IMPACTS``
impacts in a row without any advance of time end the run (status ``RUN_STALL``).

Sleep (option ``SLEEP``, a compile-time constant of the loop: with False the sleep code
is folded away and the loop is the one without sleep; True needs gravity). Bodies at rest
would cost one impact per ``tc`` each (TC hops on the floor); a sleeper costs nothing:

* falling asleep: after an impact of body i that leaves it slow (|v| and r |w| below
  ``F_SLEEP_V``) for the ``I_SLEEP_N``-th time in a row, the impact being on the floor
  (wall 2 (D - 1)) or on a sleeper that stays asleep, i sleeps (``fall_asleep``): v = w =
  0, ``SLP`` set, its counter moved, no queue entry (key inf), still in its cell; its
  kinetic energy goes to ``FS_SLEPT`` and into that impact's recorded dE. Every awake
  body of its 3^D block gets its impact with i (now static) predicted at once (i has no
  event of its own to carry it): a body whose partner was i rescans its block, the
  others scan i's cell;
* an impact of awake i on sleeper j is first resolved by the law with j's true mass and
  v = w = 0. If j would leave slower than ``F_SLEEP_V`` the bed holds it: the impact is
  resolved again with j fixed (W of a wall, ``kf = 1``), i rebounds, j's counter does not
  move (predictions with it stay valid) and ``ST_NABSORB`` counts it. Else j wakes with
  that velocity and ``wake_cluster`` wakes, from rest, every sleeper within
  ``F_WAKE_GAP`` of contact with a woken body, recursively (a list through ``WLINK``):
  all are marked first, then predicted and queued;
* a static support needs a floor under the TC model: after an impact on the floor or on
  a held sleeper, a rebound slower than ``g_n tc / 2`` (``g_n`` gravity's component
  pressing i on the support) is raised to it, the normal speed paid from i's tangential
  velocity (``min_hop``: |v| unchanged). Without it a body sliding over a sleeper with
  zero normal speed would meet it again at the same instant for ever (the law returns
  no impulse for v_N = 0);
* pair prediction of awake i (falling) against sleeper k (static): the earliest root of
  the quartic ``|d0 + u s + a s^2 / 2|^2 = (2r)^2`` (``sleeper_toi``: monotone pieces
  between the roots of f'', bracket, Illinois polish to round-off of the time), searched
  up to ``min(BEST_T, WALL_T)`` of i: i's next wall impact rescans its whole block, so a
  later root is never needed (a cell crossing keeps the best; the crossing horizon alone
  would not do). Sleepers are never paired with each other;
* ``ST_SAME`` (the stall guard) restarts when a body falls asleep: a pile woken from rest
  re-sleeps through impacts at one instant (zero-speed contacts, ``I_SLEEP_N`` each).

Recording: none, all, or the impacts involving bodies flagged in ``rec_mask``; each
record is ``rec_i = (a, b, mode)`` (``b = -1 - wall`` for a wall, ``wall = 2 axis + side``
with side 1 for the face at ``L``) and ``rec_f = (t, dE, n[D], v[D], P[D])`` (contact
space, normal first; dE includes the kinetic energy put to sleep by the impact).
Snapshots of all velocities every ``snap_dt`` (a sleeper's are 0). When a buffer is full
the loop returns (``RUN_REC_FULL`` / ``RUN_SNAP_FULL``) before touching the state, so the
caller can hand over larger buffers and call again: the run is resumable and no
allocation happens inside. Memory with recording off does not grow with the events.
"""
import math

from numba import njit

from .cache_guard import guard

# flush stale compiled code before the kernel modules below are imported (cache_guard)
guard(__name__, __file__)

from .brach import brach_2d_scalar, brach_3d_scalar
from .chatterjee_ruina import chatterjee_ruina_2d_scalar, chatterjee_ruina_3d_scalar
from .common import (LAW_BRACH, LAW_CHATTERJEE_RUINA, LAW_KANE_LEVINSON, LAW_ROUTH,
                     LAW_SMITH, MODE_NO_SOLUTION)
from .kane_levinson import kane_levinson_2d_scalar, kane_levinson_3d_scalar
from .routh import routh_2d_scalar, routh_3d_scalar
from .scheduler import q_fill_dt, q_rebuild, q_remove, q_top, q_update
from .smith import smith_2d_scalar, smith_3d_scalar

# ---- per-body float row ``bt[i]`` ---------------------------------------------------------
TL = 0        # local time of x[i], v[i] (s)
TLAST = 1     # time of the body's previous impact (s), -inf before the first
BEST_T = 2    # predicted pair impact time (s), inf if none
WALL_T = 3    # predicted wall impact time (s)
CROSS_T = 4   # predicted cell crossing time (s)
N_BT = 5

# ---- per-body int row ``bi[i]`` -----------------------------------------------------------
CNT = 0       # impacts of the body so far (its collision counter)
BEST_P = 1    # partner of the predicted pair impact (-1: none)
BEST_C = 2    # the partner's counter when predicted
WALL_K = 3    # wall of the predicted wall impact: 2 axis + side (side 1: face at L)
CROSS_K = 4   # cell face of the predicted crossing: 2 axis + (1 if upward)
CX = 5        # cell coordinates (CX + a for axis a)
CNEXT = 8     # cell list links
CPREV = 9
SLP = 10      # 1 while the body sleeps (sleep option), else 0
SLOW = 11     # consecutive impacts of the body that left it slow (sleep option)
WLINK = 12    # link of the list of bodies woken by one impact (wake_cluster)
N_BI = 13

# ---- float parameters ``fpar`` ------------------------------------------------------------
F_R = 0         # radius (m)
F_SIG2 = 1      # (2 r)^2 (m^2)
F_INVM = 2      # 1 / m (1/kg)
F_INVI = 3      # 1 / I (1/(kg m^2)); 0 for smooth bodies
F_G = 4         # gravity (m/s^2) along minus the last axis
F_E = 5         # law parameters (DESIGN §4): e, mu, e_t, Routh restitution kind, Routh tol
F_MU = 6
F_ET = 7
F_REST = 8
F_TOL = 9
F_TC = 10       # TC model contact duration tc (s)
F_TEND = 11     # end time (s), inf for none
F_L = 12        # box lengths L_0, L_1, L_2 (m)
F_CS = 15       # cell sides (m)
F_SNAP_DT = 18  # snapshot period (s); <= 0: no snapshots
F_SNAP_T0 = 19  # time of snapshot 0 (s)
F_FILL = 20     # calendar queue: mean bodies per bucket (BUCKET_FILL by default)
F_SLEEP_V = 21  # sleep speed (m/s): slow means |v| and r |w| below it
F_WAKE_GAP = 22  # gap (m) within which a woken body wakes a sleeper it touches
N_FPAR = 23

# ---- int parameters ``ipar`` ------------------------------------------------------------
I_NC = 0        # cells per axis (3 entries; 1 for the unused third axis in 2D)
I_COLLAPSE = 3  # COLLAPSE_NONE or COLLAPSE_TC
I_RECORD = 4    # REC_NONE, REC_ALL, REC_MASK
I_MAXIMP = 5    # stop after this many impacts (pair + wall) in total
I_SLEEP = 6     # 1: bodies at rest sleep (needs gravity > 0), 0: they never do
I_SLEEP_N = 7   # consecutive slow impacts before a body may fall asleep
N_IPAR = 8

COLLAPSE_NONE = 0
COLLAPSE_TC = 1
REC_NONE = 0
REC_ALL = 1
REC_MASK = 2

# ---- counters and status ``stats`` (int64) and ``fstats`` (float64) -------------------------
ST_NCOLL = 0    # pair impacts
ST_NWALL = 1    # wall impacts
ST_NCROSS = 2   # cell crossings
ST_NSTALE = 3   # stale pair predictions popped
ST_STATUS = 4
ST_NREC = 5     # records written
ST_NSNAP = 6    # snapshots written
ST_FAIL_A = 7   # bodies and law mode of a failed impact
ST_FAIL_B = 8
ST_FAIL_MODE = 9
ST_NTC = 10     # impacts resolved elastically by the TC model
ST_SAME = 11    # impacts in a row at the same time (stall guard)
ST_NSLEEP = 12  # bodies that fell asleep
ST_NWAKE = 13   # bodies woken (by an impact, or touching a woken body)
ST_NABSORB = 14  # impacts on a sleeper that left it asleep (held fixed: a slow push)
N_ST = 15
FS_T = 0        # time of the last event handled (s)
FS_SLEPT = 1    # kinetic energy removed by sleep (J): bodies falling asleep, pushes absorbed
N_FS = 2

RUN_DONE_TEND = 1     # reached t_end
RUN_DONE_MAX = 2      # reached max impacts
RUN_EMPTY = 3         # no event left (nothing moves)
RUN_REC_FULL = 4      # record buffer full: call again with a larger one
RUN_SNAP_FULL = 5     # snapshot buffer full: idem
RUN_LAW_FAILED = -1   # the law has no solution for an impact (bodies in ST_FAIL_*)
RUN_STALL = -2        # STALL_IMPACTS impacts without time advancing

CELL_MARGIN = 1e-6    # cell side >= 2 r (1 + CELL_MARGIN): round-off of positions never
                      # puts an impact partner outside the 3^D block (relative, to 2r)
STALL_IMPACTS = 100000  # impacts in a row at one instant that end the run as a stall
BUCKET_FILL = 2.0     # calendar queue: mean bodies per bucket (Smallenburg: a few)
RETUNE_EVENTS = 4     # every RETUNE_EVENTS * n events the bucket width is checked and,
                      # if off by more than a factor 2 (a cooling gas), rebuilt

_INF = math.inf
_NJ = dict(cache=True, inline="always", error_model="numpy")   # hot helpers: inlined
# into the loop (compiled with _nrt=False), so no call and no reference counting
_NJI = dict(cache=True, inline="always", error_model="numpy")  # the loop, once per entry
_NJC = dict(cache=True, error_model="numpy", _nrt=False)       # cold paths: a call
# (less code to compile in each entry; no reference counting either way)


# ---- the laws, with one signature per dimension -------------------------------------------
# ``LAW`` is a ``LAW_*`` id of ``common``, a compile-time constant of the loop (closed over
# by its entry, ``gas_entries``): Numba prunes the other laws before typing, so only the
# chosen law is compiled. W = diag(wnn, wtt[, wtt]) for round bodies.

@njit(cache=True, error_model="numpy")
def _routh_2d(vn, vt, wnn, wtt, e, mu, rest):
    """Routh 2D as a call (its scalar core is inline-only: kept out of the loop's code)."""
    return routh_2d_scalar(vn, vt, wnn, 0.0, wtt, e, mu, rest)


@njit(**_NJ)
def law_2d(LAW, vn, vt, wnn, wtt, e, mu, et, rest):
    """Law ``LAW`` on a 2D contact of round bodies: ``(mode, P_N, P_T)`` (N s)."""
    if LAW == LAW_KANE_LEVINSON:
        return kane_levinson_2d_scalar(vn, vt, wnn, 0.0, wtt, e, mu)
    if LAW == LAW_CHATTERJEE_RUINA:
        return chatterjee_ruina_2d_scalar(vn, vt, wnn, 0.0, wtt, e, mu, et)
    if LAW == LAW_BRACH:
        return brach_2d_scalar(vn, vt, wnn, 0.0, wtt, e, mu, et)
    if LAW == LAW_ROUTH:
        return _routh_2d(vn, vt, wnn, wtt, e, mu, rest)
    if LAW == LAW_SMITH:
        return smith_2d_scalar(vn, vt, wnn, 0.0, wtt, e, mu)
    return MODE_NO_SOLUTION, 0.0, 0.0


@njit(**_NJ)
def law_3d(LAW, vn, v1, v2, wnn, wtt, e, mu, et, rest, tol):
    """Law ``LAW`` on a 3D contact of round bodies: ``(mode, P_N, P_T1, P_T2)`` (N s)."""
    if LAW == LAW_KANE_LEVINSON:
        return kane_levinson_3d_scalar(vn, v1, v2, wnn, 0.0, 0.0, wtt, 0.0, wtt, e, mu)
    if LAW == LAW_CHATTERJEE_RUINA:
        return chatterjee_ruina_3d_scalar(vn, v1, v2, wnn, 0.0, 0.0, wtt, 0.0, wtt, e, mu,
                                          et)
    if LAW == LAW_BRACH:
        return brach_3d_scalar(vn, v1, v2, wnn, 0.0, 0.0, wtt, 0.0, wtt, e, mu, et)
    if LAW == LAW_ROUTH:
        return routh_3d_scalar(vn, v1, v2, wnn, 0.0, 0.0, wtt, 0.0, wtt, e, mu, rest, tol)
    if LAW == LAW_SMITH:
        return smith_3d_scalar(vn, v1, v2, wnn, 0.0, 0.0, wtt, 0.0, wtt, e, mu)
    return MODE_NO_SOLUTION, 0.0, 0.0, 0.0


# ---- flight ---------------------------------------------------------------------------

@njit(**_NJ)
def state_at(D, k, t, x, v, bt, g):
    """Position and velocity of body k at time t (exact flight from its local time):
    ``(x0, x1, x2, u0, u1, u2)``, third components 0 in 2D."""
    s = t - bt[k, TL]
    if D == 2:
        return (x[k, 0] + v[k, 0] * s, x[k, 1] + (v[k, 1] - 0.5 * g * s) * s, 0.0,
                v[k, 0], v[k, 1] - g * s, 0.0)
    return (x[k, 0] + v[k, 0] * s, x[k, 1] + v[k, 1] * s,
            x[k, 2] + (v[k, 2] - 0.5 * g * s) * s, v[k, 0], v[k, 1], v[k, 2] - g * s)


@njit(**_NJ)
def advance(D, k, t, x, v, bt, g):
    """Move body k to time t (its local time becomes t)."""
    x0, x1, x2, u0, u1, u2 = state_at(D, k, t, x, v, bt, g)
    x[k, 0] = x0
    x[k, 1] = x1
    v[k, 0] = u0
    v[k, 1] = u1
    if D == 3:
        x[k, 2] = x2
        v[k, 2] = u2
    bt[k, TL] = t


@njit(**_NJ)
def _exit(p, u, a, lo, hi):
    """First time s >= 0 at which ``p + u s + a s^2 / 2`` leaves ``[lo, hi]`` (bounds may
    be infinite; ``p`` is taken as inside: round-off outside counts as on the bound).
    Returns ``(s, side)``: side +1 through ``hi``, -1 through ``lo``, 0 never (s = inf).
    Roots in cancellation-free form (s = 2C / (-B -+ sqrt(B^2 - 4AC)))."""
    sg = 1
    if a > 0.0:          # mirror so that the acceleration is <= 0
        p, u, a, lo, hi = -p, -u, -a, -hi, -lo
        sg = -1
    if a == 0.0:
        if u > 0.0:
            if hi == _INF:
                return _INF, 0
            s = (hi - p) / u
            return (s if s > 0.0 else 0.0), sg
        if u < 0.0:
            if lo == -_INF:
                return _INF, 0
            s = (lo - p) / u
            return (s if s > 0.0 else 0.0), -sg
        return _INF, 0
    # a < 0: the parabola rises while u > 0 then falls; it always comes back down to lo
    s_hi = _INF
    if u > 0.0 and hi != _INF:
        C = p - hi
        if C > 0.0:
            C = 0.0
        d = u * u + 2.0 * a * (-C)      # B^2 - 4 A C with A = a/2, C <= 0
        if d >= 0.0:
            s_hi = -2.0 * C / (u + math.sqrt(d))
    s_lo = _INF
    if lo != -_INF:
        C = p - lo
        if C < 0.0:
            C = 0.0
        sq = math.sqrt(u * u - 2.0 * a * C)
        if u <= 0.0:
            den = sq - u
            s_lo = 2.0 * C / den if den > 0.0 else 0.0
        else:
            s_lo = (u + sq) / (-a)
    if s_hi <= s_lo:
        return s_hi, (sg if s_hi < _INF else 0)
    return s_lo, -sg


@njit(**_NJ)
def wall_time(D, k, t, x, v, bt, g, r, fpar):
    """Next wall impact of body k after time t (its state taken at t):
    ``(time, wall)``, ``wall = 2 axis + side``."""
    x0, x1, x2, u0, u1, u2 = state_at(D, k, t, x, v, bt, g)
    best = _INF
    wk = 0
    for a in range(D):
        if a == 0:
            p, u = x0, u0
        elif a == 1:
            p, u = x1, u1
        else:
            p, u = x2, u2
        acc = -g if a == D - 1 else 0.0
        s, side = _exit(p, u, acc, r, fpar[F_L + a] - r)
        if s < best:
            best = s
            wk = 2 * a + (1 if side > 0 else 0)
    return t + best, wk


@njit(**_NJ)
def cross_time(D, k, t, x, v, bt, bi, g, fpar, ipar):
    """Next exit of body k from its cell after time t: ``(time, face)``,
    ``face = 2 axis + (1 if upward)``. Faces on the box walls are never crossed."""
    x0, x1, x2, u0, u1, u2 = state_at(D, k, t, x, v, bt, g)
    best = _INF
    fk = 0
    for a in range(D):
        if a == 0:
            p, u = x0, u0
        elif a == 1:
            p, u = x1, u1
        else:
            p, u = x2, u2
        c = bi[k, CX + a]
        cs = fpar[F_CS + a]
        lo = c * cs if c > 0 else -_INF
        hi = (c + 1) * cs if c < ipar[I_NC + a] - 1 else _INF
        acc = -g if a == D - 1 else 0.0
        s, side = _exit(p, u, acc, lo, hi)
        if s < best:
            best = s
            fk = 2 * a + (1 if side > 0 else 0)
    return t + best, fk


# ---- cell list ---------------------------------------------------------------------------

@njit(**_NJ)
def cell_of(k, bi, ipar):
    return bi[k, CX] + ipar[I_NC] * (bi[k, CX + 1] + ipar[I_NC + 1] * bi[k, CX + 2])


@njit(**_NJ)
def cell_insert(k, bi, chead, ipar):
    c = cell_of(k, bi, ipar)
    h = chead[c]
    bi[k, CNEXT] = h
    bi[k, CPREV] = -1
    if h >= 0:
        bi[h, CPREV] = k
    chead[c] = k


@njit(**_NJ)
def cell_remove(k, bi, chead, ipar):
    nx = bi[k, CNEXT]
    pv = bi[k, CPREV]
    if pv >= 0:
        bi[pv, CNEXT] = nx
    else:
        chead[cell_of(k, bi, ipar)] = nx
    if nx >= 0:
        bi[nx, CPREV] = pv


# ---- awake body against a sleeping one -------------------------------------------------------
# The awake body falls (acceleration a = -g along the vertical), the sleeper is static:
# their relative position d(s) = d0 + u s + a s^2 / 2 is a parabola and the time of impact
# is the earliest root of the quartic f(s) = |d(s)|^2 - sigma^2 (sigma = 2 r) where f goes
# down through 0. It is found exactly: the roots of the quadratic f''(s)/2 cut the window
# into at most three pieces on which h = f'/2 = d . d' is monotone; on each piece f is
# monotone, or falls to one minimum, or rises to one maximum, and the first piece on which
# f falls through 0 brackets the root, polished by Illinois regula falsi with bisection
# every TOI_BISECT-th step to the round-off of the time (TOI_RTOL). f and h are evaluated
# from d(s) itself, never from expanded coefficients (no cancellation).

TOI_RTOL = 4.0 * 2.220446049250313e-16   # root bracket width, relative to the absolute time
TOI_BISECT = 4          # every TOI_BISECT-th polishing step bisects (guaranteed halving)
TOI_MAXIT = 400         # polishing steps at most (bisection alone needs < 2100 / TOI_BISECT)
TOI_WINDOW_RTOL = 1e-12  # the cheap windows (vertical end, horizontal miss) are widened by
                         # this much so that round-off in them can never drop a root


@njit(**_NJ)
def _fq(s, dx, dy, dz, ux, uy, uz, g, f0):
    """f(s) = |d(s)|^2 - sigma^2 and h(s) = d(s) . d'(s) (= f'(s) / 2), ``f0 = f(0)``.
    f is taken as ``f0 + 2 d0 . e + |e|^2`` with the displacement ``e = d(s) - d0``: near
    contact |d|^2 - sigma^2 would lose all but the round-off of sigma^2 (its sign would
    flicker for ~eps sigma^2 / h seconds around every root); this form varies smoothly
    and f0's own rounding is a constant offset."""
    ex = ux * s
    ey = uy * s
    ez = (uz - 0.5 * g * s) * s
    f = f0 + (2.0 * (dx * ex + dy * ey + dz * ez) + (ex * ex + ey * ey + ez * ez))
    return f, (dx + ex) * ux + (dy + ey) * uy + (dz + ez) * (uz - g * s)


@njit(**_NJC)
def _toi_bracket(use_h, illinois, lo, hi, ylo, yhi, ta, dx, dy, dz, ux, uy, uz, g, f0):
    """Shrink ``[lo, hi]`` (s) around the sign change of y = f (``use_h`` False) or y = h
    (True), ``y(lo) > 0 >= y(hi)`` with ``ylo``, ``yhi`` their values: regula falsi
    (Illinois if ``illinois``: the end value kept twice in a row is halved), every
    TOI_BISECT-th step a bisection, until the bracket is narrower than TOI_RTOL of the
    absolute time (``ta`` = |t| at s = 0). Returns ``(lo, hi)``. A call, not inlined at the
    four call sites in ``sleeper_toi``: compiled once per flag pair, ``sleeper_toi`` then
    compiles in 0.8 s instead of 2 s."""
    side = 0
    for it in range(TOI_MAXIT):
        if hi - lo <= TOI_RTOL * (ta + hi):
            break
        if it % TOI_BISECT == TOI_BISECT - 1:
            c = 0.5 * (lo + hi)
        else:
            c = (lo * yhi - hi * ylo) / (yhi - ylo)
        if not (lo < c < hi):
            c = 0.5 * (lo + hi)
            if not (lo < c < hi):
                break
        fc, hc = _fq(c, dx, dy, dz, ux, uy, uz, g, f0)
        yc = hc if use_h else fc
        if yc > 0.0:
            lo = c
            ylo = yc
            if illinois and side == 1:
                yhi *= 0.5
            side = 1
        else:
            hi = c
            yhi = yc
            if illinois and side == -1:
                ylo *= 0.5
            side = -1
    return lo, hi


@njit(**_NJ)
def _toi_root(lo, hi, flo, fhi, ta, dx, dy, dz, ux, uy, uz, g, f0):
    """The point where f crosses from > 0 (at lo) to <= 0 (at hi), f taking one sign on
    each side of it (Illinois, ``_toi_bracket``); returns the end where f <= 0."""
    lo, hi = _toi_bracket(False, True, lo, hi, flo, fhi, ta, dx, dy, dz, ux, uy, uz, g, f0)
    return hi


@njit(**_NJ)
def _toi_crit(lo, hi, hlo, hhi, ta, dx, dy, dz, ux, uy, uz, g, f0):
    """Root of h in [lo, hi], h monotone from > 0 (at lo) to < 0 (at hi): the maximum of f
    (plain regula falsi, ``_toi_bracket``); returns the bracket's middle."""
    lo, hi = _toi_bracket(True, False, lo, hi, hlo, hhi, ta, dx, dy, dz, ux, uy, uz, g, f0)
    return 0.5 * (lo + hi)


@njit(**_NJC)
def sleeper_toi(dx, dy, dz, ux, uy, uz, g, sig2, H, t):
    """Earliest s in [0, H] at which an awake body, at relative position ``(dx, dy, dz)``
    (m) from a sleeping one and relative velocity ``(ux, uy, uz)`` (m/s), falling with
    ``g`` (m/s^2, > 0) along minus the vertical ``z`` (2D: ``dy = uy = 0``), reaches the
    distance ``sigma`` (``sig2 = sigma^2``) moving inwards; ``inf`` if none. ``t`` (s) is
    the absolute time of s = 0 (the root is polished to TOI_RTOL of it).

    As the linear pair formula: touching or overlapping (f(0) <= 0) and approaching
    (``d0 . u < 0``, the sign the impact's normal velocity is computed with) is an impact
    now; overlapping and separating is not (the body leaves and may come back)."""
    f0 = dx * dx + dy * dy + dz * dz - sig2
    b = dx * ux + dy * uy + dz * uz
    if f0 <= 0.0 and b < 0.0:
        return 0.0
    # window 1 (vertical): after s_end the body is more than sigma below the sleeper
    sig = math.sqrt(sig2)
    c = dz + sig
    if c < 0.0 and uz <= 0.0:
        return _INF
    disc = uz * uz + 2.0 * g * c
    if disc < 0.0:
        return _INF
    sq = math.sqrt(disc)
    if uz >= 0.0:
        s_end = (uz + sq) / g
    else:
        s_end = 2.0 * c / (sq - uz)
    s_end *= 1.0 + TOI_WINDOW_RTOL
    S1 = H if H < s_end else s_end
    if not S1 >= 0.0:
        return _INF
    # window 2 (horizontal, linear motion): the closest horizontal approach on [0, S1]
    uu = ux * ux + uy * uy
    sh = 0.0
    if uu > 0.0:
        sh = -(dx * ux + dy * uy) / uu
        if sh < 0.0:
            sh = 0.0
        elif sh > S1:
            sh = S1
    qx = dx + ux * sh
    qy = dy + uy * sh
    if qx * qx + qy * qy > sig2 * (1.0 + TOI_WINDOW_RTOL):
        return _INF
    ta = abs(t)
    # pieces of monotone h: roots of h'(s) = A s^2 + B s + C in (0, S1)
    A = 1.5 * g * g
    B = -3.0 * g * uz
    C = ux * ux + uy * uy + uz * uz - g * dz
    p1 = S1
    p2 = S1
    dq = B * B - 4.0 * A * C
    if dq > 0.0:
        q = -0.5 * (B + math.copysign(math.sqrt(dq), B))
        r1 = q / A
        r2 = C / q if q != 0.0 else r1
        if r1 > r2:
            r1, r2 = r2, r1
        if 0.0 < r1 < S1:
            p1 = r1
        if 0.0 < r2 < S1:
            if p1 < S1:
                p2 = r2
            else:
                p1 = r2
    lo = 0.0
    flo = f0
    hlo = b
    for piece in range(3):
        hi = p1 if piece == 0 else (p2 if piece == 1 else S1)
        if hi <= lo:
            continue
        fhi, hhi = _fq(hi, dx, dy, dz, ux, uy, uz, g, f0)
        if hlo <= 0.0 and hhi <= 0.0:
            # f falls on the whole piece
            if flo <= 0.0:
                return lo
            if fhi <= 0.0:
                return _toi_root(lo, hi, flo, fhi, ta, dx, dy, dz, ux, uy, uz, g, f0)
        elif hlo < 0.0 < hhi:
            # f falls to a minimum, then rises: look for the minimum only while f may
            # still reach 0 (f >= f(p) + 2 h(p) (q - p) on [p, q], h increasing)
            if flo <= 0.0:
                return lo
            p = lo
            fp = flo
            hp = hlo
            q = hi
            hq = hhi
            for it in range(TOI_MAXIT):
                if fp + 2.0 * hp * (q - p) > 0.0:
                    break                     # f > 0 on the whole piece
                if q - p <= TOI_RTOL * (ta + q):
                    fq_, hq_ = _fq(q, dx, dy, dz, ux, uy, uz, g, f0)
                    if fq_ <= 0.0:
                        return _toi_root(p, q, fp, fq_, ta, dx, dy, dz, ux, uy, uz, g,
                                         f0)
                    break
                if it % TOI_BISECT == TOI_BISECT - 1:
                    m = 0.5 * (p + q)
                else:
                    m = (p * hq - q * hp) / (hq - hp)
                if not (p < m < q):
                    m = 0.5 * (p + q)
                    if not (p < m < q):
                        break
                fm, hm = _fq(m, dx, dy, dz, ux, uy, uz, g, f0)
                if fm <= 0.0:
                    # f > 0 at p, <= 0 at m, one crossing between (falls, then rises
                    # but stays <= 0 up to m)
                    return _toi_root(p, m, fp, fm, ta, dx, dy, dz, ux, uy, uz, g, f0)
                if hm < 0.0:
                    p = m
                    fp = fm
                    hp = hm
                else:
                    q = m
                    hq = hm
        elif hlo > 0.0 > hhi:
            # f rises to a maximum, then falls: the root is after the maximum (never on
            # the rise: just after an impact f is 0 within its round-off, and its sign
            # there is noise, for a time ~ eps sigma^2 / h)
            if fhi <= 0.0:
                cm = _toi_crit(lo, hi, hlo, hhi, ta, dx, dy, dz, ux, uy, uz, g, f0)
                fc, hc = _fq(cm, dx, dy, dz, ux, uy, uz, g, f0)
                if fc <= 0.0:
                    return cm
                return _toi_root(cm, hi, fc, fhi, ta, dx, dy, dz, ux, uy, uz, g, f0)
        lo = hi
        flo = fhi
        hlo = hhi
    return _INF


# ---- pair prediction -----------------------------------------------------------------------

@njit(**_NJ)
def scan_block(D, SLEEP, i, t, lo0, hi0, lo1, hi1, lo2, hi2, x, v, bt, bi, chead, fpar,
               ipar):
    """Earliest impact of body i (state at time t) with the bodies of the cells
    ``[lo0, hi0] x [lo1, hi1] x [lo2, hi2]`` (clipped to the grid) that is earlier than
    its current ``BEST_T``; updates ``BEST_T``, ``BEST_P``, ``BEST_C``."""
    g = fpar[F_G]
    sig2 = fpar[F_SIG2]
    nc0 = ipar[I_NC]
    nc1 = ipar[I_NC + 1]
    nc2 = ipar[I_NC + 2]
    if lo0 < 0:
        lo0 = 0
    if lo1 < 0:
        lo1 = 0
    if lo2 < 0:
        lo2 = 0
    if hi0 >= nc0:
        hi0 = nc0 - 1
    if hi1 >= nc1:
        hi1 = nc1 - 1
    if hi2 >= nc2:
        hi2 = nc2 - 1
    xi0, xi1, xi2, ui0, ui1, ui2 = state_at(D, i, t, x, v, bt, g)
    best = bt[i, BEST_T]
    bp = -1
    for c2 in range(lo2, hi2 + 1):
        for c1 in range(lo1, hi1 + 1):
            base = nc0 * (c1 + nc1 * c2)
            for c0 in range(lo0, hi0 + 1):
                k = chead[base + c0]
                while k >= 0:
                    if SLEEP and bi[k, SLP] != 0:
                        # k sleeps (static), i falls: the quartic, searched up to i's
                        # next wall impact (which rescans) and the best so far
                        hz = min(best, bt[i, WALL_T]) - t
                        if D == 2:
                            sk = sleeper_toi(xi0 - x[k, 0], 0.0, xi1 - x[k, 1], ui0, 0.0, ui1,
                                             g, sig2, hz, t)
                        else:
                            sk = sleeper_toi(xi0 - x[k, 0], xi1 - x[k, 1], xi2 - x[k, 2], ui0,
                                             ui1, ui2, g, sig2, hz, t)
                        tk = t + sk
                        if tk < best:
                            best = tk
                            bp = k
                    elif k != i:
                        xk0, xk1, xk2, uk0, uk1, uk2 = state_at(D, k, t, x, v, bt, g)
                        d0 = xi0 - xk0
                        d1 = xi1 - xk1
                        e0 = ui0 - uk0
                        e1 = ui1 - uk1
                        b = d0 * e0 + d1 * e1
                        cc = d0 * d0 + d1 * d1 - sig2
                        aa = e0 * e0 + e1 * e1
                        if D == 3:
                            d2 = xi2 - xk2
                            e2 = ui2 - uk2
                            b += d2 * e2
                            cc += d2 * d2
                            aa += e2 * e2
                        if b < 0.0:
                            if cc <= 0.0:
                                tk = t         # touching or round-off overlap, approaching
                            else:
                                disc = b * b - aa * cc
                                tk = t + cc / (-b + math.sqrt(disc)) if disc > 0.0 else _INF
                            if tk < best:
                                best = tk
                                bp = k
                    k = bi[k, CNEXT]
    if bp >= 0:
        bt[i, BEST_T] = best
        bi[i, BEST_P] = bp
        bi[i, BEST_C] = bi[bp, CNT]


@njit(**_NJ)
def full_scan(D, SLEEP, i, t, x, v, bt, bi, chead, fpar, ipar):
    """Forget body i's pair prediction and scan its whole 3^D block."""
    bt[i, BEST_T] = _INF
    bi[i, BEST_P] = -1
    c0 = bi[i, CX]
    c1 = bi[i, CX + 1]
    c2 = bi[i, CX + 2]
    d2 = 1 if D == 3 else 0
    scan_block(D, SLEEP, i, t, c0 - 1, c0 + 1, c1 - 1, c1 + 1, c2 - d2, c2 + d2, x, v, bt, bi,
               chead,
               fpar, ipar)


@njit(**_NJ)
def predict(D, SLEEP, i, t, x, v, bt, bi, chead, fpar, ipar):
    """All predictions of body i after a change of its velocity at time t; returns the
    body's key (earliest of the three)."""
    g = fpar[F_G]
    tw, wk = wall_time(D, i, t, x, v, bt, g, fpar[F_R], fpar)
    bt[i, WALL_T] = tw
    bi[i, WALL_K] = wk
    tc, fk = cross_time(D, i, t, x, v, bt, bi, g, fpar, ipar)
    bt[i, CROSS_T] = tc
    bi[i, CROSS_K] = fk
    full_scan(D, SLEEP, i, t, x, v, bt, bi, chead, fpar, ipar)
    return min(bt[i, BEST_T], min(tw, tc))


# ---- impacts ---------------------------------------------------------------------------

@njit(**_NJ)
def impact(D, LAW, n0, n1, n2, vn, dv0, dv1, dv2, ws0, ws1, ws2, kf, fpar, e, mu):
    """Resolve one impact by law ``LAW``. ``n`` unit normal (B into A), ``vn`` the normal
    relative velocity, ``dv`` the centres' relative velocity, ``ws`` the sum of the two
    angular velocities (A and B; a wall has none), ``kf`` 2 (pair) or 1 (wall).

    Returns ``(mode, PN, P1, P2, v1, v2, Px, Py, Pz, dw0, dw1, dw2, wnn, wtt)``: the
    impulse in contact space and in the world, the contact-space tangential velocity,
    the angular velocity change of each body and the diagonal of W."""
    r = fpar[F_R]
    invm = fpar[F_INVM]
    wnn = kf * invm
    wtt = kf * (invm + r * r * fpar[F_INVI])
    # contact point velocity v = dv - r ws x n
    c0 = dv0 - r * (ws1 * n2 - ws2 * n1)
    c1 = dv1 - r * (ws2 * n0 - ws0 * n2)
    c2 = dv2 - r * (ws0 * n1 - ws1 * n0)
    if D == 2:
        t10 = n1
        t11 = -n0
        t12 = 0.0
        v1 = c0 * t10 + c1 * t11
        v2 = 0.0
        mode, PN, P1 = law_2d(LAW, vn, v1, wnn, wtt, e, mu, fpar[F_ET], fpar[F_REST])
        P2 = 0.0
        t20 = 0.0
        t21 = 0.0
        t22 = 0.0
    else:
        # tangent basis: t1 = normalised (e_k x n) with e_k the axis least aligned with n
        a0 = abs(n0)
        a1 = abs(n1)
        a2 = abs(n2)
        if a0 <= a1 and a0 <= a2:      # e_x x n = (0, -n2, n1)
            t10, t11, t12 = 0.0, -n2, n1
        elif a1 <= a2:                 # e_y x n = (n2, 0, -n0)
            t10, t11, t12 = n2, 0.0, -n0
        else:                          # e_z x n = (-n1, n0, 0)
            t10, t11, t12 = -n1, n0, 0.0
        q = 1.0 / math.sqrt(t10 * t10 + t11 * t11 + t12 * t12)
        t10 *= q
        t11 *= q
        t12 *= q
        # t2 = n x t1 (right-handed: t1 x t2 = n)
        t20 = n1 * t12 - n2 * t11
        t21 = n2 * t10 - n0 * t12
        t22 = n0 * t11 - n1 * t10
        v1 = c0 * t10 + c1 * t11 + c2 * t12
        v2 = c0 * t20 + c1 * t21 + c2 * t22
        mode, PN, P1, P2 = law_3d(LAW, vn, v1, v2, wnn, wtt, e, mu, fpar[F_ET],
                                    fpar[F_REST], fpar[F_TOL])
    # world impulse; divided by |n|^2 (1 up to round-off) so that a mirror reflection
    # keeps |v| to round-off without a bias from the rounding of n (measured drift
    # 1.2e-12 of the energy in 2e5 elastic impacts without it)
    nn = 1.0 / (n0 * n0 + n1 * n1 + n2 * n2)
    Px = (PN * n0 + P1 * t10 + P2 * t20) * nn
    Py = (PN * n1 + P1 * t11 + P2 * t21) * nn
    Pz = (PN * n2 + P1 * t12 + P2 * t22) * nn
    # dw = -r (n x P) / I
    k = -r * fpar[F_INVI]
    dw0 = k * (n1 * Pz - n2 * Py)
    dw1 = k * (n2 * Px - n0 * Pz)
    dw2 = k * (n0 * Py - n1 * Px)
    return mode, PN, P1, P2, v1, v2, Px, Py, Pz, dw0, dw1, dw2, wnn, wtt


@njit(**_NJC)
def record(D, a, b, mode, t, n0, n1, n2, vn, v1, v2, PN, P1, P2, wnn, wtt, dsleep, stats,
           rec_i, rec_f):
    m = stats[ST_NREC]
    stats[ST_NREC] = m + 1
    rec_i[m, 0] = a
    rec_i[m, 1] = b
    rec_i[m, 2] = mode
    rec_f[m, 0] = t
    # dE = P . (v + v_f) / 2 with v_f = v + W P (W diagonal), plus dsleep (<= 0): the
    # kinetic energy removed by sleep in this event
    de = 0.5 * (PN * (2.0 * vn + wnn * PN) + P1 * (2.0 * v1 + wtt * P1)
                + P2 * (2.0 * v2 + wtt * P2))
    rec_f[m, 1] = de + dsleep if dsleep != 0.0 else de
    rec_f[m, 2] = n0
    rec_f[m, 3] = n1
    rec_f[m, 2 + D] = vn
    rec_f[m, 3 + D] = v1
    rec_f[m, 2 + 2 * D] = PN
    rec_f[m, 3 + 2 * D] = P1
    if D == 3:
        rec_f[m, 4] = n2
        rec_f[m, 4 + D] = v2
        rec_f[m, 4 + 2 * D] = P2


@njit(**_NJC)
def write_snapshots(D, t, t_end, v, w, bt, bi, g, fpar, ipar, stats, snap_t, snap_v,
                    snap_w):
    """Write the snapshots due at or before time t (and t_end): all velocities at
    ``F_SNAP_T0 + k F_SNAP_DT`` (a sleeper's are 0). Returns 0, or RUN_SNAP_FULL when the
    buffer is full."""
    sleep_on = ipar[I_SLEEP] != 0
    snap_dt = fpar[F_SNAP_DT]
    while True:
        ks = stats[ST_NSNAP]
        ts = fpar[F_SNAP_T0] + ks * snap_dt
        if not (ts <= t and ts <= t_end):
            return 0
        if ks >= snap_t.shape[0]:
            return RUN_SNAP_FULL
        snap_t[ks] = ts
        for b in range(v.shape[0]):
            s = ts - bt[b, TL]
            for a in range(D):
                snap_v[ks, b, a] = v[b, a]
            if not (sleep_on and bi[b, SLP] != 0):
                snap_v[ks, b, D - 1] -= g * s
            for a in range(w.shape[1]):
                snap_w[ks, b, a] = w[b, a]
        stats[ST_NSNAP] = ks + 1


@njit(**_NJ)
def _tc_params(i, j, t, bt, fpar, ipar, stats):
    """(e, mu) for an impact of i (and j >= 0) at time t: the law's, or (1, 0) under the
    TC model when either body's previous impact is less than tc ago."""
    if ipar[I_COLLAPSE] == COLLAPSE_TC:
        tc = fpar[F_TC]
        if t - bt[i, TLAST] < tc or (j >= 0 and t - bt[j, TLAST] < tc):
            stats[ST_NTC] += 1
            return 1.0, 0.0
    return fpar[F_E], fpar[F_MU]


@njit(**_NJ)
def _want(i, j, ipar, rec_mask):
    m = ipar[I_RECORD]
    if m == REC_ALL:
        return True
    if m == REC_MASK:
        return rec_mask[i] != 0 or (j >= 0 and rec_mask[j] != 0)
    return False


# ---- sleep and wake -------------------------------------------------------------------------

@njit(**_NJ)
def _slow(D, v0, v1, v2, w0, w1, w2, r, sleep_v2):
    """|v| and r |w| both below the sleep speed (``sleep_v2`` its square)."""
    if v0 * v0 + v1 * v1 + v2 * v2 >= sleep_v2:
        return False
    return r * r * (w0 * w0 + w1 * w1 + w2 * w2) < sleep_v2


@njit(**_NJ)
def _kinetic(D, v0, v1, v2, w0, w1, w2, invm, invi):
    """Kinetic energy (J) of velocity v and spin w (smooth bodies: invi = 0, no spin)."""
    e = 0.5 * (v0 * v0 + v1 * v1 + v2 * v2) / invm
    if invi > 0.0:
        e += 0.5 * (w0 * w0 + w1 * w1 + w2 * w2) / invi
    return e


@njit(**_NJ)
def _count_slow(D, k, v, w, bi, r, sleep_v2):
    """After an impact of k: one more consecutive slow impact, or the count restarts."""
    if D == 2:
        slow = _slow(D, v[k, 0], v[k, 1], 0.0, 0.0, 0.0, w[k, 0], r, sleep_v2)
    else:
        slow = _slow(D, v[k, 0], v[k, 1], v[k, 2], w[k, 0], w[k, 1], w[k, 2], r, sleep_v2)
    bi[k, SLOW] = bi[k, SLOW] + 1 if slow else 0


@njit(**_NJC)
def min_hop(D, k, v, n0, n1, n2, g, tc):
    """After body k's impact on a static support (the floor, or a sleeper; ``n`` the unit
    normal from the support into k), leave it at least the normal speed
    ``v_min = g_n tc / 2`` (``g_n`` gravity's component pressing k onto the support):
    the rebound of the TC model's steady bounce, one hop per ``tc``. Without it a body
    sliding over a sleeper (or along the floor) with zero normal speed meets it again at
    the same instant, for ever (the law returns no impulse for v_N = 0). The normal speed
    added is taken from k's tangential velocity (scaled down): |v| and the energy do not
    change. A body too slow to pay for it is left as is (it is slow: it will sleep)."""
    if D == 2:
        gn = g * n1
    else:
        gn = g * n2
    if not gn > 0.0:
        return
    vmin = 0.5 * gn * tc
    vn = v[k, 0] * n0 + v[k, 1] * n1
    if D == 3:
        vn += v[k, 2] * n2
    if vn >= vmin or vn <= -vmin:      # |vn| < vmin: 0 within round-off, or a feeble
        return                         # rebound (-vmin < vn <= 0: the law saw v_N >= 0)
    t0 = v[k, 0] - vn * n0
    t1 = v[k, 1] - vn * n1
    t2 = v[k, 2] - vn * n2 if D == 3 else 0.0
    vt2 = t0 * t0 + t1 * t1 + t2 * t2
    need = vmin * vmin - vn * vn
    if not vt2 > need:
        return
    kt = math.sqrt(1.0 - need / vt2)
    v[k, 0] = vmin * n0 + kt * t0
    v[k, 1] = vmin * n1 + kt * t1
    if D == 3:
        v[k, 2] = vmin * n2 + kt * t2


@njit(**_NJC)
def fall_asleep(D, k, t, x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar,
                ipar, stats):
    """Body k (out of the queue, at its impact time t) falls asleep: v = w = 0, no event,
    still in its cell. Its collision counter moves (predictions with it are stale), and
    every awake body of its 3^D block gets its impact with k, now static, predicted: a
    body whose best partner was k rescans its whole block, any other scans k's cell."""
    for a in range(D):
        v[k, a] = 0.0
    for a in range(w.shape[1]):
        w[k, a] = 0.0
    bt[k, TL] = t
    bt[k, BEST_T] = _INF
    bt[k, WALL_T] = _INF
    bt[k, CROSS_T] = _INF
    bi[k, BEST_P] = -1
    bi[k, SLP] = 1
    bi[k, SLOW] = 0
    bi[k, CNT] += 1
    qkey[k] = _INF
    stats[ST_NSLEEP] += 1
    nc0 = ipar[I_NC]
    nc1 = ipar[I_NC + 1]
    nc2 = ipar[I_NC + 2]
    k0 = bi[k, CX]
    k1 = bi[k, CX + 1]
    k2 = bi[k, CX + 2]
    d3 = 1 if D == 3 else 0
    for c2 in range(max(k2 - d3, 0), min(k2 + d3, nc2 - 1) + 1):
        for c1 in range(max(k1 - 1, 0), min(k1 + 1, nc1 - 1) + 1):
            for c0 in range(max(k0 - 1, 0), min(k0 + 1, nc0 - 1) + 1):
                m = chead[c0 + nc0 * (c1 + nc1 * c2)]
                while m >= 0:
                    if bi[m, SLP] == 0:
                        if bi[m, BEST_P] == k:
                            bt[m, BEST_T] = _INF
                            bi[m, BEST_P] = -1
                            a0, b0, a1, b1 = bi[m, CX] - 1, bi[m, CX] + 1, bi[m, CX + 1] - 1, \
                                bi[m, CX + 1] + 1
                            a2, b2 = bi[m, CX + 2] - d3, bi[m, CX + 2] + d3
                        else:
                            a0, b0, a1, b1, a2, b2 = k0, k0, k1, k1, k2, k2
                        scan_block(D, True, m, t, a0, b0, a1, b1, a2, b2, x, v, bt, bi, chead,
                                   fpar,
                                   ipar)
                        q_update(m, min(bt[m, BEST_T], min(bt[m, WALL_T], bt[m, CROSS_T])),
                                 qkey, qlink, qheap, qhead, qs, qdt)
                    m = bi[m, CNEXT]


@njit(**_NJC)
def wake_cluster(D, j, t, x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar,
                 ipar, stats):
    """Body j (just woken, awake) wakes every sleeper within ``F_WAKE_GAP`` of contact,
    and so on recursively (a list threaded through ``WLINK``). The woken bodies start
    from rest at time t (v = w = 0, counters moved: predictions with them are stale),
    all are marked first, then each is predicted and queued (j is predicted by the
    caller)."""
    reach = 2.0 * fpar[F_R] + fpar[F_WAKE_GAP]
    reach2 = reach * reach
    nc0 = ipar[I_NC]
    nc1 = ipar[I_NC + 1]
    nc2 = ipar[I_NC + 2]
    d3 = 1 if D == 3 else 0
    bi[j, WLINK] = -1
    tail = j
    c = j
    while c >= 0:
        k0 = bi[c, CX]
        k1 = bi[c, CX + 1]
        k2 = bi[c, CX + 2]
        for c2 in range(max(k2 - d3, 0), min(k2 + d3, nc2 - 1) + 1):
            for c1 in range(max(k1 - 1, 0), min(k1 + 1, nc1 - 1) + 1):
                for c0 in range(max(k0 - 1, 0), min(k0 + 1, nc0 - 1) + 1):
                    m = chead[c0 + nc0 * (c1 + nc1 * c2)]
                    while m >= 0:
                        if bi[m, SLP] != 0:
                            d2 = 0.0
                            for a in range(D):
                                da = x[m, a] - x[c, a]
                                d2 += da * da
                            if d2 <= reach2:
                                bi[m, SLP] = 0
                                bi[m, SLOW] = 0
                                bi[m, CNT] += 1
                                bt[m, TL] = t
                                bi[m, WLINK] = -1
                                bi[tail, WLINK] = m
                                tail = m
                                stats[ST_NWAKE] += 1
                        m = bi[m, CNEXT]
        c = bi[c, WLINK]
    c = bi[j, WLINK]
    while c >= 0:
        key = predict(D, True, c, t, x, v, bt, bi, chead, fpar, ipar)
        q_update(c, key, qkey, qlink, qheap, qhead, qs, qdt)
        c = bi[c, WLINK]


# ---- the event loop ----------------------------------------------------------------------

@njit(**_NJI)
def gas_loop(D, LAW, SLEEP, x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt,
             fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask, snap_t, snap_v, snap_w):
    """Run until t_end, max impacts, a full buffer, or a failure; the status is in
    ``stats[ST_STATUS]`` and returned. Resumable (see the module docstring).

    Written with a single call site per helper (one impact, one scan, one queue update
    for the one or two bodies an event changes): the loop is inlined into each entry and
    its helpers into it, and several call sites multiplied the compiled code."""
    g = fpar[F_G]
    t_end = fpar[F_TEND]
    max_imp = ipar[I_MAXIMP]
    snap_dt = fpar[F_SNAP_DT]
    recording = ipar[I_RECORD] != REC_NONE
    rec_cap = rec_i.shape[0]
    invm = fpar[F_INVM]
    invi = fpar[F_INVI]
    r = fpar[F_R]
    sleep_on = SLEEP       # compile-time: the sleep code is folded away when False
    sleep_v2 = fpar[F_SLEEP_V] * fpar[F_SLEEP_V]
    n = x.shape[0]
    status = 0
    since = 0
    tnow = -_INF             # time of the last event popped (s)
    while True:
        since += 1
        if since >= RETUNE_EVENTS * n and tnow > -_INF:
            since = 0
            dt_new = q_fill_dt(qkey, tnow, fpar[F_FILL])
            if dt_new > 0.0 and not (0.5 * qdt[0] <= dt_new <= 2.0 * qdt[0]):
                q_rebuild(qkey, qlink, qheap, qhead, qs, qdt, dt_new, tnow)
        i = q_top(qkey, qlink, qheap, qhead, qs, qdt)
        t = qkey[i] if i >= 0 else _INF
        if t == _INF and t_end == _INF:     # nothing will ever happen (all at rest)
            status = RUN_EMPTY
            break
        if snap_dt > 0.0:
            status = write_snapshots(D, t, t_end, v, w, bt, bi, g, fpar, ipar, stats,
                                     snap_t, snap_v, snap_w)
            if status != 0:
                break
        if t == _INF:
            status = RUN_EMPTY
            break
        if t > t_end:
            status = RUN_DONE_TEND
            break
        if stats[ST_NCOLL] + stats[ST_NWALL] >= max_imp:
            status = RUN_DONE_MAX
            break
        if recording and stats[ST_NREC] >= rec_cap:
            status = RUN_REC_FULL
            break
        q_remove(i, qkey, qlink, qheap, qhead, qs)      # i is the top: out of the heap
        tnow = t
        tb = bt[i, BEST_T]
        tw = bt[i, WALL_T]
        tcr = bt[i, CROSS_T]
        j = -1                 # second body changed by the event (pair impact)
        moved = False          # velocities changed: new wall, crossing and full scan
        full = False           # full rescan of the 3^D block
        ax = 0
        step = 0
        if tcr <= tb and tcr <= tw:
            # ---- cell crossing: new cell; only the newly adjacent layer is scanned
            stats[ST_NCROSS] += 1
            fk = bi[i, CROSS_K]
            ax = fk >> 1
            step = 1 if (fk & 1) else -1
            cell_remove(i, bi, chead, ipar)
            bi[i, CX + ax] += step
            cell_insert(i, bi, chead, ipar)
            p = bi[i, BEST_P]
            full = p >= 0 and bi[p, CNT] != bi[i, BEST_C]
        elif tb < tw and bi[bi[i, BEST_P], CNT] != bi[i, BEST_C]:
            # ---- stale pair prediction: rescan
            stats[ST_NSTALE] += 1
            full = True
        else:
            # ---- impact: wall (j < 0) or pair
            moved = True
            full = True
            advance(D, i, t, x, v, bt, g)
            if tw <= tb:
                wk = bi[i, WALL_K]
                wax = wk >> 1
                sgn = -1.0 if (wk & 1) else 1.0       # inward normal of the wall
                n0 = sgn if wax == 0 else 0.0
                n1 = sgn if wax == 1 else 0.0
                n2 = sgn if wax == 2 else 0.0
                vn = sgn * v[i, wax]
                e0 = v[i, 0]
                e1 = v[i, 1]
                kf = 1.0
                bpart = -1 - wk
                jsl = False
                if D == 3:
                    e2 = v[i, 2]
                    ws0, ws1, ws2 = w[i, 0], w[i, 1], w[i, 2]
                else:
                    e2 = 0.0
                    ws0, ws1, ws2 = 0.0, 0.0, w[i, 0]
            else:
                j = bi[i, BEST_P]
                jsl = sleep_on and bi[j, SLP] != 0
                if not jsl:                   # a sleeper is static (v = w = 0)
                    advance(D, j, t, x, v, bt, g)
                d0 = x[i, 0] - x[j, 0]
                d1 = x[i, 1] - x[j, 1]
                e0 = v[i, 0] - v[j, 0]
                e1 = v[i, 1] - v[j, 1]
                if D == 3:
                    d2 = x[i, 2] - x[j, 2]
                    e2 = v[i, 2] - v[j, 2]
                    ws0, ws1, ws2 = w[i, 0] + w[j, 0], w[i, 1] + w[j, 1], w[i, 2] + w[j, 2]
                else:
                    d2 = 0.0
                    e2 = 0.0
                    ws0, ws1, ws2 = 0.0, 0.0, w[i, 0] + w[j, 0]
                q = 1.0 / math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
                n0 = d0 * q
                n1 = d1 * q
                n2 = d2 * q
                vn = (d0 * e0 + d1 * e1 + d2 * e2) * q
                kf = 2.0
                bpart = j
            e, mu = _tc_params(i, j, t, bt, fpar, ipar, stats)
            held = False           # j sleeps and stays asleep: it is held fixed
            for attempt in range(2 if SLEEP else 1):
                (mode, PN, P1, P2, v1, v2, Px, Py, Pz, dw0, dw1, dw2, wnn,
                 wtt) = impact(D, LAW, n0, n1, n2, vn, e0, e1, e2, ws0, ws1, ws2, kf, fpar,
                               e, mu)
                if mode < 0 or not jsl or held:
                    break
                # j sleeps: resolved with its true mass (v = w = 0), would it leave slower
                # than the sleep speed? Then the bed holds it: solve again with j fixed
                # (W of a wall), i rebounds from it; else j wakes with that velocity
                if not _slow(D, -Px * invm, -Py * invm, -Pz * invm, dw0, dw1, dw2, r,
                             sleep_v2):
                    break
                held = True
                kf = 1.0
            if mode < 0:
                stats[ST_FAIL_A] = i
                stats[ST_FAIL_B] = bpart
                stats[ST_FAIL_MODE] = mode
                status = RUN_LAW_FAILED        # the run ends: the state is not resumable
                break
            v[i, 0] += Px * invm
            v[i, 1] += Py * invm
            if D == 2:
                w[i, 0] += dw2
            else:
                v[i, 2] += Pz * invm
                w[i, 0] += dw0
                w[i, 1] += dw1
                w[i, 2] += dw2
            bi[i, CNT] += 1
            bt[i, TLAST] = t
            slept = 0.0                # kinetic energy removed by sleep in this event (J)
            woke = jsl and not held
            if j >= 0:
                if held:
                    stats[ST_NABSORB] += 1
                else:
                    if woke:
                        bi[j, SLP] = 0
                        bt[j, TL] = t
                        stats[ST_NWAKE] += 1
                    v[j, 0] -= Px * invm
                    v[j, 1] -= Py * invm
                    if D == 2:
                        w[j, 0] += dw2
                    else:
                        v[j, 2] -= Pz * invm
                        w[j, 0] += dw0
                        w[j, 1] += dw1
                        w[j, 2] += dw2
                    bi[j, CNT] += 1
                    bt[j, TLAST] = t
                stats[ST_NCOLL] += 1
            else:
                stats[ST_NWALL] += 1
            i_sleeps = False
            if sleep_on:
                if (j < 0 and bi[i, WALL_K] == 2 * (D - 1)) or held:
                    # static support (floor, sleeper): at least the TC model's hop
                    min_hop(D, i, v, n0, n1, n2, g, fpar[F_TC])
                # consecutive slow impacts; i falls asleep on the floor or on a sleeper
                _count_slow(D, i, v, w, bi, r, sleep_v2)
                if j >= 0 and not jsl:
                    _count_slow(D, j, v, w, bi, r, sleep_v2)
                if bi[i, SLOW] >= ipar[I_SLEEP_N] and (
                        (j < 0 and bi[i, WALL_K] == 2 * (D - 1)) or held):
                    i_sleeps = True
                    if D == 2:
                        slept += _kinetic(D, v[i, 0], v[i, 1], 0.0, 0.0, 0.0, w[i, 0], invm,
                                          invi)
                    else:
                        slept += _kinetic(D, v[i, 0], v[i, 1], v[i, 2], w[i, 0], w[i, 1],
                                          w[i, 2], invm, invi)
                fstats[FS_SLEPT] += slept
            if recording and _want(i, j, ipar, rec_mask):
                record(D, i, bpart, mode, t, n0, n1, n2, vn, v1, v2, PN, P1, P2, wnn, wtt,
                       -slept, stats, rec_i, rec_f)
            if t == fstats[FS_T] and not i_sleeps:
                stats[ST_SAME] += 1
            else:
                stats[ST_SAME] = 0         # time advanced, or a body fell asleep
            fstats[FS_T] = t
            if stats[ST_SAME] >= STALL_IMPACTS:
                status = RUN_STALL
            if held:
                j = -1                     # j did not change: no new predictions
            if woke:
                # bodies touching the woken sleeper wake too (recursively): nothing is
                # left floating when its support moves
                wake_cluster(D, j, t, x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs,
                             qdt, fpar, ipar, stats)
            if i_sleeps:
                fall_asleep(D, i, t, x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs,
                            qdt, fpar, ipar, stats)
                i = -1                     # nothing left to predict (j is -1 too)
        # ---- new predictions of the one or two bodies, and their queue keys
        for kk in range(2):
            b = i if kk == 0 else j
            if b < 0:
                break               # i < 0 (fell asleep): j < 0 as well
            if moved:
                tw2, wk2 = wall_time(D, b, t, x, v, bt, g, fpar[F_R], fpar)
                bt[b, WALL_T] = tw2
                bi[b, WALL_K] = wk2
            if moved or step != 0:
                tc2, fk2 = cross_time(D, b, t, x, v, bt, bi, g, fpar, ipar)
                bt[b, CROSS_T] = tc2
                bi[b, CROSS_K] = fk2
            c0 = bi[b, CX]
            c1 = bi[b, CX + 1]
            c2 = bi[b, CX + 2]
            d3 = 1 if D == 3 else 0
            lo0, hi0, lo1, hi1, lo2, hi2 = c0 - 1, c0 + 1, c1 - 1, c1 + 1, c2 - d3, c2 + d3
            if full:
                bt[b, BEST_T] = _INF
                bi[b, BEST_P] = -1
            else:
                layer = bi[b, CX + ax] + step
                if ax == 0:
                    lo0, hi0 = layer, layer
                elif ax == 1:
                    lo1, hi1 = layer, layer
                else:
                    lo2, hi2 = layer, layer
            scan_block(D, SLEEP, b, t, lo0, hi0, lo1, hi1, lo2, hi2, x, v, bt, bi, chead, fpar,
                       ipar)
            q_update(b, min(bt[b, BEST_T], min(bt[b, WALL_T], bt[b, CROSS_T])),
                     qkey, qlink, qheap, qhead, qs, qdt)
        if status != 0:
            break
    stats[ST_STATUS] = status
    return status


# ---- set-up and end of a run (not hot) ----------------------------------------------------

@njit(**_NJI)
def gas_prepare(D, SLEEP, x, v, bt, bi, chead, qkey, fpar, ipar, t0):
    """Cells from the positions, local times ``t0``, all predictions; the keys are
    written to ``qkey`` (the caller then sizes and fills the queue)."""
    n = x.shape[0]
    for c in range(chead.shape[0]):
        chead[c] = -1
    for i in range(n):
        bt[i, TL] = t0
        bt[i, TLAST] = -_INF
        bi[i, CNT] = 0
        bi[i, CX + 2] = 0
        bi[i, SLOW] = 0
        bi[i, WLINK] = -1
        if not SLEEP:
            bi[i, SLP] = 0
        for a in range(D):
            c = int(math.floor(x[i, a] / fpar[F_CS + a]))
            if c < 0:
                c = 0
            if c >= ipar[I_NC + a]:
                c = ipar[I_NC + a] - 1
            bi[i, CX + a] = c
        cell_insert(i, bi, chead, ipar)
    for i in range(n):
        if bi[i, SLP] != 0:          # a sleeper (set by the caller): no event
            bt[i, BEST_T] = _INF
            bt[i, WALL_T] = _INF
            bt[i, CROSS_T] = _INF
            bi[i, BEST_P] = -1
            qkey[i] = _INF
        else:
            qkey[i] = predict(D, SLEEP, i, t0, x, v, bt, bi, chead, fpar, ipar)


@njit(**_NJI)
def gas_finish(D, t, x, v, bt, bi, g):
    """Advance every awake body to time t (end of a run); sleepers stay."""
    for i in range(x.shape[0]):
        if bi[i, SLP] != 0:
            bt[i, TL] = t
        else:
            advance(D, i, t, x, v, bt, g)
