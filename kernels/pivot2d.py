"""Persistent contact in 2D: a body pivoting on one of its vertices on a plane, or an
ellipse rolling / sliding on a plane on its curved boundary, sticking or sliding with
Coulomb friction, or a body sliding on two planes at once (section "Two contacts"),
integrated with error control and event location (the 2D counterpart of ``pivot3d``; used
by ``stepper2d``'s ``PM_PIVOT``). The held feature is
``w[CP_KIND]``: ``KIND_VERTEX`` (below) or ``KIND_ELLIPSE`` (section "Ellipse"); the
integrator, the events and the recorded pieces are the same for both.

Model (Newton-Euler with one unilateral contact and Coulomb friction; e.g. Pfeiffer &
Glocker, *Multibody Dynamics with Unilateral Contacts*, 1996, ch. 6). Plane ``n . q >= d``
with tangent ``t = (n_y, -n_x)`` (DESIGN §3); body of mass ``m`` and inertia ``I`` with a
vertex ``p`` (body frame) carrying a radius ``rad`` (0 for a polygon corner, the capsule
radius for a rod end) held on the plane. With ``r = R(angle) p``, ``xi = t . r``,
``eta = n . r``, ``eta_c = eta - rad`` (normal offset of the contact point) and the contact
force ``lam n + f t`` at the contact point, ``m a = m g + lam n + f t`` and
``I dw/dt = xi lam - eta_c f`` (Euler). The vertex centre stays at height ``d + rad``:

* reduced coordinates ``y = (u, angle, du/dt, w)``, ``u = t . (x + r)``; the centre of mass
  is ``x = u t + (d + rad) n - r`` and ``v = (du/dt) t - w J r`` (``J`` the quarter turn), so
  the contact constraint holds exactly along the integrated solution (no drift). The slip
  velocity of the contact point is ``v_T = du/dt + w rad``.
* **sticking** (``v_T = 0``): ``dw/dt (I + m (xi^2 + eta_c^2)) = m (w^2 xi rad - xi g_n +
  eta_c g_t)``, ``lam = m (w^2 eta - g_n - xi dw/dt)``, ``f = m (eta_c dw/dt + w^2 xi - g_t)``,
  ``d2u/dt2 = -rad dw/dt`` (for ``rad = 0``: the rigid pendulum about the corner);
* **sliding** along ``sig t`` (``sig = +-1``): ``f = -mu sig lam``, ``kap = xi + mu sig eta_c``,
  ``D = I + m xi kap``, ``lam = m I (w^2 eta - g_n) / D``, ``dw/dt = kap lam / I``,
  ``d2u/dt2 = g_t + f/m - eta dw/dt - w^2 xi``. ``D / (m I) = W_NN - mu sig W_NT``: ``D <= 0``
  is the Painleve paradox (no solution in this model): ``PV_PAINLEVE``.

Ellipse (``KIND_ELLIPSE``: semi-axes ``a`` on the body x axis, ``b`` on y, centred on the
centre of mass; rolling or sliding on a curved boundary, DESIGN §6a). With the body-frame
plane normal ``nb = (c n_x + s n_y, -s n_x + c n_y)`` (``c, s`` of the angle; ``dnb0/dangle =
nb1``, ``dnb1/dangle = -nb0``) the support ``h = sqrt(a^2 nb0^2 + b^2 nb1^2)`` is the height of
the centre above the plane, ``h' = (a^2 - b^2) nb0 nb1 / h``, ``h'' = ((a^2 - b^2) (nb1^2 -
nb0^2) - h'^2) / h`` (``ellipse_support3``; ``h + h'' = a^2 b^2 / h^3 > 0`` is the radius of
curvature at the contact point). The contact point's arm (from the centre of mass) has
normal component ``-h`` and tangential component ``-h'``, so the torque of ``lam n + f t`` is
``h f - h' lam``. There is no material contact point, so the reduced coordinates are
``y = (u, angle, du/dt, w)`` with ``u = t . x`` (the centre's tangential coordinate); the
centre is ``x = u t + (d + h) n``, ``v = (du/dt) t + h' w n`` (the constraint holds exactly),
and the slip of the contact point is ``v_T = du/dt + h w``. Newton-Euler:
``m d2u/dt2 = m g_t + f``, ``m (h'' w^2 + h' dw/dt) = m g_n + lam``, ``I dw/dt = h f - h' lam``:

* **rolling** (sticking, ``v_T = 0``, ``d2u/dt2 = -h dw/dt - h' w^2``): ``dw/dt (I + m (h^2 +
  h'^2)) = -m h' w^2 (h + h'') - m h g_t + m h' g_n``, ``f = m (d2u/dt2 - g_t)``,
  ``lam = m (h'' w^2 + h' dw/dt - g_n)`` (the Lagrangian of rolling without slip:
  ``T = (I + m (h^2 + h'^2)) w^2 / 2``, ``V = -m g_n h - m g_t u``);
* **sliding** along ``sig t``: ``f = -mu sig lam``, ``kap = h' + mu sig h``, ``D = I + m h' kap``,
  ``lam = m I (h'' w^2 - g_n) / D``, ``dw/dt = -kap lam / I``, ``d2u/dt2 = g_t + f / m``;
  ``D / (m I) = W_NN - mu sig W_NT`` and ``D <= 0`` is ``PV_PAINLEVE``.

The events are those of a vertex (lift-off, stick -> slip, slip -> stick or reverse, and
the gap ``n_q . x - d_q - h_q(angle)`` of the ellipse to every other plane q). A rough
ellipse rolling on a level plane rocks for ever (rolling is conservative).

Two contacts (``CP_TWO = 1``: a body held on two planes, a groove or a corner; the second
contact's plane, vertex and friction in ``CP_N2X ... CP_MU2``): each held feature k keeps
``n_k . x = c_k(angle)`` (a vertex: ``c = d + rad - n . R p``, ``c' = -xi``, ``c'' = n . R p``;
the ellipse: ``c = d + h``, ``c' = h'``, ``c'' = h''``; ``_offset``), so with ``N`` the matrix
of the two normals (planes not parallel) the centre is ``x = N^-1 c``, ``v = A1 w`` and ``a =
A1 dw/dt + A0 w^2`` with ``A1 = N^-1 c'``, ``A0 = N^-1 c''`` (``two_geometry``): one degree of
freedom, the angle (the reduced state keeps ``u = t_1 . x`` and ``du/dt``, which follow).
Both contacts slip together, ``v_Tk = k_k w`` with ``k_k = t_k . A1 - eta_ck`` (a disk: its
centre is fixed, ``A1 = 0``, and it spins, ``k = rad``); sticking at both is rest, a static
equilibrium (``wedge2d``), so a moving body slides at both with ``f_k = -mu_k sig_k lam_k``,
``sig_k = sign(k_k w)``. Newton-Euler with the force directions ``e_k = n_k - mu_k sig_k t_k``
and torque arms ``kap_k = xi_k + mu_k sig_k eta_ck`` (``E = [e_1 e_2]``):
``m (A1 dw/dt + A0 w^2) = m g + E lam``, ``I dw/dt = kap . lam``, so
``lam = m E^-1 (A1 dw/dt + A0 w^2 - g)`` and ``D dw/dt = m kap . E^-1 (A0 w^2 - g)`` with
``D = I - m kap . E^-1 A1`` (``two_forces``; without friction ``D = I + m |A1|^2``, the
reduced inertia of the Lagrangian ``T = (I + m |A1|^2) w^2 / 2``). ``D <= 0`` or ``det E = 0``
is ``PV_PAINLEVE``. Events: either ``lam_k`` reaching 0 (that contact leaves: the body
pivots on the other), a slip direction reversing while w does not (``k_k`` through 0:
``sig_k s k_k``, s the sign of w), ``w`` reaching 0 (``PE_TURN``: both slips vanish; the
stepper decides rest or a new direction), and the gaps of the other vertices. Friction
works ``sum_k f_k v_Tk = -sum_k mu_k lam_k |k_k w| <= 0``: never energy created.

The normal force does no work (``v_N = 0``) and the friction force works ``f v_T <= 0``:
the motion never creates energy. Frictionless sliding (``mu = 0``) conserves energy and the
horizontal momentum on a level plane.

Events (functions that must stay positive; the phase ends at the first root, located on
the dense output): ``lam`` reaching 0 (lift-off); a sticking force reaching its friction
cone ``mu lam - |f| = 0`` (slip starts); the slip ``sig v_T`` of a sliding contact reaching
0 (it sticks or reverses; not for ``mu = 0``); the gap of any other vertex to any plane
(and of the held vertex to the other planes) reaching 0 (an impact). A function starting
below its arm (``FORCE_ARM m |g|``, ``SLIP_ARM V``, ``GAP_ARM L``) fires below
``min(0, start) - arm`` instead (a gap: no deeper than ``-GAP_FLOOR L`` when it starts
above that, so the allowance taken anew at each step cannot let a vertex sink step by
step). Each step also samples the events where ``w`` changes
sign (a swing turning back), so a corner that swings onto the plane and back within one
step is seen; otherwise two roots of one function inside one step are not (steps rotate
the body by at most ``MAX_ANGLE``: a stated limitation, as in ``pivot3d``).

Integration: Dormand-Prince RK5(4) (``dopri5``) on ``y`` with its 4th-order dense output,
component scales ``(L, 1, V, V/L)`` (``L`` the body's size, ``V = |v| + |w| L + sqrt(|g| L)``
at the start of the pass) and error tolerance ``PIVOT_TOL``.

Trajectory output: the segment rows of ``stepper2d`` are exact constant-acceleration
motions (``flight2d.sample_segments``), so an integrated phase is recorded as consecutive
*velocity-interpolating* quadratic pieces: each piece starts at the integrated state and
has the constant accelerations ``(v(s + h) - v(s)) / h``, ``(w(s + h) - w(s)) / h`` that make
its velocities agree with the integrated ones at both ends. The piece length ``h`` is
chosen so that, against the integrated solution, the piece's energy deviates by at most
``PIECE_ETOL m V^2``, its points (centre of mass and every point of the body within
``L``) by at most ``PIECE_LTOL L`` and their velocities by at most ``PIECE_VTOL V``; so the
sampled trajectory never creates energy nor penetrates beyond those bounds (leading
errors: energy and velocity ``O(h^2)``, position ``O(h^3)``). A held ellipse uses
``PIECE_ETOL_CURVED`` instead of ``PIECE_ETOL``: its phase has no end (an ellipse rocks for
ever), and a piece's energy deviation, first order in its velocity deviation, is what sets
the piece length.
"""
import math

