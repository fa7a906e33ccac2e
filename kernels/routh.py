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
* ``MODE_NOT_CONVERGED`` (3D only): more than ``MAX_STEPS`` Runge-Kutta step attempts.

2D is exact: at most two straight segments (slip; stick or reversed slip), every event
impulse in closed form, no iteration; the slopes and ``v_N`` where the slip stops are
formed with error-free transformations (FMA), so the result is the exact path of the
float inputs to a few ulps for any SPD ``W`` (tested against rational arithmetic).

Stick slopes are never formed as a difference of large numbers: 2D ``det W / W_TT`` (FMA
determinant), 3D ``det W / det W_TT`` (``common.schur3``); ``W_TT^-1 W_TN`` by Cramer's rule
with compensated numerators and determinant.

3D: Dormand-Prince 5(4) (FSAL, local extrapolation) on the state ``(v_T, P_T, Wk)``, ``Wk =
int v_N dp``, with ``v_N = v_N0 + kappa p + z.(v_T - v_T0)``, ``z = C^-1 w``; ``P_T`` is
carried along (``dP_T/dp = -mu u``: on the friction cone up to truncation error, and
clipped onto it at the end) instead of being recovered as ``C^-1 (v_T - v_T0 - w p)``,
which multiplies the tol-level error of ``v_T`` by ``||C^-1||``; error control
on ``v_T`` and ``Wk`` to ``tol`` relative to ``|v0|`` (max norm), predictive step control;
events (``v_N = 0``, energetic/newton termination) located on Shampine's 4th-order
continuous extension with a safeguarded Newton polish; poisson lands on ``p_f`` exactly.
Why DP5: at tol 1e-6..1e-10 it needs within ~25 % of the right-hand-side evaluations of
DOP853 on the swerve case (scipy counts: 276 vs 216 at 1e-10), has a free continuous
extension for the events (DOP853's costs 3 more stages), and each evaluation is one
dependent sqrt and division; below ~1e-11 DOP853 would be cheaper (about 2x at 1e-12).
The ODE is singular at ``v_T = 0``: steps are capped (SING_STEP_FRAC) while ``|v_T|``
shrinks, and near a ray that attracts the slip angle they are kept in the stability
interval of the angle's rate ``dF/dphi / |v_T|`` (STIFF_STEP); when the slip is within LOCK_REL tol |v0| of an invariant ray that attracts it,
the rest is that straight ray (to ``v_T = 0`` if lambda < 0, for good if lambda > 0);
in the singular zone (SING_VT_*) the approach is finished on a straight line. From
``v_T = 0`` on everything is exact and closed form (stick, or the diverging ray).

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
SING_STEP_FRAC = 0.9   # while |v_T| decreases, a step may cover at most this fraction of the
                       #   impulse |v_T| / (-d|v_T|/dp) predicted to reach v_T = 0 (-), so
                       #   that no stage crosses the singularity; |v_T| then shrinks
                       #   geometrically (x10 per step) into the singular zone.
STIFF_STEP = 2.0       # near a ray that attracts the slip angle (dF/dphi < 0) a step is at most
                       #   STIFF_STEP |v_T| / |dF/dphi| (N s): h times the angle's rate
                       #   |dF/dphi| / |v_T| stays in DP5's real stability interval (-3.3, 0),
                       #   amplification |R(-2)| = 0.17. Without it the error control accepts
                       #   unstable steps when |v_T| ~ 10 tol |v0| and the discrete slip
                       #   circles v_T = 0 until MAX_STEPS (MODE_NOT_CONVERGED).
LOCK_REL = 1.0         # ray lock-on: when v_T is within LOCK_REL * tol * |v0| / zs (m/s, distance
                       #   |v_T| |phi - phi*|) of an invariant ray phi* that attracts the slip
                       #   angle faster than |v_T| changes (dF/dphi < -|lambda|), the rest of
                       #   the slip is that straight ray. Makes stiff approaches
                       #   (dF/dphi << -|lambda|) cheap and exact; slower ones are integrated.
LOCK_ACCEPT = 4.0      # the ray found by Newton on F (``_ray_near``) is taken only if it lies
                       #   within LOCK_ACCEPT * LOCK_REL * tol |v0| / zs of v_T (same distance):
                       #   where F is flat to round-off (W_TT isotropic and W_TN = 0: every
                       #   direction is invariant) Newton's step F/dF is noise over noise.
MAX_STEPS = 20000      # step attempts (accepted + rejected) before MODE_NOT_CONVERGED
H0_FRAC = 1.0          # first step = H0_FRAC * tol^(1/5) * min(|v_N0|/W_NN, |v_T0|/|dv_T/dp|) (N s)
SAFETY = 0.9           # step-size controller (-): h_new = h * clip(fac, FAC_MIN, FAC_MAX) with
FAC_MIN = 0.2          #   fac = SAFETY err^(-1/5), after an accepted step the smaller of that
FAC_MAX = 10.0         #   and Gustafsson's predictive factor (err_prev/err)^(1/5) h/h_prev
N_RAY_SCAN = 72        # jam check: sign scan of F(phi) = u x (w - mu C u) in steps of
                       #   360/N_RAY_SCAN degrees for the next invariant ray, then polished
ROOT_MAX_ITER = 80     # safeguarded Newton/bisection iterations (dense-output events, rays)
ROOT_XTOL = 4e-16      # root polishing stops at this width: step fraction th in [0, 1] (-),
                       #   ray angle (rad), or relative width for the ray rate lambda

_TWO_PI = 2.0 * math.pi

# ---- Dormand-Prince 5(4) tableau (Dormand & Prince 1980; same as scipy RK45) --------------
_C2, _C3, _C4, _C5 = 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0
_A21 = 1.0 / 5.0
_A31, _A32 = 3.0 / 40.0, 9.0 / 40.0
_A41, _A42, _A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
_A51, _A52, _A53, _A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
_A61, _A62, _A63, _A64, _A65 = (9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0,
                                49.0 / 176.0, -5103.0 / 18656.0)
_B1, _B3, _B4, _B5, _B6 = 35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0
_E1, _E3, _E4, _E5, _E6, _E7 = (-71.0 / 57600.0, 71.0 / 16695.0, -71.0 / 1920.0,
                                17253.0 / 339200.0, -22.0 / 525.0, 1.0 / 40.0)
# Shampine's 4th-order continuous extension: y(p0 + th h) = y0 + h sum_j K_j b_j(th),
# b_j(th) = sum_m D_jm th^(m+1) (row 2 is zero; b_j(1) = B_j).
_D10, _D11, _D12, _D13 = (1.0, -8048581381.0 / 2820520608.0, 8663915743.0 / 2820520608.0,
                          -12715105075.0 / 11282082432.0)
_D31, _D32, _D33 = (131558114200.0 / 32700410799.0, -68118460800.0 / 10900136933.0,
                    87487479700.0 / 32700410799.0)
_D41, _D42, _D43 = (-1754552775.0 / 470086768.0, 14199869525.0 / 1410260304.0,
                    -10690763975.0 / 1880347072.0)
_D51, _D52, _D53 = (127303824393.0 / 49829197408.0, -318862633887.0 / 49829197408.0,
                    701980252875.0 / 199316789632.0)
_D61, _D62, _D63 = (-282668133.0 / 205662961.0, 2019193451.0 / 616988883.0,
                    -1453857185.0 / 822651844.0)
_D71, _D72, _D73 = (40617522.0 / 29380423.0, -110615467.0 / 29380423.0,
                    69997945.0 / 29380423.0)


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
def _rhs(x1, x2, p, w1, w2, m00, m01, m11, mu, vN0, kap, z1, z2, x01, x02):
    """Sliding ODE in p: returns ``(dv_T1/dp, dv_T2/dp, v_N, dP_T1/dp, dP_T2/dp)`` with
    ``dP_T/dp = -mu u``, ``u = v_T/|v_T|``, ``dv_T/dp = w - mu C u`` (``m = mu C``
    precomputed), and ``dWk/dp = v_N``. mu C v_T is formed while the square root runs."""
    r2 = x1 * x1 + x2 * x2
    g1 = m00 * x1 + m01 * x2
    g2 = m01 * x1 + m11 * x2
    vN = vN0 + kap * p + z1 * (x1 - x01) + z2 * (x2 - x02)
    if r2 > 0.0:
        ir = 1.0 / math.sqrt(r2)
        mi = mu * ir
        return w1 - g1 * ir, w2 - g2 * ir, vN, -mi * x1, -mi * x2
    return w1, w2, vN, 0.0, 0.0


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


# m^(-1/5) on [0.5, 1]: quadratic through m = 0.5, 0.75, 1 (relative error < 1.6e-3)
_RQ0, _RQ1, _RQ2 = 1.4183994, -0.66040478, 0.24200538
_R5_1, _R5_2, _R5_3, _R5_4 = 2.0 ** -0.2, 2.0 ** -0.4, 2.0 ** -0.6, 2.0 ** -0.8


@njit(cache=True, error_model="numpy", inline="always")
def _err_pow(err):
    """err^(-1/5) to ~2e-3 relative (step-size controller only), err > 0: frexp and a
    quadratic, several times cheaper than math.pow."""
    m, k = math.frexp(err)                         # err = m 2^k, m in [0.5, 1)
    q = k // 5
    j = k - 5 * q
    y = _RQ0 + m * (_RQ1 + m * _RQ2)
    if j == 1:
        y *= _R5_1
    elif j == 2:
        y *= _R5_2
    elif j == 3:
        y *= _R5_3
    elif j == 4:
        y *= _R5_4
    return math.ldexp(y, -q)


@njit(cache=True, error_model="numpy", inline="always")
def _dense_b(th):
    """Weights b_j(th) of the DP5 continuous extension (j = 1, 3..7)."""
    b1 = th * (_D10 + th * (_D11 + th * (_D12 + th * _D13)))
    t2 = th * th
    b3 = t2 * (_D31 + th * (_D32 + th * _D33))
    b4 = t2 * (_D41 + th * (_D42 + th * _D43))
    b5 = t2 * (_D51 + th * (_D52 + th * _D53))
    b6 = t2 * (_D61 + th * (_D62 + th * _D63))
    b7 = t2 * (_D71 + th * (_D72 + th * _D73))
    return b1, b3, b4, b5, b6, b7


@njit(cache=True, error_model="numpy", inline="always")
def _event_root(g0, h, G1, G3, G4, G5, G6, G7):
    """Root th in [0, 1] of the dense-output polynomial g(th) = g0 + h sum_j G_j b_j(th)
    (G_j the stage derivatives of the event function), given g0 < 0 <= g(1)."""
    q1 = h * (_D10 * G1)
    q2 = h * (_D11 * G1 + _D31 * G3 + _D41 * G4 + _D51 * G5 + _D61 * G6 + _D71 * G7)
    q3 = h * (_D12 * G1 + _D32 * G3 + _D42 * G4 + _D52 * G5 + _D62 * G6 + _D72 * G7)
    q4 = h * (_D13 * G1 + _D33 * G3 + _D43 * G4 + _D53 * G5 + _D63 * G6 + _D73 * G7)
    g1 = g0 + q1 + q2 + q3 + q4
    if g1 <= 0.0:
        return 1.0
    lo = 0.0
    hi = 1.0
    th = g0 / (g0 - g1)
    for _ in range(ROOT_MAX_ITER):
        val = g0 + th * (q1 + th * (q2 + th * (q3 + th * q4)))
        if val < 0.0:
            lo = th
        elif val > 0.0:
            hi = th
        else:
            return th
        der = q1 + th * (2.0 * q2 + th * (3.0 * q3 + th * 4.0 * q4))
        tn = th - val / der if der != 0.0 else -1.0
        if not (tn > lo and tn < hi):
            tn = 0.5 * (lo + hi)
        if abs(tn - th) <= ROOT_XTOL or hi - lo <= ROOT_XTOL:
            return tn
        th = tn
    return th


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


@njit(cache=True, error_model="numpy", inline="always")
def _h_stiff(x1, x2, w1, w2, c00, c01, c11, mu):
    """Largest step STIFF_STEP |v_T| / |dF/dphi| allowed where the slip angle is attracted
    (dF/dphi < 0) to a ray (N s); inf elsewhere or at v_T = 0."""
    r = math.sqrt(x1 * x1 + x2 * x2)
    if not (r > 0.0):
        return np.inf
    dF = _ray_dF(x1 / r, x2 / r, w1, w2, c00, c01, c11, mu)
    return STIFF_STEP * r / (-dF) if dF < 0.0 else np.inf


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
# 3D
# ============================================================================================
@njit(cache=True, error_model="numpy")
def routh_3d_scalar(vN0, x01, x02, a, w1, w2, c00, c01, c11, e, mu, r, tol):
    """Routh's law, 3D contact. Scalars in: ``v = (vN0, x01, x02)`` (m/s); ``W`` (1/kg) as
    ``a = W_NN``, ``w = (w1, w2) = W_TN``, ``C = [[c00, c01], [c01, c11]] = W_TT``; ``e``,
    ``mu``, ``r`` (REST_*, as float), ``tol`` (relative, <= 0 means TOL_DEFAULT). Returns
    ``(mode, P_N, P_T1, P_T2)`` (N s), ``P = 0`` on failure.

    Slides with the DP5 integrator described in the module docstring, then finishes
    exactly from ``v_T = 0`` (or from a locked-on invariant ray). The tangential impulse
    is integrated with the slip (``dP_T/dp = -mu u``, the same Runge-Kutta weights as
    ``v_T``), never recovered through ``W_TT^-1`` (which would amplify tol-level velocity
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
    sc_x = 1.0 / (tol * vscale)                    # error weights: v_T (m/s) ...
    sc_w = a / (tol * vscale * vscale)             # ... and Wk (J), with p scale |v0|/W_NN

    p = 0.0
    x1 = x01
    x2 = x02
    P1 = 0.0                                       # tangential impulse (N s)
    P2 = 0.0
    Wk = 0.0
    comp = True
    pc = 0.0
    Wc = 0.0
    pf = np.inf
    r0 = math.sqrt(x01 * x01 + x02 * x02)
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
        f1, f2, f3, f4, f5 = _rhs(x1, x2, p, w1, w2, m00, m01, m11, mu, vN0, kap, z1, z2,
                                  x01, x02)
        fn = math.sqrt(f1 * f1 + f2 * f2)
        ps = -vN0 / a
        if fn * ps > r0 or ps == 0.0:             # (ps == 0: an impact without collision)
            ps = r0 / fn
        h = H0_FRAC * math.pow(tol, 0.2) * ps
        hstiff = _h_stiff(x1, x2, w1, w2, c00, c01, c11, mu)
        h_prev = 0.0
        rho_prev = 1.0
        rejected = False
        nstep = 0
        while True:
            if nstep >= MAX_STEPS:
                return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0
            nstep += 1
            hh = h
            r2 = x1 * x1 + x2 * x2
            rr2 = x1 * f1 + x2 * f2                # |v_T| d|v_T|/dp
            if rr2 < 0.0 and hh * (-rr2) > SING_STEP_FRAC * r2:
                hh = SING_STEP_FRAC * r2 / (-rr2)  # at most a fraction of the way to v_T = 0
            # the slip angle obeys dphi/dp = F(phi)/|v_T|: near an attracting ray its rate
            # dF/dphi / |v_T| grows without bound as |v_T| -> 0 (stiff); keep the step in
            # DP5's stability interval so that the angle converges onto the ray (lock-on)
            # instead of oscillating around it (hstiff: formed at the end of the previous
            # step, off this step's critical path)
            if hh > hstiff:
                hh = hstiff
            last = False
            if not comp and rest == REST_POISSON and p + hh >= pf:
                hh = pf - p
                last = True
            # ---- Dormand-Prince 5(4) step, FSAL (k1 = f). Stage sums add the newest stage
            # last, so that only one multiply-add separates consecutive stages ----
            k11, k12, k13, k14, k15 = f1, f2, f3, f4, f5
            k21, k22, k23, k24, k25 = _rhs(x1 + (hh * _A21) * k11, x2 + (hh * _A21) * k12,
                                 p + _C2 * hh,
                                 w1, w2, m00, m01, m11, mu, vN0, kap, z1, z2, x01, x02)
            k31, k32, k33, k34, k35 = _rhs((x1 + hh * (_A31 * k11)) + (hh * _A32) * k21,
                                 (x2 + hh * (_A31 * k12)) + (hh * _A32) * k22,
                                 p + _C3 * hh,
                                 w1, w2, m00, m01, m11, mu, vN0, kap, z1, z2, x01, x02)
            k41, k42, k43, k44, k45 = _rhs((x1 + hh * (_A41 * k11 + _A42 * k21)) + (hh * _A43) * k31,
                                 (x2 + hh * (_A41 * k12 + _A42 * k22)) + (hh * _A43) * k32,
                                 p + _C4 * hh,
                                 w1, w2, m00, m01, m11, mu, vN0, kap, z1, z2, x01, x02)
            k51, k52, k53, k54, k55 = _rhs(
                (x1 + hh * (_A51 * k11 + _A52 * k21 + _A53 * k31)) + (hh * _A54) * k41,
                (x2 + hh * (_A51 * k12 + _A52 * k22 + _A53 * k32)) + (hh * _A54) * k42,
                p + _C5 * hh, w1, w2, m00, m01, m11, mu, vN0, kap, z1, z2, x01, x02)
            k61, k62, k63, k64, k65 = _rhs(
                (x1 + hh * (_A61 * k11 + _A62 * k21 + _A63 * k31 + _A64 * k41))
                + (hh * _A65) * k51,
                (x2 + hh * (_A61 * k12 + _A62 * k22 + _A63 * k32 + _A64 * k42))
                + (hh * _A65) * k52,
                p + hh, w1, w2, m00, m01, m11, mu, vN0, kap, z1, z2, x01, x02)
            pn = pf if last else p + hh
            y1 = (x1 + hh * (_B1 * k11 + _B3 * k31 + _B4 * k41 + _B5 * k51)) + (hh * _B6) * k61
            y2 = (x2 + hh * (_B1 * k12 + _B3 * k32 + _B4 * k42 + _B5 * k52)) + (hh * _B6) * k62
            yw = Wk + hh * (_B1 * k13 + _B3 * k33 + _B4 * k43 + _B5 * k53 + _B6 * k63)
            k71, k72, k73, k74, k75 = _rhs(y1, y2, pn,
                                 w1, w2, m00, m01, m11, mu, vN0, kap, z1, z2, x01, x02)
            e1 = hh * (_E1 * k11 + _E3 * k31 + _E4 * k41 + _E5 * k51 + _E6 * k61 + _E7 * k71)
            e2 = hh * (_E1 * k12 + _E3 * k32 + _E4 * k42 + _E5 * k52 + _E6 * k62 + _E7 * k72)
            e3 = hh * (_E1 * k13 + _E3 * k33 + _E4 * k43 + _E5 * k53 + _E6 * k63 + _E7 * k73)
            err = max(max(abs(e1), abs(e2)) * sc_x, abs(e3) * sc_w)
            if not (err <= 1.0):
                if not (err < np.inf):             # non-finite stage: give up on this input
                    return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
                h = hh * max(FAC_MIN, SAFETY * _err_pow(err))
                rejected = True
                continue
            # ---- accepted: next step (Gustafsson's predictive controller, capped by the
            # elementary one) ----
            if err > 0.0:
                rho = _err_pow(err)
                fac = SAFETY * rho
                if h_prev > 0.0:
                    fac = min(fac, fac * (hh / h_prev) * (rho / rho_prev))
                fac = min(FAC_MAX, max(FAC_MIN, fac))
            else:
                rho = rho_prev
                fac = FAC_MAX
            if rejected:
                fac = min(fac, 1.0)
            h = hh * fac
            h_prev = hh
            rho_prev = rho
            rejected = False
            # ---- events inside the accepted step ----
            ev = 0                                 # 1: compression end, 2: termination
            g0 = 0.0
            if comp:
                if k73 >= 0.0:
                    ev = 1
                    g0 = f3
            elif rest == REST_NEWTON:
                if k73 + e * vN0 >= 0.0:
                    ev = 2
                    g0 = f3 + e * vN0
            elif rest == REST_ENERGETIC:
                if yw - (1.0 - e * e) * Wc >= 0.0:
                    ev = 2
                    g0 = Wk - (1.0 - e * e) * Wc
            if ev != 0:
                if ev == 2 and rest == REST_ENERGETIC:
                    th = _event_root(g0, hh, k13, k33, k43, k53, k63, k73)
                else:                              # event on v_N: stage slopes a + w.dP_T
                    th = _event_root(g0, hh,
                                     a + (w1 * k14 + w2 * k15), a + (w1 * k34 + w2 * k35),
                                     a + (w1 * k44 + w2 * k45), a + (w1 * k54 + w2 * k55),
                                     a + (w1 * k64 + w2 * k65), a + (w1 * k74 + w2 * k75))
                b1, b3, b4, b5, b6, b7 = _dense_b(th)
                x1 = x1 + hh * (b1 * k11 + b3 * k31 + b4 * k41 + b5 * k51 + b6 * k61 + b7 * k71)
                x2 = x2 + hh * (b1 * k12 + b3 * k32 + b4 * k42 + b5 * k52 + b6 * k62 + b7 * k72)
                Wk = Wk + hh * (b1 * k13 + b3 * k33 + b4 * k43 + b5 * k53 + b6 * k63 + b7 * k73)
                P1 = P1 + hh * (b1 * k14 + b3 * k34 + b4 * k44 + b5 * k54 + b6 * k64 + b7 * k74)
                P2 = P2 + hh * (b1 * k15 + b3 * k35 + b4 * k45 + b5 * k55 + b6 * k65 + b7 * k75)
                p = p + th * hh
                if ev == 2:
                    status = 1
                    break
                comp = False
                pc = p
                Wc = Wk
                if e <= 0.0:
                    status = 1
                    break
                pf = (1.0 + e) * pc
                if rest == REST_POISSON and not (pf > pc):
                    status = 1                     # (1 + e) p_c == p_c in floating point
                    break
                h = max(h, hh)
                hstiff = _h_stiff(x1, x2, w1, w2, c00, c01, c11, mu)
                f1, f2, f3, f4, f5 = _rhs(x1, x2, p, w1, w2, m00, m01, m11, mu, vN0, kap,
                                          z1, z2, x01, x02)
            else:
                if comp:
                    S = a + (w1 * k74 + w2 * k75)  # normal slope a - mu w.u at the step end
                    if S <= 0.0 and not stick_ok:  # (stable stick: the slip always stops)
                        rn = math.sqrt(y1 * y1 + y2 * y2)
                        if rn > 0.0 and _jam_ahead(y1 / rn, y2 / rn, a, w1, w2, c00, c01,
                                                   c11, mu):
                            return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
                elif k73 <= 0.0 and a + (w1 * k74 + w2 * k75) <= 0.0:
                    # v_N came back down to 0 before termination (not mere round-off
                    # right after p_c, where v_N ~ 0 and increases)
                    return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
                p = pn
                x1 = y1
                x2 = y2
                Wk = yw
                P1 = P1 + hh * (_B1 * k14 + _B3 * k34 + _B4 * k44 + _B5 * k54 + _B6 * k64)
                P2 = P2 + hh * (_B1 * k15 + _B3 * k35 + _B4 * k45 + _B5 * k55 + _B6 * k65)
                f1, f2, f3, f4, f5 = k71, k72, k73, k74, k75
                if last:
                    status = 1
                    break
            r2 = x1 * x1 + x2 * x2
            if r2 < thr * thr:
                status = 2
                break
            # ---- ray lock-on: |v_T| |phi - phi*| = |v_T x f| / |dF/dphi| ----
            xc = x1 * f2 - x2 * f1                 # |v_T| F(phi)
            r = math.sqrt(r2)
            u1 = x1 / r
            u2 = x2 / r
            dF = _ray_dF(u1, u2, w1, w2, c00, c01, c11, mu)
            hstiff = STIFF_STEP * r / (-dF) if dF < 0.0 else np.inf
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
