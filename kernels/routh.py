"""Routh's law: integration of the impact in normal-impulse space, with Coulomb friction.

Sources: Routh, *Dynamics of a System of Rigid Bodies* (1897), the impulse-space picture;
Stronge, J. Appl. Mech. 58:1049 (1991), energetic termination; Wang & Mason (1992), the
planar case as straight segments in impulse space; Mirtich's thesis (1996) and Baber's
correction, Bhatt & Koechling (1995), the 3D sliding ODE, sticking and invariant rays.

Conventions (DESIGN §3): normal first, ``v = (v_N, v_T[, v_T2])`` (m/s), ``P`` (N s) is
the impulse on A, ``W`` (1/kg) the SPD contact-space inverse mass, ``v(p) = v0 + W P(p)``,
``a = W_NN``, ``w = W_TN``, ``C = W_TT``. The independent variable is ``p = P_N`` (N s).

* Sliding with unit direction ``u = v_T/|v_T|``: ``dP_T/dp = -mu u``, ``dv/dp = W (1, -mu u)``:
  ``dv_T/dp = w - mu C u`` and the normal slope ``dv_N/dp = a - mu w.u``.
* ``v_T = 0``: sticking is stable iff ``|C^-1 w| <= mu`` (2D ``|W_TN| <= mu W_TT``); then
  ``dP_T/dp = -C^-1 w`` and ``dv_N/dp = kappa = 1/(W^-1)_NN > 0``. Otherwise slip resumes on
  the diverging invariant ray ``w - mu C u = lambda u``, ``lambda > 0``, i.e.
  ``u = (lambda I + mu C)^-1 w`` with ``|u| = 1``: it exists iff sticking is unstable and
  is then unique (``|(lambda I + mu C)^-1 w|`` decreases strictly for lambda >= 0). 2D:
  ``u = sign(W_TN)``, a reversal when a slip has just stopped.
* Compression ends at ``v_N = 0`` (impulse ``p_c``, normal work ``W_c = int_0^pc v_N dp``).
  Termination: poisson ``p_f = (1+e) p_c``; energetic (Stronge)
  ``int_0^pf v_N dp = (1-e^2) W_c``; newton ``v_N(p_f) = -e v_N(0)``.

Touching contacts (``v_N = 0``): the law gives an impact only while the contact slides
with a negative normal slope ``a - mu w.u < 0``: v_N would become negative at once, the
Painleve configuration in which sliding has no consistent contact force. Integrating from
``v_N = 0`` is then the impact without collision (tangential impact) of Genot & Brogliato
(Eur. J. Mech. A 18, 1999) and Or & Rubin (2012): compression until the slip stops or
turns to a positive slope, restitution as for any impact. Otherwise ``MODE_SEPARATING``.

Failure modes (``P_out`` zeroed):
* ``MODE_NO_SOLUTION``: ``v_N`` can never reach 0 in compression (Painleve-type jam: the
  normal slope stays <= 0 on the rest of the slip path), ``v_N`` returns to 0 during
  restitution before the termination condition, invalid parameters (``mu < 0``, ``e``
  outside [0, 1], unknown restitution kind), non-finite input, ``W_NN <= 0`` or ``W_TT``
  not positive definite. For SPD ``W`` compression always ends: kappa > 0, and on the
  diverging ray ``a - mu w.u = a - mu lambda - mu^2 u.Cu > lambda^2 u.C^-1 u + mu lambda
  > 0`` (using ``a > w.C^-1 w``); in 2D ``|W_TN| > mu W_TT`` and ``W_NN <= mu |W_TN|`` would
  give ``W_TN^2 > W_NN W_TT``. So the jam branch is reached only for non-SPD ``W``.
* ``MODE_NOT_CONVERGED`` (3D only): more than ``MAX_STEPS`` Taylor steps.

2D is exact: at most two straight segments (slip; stick or reversed slip), every event
impulse in closed form, no iteration; the slopes and ``v_N`` where the slip stops are
formed with error-free transformations (FMA), so the result is the exact path of the
float inputs to a few ulps for any SPD ``W`` (tested against rational arithmetic).

Stick slopes are never formed as a difference of large numbers: 2D ``det W / W_TT`` (FMA
determinant), 3D ``det W / det W_TT`` (``common.schur3``); ``W_TT^-1 W_TN`` by Cramer's rule
with compensated numerators and determinant.

3D: a Taylor-series integrator in the regularised variable ``tau``, ``dp = |v_T| dtau``
(a Sundman-type time transformation). With ``s = |v_T|`` the sliding ODE becomes
``dv_T/dtau = s w - mu C v_T``, ``dp/dtau = s``, ``dP_T/dtau = -mu v_T``,
``dQ/dtau = s^2`` (``Q = int |v_T| dp``; ``v_N = v_N0 + kappa p + z.(v_T - v_T0)``,
``z = C^-1 w``): no division by ``s``, and the sharp swerve of the slip direction where
``|v_T|`` passes close to 0 (a short impulse interval in ``p``) is spread over a ``tau``
interval of order ``1/|dF/dphi|``, independent of ``|v_T|`` (the ODE is homogeneous of
degree one in ``v_T``). The Taylor coefficients come from the recurrences of automatic
differentiation (``_taylor``; Jorba & Zou, Experiment. Math. 14:99, 2005), rearranged so
that the serial chain s_(K-1) -> v_K -> s_K costs one multiply-add per order, at the
order ``TAYLOR_ORDER_*`` chosen from ``tol``; the step from the last two coefficients
(of ``v_T`` and of the normal work ``Wk = int v_N dp``, both terms below ``tol |v0|``,
``TAYLOR_SAFETY``) and a fraction of the estimated radius of convergence
(``TAYLOR_RHO_FRAC``). The normal work itself is evaluated from the work identity
``Wk = P.(v0 + v)/2 + mu Q`` (``_wk_at``), whose error at the energetic termination is
that of ``p`` times ``v_N`` (a series of ``Wk`` has its own truncation error, which the
termination divides by ``v_N``). The series is the dense output: events (``v_N = 0``,
energetic/newton termination, poisson ``p = p_f``) are roots polished by safeguarded
Newton from a quadratic model, and a step goes on past the compression end to the
termination on the same series (no new expansion at ``p_c``). Measured (bench_laws
contacts, e = 0.5, mu = 0.3, energetic, tol 1e-10): 4.3 steps per contact on average
against 26 Dormand-Prince 5(4) steps in ``p`` (the former integrator), at a smaller error
against a tol = 1e-13 reference. ``P_T`` is
carried along (on the friction cone up to truncation error, clipped onto it at the end)
instead of being recovered as ``C^-1 (v_T - v_T0 - w p)``, which multiplies the
tol-level error of ``v_T`` by ``||C^-1||``. When the slip is within LOCK_REL tol |v0| of
an invariant ray that attracts it, the rest is that straight ray (to ``v_T = 0`` if
lambda < 0, for good if lambda > 0); in the singular zone (SING_VT_*) the approach is
finished on a straight line. From ``v_T = 0`` on everything is exact and closed form
(stick, or the diverging ray).

All functions use ``error_model="numpy"`` (IEEE division, no hidden ZeroDivisionError:
kernels can never raise). The array kernels are thin wrappers around scalar cores
(``routh_2d_scalar``, ``routh_3d_scalar``), which user njit code can call directly.
"""
import math

import numpy as np
from numba import njit

from .cache_guard import guard

# flush stale compiled code before the kernel modules below are imported (cache_guard)
guard(__name__, __file__)

from .common import (
    P_E, P_MU, P_REST, P_TOL,
    REST_ENERGETIC, REST_POISSON, REST_NEWTON,
    MODE_SEPARATING, MODE_STICK, MODE_SLIP, MODE_SLIP_STICK, MODE_SLIP_REVERSE,
    MODE_NO_SOLUTION, MODE_NOT_CONVERGED,
    det2k, schur3, solve2, two_sum,
)
from .common import fma as _fma
from numba import carray, types
from numba.core import cgutils
from numba.extending import intrinsic, overload


@njit(cache=True, error_model="numpy", inline="always")
def _schur2_fma(a, b, c):
    """Stick slope a - b^2/c = det/c of the SPD [[a, b], [b, c]], the determinant by Kahan's
    FMA algorithm (``common.det2k``: error <= 2 ulps of the result)."""
    return det2k(a, c, b, b) / c


@njit(cache=True, error_model="numpy", inline="always")
def _axpy_dd(a, m, b):
    """a - m b as an unevaluated sum (hi, lo), exact to ~eps^2 (|a| + |m b|) (FMA two-product
    and two-sum): the sliding slopes W_NN - mu s W_TN and W_TN - mu s W_TT, which cancel when
    the slip nearly jams or nearly stalls."""
    q = m * b
    qe = _fma(m, b, -q)                          # m b = q + qe exactly
    s, se = two_sum(a, -q)
    lo = se - qe
    hi = s + lo
    return hi, lo - (hi - s)