from numba import njit

from .cache_guard import guard

# flush stale compiled callers before any kernel module below is imported (cache_guard)
guard(__name__, __file__)

from .dopri5 import MAX_TRIES, dense_out, dopri5_step
from .evbuf import CN_SEGS
from .flight2d import body_energy, fly_into

# ---- workspace w (float64[N_W], flat): contact parameters, integrator, scratch ----------
CP_M = 0        # mass (kg)
CP_I = 1        # moment of inertia about the centre of mass (kg m^2)
CP_GN = 2       # gravity along n (m/s^2; < 0: it pushes the body onto the plane)
CP_GT = 3       # gravity along t (m/s^2)
CP_NX = 4       # plane normal n
CP_NY = 5
CP_D = 6        # plane offset d (m)
CP_RAD = 7      # vertex radius (m)
CP_PX = 8       # body-frame vertex p (m)
CP_PY = 9
CP_MU = 10      # friction coefficient
CP_SIG = 11     # 0: sticking; +1 / -1: sliding along +t / -t
CP_L = 12       # body size L (m): largest |p_k| + rad (an ellipse: max(a, b))
CP_V = 13       # velocity scale V (m/s)
CP_KIND = 14    # held feature: KIND_VERTEX (p, rad) or KIND_ELLIPSE (the curve a, b)
CP_EA = 15      # ellipse semi-axes a (body x), b (body y) (m)
CP_EB = 16
# the second held contact of a body held on two planes (CP_TWO = 1; module docstring,
# "Two contacts"): its plane (normal, offset, index), its vertex (body frame, index),
# friction coefficient and slip direction; CP_DIR is the sign s of w
CP_TWO = 17     # 0: one held contact; 1: two (the second below)
CP_N2X = 18
CP_N2Y = 19
CP_D2 = 20
CP_Q2 = 21      # plane index of the second contact
CP_P2X = 22
CP_P2Y = 23
CP_K2 = 24      # vertex index (body-relative) of the second contact
CP_MU2 = 25
CP_SIG2 = 26
CP_DIR = 27     # +1 / -1: the sign of w while the body slides on its two contacts
N_CP = 28
W_TOL = 28      # integrator: tolerance, step, next step, largest step, step start (s)
W_H = 29
W_HNEXT = 30
W_HMAX = 31
W_S0 = 32
W_SC = 36       # 36:40 error scales of (u, angle, du/dt, w)
W_Y = 40        # step start
W_YT = 44       # stage argument
W_Y1 = 48       # step end
W_K = 52        # 52:80 seven stages
W_RC = 80       # 80:100 dense output
W_YA = 100      # scratch states (4 each)
W_YB = 104
W_ROW = 108     # 108:117 a state row (x, y, angle, vx, vy, w, ax, ay, alpha)
W_ROWB = 117    # 117:126 a second one
W_ROWC = 126    # 126:135 a third one
N_W = 135
NY = 4

# ---- tolerances (named, dimensionless unless stated) -------------------------------------
PIVOT_TOL = 1e-12   # RK error tolerance per step, relative to the scales (L, 1, V, V/L)
MAX_ANGLE = 0.05    # rad of rotation (or of sqrt(|g|/L) time) per step at most
PIECE_ETOL = 1e-13  # energy deviation of a recorded piece, relative to m V^2 (the drop
#                    campaign holds energy to 1e-12 of the scene energy: 1e-10 was too loose)
PIECE_ETOL_CURVED = 1e-11  # the same for a held ellipse (KIND_ELLIPSE): it may stay held
#                    for the whole run (rocking for ever), and the pieces needed grow as
#                    PIECE_ETOL^-1/2 (1e-13: 1.7e6 pieces, 150 MB, per second of rocking); the
#                    sampled energy stays within 1e-11 m V^2 (~1e-10 of the scene's energy)
PIECE_LTOL = 1e-10  # point deviation of a recorded piece, relative to L
PIECE_VTOL = 1e-9   # point velocity deviation of a recorded piece, relative to V
PIECE_BUDGET = 512  # recorded pieces per call of pivot_advance at most (buffer margin)
FORCE_ARM = 1e-9    # force events starting below FORCE_ARM m |g| are armed (see above)
SLIP_ARM = 1e-12    # slip event armed below SLIP_ARM V
GAP_ARM = 1e-12     # gap events armed below GAP_ARM L
GAP_FLOOR = 1e-10   # ... but a gap event whose step starts above -GAP_FLOOR L fires there at
                    # the latest: the arm's allowance is taken anew at every step (and every
                    # pass), so a vertex touching at a step start could otherwise sink by up
                    # to GAP_ARM L per step; a pivot bounded by a partner crawling in
                    # passes of one step each let a corner sink 1.8e-8 m (a three-box drop)
EVENT_ITER = 200    # secant/bisection iterations locating an event on the dense output
MAX_ATTEMPTS = 200_000  # RK step attempts per call at most (PI_TOO_MANY_STEPS)
PIECE_ITER = 60     # shrinks of one piece at most (then it is accepted as is)

# held features (w[CP_KIND])
KIND_VERTEX = 0     # a vertex p (body frame) with radius rad
KIND_ELLIPSE = 1    # the boundary of the ellipse (a, b) centred on the centre of mass

# force codes
PV_OK = 0
PV_PAINLEVE = 1     # sliding with D = I + m xi kap <= 0

# integrator codes
PI_OK = 0
PI_TOO_MANY_STEPS = 1
PI_FORCES = 2       # Painleve during the integration

# event kinds (returned by pivot_advance)
PE_NONE = 0         # the call ended (piece budget or end of window) without an event
PE_LIFT = 1         # lam reaches 0
PE_SLIP = 2         # a sticking force reaches the friction cone
PE_STOP = 3         # a sliding contact's slip reaches 0
PE_GAP = 4          # another vertex reaches a plane (index: plane * nv + vertex)
PE_TURN = 5         # two contacts: w reaches 0 (both slips vanish together)

# event functions (``_event``): the force and slip events, then one gap per (plane, vertex)
EF_LAM = 0          # lam of the (first) held contact
EF_SLIP = 1         # its stick margin, or its slip (two contacts: its slip direction)
EF_LAM2 = 2         # two contacts: lam of the second
EF_SLIP2 = 3        # two contacts: the slip direction of the second
EF_TURN = 4         # two contacts: s w
N_EF = 5            # gap events are N_EF + plane * nv + vertex


# ------------------------------------------------------------------ state and forces


@njit(cache=True, _nrt=False, inline="always")
def _arm(w, th):
    """r = R(th) p (m) and its components xi = t . r, eta = n . r."""
    c = math.cos(th)
    s = math.sin(th)
    px = w[CP_PX]
    py = w[CP_PY]
    rx = c * px - s * py
    ry = s * px + c * py
    nx = w[CP_NX]
    ny = w[CP_NY]
    return rx, ry, ny * rx - nx * ry, nx * rx + ny * ry


@njit(cache=True, _nrt=False, inline="always")
def ellipse_support3(ea, eb, th, nx, ny):
    """Support of the ellipse (semi-axes ea, eb on the body axes, body angle th) along
    ``-n``: the height ``h`` (m) of its centre above its tangent line with normal n, and
    ``h' = dh/dth`` (m/rad), ``h'' = d2h/dth2`` (m/rad^2). With the body-frame normal
    ``nb = (c n_x + s n_y, -s n_x + c n_y)`` (``dnb0/dth = nb1``, ``dnb1/dth = -nb0``):
    ``h^2 = a^2 nb0^2 + b^2 nb1^2``, ``h h' = (a^2 - b^2) nb0 nb1``,
    ``h h'' + h'^2 = (a^2 - b^2) (nb1^2 - nb0^2)``."""
    c = math.cos(th)
    s = math.sin(th)
    n0 = c * nx + s * ny
    n1 = -s * nx + c * ny
    a2 = ea * ea
    b2 = eb * eb
    h = math.sqrt(a2 * n0 * n0 + b2 * n1 * n1)
    h1 = (a2 - b2) * n0 * n1 / h
    h2 = ((a2 - b2) * (n1 * n1 - n0 * n0) - h1 * h1) / h
    return h, h1, h2