# ---- named tolerances and limits (3D integrator) -----------------------------------------
TOL_DEFAULT = 1e-10   # relative tolerance used when params[P_TOL] is <= 0 or not finite (-)
TOL_MIN = 1e-14       # params[P_TOL] is clipped to [TOL_MIN, TOL_MAX]: below ~1e-14 the
TOL_MAX = 1e-2        #   target is below round-off; above 1e-2 the result is meaningless (-)
SING_VT_PER_TOL = 1.0  # singular zone: |v_T| < max(SING_VT_PER_TOL tol / zs, SING_VT_MIN) |v0|
SING_VT_MIN = 1e-14    #   (m/s per m/s of the velocity scale |v0|), zs = max(1, |W_TT^-1 W_TN|).
                       #   Inside it the approach to v_T = 0 is finished on a straight line.
                       #   An error dv_T in where the slip ends moves v_N by z . dv_T
                       #   (v_N = v_N0 + kappa p + z . (v_T - v_T0) on every path), hence the
                       #   1/zs: the error this makes in v is O(tol |v0|) (ray lock-on: same).
FRICTION_NEGLIGIBLE = 1.0  # mu (1 + |W_TN| / W_NN) <= FRICTION_NEGLIGIBLE * tol: friction
                       #   changes the impulse by less than tol of it, and the frictionless
                       #   impulse is returned (exact in energy: with e = 1 and mu -> 0 the
                       #   integrator's tol-level error alone would decide the sign of dE)
SHORT_TURN = 1.0       # a compression too short to turn the slip: when the slip would change by at
                       #   most SHORT_TURN * tol * |v_T| over the whole impact at its start slope,
                       #   the impulse is the closed form along the start direction (a v_N0 of
                       #   round-off size under a finite slip: the integrator's first step is
                       #   longer than the whole impact)
LOCK_REL = 1.0         # ray lock-on: when v_T is within LOCK_REL * tol * |v0| / zs (m/s, distance
                       #   |v_T| |phi - phi*|) of an invariant ray phi* that attracts the slip
                       #   angle faster than |v_T| changes (dF/dphi < -|lambda|), the rest of
                       #   the slip is that straight ray. Makes stiff approaches
                       #   (dF/dphi << -|lambda|) cheap and exact; slower ones are integrated.
LOCK_ACCEPT = 4.0      # the ray found by Newton on F (``_ray_near``) is taken only if it lies
                       #   within LOCK_ACCEPT * LOCK_REL * tol |v0| / zs of v_T (same distance):
                       #   where F is flat to round-off (W_TT isotropic and W_TN = 0: every
                       #   direction is invariant) Newton's step F/dF is noise over noise.
MAX_STEPS = 20000      # Taylor steps before MODE_NOT_CONVERGED
TAYLOR_ORDER_PER_DIGIT = 1.15  # series order N = ceil(TAYLOR_ORDER_PER_DIGIT * digits) + 1,
TAYLOR_ORDER_MIN = 6           #   digits = -log10(tol), clipped to [TAYLOR_ORDER_MIN,
TAYLOR_ORDER_MAX = 20          #   TAYLOR_ORDER_MAX] (-): Jorba & Zou's optimal order
                               #   -ln(tol)/2 + 1 for a series with a finite radius
TAYLOR_SAFETY = 1.0    # step h = TAYLOR_SAFETY * min((eps/|c_N|)^(1/N), (eps/|c_N-1|)^(1/(N-1)))
                       #   in tau (units N s per m/s = kg, since dp = |v_T| dtau), eps = tol |v0|
                       #   (m/s), c_k the k-th Taylor coefficient of v_T, of W_NN/|v0| Wk and of
                       #   mu W_NN/|v0| Q (Q = int |v_T| dp: the normal work is evaluated from
                       #   the identity Wk = P.(v0 + v)/2 + mu Q, ``_wk_at``)
                       #   (m/s per kg^k): the last two terms of the series are then at most
                       #   eps (Jorba & Zou 2005); measured error against a tight reference
                       #   stays below ~1 tol |v0| (99th percentile, random contacts)
TAYLOR_RHO_FRAC = 0.8  # and h <= TAYLOR_RHO_FRAC (|v_T|/|c_N|)^(1/N): at most this fraction of
                       #   the radius of convergence estimated from the same coefficient (-)
TAYLOR_P_STEP = 10.0   # and the normal impulse grows by at most TAYLOR_P_STEP |v0| / W_NN per
                       #   step (N s): bounds a step whose high coefficients vanish (straight
                       #   slip at constant speed)
TAYLOR_CONT = 0.1      # a step that reaches the compression end goes on (on the same series) to
                       #   at most the point where the truncation error estimate, ~ (t/h)^(N+1)
                       #   of its value at h, is TAYLOR_CONT of it: t = TAYLOR_CONT^(1/(N+1)) h
                       #   (0.77 h at order 8, 0.85 h at order 13): ending the impact close to
                       #   h puts a whole step's error on the result (-). Measured on the
                       #   bench_laws contacts at tol 1e-6: 22 per 1e5 beyond 2 tol |v0|
                       #   without this limit, 3 with it, 0 when every step ended at p_c
N_RAY_SCAN = 72        # jam check: sign scan of F(phi) = u x (w - mu C u) in steps of
                       #   360/N_RAY_SCAN degrees for the next invariant ray, then polished
ROOT_MAX_ITER = 80     # safeguarded Newton/bisection iterations (dense-output events, rays)
ROOT_NOISE = 4.0       # dense-output event roots also stop when the event function is within
                       #   ROOT_NOISE * N ulps of the sum of the magnitudes of its terms
                       #   (its rounding error, Higham's bound for Horner's rule): below
                       #   that, Newton's steps are noise and only bisection would narrow
                       #   the bracket further (-)
ROOT_QUAD = 1e-8       # an event root is accepted after a Newton step inside the bracket of at
                       #   most ROOT_QUAD * h: Newton's next error, ~ (g''/2g') dt^2 <= N dt^2/h
                       #   for a degree-N polynomial on [0, h], is then ~1e-15 h (-)
ROOT_XTOL = 4e-16      # root polishing stops at this width: fraction of the Taylor step (-),
                       #   ray angle (rad), or relative width for the ray rate lambda

_TWO_PI = 2.0 * math.pi

# ============================================================================================
# shared: straight segment in impulse space (v_N linear in p)
# ============================================================================================
@njit(cache=True, error_model="numpy", inline="always")
def _advance_linear(p, vN, Wk, comp, pc, Wc, k, hmax, e, rest, vN0):
    """Advance along a straight impulse-space segment: ``v_N(p + h) = v_N + k h``.

    ``k`` (1/kg) normal slope, ``hmax`` (N s, may be inf) segment length, ``Wk`` (J) normal
    work ``int_0^p v_N dp``, ``comp`` True while compressing, ``pc``/``Wc`` end of
    compression. Locates the compression end and the termination in closed form (energetic:
    the quadratic ``vN h + k h^2/2 = D`` solved as ``h = 2D / (vN + sqrt(vN^2 + 2kD))``, no
    cancellation). Returns ``(code, p, vN, Wk, comp, pc, Wc)``; code 0: segment end reached,
    1: terminated at ``p``, -1: no solution (jam, or v_N back to 0 before termination).
    """
    left = hmax
    if comp:
        hc = -vN / k if k > 0.0 else np.inf
        if hc > left:
            if left == np.inf:
                return -1, p, vN, Wk, comp, pc, Wc        # v_N never reaches 0: jam
            Wk += left * (vN + 0.5 * k * left)
            return 0, p + left, vN + k * left, Wk, comp, pc, Wc
        Wk += 0.5 * vN * hc                                # int of a linear v_N ending at 0
        p += hc
        left -= hc
        vN = 0.0
        comp = False
        pc = p
        Wc = Wk
        if e <= 0.0:
            return 1, p, vN, Wk, comp, pc, Wc
    # restitution: impulse hf to termination, h0 to a return of v_N to 0
    if rest == REST_POISSON:
        hf = max((1.0 + e) * pc - p, 0.0)
    elif rest == REST_NEWTON:
        d = -e * vN0 - vN
        if d <= 0.0:
            hf = 0.0
        elif k > 0.0:
            hf = d / k
        else:
            hf = np.inf
    else:
        D = (1.0 - e * e) * Wc - Wk                        # remaining restitution work (J)
        if D <= 0.0:
            hf = 0.0
        else:
            disc = vN * vN + 2.0 * k * D
            hf = np.inf
            if disc >= 0.0:
                den = vN + math.sqrt(disc)
                if den > 0.0:
                    hf = 2.0 * D / den
    h0 = max(vN, 0.0) / (-k) if k < 0.0 else np.inf
    if hf < np.inf and hf <= left and hf <= h0:
        Wk += hf * (vN + 0.5 * k * hf)
        return 1, p + hf, vN + k * hf, Wk, comp, pc, Wc
    if h0 <= left:
        return -1, p, vN, Wk, comp, pc, Wc
    Wk += left * (vN + 0.5 * k * left)
    return 0, p + left, vN + k * left, Wk, comp, pc, Wc