@njit(cache=True, _nrt=False)
def _ellipse_forces(w, y1, y3):
    """``pivot_forces`` for the held ellipse (module docstring, "Ellipse")."""
    m = w[CP_M]
    inertia = w[CP_I]
    gn = w[CP_GN]
    gt = w[CP_GT]
    sig = w[CP_SIG]
    h, h1, h2 = ellipse_support3(w[CP_EA], w[CP_EB], y1, w[CP_NX], w[CP_NY])
    om2 = y3 * y3
    if sig == 0.0:
        wd = m * (h1 * gn - h * gt - h1 * om2 * (h + h2)) / (inertia + m * (h * h + h1 * h1))
        lam = m * (h2 * om2 + h1 * wd - gn)
        ud = -h * wd - h1 * om2
        f = m * (ud - gt)
        return PV_OK, lam, f, ud, wd
    mu = w[CP_MU]
    kap = h1 + mu * sig * h
    D = inertia + m * h1 * kap
    if not D > 0.0:
        return PV_PAINLEVE, 0.0, 0.0, 0.0, 0.0
    lam = m * inertia * (h2 * om2 - gn) / D
    wd = -kap * lam / inertia
    f = -mu * sig * lam
    return PV_OK, lam, f, gt + f / m, wd


@njit(cache=True, _nrt=False)
def pivot_forces(w, y0, y1, y2, y3):
    """Contact force and accelerations at the reduced state (u, angle, du/dt, w).
    Returns (code, lam (N), f (N), d2u/dt2 (m/s^2), dw/dt (rad/s^2)); see the module
    docstring for the equations."""
    if w[CP_TWO] != 0.0:
        code, lam1, lam2, wd, ax, ay = two_forces(w, y1, y3)
        return code, lam1, -w[CP_MU] * w[CP_SIG] * lam1, w[CP_NY] * ax - w[CP_NX] * ay, wd
    if w[CP_KIND] == KIND_ELLIPSE:
        return _ellipse_forces(w, y1, y3)
    m = w[CP_M]
    inertia = w[CP_I]
    gn = w[CP_GN]
    gt = w[CP_GT]
    rad = w[CP_RAD]
    sig = w[CP_SIG]
    rx, ry, xi, eta = _arm(w, y1)
    etac = eta - rad
    om2 = y3 * y3
    if sig == 0.0:
        wd = m * (om2 * xi * rad - xi * gn + etac * gt) / (inertia + m * (xi * xi + etac * etac))
        lam = m * (om2 * eta - gn - xi * wd)
        f = m * (etac * wd + om2 * xi - gt)
        return PV_OK, lam, f, -rad * wd, wd
    mu = w[CP_MU]
    kap = xi + mu * sig * etac
    D = inertia + m * xi * kap
    if not D > 0.0:
        return PV_PAINLEVE, 0.0, 0.0, 0.0, 0.0
    lam = m * inertia * (om2 * eta - gn) / D
    wd = kap * lam / inertia
    f = -mu * sig * lam
    return PV_OK, lam, f, gt + f / m - eta * wd - om2 * xi, wd


@njit(cache=True, _nrt=False)
def pivot_row(w, y0, y1, y2, y3, row):
    """Full state row ``(x, y, angle, vx, vy, w, ax, ay, alpha)`` of the reduced state into
    ``row`` (the accelerations are the contact motion's own). Returns the force code."""
    nx = w[CP_NX]
    ny = w[CP_NY]
    tx = ny
    ty = -nx
    if w[CP_TWO] != 0.0:
        # the angle and w determine the motion (y0, y2 follow: u = t . x)
        code, lam1, lam2, wd, ax, ay = two_forces(w, y1, y3)
        x, y, a1x, a1y, a0x, a0y, xi1, ec1, xi2, ec2, k1, k2 = two_geometry(w, y1)
        row[0] = x
        row[1] = y
        row[2] = y1
        row[3] = a1x * y3
        row[4] = a1y * y3
        row[5] = y3
        row[6] = ax
        row[7] = ay
        row[8] = wd
        return code
    if w[CP_KIND] == KIND_ELLIPSE:
        # centre at u t + (d + h) n, velocity (du/dt) t + h' w n
        h, h1, h2 = ellipse_support3(w[CP_EA], w[CP_EB], y1, nx, ny)
        z = w[CP_D] + h
        row[0] = y0 * tx + z * nx
        row[1] = y0 * ty + z * ny
        row[2] = y1
        row[3] = y2 * tx + h1 * y3 * nx
        row[4] = y2 * ty + h1 * y3 * ny
        row[5] = y3
        code, lam, f, ud, wd = pivot_forces(w, y0, y1, y2, y3)
        an = h2 * y3 * y3 + h1 * wd
        row[6] = ud * tx + an * nx
        row[7] = ud * ty + an * ny
        row[8] = wd
        return code
    rx, ry, xi, eta = _arm(w, y1)
    h = w[CP_D] + w[CP_RAD]
    row[0] = y0 * tx + h * nx - rx
    row[1] = y0 * ty + h * ny - ry
    row[2] = y1
    row[3] = y2 * tx + y3 * ry
    row[4] = y2 * ty - y3 * rx
    row[5] = y3
    code, lam, f, ud, wd = pivot_forces(w, y0, y1, y2, y3)
    om2 = y3 * y3
    row[6] = ud * tx + wd * ry + om2 * rx
    row[7] = ud * ty - wd * rx + om2 * ry
    row[8] = wd
    return code


@njit(cache=True, _nrt=False)
def pivot_reduce(w, row, out):
    """Reduced state (u, angle, du/dt, w) of a full state row (vertex on the plane)."""
    nx = w[CP_NX]
    ny = w[CP_NY]
    if w[CP_KIND] == KIND_ELLIPSE or w[CP_TWO] != 0.0:
        out[0] = ny * row[0] - nx * row[1]
        out[1] = row[2]
        out[2] = ny * row[3] - nx * row[4]
        out[3] = row[5]
        return
    rx, ry, xi, eta = _arm(w, row[2])
    out[0] = ny * (row[0] + rx) - nx * (row[1] + ry)
    out[1] = row[2]
    out[2] = ny * (row[3] - row[5] * ry) - nx * (row[4] + row[5] * rx)
    out[3] = row[5]


@njit(cache=True, _nrt=False, inline="always")
def _energy_row(w, row):
    """Kinetic plus gravitational energy (J) of a state row (``flight2d.body_energy``)."""
    nx = w[CP_NX]
    ny = w[CP_NY]
    return body_energy(row, w[CP_M], w[CP_I], w[CP_GN] * nx + w[CP_GT] * ny,
                       w[CP_GN] * ny - w[CP_GT] * nx)