@njit(cache=True, error_model="numpy", inline="always")
def _check_params(e, mu, r):
    """(ok, rest) for e, mu and the float restitution code r: ok False for invalid
    parameters, rest the int REST_* code."""
    ok = (e >= 0.0) and (e <= 1.0) and (mu >= 0.0) and (mu < np.inf)
    rest = REST_ENERGETIC
    if r == REST_POISSON:
        rest = REST_POISSON
    elif r == REST_NEWTON:
        rest = REST_NEWTON
    elif r != REST_ENERGETIC:
        ok = False
    return ok, rest


# ============================================================================================
# 2D
# ============================================================================================
@njit(cache=True, error_model="numpy", inline="always")
def routh_2d_scalar(vN0, vT, a, b, c, e, mu, r):
    """Routh's law, planar contact: exact, piecewise linear in p (Wang & Mason 1992).

    Scalars in: ``v = (vN0, vT)`` (m/s), ``W = [[a, b], [b, c]]`` (1/kg), ``e``, ``mu``,
    ``r`` the restitution kind (REST_*, as float). Returns ``(mode, P_N, P_T)`` (N s);
    ``P = 0`` on failure. Callable from user njit code without arrays.
    Segments: slip with ``s = sign(v_T)`` (``dP_T/dp = -mu s``, ``dv/dp = W (1, -mu s)``)
    until ``v_T = 0``; then stick if ``|W_TN| <= mu W_TT`` (``dP_T/dp = -W_TN/W_TT``,
    ``dv_N/dp = det W / W_TT``), else slip along ``sign(W_TN)`` (reversal). Returns
    MODE_STICK / SLIP / SLIP_STICK / SLIP_REVERSE, MODE_SEPARATING, or MODE_NO_SOLUTION.

    Accuracy (W, v taken as exact): the slopes ``W_NN - mu s W_TN``, ``W_TN - mu s W_TT``
    (FMA two-product, ``_axpy_dd``) and the stick slope ``det W / W_TT`` (``_schur2_fma``)
    are correct to ~1 ulp, and ``v_N`` where the slip stops, ``v_N0 - k v_T / k_T``, is
    formed in double-double: it is a small difference of O(|v_N0|) terms when the slip
    nearly reaches the compression end (thin rods), and the stick phase divides it by a
    slope that can be ~cond(W)^-1 W_NN. A single segment (no slip stop) terminates at
    ``p_f = (1 + e) p_c`` for every restitution kind.
    """
    if vN0 > 0.0 or (vN0 == 0.0 and (vT == 0.0 or mu == 0.0)):
        return MODE_SEPARATING, 0.0, 0.0           # (sticking slopes are > 0 for SPD W)
    ok, rest = _check_params(e, mu, r)
    finite = abs(vN0) + abs(vT) + abs(a) + abs(b) + abs(c) < np.inf   # False for NaN too
    if not ok or not finite or not (a > 0.0) or not (c > 0.0):
        return MODE_NO_SOLUTION, 0.0, 0.0
    if mu == 0.0:                                 # frictionless: v_N slope W_NN throughout
        return MODE_SLIP, -(1.0 + e) * vN0 / a, 0.0
    stick_ok = abs(b) <= mu * c
    if vT == 0.0:
        if stick_ok:
            return _single_2d(MODE_STICK, vN0, _schur2_fma(a, b, c), -b / c, e)
        s = 1.0 if b > 0.0 else -1.0              # diverging direction: d v_T/dp has sign s
        k, _ = _axpy_dd(a, mu * s, b)
        return _single_2d(MODE_SLIP, vN0, k, -mu * s, e)
    s = 1.0 if vT > 0.0 else -1.0
    ms = mu * s                                   # exact: s = +-1
    kh, kl = _axpy_dd(a, ms, b)                   # normal slope while slipping
    kTh, kTl = _axpy_dd(b, ms, c)                 # tangential slope
    if vN0 == 0.0 and not kh < 0.0:
        return MODE_SEPARATING, 0.0, 0.0           # touching, and no impact without collision
    if s * kTh >= 0.0:                            # the slip never stops
        return _single_2d(MODE_SLIP, vN0, kh, -ms, e)
    # ---- the slip stops at h1 = -vT/kT; v_N there in double-double ----
    t = vT / kTh
    t_lo = (_fma(-kTh, t, vT) - kTl * t) / kTh    # vT/kT = t + t_lo to ~eps^2
    h1 = -t
    q = kh * t
    qe = _fma(kh, t, -q)
    sN, sNe = two_sum(vN0, -q)
    vN1 = sN + (sNe - (qe + kh * t_lo + kl * t))  # vN0 - k vT/kT
    k = kh + kl
    if stick_ok:
        k2 = _schur2_fma(a, b, c)
        g2 = -b / c
        mode2 = MODE_SLIP_STICK
    else:
        k2, _ = _axpy_dd(a, -ms, b)
        g2 = ms
        mode2 = MODE_SLIP_REVERSE
    rest_f = rest
    # ---- segment 1: slip, p in [0, h1] ----
    Wk = 0.0
    if vN1 < 0.0:                                  # still compressing at the stop
        p = h1
        Wk = 0.5 * h1 * (vN0 + vN1)
        code, p, vN, Wk, comp, pc, Wc = _advance_linear(p, vN1, Wk, True, 0.0, 0.0, k2,
                                                        np.inf, e, rest_f, vN0)
        PT = -ms * h1 + g2 * (p - h1)
        if code != 1 or not (abs(p) + abs(PT) < np.inf):
            return MODE_NO_SOLUTION, 0.0, 0.0
        return mode2, p, PT
    # compression ends inside segment 1 (k > 0 here since vN1 >= 0 > vN0)
    pc = -vN0 / k
    if pc > h1:
        pc = h1
    Wc = 0.5 * vN0 * pc
    if e <= 0.0:
        return MODE_SLIP, pc, -ms * pc
    pf = (1.0 + e) * pc                             # single-segment termination (all kinds)
    if pf <= h1:
        return MODE_SLIP, pf, -ms * pf
    # termination after the stop: continue on segment 2 from (h1, vN1)
    Wk = Wc + 0.5 * (h1 - pc) * vN1                 # int_pc^h1 of a linear v_N from 0
    code, p, vN, Wk, comp, pc, Wc = _advance_linear(h1, vN1, Wk, False, pc, Wc, k2, np.inf,
                                                    e, rest_f, vN0)
    PT = -ms * h1 + g2 * (p - h1)
    if code != 1 or not (abs(p) + abs(PT) < np.inf):
        return MODE_NO_SOLUTION, 0.0, 0.0
    return mode2, p, PT


@njit(cache=True, error_model="numpy", inline="always")
def _single_2d(mode, vN0, k, g, e):
    """One unbounded straight segment from p = 0 with normal slope ``k`` and ``dP_T/dp = g``:
    ``p_c = -v_N0/k`` and, for every termination kind, ``p_f = (1 + e) p_c`` (poisson by
    definition; newton ``v_N = k (p_f - p_c) = -e v_N0``; energetic ``k h^2/2 = e^2 |W_c|``
    with ``W_c = v_N0 p_c / 2``). ``k <= 0``: v_N never reaches 0 (jam)."""
    if not (k > 0.0):
        return MODE_NO_SOLUTION, 0.0, 0.0
    pf = ((1.0 + e) * -vN0) / k
    PT = g * pf
    if not (pf < np.inf and abs(PT) < np.inf):
        return MODE_NO_SOLUTION, 0.0, 0.0
    return mode, pf, PT

@njit(cache=True, error_model="numpy")
def routh_2d(v, W, params, P_out):
    """Routh's law, planar contact, kernel contract ``mode = routh_2d(v, W, params, P_out)``
    (see ``routh_2d_scalar``; W is read as symmetric from its upper triangle)."""
    mode, P0, P1 = routh_2d_scalar(v[0], v[1], W[0, 0], W[0, 1], W[1, 1],
                                   params[P_E], params[P_MU], params[P_REST])
    P_out[0] = P0
    P_out[1] = P1
    return mode


# ============================================================================================
# 3D helpers
# ============================================================================================
@njit(cache=True, error_model="numpy", inline="always")
def _cone(p, P1, P2, mu):
    """(P1, P2) scaled onto the friction cone |P_T| <= mu p if (by round-off or truncation
    error of the integrator) it lies outside."""
    n = math.sqrt(P1 * P1 + P2 * P2)
    lim = mu * p
    if n > lim:
        f = lim / n
        return P1 * f, P2 * f
    return P1, P2



@njit(cache=True, error_model="numpy")
def _ray_F(phi, w1, w2, c00, c01, c11, mu):
    """F(phi) = u x (w - mu C u), u = (cos, sin): zero on invariant rays; and its derivative."""
    cs = math.cos(phi)
    sn = math.sin(phi)
    c2 = cs * cs - sn * sn
    s2 = 2.0 * sn * cs
    A = w2
    B = -w1
    Dd = -mu * c01
    E = -0.5 * mu * (c11 - c00)
    F = A * cs + B * sn + Dd * c2 + E * s2
    dF = -A * sn + B * cs + 2.0 * (E * c2 - Dd * s2)
    return F, dF


@njit(cache=True, error_model="numpy", inline="always")
def _ray_dF(u1, u2, w1, w2, c00, c01, c11, mu):
    """dF/dphi at u = (cos phi, sin phi), F(phi) = u x (w - mu C u) (no trig needed)."""
    c2 = u1 * u1 - u2 * u2
    s2 = 2.0 * u1 * u2
    return -w2 * u2 - w1 * u1 + 2.0 * (-0.5 * mu * (c11 - c00) * c2 + mu * c01 * s2)


@njit(cache=True, error_model="numpy")
def _ray_near(u1, u2, w1, w2, c00, c01, c11, mu):
    """Invariant ray next to the unit direction u (Newton on F(phi), a few iterations).
    Returns (u1*, u2*, lambda*, dF/dphi at u*)."""
    phi = math.atan2(u2, u1)
    for _ in range(ROOT_MAX_ITER):
        F, dF = _ray_F(phi, w1, w2, c00, c01, c11, mu)
        if dF == 0.0:
            break
        d = F / dF
        phi -= d
        if abs(d) <= ROOT_XTOL:
            break
    F, dF = _ray_F(phi, w1, w2, c00, c01, c11, mu)
    return (math.cos(phi), math.sin(phi), _ray_lambda(phi, w1, w2, c00, c01, c11, mu), dF)


@njit(cache=True, error_model="numpy")
def _ray_polish(lo, hi, Flo, w1, w2, c00, c01, c11, mu):
    """Root of F on [lo, hi] (sign change, Flo = F(lo)) by safeguarded Newton/bisection."""
    th = 0.5 * (lo + hi)
    for _ in range(ROOT_MAX_ITER):
        F, dF = _ray_F(th, w1, w2, c00, c01, c11, mu)
        if F == 0.0:
            return th
        if (F < 0.0) == (Flo < 0.0):
            lo = th
        else:
            hi = th
        tn = th - F / dF if dF != 0.0 else lo - 1.0
        if not (tn > lo and tn < hi):
            tn = 0.5 * (lo + hi)
        if abs(tn - th) <= ROOT_XTOL or hi - lo <= ROOT_XTOL:
            return tn
        th = tn
    return th


@njit(cache=True, error_model="numpy")
def _ray_lambda(phi, w1, w2, c00, c01, c11, mu):
    """lambda = u.(w - mu C u): growth rate of |v_T| along the ray u(phi) (1/kg)."""
    cs = math.cos(phi)
    sn = math.sin(phi)
    return w1 * cs + w2 * sn - mu * (c00 * cs * cs + 2.0 * c01 * cs * sn + c11 * sn * sn)


@njit(cache=True, error_model="numpy")
def _diverging_ray(w1, w2, c00, c01, c11, mu):
    """The diverging invariant ray: unit u with ``w - mu C u = lambda u``, ``lambda > 0``.

    Equivalently ``u = (lambda I + mu C)^-1 w`` with ``|u| = 1``. For lambda >= 0 the matrix
    is SPD and ``g(lambda) = |(lambda I + mu C)^-1 w|`` decreases strictly from
    ``g(0) = |C^-1 w| / mu`` to 0, so the ray exists iff sticking is unstable
    (``|C^-1 w| > mu``) and is then unique (cf. Bhatt & Koechling 1995). Root of
    ``1/g - 1`` on [0, |w|] by safeguarded Newton from ``|w|``. The caller has found
    sticking unstable, so ``psi(0) = mu / |C^-1 w| - 1 < 0`` is known and ``lambda = 0`` is
    never evaluated: there ``(mu C)^-1`` underflows for tiny mu (mu = 1e-200 gave 0/0).
    Returns (found, u1, u2, lambda)."""
    lo = 0.0
    hi = math.sqrt(w1 * w1 + w2 * w2)        # g(|w|) <= |w| / (|w| + mu c_min) < 1
    if not (hi > 0.0):
        return False, 0.0, 0.0, 0.0
    lam = hi
    y1 = 0.0
    y2 = 0.0
    for _ in range(ROOT_MAX_ITER):
        m00 = lam + mu * c00
        m01 = mu * c01
        m11 = lam + mu * c11
        y1, y2 = solve2(m00, m01, m11, w1, w2)
        g = math.sqrt(y1 * y1 + y2 * y2)
        if not (g < np.inf):                     # M underflowed near lambda = 0: g -> inf
            lo = lam
            ln = 0.5 * (lo + hi)
            lam = ln
            continue
        psi = 1.0 / g - 1.0
        if psi < 0.0:
            lo = lam
        else:
            hi = lam
        if psi == 0.0 or hi - lo <= ROOT_XTOL * hi:
            break
        q1, q2 = solve2(m00, m01, m11, y1, y2)
        dpsi = (y1 * q1 + y2 * q2) / (g * g * g)  # d(1/g)/dlambda = (y.M^-1 y)/g^3 > 0
        ln = lam - psi / dpsi
        if not (ln > lo and ln < hi):
            ln = 0.5 * (lo + hi)
        if abs(ln - lam) <= ROOT_XTOL * abs(ln):
            lam = ln
            break
        lam = ln
    if not (lam > 0.0):
        return False, 0.0, 0.0, 0.0
    y1, y2 = solve2(lam + mu * c00, mu * c01, lam + mu * c11, w1, w2)
    g = math.sqrt(y1 * y1 + y2 * y2)
    return True, y1 / g, y2 / g, lam


@njit(cache=True, error_model="numpy")
def _jam_ahead(u1, u2, a, w1, w2, c00, c01, c11, mu):
    """True if the normal slope a - mu w.u stays <= 0 for the whole remaining slip.

    The slip angle phi obeys an autonomous 1D ODE (d phi/d tau = F(phi), d tau = dp/|v_T|),
    so it moves monotonically to the first zero phi_inf of F in the direction sign F(phi);
    if that ray diverges (lambda > 0) the slip never stops and p -> inf. The slope is a
    first harmonic a - mu |w| cos(phi - psi), maximised on the arc in closed form."""
    phi0 = math.atan2(u2, u1)
    F0, _ = _ray_F(phi0, w1, w2, c00, c01, c11, mu)
    phinf = phi0
    if F0 != 0.0:
        d = 1.0 if F0 > 0.0 else -1.0
        dphi = d * _TWO_PI / N_RAY_SCAN
        prev = phi0
        Fprev = F0
        hit = False
        for i in range(1, N_RAY_SCAN + 1):
            cur = phi0 + i * dphi
            F, _ = _ray_F(cur, w1, w2, c00, c01, c11, mu)
            if F == 0.0:
                phinf = cur
                hit = True
                break
            if (F < 0.0) != (Fprev < 0.0):
                if d > 0.0:
                    phinf = _ray_polish(prev, cur, Fprev, w1, w2, c00, c01, c11, mu)
                else:
                    phinf = _ray_polish(cur, prev, F, w1, w2, c00, c01, c11, mu)
                hit = True
                break
            prev = cur
            Fprev = F
        if not hit:
            return False
    if _ray_lambda(phinf, w1, w2, c00, c01, c11, mu) <= 0.0:
        return False                                   # converging ray: v_T -> 0, sticks
    wn = math.sqrt(w1 * w1 + w2 * w2)
    psi = math.atan2(w2, w1)
    arc = abs(phinf - phi0)
    # does the arc from phi0 (direction of phinf) contain psi + pi, where cos(phi-psi) = -1?
    if phinf >= phi0:
        off = (psi + math.pi - phi0) % _TWO_PI
    else:
        off = (phi0 - psi - math.pi) % _TWO_PI
    if off <= arc:
        cmin = -1.0
    else:
        cmin = min(math.cos(phi0 - psi), math.cos(phinf - psi))
    return a - mu * wn * cmin <= 0.0


# ============================================================================================
# 3D: Taylor series of the sliding motion in the regularised variable tau (dp = |v_T| dtau)
# ============================================================================================
_NMAX = TAYLOR_ORDER_MAX + 1          # coefficients 0..N of each series (N <= TAYLOR_ORDER_MAX)
_R_X1, _R_X2, _R_S, _R_P, _R_P1, _R_P2, _R_VN, _R_Q = 0, 1, 2, 3, 4, 5, 6, 7
_ROWS = 8                             # series: v_T1, v_T2, |v_T|, p, P_T1, P_T2, v_N, Q
_SCRATCH = _ROWS * _NMAX
_INV = np.array([0.0] + [1.0 / k for k in range(1, _NMAX + 1)])   # 1/k (constants)
_CFRAC = np.array([TAYLOR_CONT ** (1.0 / (n + 1)) for n in range(_NMAX + 1)])  # TAYLOR_CONT
_LN_RHO = math.log(TAYLOR_RHO_FRAC / TAYLOR_SAFETY)
_TOL_AT_ORDER = np.array([10.0 ** (-(n - 1) / TAYLOR_ORDER_PER_DIGIT)
                          for n in range(_NMAX + 1)])   # smallest tol for order n
_LOG_ONE_MIN = 1e-300   # ln eps in one logarithm for eps >= this (m/s; above the
#                         subnormal range, where log would lose digits), else ln tol + ln |v0|
_RHO_POW = np.array([(TAYLOR_RHO_FRAC / TAYLOR_SAFETY) ** n for n in range(_NMAX + 1)])