@njit(cache=True, _nrt=False)
def slip_velocity(w, row):
    """Slip velocity v_T (m/s) of the held contact point of a state row."""
    if w[CP_KIND] == KIND_ELLIPSE:
        h, h1, h2 = ellipse_support3(w[CP_EA], w[CP_EB], row[2], w[CP_NX], w[CP_NY])
        return w[CP_NY] * row[3] - w[CP_NX] * row[4] + h * row[5]
    rx, ry, xi, eta = _arm(w, row[2])
    rad = w[CP_RAD]
    cx = rx - rad * w[CP_NX]
    cy = ry - rad * w[CP_NY]
    return w[CP_NY] * (row[3] - row[5] * cy) - w[CP_NX] * (row[4] + row[5] * cx)


@njit(cache=True, _nrt=False)
def pivot_slip_rate(w, y1, y3, ud, wd):
    """Rate of change (m/s^2) of the slip v_T of the held contact point at the reduced
    state (angle y1, w y3) with accelerations (ud, wd) (``pivot_forces``): a vertex
    ``ud + rad wd``, the ellipse ``ud + h wd + h' w^2``."""
    if w[CP_KIND] == KIND_ELLIPSE:
        h, h1, h2 = ellipse_support3(w[CP_EA], w[CP_EB], y1, w[CP_NX], w[CP_NY])
        return ud + h * wd + h1 * y3 * y3
    return ud + wd * w[CP_RAD]


# ------------------------------------------------------------------ two contacts


@njit(cache=True, _nrt=False, inline="always")
def _offset(w, th, nx, ny, d, px, py):
    """A held feature's constraint ``n . x = c(angle)`` on the plane (n, d): returns
    ``(c, dc/dangle, d2c/dangle2, xi, eta_c)`` with the contact point's arm (from the centre
    of mass) ``xi t + eta_c n``. A vertex p with radius rad: ``c = d + rad - n . R p``,
    ``c' = -xi``, ``c'' = n . R p``, ``eta_c = n . R p - rad``; the ellipse: ``c = d + h``,
    ``c' = h'``, ``c'' = h''``, arm ``(-h', -h)`` (``ellipse_support3``)."""
    if w[CP_KIND] == KIND_ELLIPSE:
        h, h1, h2 = ellipse_support3(w[CP_EA], w[CP_EB], th, nx, ny)
        return d + h, h1, h2, -h1, -h
    c = math.cos(th)
    s = math.sin(th)
    rx = c * px - s * py
    ry = s * px + c * py
    xi = ny * rx - nx * ry
    eta = nx * rx + ny * ry
    return d + w[CP_RAD] - eta, -xi, eta, xi, eta - w[CP_RAD]


@njit(cache=True, _nrt=False)
def two_geometry(w, th):
    """Kinematics of a body held on two planes at the angle th (module docstring, "Two
    contacts"): the centre ``x = N^-1 c`` (m), its velocity per unit w ``A1 = N^-1 c'``
    (m/rad) and acceleration term ``A0 = N^-1 c''`` (``a = A1 dw/dt + A0 w^2``), both
    contacts' arms ``(xi_k, eta_ck)`` and slips per unit w ``k_k = t_k . A1 - eta_ck`` (m).
    Returns ``(x, y, a1x, a1y, a0x, a0y, xi1, ec1, xi2, ec2, k1, k2)``."""
    n1x = w[CP_NX]
    n1y = w[CP_NY]
    n2x = w[CP_N2X]
    n2y = w[CP_N2Y]
    c1, d1, dd1, xi1, ec1 = _offset(w, th, n1x, n1y, w[CP_D], w[CP_PX], w[CP_PY])
    c2, d2, dd2, xi2, ec2 = _offset(w, th, n2x, n2y, w[CP_D2], w[CP_P2X], w[CP_P2Y])
    det = n1x * n2y - n1y * n2x
    x = (n2y * c1 - n1y * c2) / det
    y = (n1x * c2 - n2x * c1) / det
    a1x = (n2y * d1 - n1y * d2) / det
    a1y = (n1x * d2 - n2x * d1) / det
    a0x = (n2y * dd1 - n1y * dd2) / det
    a0y = (n1x * dd2 - n2x * dd1) / det
    k1 = n1y * a1x - n1x * a1y - ec1
    k2 = n2y * a1x - n2x * a1y - ec2
    return x, y, a1x, a1y, a0x, a0y, xi1, ec1, xi2, ec2, k1, k2


@njit(cache=True, _nrt=False)
def two_forces(w, th, om):
    """Normal forces and accelerations of a body sliding on two planes at (angle th, w om):
    ``(code, lam1 (N), lam2 (N), dw/dt (rad/s^2), ax, ay (m/s^2))``; ``PV_PAINLEVE`` when
    the sliding system has no unique solution (``D <= 0`` or the force directions
    parallel). Equations in the module docstring ("Two contacts")."""
    x, y, a1x, a1y, a0x, a0y, xi1, ec1, xi2, ec2, k1, k2 = two_geometry(w, th)
    m = w[CP_M]
    inertia = w[CP_I]
    n1x = w[CP_NX]
    n1y = w[CP_NY]
    n2x = w[CP_N2X]
    n2y = w[CP_N2Y]
    gx = w[CP_GN] * n1x + w[CP_GT] * n1y
    gy = w[CP_GN] * n1y - w[CP_GT] * n1x
    s1 = w[CP_MU] * w[CP_SIG]
    s2 = w[CP_MU2] * w[CP_SIG2]
    # force directions e_k = n_k - mu_k sig_k t_k (t = (n_y, -n_x)), torque arms kap_k
    e1x = n1x - s1 * n1y
    e1y = n1y + s1 * n1x
    e2x = n2x - s2 * n2y
    e2y = n2y + s2 * n2x
    kap1 = xi1 + s1 * ec1
    kap2 = xi2 + s2 * ec2
    dete = e1x * e2y - e1y * e2x
    if dete == 0.0:
        return PV_PAINLEVE, 0.0, 0.0, 0.0, 0.0, 0.0
    om2 = om * om
    bx = a0x * om2 - gx
    by = a0y * om2 - gy
    ka1 = kap1 * (e2y * a1x - e2x * a1y) + kap2 * (e1x * a1y - e1y * a1x)
    kb = kap1 * (e2y * bx - e2x * by) + kap2 * (e1x * by - e1y * bx)
    D = inertia - m * ka1 / dete
    if not D > 0.0:
        return PV_PAINLEVE, 0.0, 0.0, 0.0, 0.0, 0.0
    wd = m * kb / dete / D
    rx = a1x * wd + bx
    ry = a1y * wd + by
    lam1 = m * (e2y * rx - e2x * ry) / dete
    lam2 = m * (e1x * ry - e1y * rx) / dete
    return PV_OK, lam1, lam2, wd, a1x * wd + a0x * om2, a1y * wd + a0y * om2