@intrinsic
def _alloca_f64(typingctx, n):
    """Pointer to ``n`` doubles on the calling kernel's stack (``n`` a compile-time
    constant): scratch memory without a heap allocation (freed on return)."""
    if not isinstance(n, types.IntegerLiteral):
        return None
    size = n.literal_value

    def codegen(context, builder, sig, args):
        return cgutils.alloca_once(builder, context.get_value_type(types.float64), size=size)
    return types.CPointer(types.float64)(n), codegen


def _scratch():
    """(_ROWS, _NMAX) float64 scratch for the Taylor coefficients. In compiled code a view
    of stack memory of the calling kernel (no allocation); run as Python (the stability
    suite's shadow runs) an ordinary array."""
    return np.empty((_ROWS, _NMAX))


@overload(_scratch, inline="always")
def _scratch_overload():
    def impl():
        return carray(_alloca_f64(_SCRATCH), (_ROWS, _NMAX))
    return impl


@njit(cache=True, error_model="numpy", inline="always")
def _taylor_order(tol):
    """Series order N for the relative tolerance tol (TAYLOR_ORDER_*): the least N in
    [TAYLOR_ORDER_MIN, TAYLOR_ORDER_MAX] with ceil(TAYLOR_ORDER_PER_DIGIT digits) + 1 <= N,
    i.e. tol >= 10^(-(N - 1)/TAYLOR_ORDER_PER_DIGIT) (``_TOL_AT_ORDER``; a table search
    instead of a logarithm)."""
    n = TAYLOR_ORDER_MIN
    while n < TAYLOR_ORDER_MAX and tol < _TOL_AT_ORDER[n]:
        n += 1
    return n


@njit(cache=True, error_model="numpy", inline="always")
def _taylor(T, N, x1, x2, p, P1, P2, Q, w1, w2, m00, m01, m11, mu, c0, kap, z1, z2):
    """Taylor coefficients 0..N (in tau) of the sliding motion from the state (v_T = (x1, x2),
    p, P_T, Q), into the rows of T. With dp = s dtau, s = |v_T|, the sliding ODE
    (Routh; Mirtich 1996) dv_T/dp = w - mu C v_T/s, dP_T/dp = -mu v_T/s becomes polynomial
    apart from s (a Sundman-type regularisation: no division by s, no singularity at
    v_T = 0 for finite tau):
        dv_T/dtau = s w - M v_T,  dp/dtau = s,  dP_T/dtau = -mu v_T,  dQ/dtau = s^2,
    M = mu C, Q = int_0^p |v_T| dp (the friction work is -mu Q; ``_wk_at``), and the row
    v_N = c0 + kappa p + z . v_T (c0 = v_N0 - z . v_T0). Coefficients by the recurrences of
    automatic differentiation (Jorba & Zou, Experiment. Math. 14:99, 2005):
    y_(K+1) = (dy/dtau)_K / (K + 1), and s from the Cauchy product s^2 = v_T . v_T,
        2 s_0 s_K = 2 v_0 . v_K + sum_(0<j<K) (v_j . v_(K-j) - s_j s_(K-j)).
    The recurrence is a serial chain (s_K needs v_K, which needs s_(K-1)); to shorten it,
    v_K = (w s_(K-1) - M v_(K-1))/K is substituted into v_0 . v_K and the j = 1, K-1 terms
    are split off: s_K = beta_K s_(K-1) + gamma_K, beta_K = u.w/K - s_1/s_0 (u = v_0/s_0;
    s_1/(2 s_0) for K = 2), gamma_K = (v_1/s_0 - M u/K) . v_(K-1) + R_K/(2 s_0) (v_1/(2 s_0)
    for K = 2), R_K = sum_(1<j<K-1) (v_j . v_(K-j) - s_j s_(K-j)): one multiply-add on the
    chain per order, the rest computed off it. (s^2)_K = sum_j s_j s_(K-j) gives Q.
    Requires s_0 > 0. Inlined into the integrator loop (``inline="always"``: the scratch's
    strides become constants; measured 1.1x per contact). Explicit FMAs in the Cauchy sums
    were slower (one longer dependency chain instead of two)."""
    T[_R_X1, 0] = x1
    T[_R_X2, 0] = x2
    T[_R_P, 0] = p
    T[_R_P1, 0] = P1
    T[_R_P2, 0] = P2
    T[_R_Q, 0] = Q
    ss0 = x1 * x1 + x2 * x2
    s0 = math.sqrt(ss0)
    T[_R_S, 0] = s0
    i_s0 = 1.0 / s0
    inv2s = 0.5 * i_s0
    u1 = x1 * i_s0
    u2 = x2 * i_s0
    uw = u1 * w1 + u2 * w2                 # u . w
    mu1 = m00 * u1 + m01 * u2              # M u (M symmetric)
    mu2 = m01 * u1 + m11 * u2
    T[_R_VN, 0] = c0 + kap * p + z1 * x1 + z2 * x2
    # order 1
    b1 = w1 * s0 - (m00 * x1 + m01 * x2)
    b2 = w2 * s0 - (m01 * x1 + m11 * x2)
    T[_R_X1, 1] = b1
    T[_R_X2, 1] = b2
    T[_R_P, 1] = s0
    T[_R_P1, 1] = -mu * x1
    T[_R_P2, 1] = -mu * x2
    T[_R_Q, 1] = ss0
    s1 = u1 * b1 + u2 * b2
    T[_R_S, 1] = s1
    T[_R_VN, 1] = kap * s0 + z1 * b1 + z2 * b2
    g1 = b1 * i_s0                         # v_1 / s_0: the j = 1 and K-1 terms
    g2 = b2 * i_s0
    sc = s1 * i_s0
    # order 2 (the j = 1 term counted once)
    ik = _INV[2]
    T[_R_X1, 2] = (w1 * s1 - (m00 * b1 + m01 * b2)) * ik
    T[_R_X2, 2] = (w2 * s1 - (m01 * b1 + m11 * b2)) * ik
    T[_R_P, 2] = s1 * ik
    T[_R_P1, 2] = -mu * b1 * ik
    T[_R_P2, 2] = -mu * b2 * ik
    T[_R_Q, 2] = 2.0 * s0 * s1 * ik
    sk = (uw * ik - 0.5 * sc) * s1 + ((0.5 * g1 - mu1 * ik) * b1 + (0.5 * g2 - mu2 * ik) * b2)
    T[_R_S, 2] = sk
    T[_R_VN, 2] = kap * T[_R_P, 2] + z1 * T[_R_X1, 2] + z2 * T[_R_X2, 2]
    sq = 2.0 * s0 * sk + s1 * s1           # (s^2)_2
    for k in range(2, N):
        K = k + 1
        ik = _INV[K]
        a1 = T[_R_X1, k]
        a2 = T[_R_X2, k]
        T[_R_X1, K] = (w1 * sk - (m00 * a1 + m01 * a2)) * ik
        T[_R_X2, K] = (w2 * sk - (m01 * a1 + m11 * a2)) * ik
        T[_R_P, K] = sk * ik
        T[_R_P1, K] = -mu * a1 * ik
        T[_R_P2, K] = -mu * a2 * ik
        T[_R_Q, K] = sq * ik
        # s_K: the pairs (j, K-j), 2 <= j < K-j, once and doubled, and the middle term
        RX = 0.0
        RS = 0.0
        for j in range(2, (K + 1) // 2):
            RX += T[_R_X1, j] * T[_R_X1, K - j] + T[_R_X2, j] * T[_R_X2, K - j]
            RS += T[_R_S, j] * T[_R_S, K - j]
        RX = 2.0 * RX
        RS = 2.0 * RS
        if K % 2 == 0:
            m = K // 2
            RX += T[_R_X1, m] * T[_R_X1, m] + T[_R_X2, m] * T[_R_X2, m]
            RS += T[_R_S, m] * T[_R_S, m]
        gam = (g1 - mu1 * ik) * a1 + (g2 - mu2 * ik) * a2 + (RX - RS) * inv2s
        sq = 2.0 * s1 * sk + RS             # (s^2)_K without its 2 s_0 s_K term
        sk = (uw * ik - sc) * sk + gam
        sq += 2.0 * s0 * sk
        T[_R_S, K] = sk
        T[_R_VN, K] = kap * T[_R_P, K] + z1 * T[_R_X1, K] + z2 * T[_R_X2, K]


@njit(cache=True, error_model="numpy", inline="always")
def _wk_coefs(T, N):
    """Taylor coefficients N and N - 1 of the normal work Wk = int v_N dp in tau
    (dWk/dtau = v_N s: Wk_K = sum_(j<K) (v_N)_j s_(K-1-j) / K), for the step control."""
    aN = 0.0
    aM = 0.0
    for j in range(N - 1):
        aN += T[_R_VN, j] * T[_R_S, N - 1 - j]
        aM += T[_R_VN, j] * T[_R_S, N - 2 - j]
    aN += T[_R_VN, N - 1] * T[_R_S, 0]
    return aN * _INV[N], aM * _INV[N - 1]


@njit(cache=True, error_model="numpy", inline="always")
def _wk_at(vN0, x01, x02, mu, vN, p, x1, x2, P1, P2, Q):
    """Normal work Wk = int_0^p v_N dp (J) from the work identity: with v = v0 + W P and W
    symmetric, int v . dP = P . (v0 + v) / 2 along any path, and v_T . dP_T = -mu |v_T| dp
    while sliding (Coulomb), so Wk = P . (v0 + v) / 2 + mu Q, Q = int_0^p |v_T| dp. Its
    error near the energetic termination is the error of p times v_N there (a series of Wk
    itself has a truncation error of its own, which the termination divides by v_N)."""
    return 0.5 * ((vN0 + vN) * p + (x01 + x1) * P1 + (x02 + x2) * P2) + mu * Q


@njit(cache=True, error_model="numpy", inline="always")
def _poly(T, r, N, t):
    """Row r of T as a polynomial of degree N, at t (Horner)."""
    y = T[r, N]
    for k in range(N - 1, -1, -1):
        y = y * t + T[r, k]
    return y


@njit(cache=True, error_model="numpy", inline="always")
def _poly_state(T, N, t):
    """The series of v_T1, v_T2, p, P_T1, P_T2, Q at t, in one interleaved Horner loop."""
    y1 = T[_R_X1, N]
    y2 = T[_R_X2, N]
    yp = T[_R_P, N]
    q1 = T[_R_P1, N]
    q2 = T[_R_P2, N]
    yq = T[_R_Q, N]
    for k in range(N - 1, -1, -1):
        y1 = y1 * t + T[_R_X1, k]
        y2 = y2 * t + T[_R_X2, k]
        yp = yp * t + T[_R_P, k]
        q1 = q1 * t + T[_R_P1, k]
        q2 = q2 * t + T[_R_P2, k]
        yq = yq * t + T[_R_Q, k]
    return y1, y2, yp, q1, q2, yq


@njit(cache=True, error_model="numpy", inline="always")
def _poly_state_s(T, N, t):
    """``_poly_state`` and the series of |v_T| at t, in one interleaved Horner loop (the
    Newton iterations of ``_wk_root``: one pass over the coefficients instead of two)."""
    y1 = T[_R_X1, N]
    y2 = T[_R_X2, N]
    yp = T[_R_P, N]
    q1 = T[_R_P1, N]
    q2 = T[_R_P2, N]
    yq = T[_R_Q, N]
    ys = T[_R_S, N]
    for k in range(N - 1, -1, -1):
        y1 = y1 * t + T[_R_X1, k]
        y2 = y2 * t + T[_R_X2, k]
        yp = yp * t + T[_R_P, k]
        q1 = q1 * t + T[_R_P1, k]
        q2 = q2 * t + T[_R_P2, k]
        yq = yq * t + T[_R_Q, k]
        ys = ys * t + T[_R_S, k]
    return y1, y2, yp, q1, q2, yq, ys


@njit(cache=True, error_model="numpy", inline="always")
def _poly_d2(T, r, N, t):
    """Row r of T as a polynomial of degree N at t, with its first and second derivatives."""
    y = T[r, N]
    d1 = 0.0
    d2 = 0.0
    for k in range(N - 1, -1, -1):
        d2 = d2 * t + d1
        d1 = d1 * t + y
        y = y * t + T[r, k]
    return y, d1, 2.0 * d2


@njit(cache=True, error_model="numpy", inline="always")
def _root_start(g0, d1, d2, lo, hi, g_hi):
    """First iterate for an increasing event function g on [lo, hi] with g(lo) = g0 < 0 <=
    g(hi) = g_hi: the root of its quadratic Taylor model at lo,
    dt = 2 |g0| / (g' + sqrt(g'^2 + 2 g'' |g0|)) (no cancellation), inside the bracket;
    else the secant (regula falsi) point."""
    disc = d1 * d1 + 2.0 * d2 * -g0
    if disc >= 0.0:
        den = d1 + math.sqrt(disc)
        if den > 0.0:
            t = lo + 2.0 * -g0 / den
            if t > lo and t < hi:
                return t
    return lo + (hi - lo) * (g0 / (g0 - g_hi))


@njit(cache=True, error_model="numpy", inline="always")
def _newton_safe(t, g, dy, lo, hi, h):
    """One safeguarded Newton step of the event roots on [lo, hi] (step h): the bracket
    shrunk by the sign of g, then Newton ``t - g / dy``, or the bisection when it leaves the
    bracket. Returns ``(t_next, lo, hi, done)``: done when the step converged
    quadratically (ROOT_QUAD h) or to ROOT_XTOL h."""
    if g < 0.0:
        lo = t
    else:
        hi = t
    tn = t - g / dy if dy != 0.0 else -1.0
    if not (tn > lo and tn < hi):
        tn = 0.5 * (lo + hi)
    elif abs(tn - t) <= ROOT_QUAD * h:
        return tn, lo, hi, True                    # quadratic convergence
    if abs(tn - t) <= ROOT_XTOL * h or hi - lo <= ROOT_XTOL * h:
        return tn, lo, hi, True
    return tn, lo, hi, False


@njit(cache=True, error_model="numpy")
def _poly_root(T, r, N, target, t0, h, g_h):
    """Root t in [t0, h] of poly_r(t) = target, given poly_r(t0) < target <= poly_r(h)
    (``g_h = poly_r(h) - target``): safeguarded Newton (bisection when Newton leaves the
    bracket) from the root of the quadratic model at t0 (``_root_start``), to ROOT_XTOL h
    or to the rounding level of the polynomial (ROOT_NOISE)."""
    lo = t0
    hi = h
    if t0 == 0.0:                                  # (the series' own coefficients)
        g0, d1, d2 = T[r, 0], T[r, 1], 2.0 * T[r, 2]
    else:
        g0, d1, d2 = _poly_d2(T, r, N, t0)
    if not (g0 < target and t0 < h):
        return t0                                  # reached at t0 already (e.g. e^2 = 0)
    t = _root_start(g0 - target, d1, d2, t0, h, g_h)
    noise = ROOT_NOISE * N * 2.220446049250313e-16
    for _ in range(ROOT_MAX_ITER):
        y = T[r, N]
        ya = abs(y)
        dy = 0.0
        for k in range(N - 1, -1, -1):
            dy = dy * t + y
            y = y * t + T[r, k]
            ya = ya * t + abs(T[r, k])
        g = y - target
        if abs(g) <= noise * (ya + abs(target)):
            return t                               # g is zero to rounding
        t, lo, hi, done = _newton_safe(t, g, dy, lo, hi, h)
        if done:
            return t
    return t


@njit(cache=True, error_model="numpy")
def _wk_root(T, N, target, t0, h, g_h, vN0, x01, x02, mu, c0, kap, z1, z2, y1, y2, yp, q1,
             q2, yq):
    """Root t in [t0, h] of Wk(t) = target (energetic termination), given Wk(t0) < target
    <= Wk(h) (``g_h = Wk(h) - target``), Wk from the work identity (``_wk_at``) on the
    series: safeguarded Newton (dWk/dtau = v_N s, d2Wk/dtau2 = v_N' s + v_N s') from the
    root of the quadratic model at t0, to ROOT_XTOL h or to the rounding level of the
    identity (ROOT_NOISE). ``(y1, y2, yp, q1, q2, yq)`` is ``_poly_state(T, N, t0)``, which
    the caller has (the compression end, or the step's start where it is the series'
    constant terms exactly)."""
    lo = t0
    hi = h
    if t0 == 0.0:                                  # (the series' own coefficients)
        vN, dvN, sv, ds = T[_R_VN, 0], T[_R_VN, 1], T[_R_S, 0], T[_R_S, 1]
    else:
        vN, dvN, _ = _poly_d2(T, _R_VN, N, t0)
        sv, ds, _ = _poly_d2(T, _R_S, N, t0)
    g0 = _wk_at(vN0, x01, x02, mu, vN, yp, y1, y2, q1, q2, yq) - target
    if not (g0 < 0.0 and t0 < h):
        return t0                                  # reached at t0 already (e.g. e^2 = 0)
    t = _root_start(g0, vN * sv, dvN * sv + vN * ds, t0, h, g_h)
    noise = ROOT_NOISE * N * 2.220446049250313e-16
    for _ in range(ROOT_MAX_ITER):
        y1, y2, yp, q1, q2, yq, ys = _poly_state_s(T, N, t)
        vN = c0 + kap * yp + z1 * y1 + z2 * y2
        g = _wk_at(vN0, x01, x02, mu, vN, yp, y1, y2, q1, q2, yq) - target
        mag = (0.5 * (abs(vN0 * yp) + abs(vN * yp) + abs((x01 + y1) * q1)
                      + abs((x02 + y2) * q2)) + mu * abs(yq) + abs(target))
        if abs(g) <= noise * mag:
            return t                               # g is zero to rounding
        dy = vN * ys
        t, lo, hi, done = _newton_safe(t, g, dy, lo, hi, h)
        if done:
            return t
    return t


# ============================================================================================
# 3D
# ============================================================================================
@njit(cache=True, error_model="numpy")
def routh_3d_scalar(vN0, x01, x02, a, w1, w2, c00, c01, c11, e, mu, r, tol):
    """Routh's law, 3D contact. Scalars in: ``v = (vN0, x01, x02)`` (m/s); ``W`` (1/kg) as
    ``a = W_NN``, ``w = (w1, w2) = W_TN``, ``C = [[c00, c01], [c01, c11]] = W_TT``; ``e``,
    ``mu``, ``r`` (REST_*, as float), ``tol`` (relative, <= 0 means TOL_DEFAULT). Returns
    ``(mode, P_N, P_T1, P_T2)`` (N s), ``P = 0`` on failure.

    Slides with the Taylor integrator in tau described in the module docstring, then
    finishes exactly from ``v_T = 0`` (or from a locked-on invariant ray). The tangential
    impulse is integrated with the slip (``dP_T/dtau = -mu v_T``, a series like ``v_T``), never recovered through ``W_TT^-1`` (which would amplify tol-level velocity
    errors by ``||W_TT^-1||``), and is finally held on the friction cone (``_cone``). The
    stick slope ``kappa = det W / det W_TT`` (``common.schur3``) and ``z = W_TT^-1 W_TN``
    (compensated numerators and determinant) are accurate to a few ulps for any SPD ``W``,
    so that no stable stick is taken for a jam. Returns MODE_STICK (sticks from the start),
    MODE_SLIP (slides throughout, possibly starting on the diverging ray),
    MODE_SLIP_STICK, MODE_SLIP_REVERSE (stops, resumes on the diverging ray),
    MODE_SEPARATING, MODE_NO_SOLUTION or MODE_NOT_CONVERGED.
    """
    if vN0 > 0.0:
        return MODE_SEPARATING, 0.0, 0.0, 0.0
    if vN0 == 0.0 and (mu == 0.0 or (x01 == 0.0 and x02 == 0.0) or not (
            a - mu * (w1 * x01 + w2 * x02) / math.sqrt(x01 * x01 + x02 * x02) < 0.0)):
        # touching: an impact without collision only while sliding with a negative normal
        # slope (as in 2D: sticking and the diverging ray have positive slopes for SPD W)
        return MODE_SEPARATING, 0.0, 0.0, 0.0
    ok, rest = _check_params(e, mu, r)
    vscale = math.sqrt(vN0 * vN0 + x01 * x01 + x02 * x02)
    detC = det2k(c00, c11, c01, c01)
    finite = vscale + abs(a) + abs(w1) + abs(w2) + abs(c00) + abs(c01) + abs(c11) < np.inf
    if not ok or not finite or not (a > 0.0) or not (c00 > 0.0) or not (detC > 0.0):
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    if mu == 0.0:                                  # frictionless: v_N slope W_NN throughout
        return MODE_SLIP, -(1.0 + e) * vN0 / a, 0.0, 0.0
    if not (tol > 0.0 and tol < np.inf):
        tol = TOL_DEFAULT
    tol = min(max(tol, TOL_MIN), TOL_MAX)
    z1 = det2k(c11, w1, c01, w2) / detC            # z = C^-1 w, compensated Cramer
    z2 = det2k(c00, w2, c01, w1) / detC
    kap = schur3(a, w1, w2, c00, c01, c11)         # 1/(W^-1)_NN = det W / det C > 0
    stick_ok = z1 * z1 + z2 * z2 <= mu * mu
    zs = max(1.0, math.sqrt(z1 * z1 + z2 * z2))  # dv_N / dv_T at fixed p (SING_VT_*)
    thr = max(SING_VT_PER_TOL * tol / zs, SING_VT_MIN) * vscale
    lock = LOCK_REL * tol * vscale / zs

    if mu * (1.0 + math.sqrt(w1 * w1 + w2 * w2) / a) <= FRICTION_NEGLIGIBLE * tol:
        return MODE_SLIP, -(1.0 + e) * vN0 / a, 0.0, 0.0     # as for mu = 0
    r0 = math.sqrt(x01 * x01 + x02 * x02)
    if r0 > 0.0:
        # short compression (SHORT_TURN): one segment of constant slope along u = v_T/|v_T|,
        # v_N = vN0 + (W_NN - mu W_TN . u) p, so p_f = (1 + e) p_c for every termination
        u1 = x01 / r0
        u2 = x02 / r0
        kN = a - mu * (w1 * u1 + w2 * u2)
        d1 = w1 - mu * (c00 * u1 + c01 * u2)       # d v_T / dp
        d2 = w2 - mu * (c01 * u1 + c11 * u2)
        if kN > 0.0:
            pl = -(1.0 + e) * vN0 / kN
            if pl * math.sqrt(d1 * d1 + d2 * d2) <= SHORT_TURN * tol * r0:
                return MODE_SLIP, pl, -mu * u1 * pl, -mu * u2 * pl
    p = 0.0
    x1 = x01
    x2 = x02
    P1 = 0.0                                       # tangential impulse (N s)
    P2 = 0.0
    Q = 0.0                                        # int_0^p |v_T| dp (N s m/s; _wk_at)
    comp = True
    pc = 0.0
    Wc = 0.0
    pf = np.inf
    mode = MODE_SLIP
    # status: 0 sliding, 1 terminated while sliding, 2 singular zone (|v_T| < thr),
    # 3 v_T = 0 exactly at the start, 4 locked on the invariant ray (u1, u2) with rate lam
    status = 0
    u1 = 0.0
    u2 = 0.0
    lam = 0.0
    if r0 == 0.0:
        status = 3
    elif r0 < thr:
        status = 2
    if status == 0:
        m00 = mu * c00
        m01 = mu * c01
        m11 = mu * c11
        c0 = vN0 - (z1 * x01 + z2 * x02)           # v_N = c0 + kappa p + z . v_T
        N = _taylor_order(tol)
        invN = 1.0 / N
        invN1 = 1.0 / (N - 1)
        eps = tol * vscale                         # error target per step (m/s)
        # ln eps (two logarithms only where eps would be subnormal: tiny |v0|)
        leps = (math.log(eps) if eps >= _LOG_ONE_MIN
                else math.log(tol) + math.log(vscale))
        cfrac = _CFRAC[N]
        lrho = _LN_RHO * N
        erho = eps / _RHO_POW[N]                   # s0 below this the radius bound can act (m/s)
        wsc = a / vscale                           # Wk (J) -> m/s, with p scale |v0|/W_NN
        dpmax = TAYLOR_P_STEP * vscale / a         # largest impulse increment per step (N s)
        T = _scratch()
        nstep = 0
        while True:
            if nstep >= MAX_STEPS:
                return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0
            nstep += 1
            _taylor(T, N, x1, x2, p, P1, P2, Q, w1, w2, m00, m01, m11, mu, c0, kap, z1, z2)
            # ---- step size from the last two coefficients (Jorba & Zou) ----
            s0 = T[_R_S, 0]
            wN, wM = _wk_coefs(T, N)
            cN = max(max(abs(T[_R_X1, N]), abs(T[_R_X2, N])),
                     wsc * max(abs(wN), mu * abs(T[_R_Q, N])))
            cM = max(max(abs(T[_R_X1, N - 1]), abs(T[_R_X2, N - 1])),
                     wsc * max(abs(wM), mu * abs(T[_R_Q, N - 1])))
            h = dpmax / s0
            # (the three bounds in log form: one exp instead of three pow; the radius
            # bound needs ln s0 only when it can bind, s0 < eps / TAYLOR_RHO_FRAC^N)
            lh = np.inf
            if cN > 0.0:
                lcN = math.log(cN)
                lh = leps - lcN
                if s0 < erho:
                    lh = min(leps, lrho + math.log(s0)) - lcN
                lh *= invN
            if cM > 0.0:
                lh = min(lh, (leps - math.log(cM)) * invN1)
            if lh < np.inf:
                h = min(h, TAYLOR_SAFETY * math.exp(lh))
            # ---- events inside the step: sign of the event function at its end. The
            # series is valid on all of [0, h]: after the compression end t_c the step goes
            # on to the termination check on [t_c, he], he = max(t_c, TAYLOR_CONT^(1/(N+1))
            # h) (no new expansion at p_c) ----
            t0 = 0.0
            he = h                                 # end of this step
            have_h = False                         # y* below hold the state at he
            ev = 0                                 # 1: compression end, 2: termination
            b1, b2, bp, bq1, bq2, bq = x1, x2, p, P1, P2, Q   # _poly_state(T, N, 0) exactly
            gh = 0.0
            if comp:
                # the state at h, v_N there from it (the row v_N is c0 + kappa p + z . v_T):
                # one interleaved Horner pass, kept for the step's end if no event
                y1, y2, yp, yq1, yq2, yq = _poly_state(T, N, h)
                have_h = True
                gh = c0 + kap * yp + z1 * y1 + z2 * y2
            elif rest == REST_NEWTON:
                gh = _poly(T, _R_VN, N, h)
            if comp and gh >= 0.0:
                t0 = _poly_root(T, _R_VN, N, 0.0, 0.0, h, gh)
                he = max(t0, cfrac * h)            # (TAYLOR_CONT)
                have_h = False
                if he < h and rest == REST_NEWTON:
                    gh = _poly(T, _R_VN, N, he)
                y1, y2, yp, yq1, yq2, yq = _poly_state(T, N, t0)
                b1, b2, bp, bq1, bq2, bq = y1, y2, yp, yq1, yq2, yq   # state at t0
                comp = False
                pc = yp
                Wc = _wk_at(vN0, x01, x02, mu, c0 + kap * yp + z1 * y1 + z2 * y2, yp, y1, y2,
                            yq1, yq2, yq)
                ev = 1
                if e <= 0.0:
                    ev = 2
                else:
                    pf = (1.0 + e) * pc
                    if rest == REST_POISSON and not (pf > pc):
                        ev = 2                     # (1 + e) p_c == p_c in floating point
            if not comp and ev != 2:
                if rest == REST_NEWTON:
                    target = -e * vN0
                    if gh >= target:
                        t0 = _poly_root(T, _R_VN, N, target, t0, he, gh - target)
                        ev = 2
                elif rest == REST_ENERGETIC:
                    target = (1.0 - e * e) * Wc
                    y1, y2, yp, yq1, yq2, yq = _poly_state(T, N, he)
                    have_h = True
                    gh = _wk_at(vN0, x01, x02, mu, c0 + kap * yp + z1 * y1 + z2 * y2, yp, y1, y2,
                                yq1, yq2, yq) - target
                    if gh >= 0.0:
                        t0 = _wk_root(T, N, target, t0, he, gh, vN0, x01, x02, mu, c0, kap, z1,
                                      z2, b1, b2, bp, bq1, bq2, bq)
                        ev = 2
                else:
                    gh = _poly(T, _R_P, N, he) - pf
                    if gh >= 0.0:
                        t0 = _poly_root(T, _R_P, N, pf, t0, he, gh)
                        ev = 3
                if ev >= 2:
                    y1, y2, yp, yq1, yq2, yq = _poly_state(T, N, t0)
            if ev < 2:
                if not have_h:
                    y1, y2, yp, yq1, yq2, yq = _poly_state(T, N, he)
                rn = math.sqrt(y1 * y1 + y2 * y2)
                vNe = c0 + kap * yp + z1 * y1 + z2 * y2
                S = a - mu * (w1 * y1 + w2 * y2) / rn if rn > 0.0 else a
                if comp:
                    if S <= 0.0 and not stick_ok:  # (stable stick: the slip always stops)
                        if rn > 0.0 and _jam_ahead(y1 / rn, y2 / rn, a, w1, w2, c00, c01,
                                                   c11, mu):
                            return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
                elif vNe <= 0.0 and S <= 0.0:
                    # v_N came back down to 0 before termination (not mere round-off
                    # right after p_c, where v_N ~ 0 and increases)
                    return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
            x1 = y1
            x2 = y2
            p = yp
            Q = yq
            P1 = yq1
            P2 = yq2
            if ev == 3:
                p = pf                             # poisson lands on p_f exactly
            if ev >= 2:
                status = 1
                break
            r2 = x1 * x1 + x2 * x2
            if r2 < thr * thr:
                status = 2
                break
            # ---- ray lock-on: |v_T| |phi - phi*| = |v_T x f| / |dF/dphi|, f = dv_T/dp ----
            r = math.sqrt(r2)
            u1 = x1 / r
            u2 = x2 / r
            f1 = w1 - (m00 * u1 + m01 * u2)
            f2 = w2 - (m01 * u1 + m11 * u2)
            xc = x1 * f2 - x2 * f1                 # |v_T| F(phi)
            dF = _ray_dF(u1, u2, w1, w2, c00, c01, c11, mu)
            lam = u1 * f1 + u2 * f2
            if dF < -abs(lam) and abs(xc) <= lock * (-dF):
                v1, v2, lam_s, dF_s = _ray_near(u1, u2, w1, w2, c00, c01, c11, mu)
                near = u1 * v1 + u2 * v2 > 0.0 and r * abs(u1 * v2 - u2 * v1) <= (
                    LOCK_ACCEPT * lock)
                if near and lam_s != 0.0 and dF_s < -abs(lam_s):
                    u1, u2, lam, dF = v1, v2, lam_s, dF_s
                    status = 4
                    break

    if status == 1:
        # terminated while sliding
        PT1, PT2 = _cone(p, P1, P2, mu)
        if not (abs(p) + abs(PT1) + abs(PT2) < np.inf):
            return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
        return mode, p, PT1, PT2

    vN = vN0 + kap * p + z1 * (x1 - x01) + z2 * (x2 - x02)
    Wk = _wk_at(vN0, x01, x02, mu, vN, p, x1, x2, P1, P2, Q)    # 0 if nothing integrated
    if status == 2 or status == 4:
        r = math.sqrt(x1 * x1 + x2 * x2)
        if status == 2:
            # singular zone: finish the approach to v_T = 0 on a straight line
            u1 = x1 / r if r > 0.0 else 0.0
            u2 = x2 / r if r > 0.0 else 0.0
            lam = u1 * (w1 - mu * (c00 * u1 + c01 * u2)) + u2 * (w2 - mu * (c01 * u1 + c11 * u2))
            if not (lam < 0.0):
                lam = -np.inf                      # not approaching: v_T = 0 here
        # straight line along u: to v_T = 0 (lam < 0) or for good (lam > 0)
        S = a - mu * (w1 * u1 + w2 * u2)
        dl = r / (-lam) if lam < 0.0 else np.inf
        PT1 = P1
        PT2 = P2
        p_old = p
        code, p, vN, Wk, comp, pc, Wc = _advance_linear(p, vN, Wk, comp, pc, Wc, S, dl,
                                                        e, rest, vN0)
        if code == -1:
            return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
        if code == 1:
            PT1 -= mu * u1 * (p - p_old)
            PT2 -= mu * u2 * (p - p_old)
            PT1, PT2 = _cone(p, PT1, PT2, mu)
            if not (abs(p) + abs(PT1) + abs(PT2) < np.inf):
                return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
            return MODE_SLIP, p, PT1, PT2
        if stick_ok:
            mode = MODE_SLIP_STICK
        else:
            mode = MODE_SLIP_REVERSE
        P1 = PT1 - mu * u1 * (p - p_old)           # impulse where v_T reaches 0
        P2 = PT2 - mu * u2 * (p - p_old)
        vN = vN0 + kap * p - z1 * x01 - z2 * x02   # v_T = 0 exactly from here on
    else:
        mode = MODE_STICK if stick_ok else MODE_SLIP
    # ---- exact tail from v_T = 0: stick, or the diverging invariant ray ----
    ps = p
    if stick_ok:
        code, p, vN, Wk, comp, pc, Wc = _advance_linear(p, vN, Wk, comp, pc, Wc, kap, np.inf,
                                                        e, rest, vN0)
        PT1 = P1 - z1 * (p - ps)                   # stick: dP_T/dp = -C^-1 w
        PT2 = P2 - z2 * (p - ps)
    else:
        found, u1, u2, lam = _diverging_ray(w1, w2, c00, c01, c11, mu)
        if not found:
            return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
        S = a - mu * (w1 * u1 + w2 * u2)
        code, p, vN, Wk, comp, pc, Wc = _advance_linear(p, vN, Wk, comp, pc, Wc, S, np.inf,
                                                        e, rest, vN0)
        PT1 = P1 - mu * u1 * (p - ps)
        PT2 = P2 - mu * u2 * (p - ps)
    if code != 1 or not (abs(p) + abs(PT1) + abs(PT2) < np.inf):
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    PT1, PT2 = _cone(p, PT1, PT2, mu)
    return mode, p, PT1, PT2

@njit(cache=True, error_model="numpy")
def routh_3d(v, W, params, P_out):
    """Routh's law, 3D contact, kernel contract ``mode = routh_3d(v, W, params, P_out)``
    (see ``routh_3d_scalar``; W is read as symmetric from its lower triangle)."""
    mode, P0, P1, P2 = routh_3d_scalar(v[0], v[1], v[2], W[0, 0], W[1, 0], W[2, 0],
                                       W[1, 1], W[2, 1], W[2, 2], params[P_E], params[P_MU],
                                       params[P_REST], params[P_TOL])
    P_out[0] = P0
    P_out[1] = P1
    P_out[2] = P2
    return mode


@njit(cache=True, error_model="numpy")
def routh(v, W, params, P_out):
    """Routh's law, dispatching on ``v.shape[0]`` (2: planar, 3: spatial). In hot 2D loops
    prefer ``routh_2d`` / ``routh_2d_scalar``: because this function may call the
    out-of-line 3D core, Numba keeps one array reference-count pair per call here
    (~50 ns on the development machine, as much as the 2D law itself)."""
    if v.shape[0] == 2:
        mode, P0, P1 = routh_2d_scalar(v[0], v[1], W[0, 0], W[0, 1], W[1, 1],
                                       params[P_E], params[P_MU], params[P_REST])
        P2 = 0.0
    else:
        mode, P0, P1, P2 = routh_3d_scalar(v[0], v[1], v[2], W[0, 0], W[1, 0], W[2, 0],
                                           W[1, 1], W[2, 1], W[2, 2], params[P_E],
                                           params[P_MU], params[P_REST], params[P_TOL])
    P_out[0] = P0
    P_out[1] = P1
    if v.shape[0] == 3:
        P_out[2] = P2
    return mode