@njit(cache=True, _nrt=False)
def two_slip_signs(w, th):
    """Set the slip directions of a body sliding on two planes with w of sign ``w[CP_DIR]``
    at the angle th: ``sig_k = sign(k_k s)`` (a contact at the instantaneous centre, k_k =
    0, takes +s; its reversal event fires at once if that is wrong)."""
    x, y, a1x, a1y, a0x, a0y, xi1, ec1, xi2, ec2, k1, k2 = two_geometry(w, th)
    s = w[CP_DIR]
    w[CP_SIG] = 1.0 if k1 * s >= 0.0 else -1.0
    w[CP_SIG2] = 1.0 if k2 * s >= 0.0 else -1.0


# ------------------------------------------------------------------ integrator


@njit(cache=True, _nrt=False, inline="always")
def _rhs(w, yo, ko):
    """dy/ds at w[yo:yo+4] into w[ko:ko+4]; returns the force code."""
    code, lam, f, ud, wd = pivot_forces(w, w[yo], w[yo + 1], w[yo + 2], w[yo + 3])
    w[ko] = w[yo + 2]
    w[ko + 1] = w[yo + 3]
    w[ko + 2] = ud
    w[ko + 3] = wd
    return code


@njit(cache=True, _nrt=False)
def _stage(w, yo, ko):
    """The right-hand side of ``dopri5_step``: ``_rhs``, PI_OK or PI_FORCES."""
    return PI_OK if _rhs(w, yo, ko) == PV_OK else PI_FORCES


@njit(cache=True, _nrt=False)
def _step(w, h):
    """One error-controlled step from w[W_Y] with first trial h (stage 1 already at
    w[W_K]). Returns (code, number of attempts); the accepted step is w[W_H]."""
    return dopri5_step(_stage, (), w, NY, W_Y, W_YT, W_Y1, W_K, W_RC, W_SC, W_H, W_HNEXT,
                       w[W_TOL], h, MAX_TRIES, True, 0.0, 0.0, PI_TOO_MANY_STEPS)


@njit(cache=True, _nrt=False, inline="always")
def _dense(w, s, yo):
    """Dense output at s (within the current step) into w[yo:yo+4]."""
    dense_out(w, NY, W_RC, W_S0, W_H, s, w, yo)


# ------------------------------------------------------------------ events


@njit(cache=True, _nrt=False)
def _event(w, yo, e, verts, v0, nv, planes, p0, k0):
    """Value of event function e at the reduced state w[yo:yo+4] (inf where it does not
    apply): ``EF_LAM`` lam (N); ``EF_SLIP`` the stick margin mu lam - |f| (N) or the slip
    sig v_T (m/s; inf for mu = 0); with two contacts ``EF_SLIP`` and ``EF_SLIP2`` the slip
    directions ``sig_k s k_k`` (m), ``EF_LAM2`` the second lam (N), ``EF_TURN`` ``s w``
    (rad/s); ``e >= N_EF`` the gap (m) of vertex (e - N_EF) % nv to plane
    (e - N_EF) // nv (inf for a held vertex on its plane)."""
    y0 = w[yo]
    y1 = w[yo + 1]
    y2 = w[yo + 2]
    y3 = w[yo + 3]
    two = w[CP_TWO] != 0.0
    if e < N_EF:
        if two:
            if e == EF_TURN:
                return w[CP_DIR] * y3
            if e == EF_LAM or e == EF_LAM2:
                code, lam1, lam2, wd, ax, ay = two_forces(w, y1, y3)
                return lam1 if e == EF_LAM else lam2
            mu = w[CP_MU] if e == EF_SLIP else w[CP_MU2]
            if mu == 0.0:
                return math.inf
            x, y, a1x, a1y, a0x, a0y, xi1, ec1, xi2, ec2, k1, k2 = two_geometry(w, y1)
            if e == EF_SLIP:
                return w[CP_SIG] * w[CP_DIR] * k1
            return w[CP_SIG2] * w[CP_DIR] * k2
        if e > EF_SLIP:
            return math.inf
        code, lam, f, ud, wd = pivot_forces(w, y0, y1, y2, y3)
        if e == EF_LAM:
            return lam
        if w[CP_SIG] == 0.0:
            return w[CP_MU] * lam - abs(f)
        if w[CP_MU] == 0.0:
            return math.inf
        if w[CP_KIND] == KIND_ELLIPSE:
            h, h1, h2 = ellipse_support3(w[CP_EA], w[CP_EB], y1, w[CP_NX], w[CP_NY])
            return w[CP_SIG] * (y2 + y3 * h)
        return w[CP_SIG] * (y2 + y3 * w[CP_RAD])
    q = (e - N_EF) // nv
    k = (e - N_EF) % nv
    if q == p0 and k == k0:
        return math.inf
    if two and q == int(w[CP_Q2]) and k == int(w[CP_K2]):
        return math.inf
    nx = w[CP_NX]
    ny = w[CP_NY]
    if two:
        x, yy, a1x, a1y, a0x, a0y, xi1, ec1, xi2, ec2, k1, k2 = two_geometry(w, y1)
    elif w[CP_KIND] == KIND_ELLIPSE:
        h, h1, h2 = ellipse_support3(w[CP_EA], w[CP_EB], y1, nx, ny)
        z = w[CP_D] + h
        x = y0 * ny + z * nx
        yy = -y0 * nx + z * ny
    else:
        rx, ry, xi, eta = _arm(w, y1)
        h = w[CP_D] + w[CP_RAD]
        x = y0 * ny + h * nx - rx
        yy = -y0 * nx + h * ny - ry
    if w[CP_KIND] == KIND_ELLIPSE:
        # the ellipse's gap to plane q: n_q . x - d_q - h_q(angle)
        hq, hq1, hq2 = ellipse_support3(w[CP_EA], w[CP_EB], y1, planes[q, 0], planes[q, 1])
        return planes[q, 0] * x + planes[q, 1] * yy - planes[q, 2] - hq
    c = math.cos(y1)
    s = math.sin(y1)
    px = verts[v0 + k, 0]
    py = verts[v0 + k, 1]
    return (planes[q, 0] * (x + c * px - s * py) + planes[q, 1] * (yy + s * px + c * py)
            - planes[q, 2] - w[CP_RAD])


@njit(cache=True, _nrt=False, inline="always")
def _floor(w, e, v):
    """Firing level of event e for a step starting at value v (see the module docstring)."""
    L = w[CP_L]
    gap = False
    if e == EF_LAM or e == EF_LAM2:
        arm = FORCE_ARM * w[CP_M] * math.hypot(w[CP_GN], w[CP_GT])
    elif e == EF_TURN:
        arm = SLIP_ARM * w[CP_V] / L
    elif e == EF_SLIP2 or (e == EF_SLIP and w[CP_TWO] != 0.0):
        arm = SLIP_ARM * L
    elif e == EF_SLIP:
        if w[CP_SIG] == 0.0:
            arm = FORCE_ARM * w[CP_M] * math.hypot(w[CP_GN], w[CP_GT])
        else:
            arm = SLIP_ARM * w[CP_V]
    else:
        arm = GAP_ARM * L
        gap = True
    if v > arm:
        return 0.0
    fl = min(0.0, v) - arm
    if gap and v > -GAP_FLOOR * L:
        return max(fl, -GAP_FLOOR * L)     # a gap starting above -GAP_FLOOR L
    return fl


@njit(cache=True, _nrt=False)
def _locate(w, e, fl, sa, sb, verts, v0, nv, planes, p0, k0, t0, rtol, atol):
    """First root of event e (minus its floor fl) in (sa, sb] on the dense output, with
    value > 0 at sa and <= 0 at sb. Returns the time on the <= 0 side for a force or slip
    event (the new mode is consistent there), on the > 0 side for a gap (as the flight
    search: the impact is taken with the vertex not yet through the plane)."""
    w0 = W_YA
    _dense(w, sa, w0)
    fa = _event(w, w0, e, verts, v0, nv, planes, p0, k0) - fl
    _dense(w, sb, w0)
    fb = _event(w, w0, e, verts, v0, nv, planes, p0, k0) - fl
    for it in range(EVENT_ITER):
        if sb - sa <= atol + rtol * abs(t0 + sb):
            break
        sm = sb - fb * (sb - sa) / (fb - fa) if fb != fa else 0.5 * (sa + sb)
        if not (sa < sm < sb) or it % 3 == 2:
            sm = 0.5 * (sa + sb)
        _dense(w, sm, w0)
        fm = _event(w, w0, e, verts, v0, nv, planes, p0, k0) - fl
        if fm > 0.0:
            sa = sm
            fa = fm
        else:
            sb = sm
            fb = fm
    return sa if e >= N_EF else sb


@njit(cache=True, _nrt=False)
def _first_event(w, sa, sb, ne, verts, v0, nv, planes, off, p0, k0, t0, rtol, atol):
    """Earliest event in the step part (sa, sb]: samples at sb and, when w changes sign,
    at the turning point. Returns (s, e) with e = -1 when none fires."""
    best = math.inf
    be = -1
    # sample points: the turning point of the swing (if any) and the end
    _dense(w, sa, W_YA)
    wa = w[W_YA + 3]
    _dense(w, sb, W_YA)
    wb = w[W_YA + 3]
    sm = sb
    if wa * wb < 0.0:
        lo = sa
        hi = sb
        for it in range(EVENT_ITER):
            if hi - lo <= atol + rtol * abs(t0 + hi):
                break
            mid = 0.5 * (lo + hi)
            _dense(w, mid, W_YA)
            if (w[W_YA + 3] > 0.0) == (wa > 0.0):
                lo = mid
            else:
                hi = mid
        sm = hi
    for e in range(ne):
        if e >= N_EF and off[(e - N_EF) // nv] != 0:
            continue
        _dense(w, sa, W_YB)
        v = _event(w, W_YB, e, verts, v0, nv, planes, p0, k0)
        if v == math.inf:
            continue
        fl = _floor(w, e, v)
        for smp in range(2):
            sx = sm if smp == 0 else sb
            if smp == 0 and sm == sb:
                continue
            _dense(w, sx, W_YB)
            if _event(w, W_YB, e, verts, v0, nv, planes, p0, k0) - fl <= 0.0:
                r = _locate(w, e, fl, sa, sx, verts, v0, nv, planes, p0, k0, t0, rtol, atol)
                if r < best:
                    best = r
                    be = e
                break
    return best, be


# ------------------------------------------------------------------ recorded pieces


@njit(cache=True, _nrt=False)
def _piece_dev(w, sa, h):
    """Deviation of the velocity-interpolating piece from the integrated solution over
    [sa, sa + h]: (energy deviation / (PIECE_ETOL m V^2; PIECE_ETOL_CURVED for an
    ellipse), max(point deviation /
    (PIECE_LTOL L), point velocity deviation / (PIECE_VTOL V))), the larger of the values
    at h/2 and h. The piece row (start state and accelerations) is left in w[W_ROW]."""
    row = w[W_ROW:W_ROW + 9]
    rb = w[W_ROWB:W_ROWB + 9]
    rc = w[W_ROWC:W_ROWC + 9]
    _dense(w, sa, W_YA)
    pivot_row(w, w[W_YA], w[W_YA + 1], w[W_YA + 2], w[W_YA + 3], row)
    _dense(w, sa + h, W_YA)
    pivot_row(w, w[W_YA], w[W_YA + 1], w[W_YA + 2], w[W_YA + 3], rb)
    for j in range(3):
        row[6 + j] = (rb[3 + j] - row[3 + j]) / h
    L = w[CP_L]
    if w[CP_KIND] == KIND_ELLIPSE:
        etol = PIECE_ETOL_CURVED * w[CP_M] * w[CP_V] * w[CP_V]
    else:
        etol = PIECE_ETOL * w[CP_M] * w[CP_V] * w[CP_V]
    ltol = PIECE_LTOL * L
    vtol = PIECE_VTOL * w[CP_V]
    de = 0.0
    dp = 0.0
    for smp in range(2):
        # the end (rb already holds the integrated state there), then the midpoint
        s = h if smp == 0 else 0.5 * h
        if smp == 1:
            _dense(w, sa + s, W_YA)
            pivot_row(w, w[W_YA], w[W_YA + 1], w[W_YA + 2], w[W_YA + 3], rb)
        fly_into(row, s, rc)                 # the piece at s
        de = max(de, abs(_energy_row(w, rc) - _energy_row(w, rb)) / etol)
        dp = max(dp, (math.hypot(rc[0] - rb[0], rc[1] - rb[1]) + L * abs(rc[2] - rb[2])) / ltol,
                 (math.hypot(rc[3] - rb[3], rc[4] - rb[4]) + L * abs(rc[5] - rb[5])) / vtol)
    return de, dp


@njit(cache=True, _nrt=False)
def _emit(w, sa, sb, hp, budget, t0, seg_t, seg_b, seg_s, cnt, ib):
    """Record [sa, sb] (within the current step) as pieces; at most ``budget`` rows.
    Returns (s reached, next piece length guess, rows written)."""
    s = sa
    n = 0
    while s < sb and n < budget:
        h = min(hp, sb - s)
        last = h == sb - s
        for it in range(PIECE_ITER):
            de, dp = _piece_dev(w, s, h)
            r = max(de, dp)
            if r <= 1.0:
                break
            # energy deviation ~ h^2, point deviation ~ h^3
            h = h * max(0.1, 0.8 / math.sqrt(r))
            last = False
        k = cnt[CN_SEGS]
        seg_t[k] = t0 + s
        seg_b[k] = ib
        for j in range(9):
            seg_s[k, j] = w[W_ROW + j]
        cnt[CN_SEGS] = k + 1
        n += 1
        if r < 0.25:
            hp = h * min(2.0, 0.9 / math.sqrt(max(r, 1e-6)))
        else:
            hp = h
        s = sb if last else s + h
    return s, hp, n


# ------------------------------------------------------------------ one call


@njit(cache=True, _nrt=False)
def pivot_advance(w, row, verts, v0, nv, planes, off, p0, k0, t0, S, rtol, atol, seg_t,
                  seg_b, seg_s, cnt, ib):
    """Integrate the held contact (parameters in ``w[:N_CP]``) from the state ``row``
    (float64[9], at ``t0``; its vertex ``k0`` on plane ``p0``) until the first event, the
    end of the window ``S`` (s) or ``PIECE_BUDGET`` recorded pieces, whichever comes
    first, recording the motion from ``t0`` as segment rows of body ``ib``. ``off[q]``: plane
    q disabled. On return ``row`` holds the state at ``t0 + s``. Returns
    ``(s, kind, index, code)``: kind ``PE_*`` (index: the plane * nv + vertex of a gap),
    code ``PI_*``."""
    L = w[CP_L]
    gl = math.hypot(w[CP_GN], w[CP_GT])
    vv = math.hypot(row[3], row[4])
    V = vv + abs(row[5]) * L + math.sqrt(gl * L)
    w[CP_V] = V
    w[W_TOL] = PIVOT_TOL
    w[W_SC] = L
    w[W_SC + 1] = 1.0
    w[W_SC + 2] = V
    w[W_SC + 3] = V / L
    hmax = MAX_ANGLE * L / V
    w[W_HMAX] = hmax
    h = min(hmax, hmax * PIVOT_TOL ** 0.2 * 10.0)
    pivot_reduce(w, row, w[W_Y:W_Y + NY])
    w[W_S0] = 0.0
    if w[CP_TWO] != 0.0:
        two_slip_signs(w, row[2])
    ne = N_EF + planes.shape[0] * nv
    if _rhs(w, W_Y, W_K) != PV_OK:
        return 0.0, PE_NONE, 0, PI_FORCES
    hp = math.inf
    rows = 0
    att = 0
    while True:
        # cap the rotation of the step at MAX_ANGLE at its starting angular speed
        om = abs(w[W_Y + 3])
        hcap = hmax
        if om * hcap > MAX_ANGLE:
            hcap = MAX_ANGLE / om
        h = min(h, hcap, S - w[W_S0])
        if not h > 0.0:
            h = S - w[W_S0]
        code, a = _step(w, h)
        att += a
        if code != PI_OK:
            return w[W_S0], PE_NONE, 0, code
        if att > MAX_ATTEMPTS:
            return w[W_S0], PE_NONE, 0, PI_TOO_MANY_STEPS
        s0 = w[W_S0]
        s1 = s0 + w[W_H]
        if s1 > S:
            s1 = S
        se, e = _first_event(w, s0, s1, ne, verts, v0, nv, planes, off, p0, k0, t0, rtol,
                             atol)
        send = se if e >= 0 else s1
        if hp == math.inf:
            hp = w[W_H]
        sr, hp, n = _emit(w, s0, send, hp, PIECE_BUDGET - rows, t0, seg_t, seg_b, seg_s,
                          cnt, ib)
        rows += n
        if sr < send:
            # piece budget used up inside the step: end the call there (the next call
            # restarts the integration from this state)
            _dense(w, sr, W_YA)
            pivot_row(w, w[W_YA], w[W_YA + 1], w[W_YA + 2], w[W_YA + 3], row)
            return sr, PE_NONE, 0, PI_OK
        if e >= 0 or send >= S:
            _dense(w, send, W_YA)
            pivot_row(w, w[W_YA], w[W_YA + 1], w[W_YA + 2], w[W_YA + 3], row)
            if e < 0:
                return send, PE_NONE, 0, PI_OK
            if e == EF_LAM or e == EF_LAM2:
                return send, PE_LIFT, (0 if e == EF_LAM else 1), PI_OK
            if e == EF_SLIP:
                return send, (PE_SLIP if w[CP_SIG] == 0.0 else PE_STOP), 0, PI_OK
            if e == EF_SLIP2:
                return send, PE_STOP, 1, PI_OK
            if e == EF_TURN:
                return send, PE_TURN, 0, PI_OK
            return send, PE_GAP, e - N_EF, PI_OK
        if rows >= PIECE_BUDGET:
            for j in range(NY):
                w[W_YA + j] = w[W_Y1 + j]
            pivot_row(w, w[W_YA], w[W_YA + 1], w[W_YA + 2], w[W_YA + 3], row)
            return s1, PE_NONE, 0, PI_OK
        # next step: from the step end (FSAL: its derivative is stage 7)
        for j in range(NY):
            w[W_Y + j] = w[W_Y1 + j]
            w[W_K + j] = w[W_K + 24 + j]
        w[W_S0] = s1
        h = w[W_HNEXT]
