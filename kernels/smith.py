"""Smith's collision law (C. E. Smith, J. Appl. Mech. 58:754, 1991), 2D and 3D kernels.

Contact space, normal first (DESIGN §3): ``v = (v_N, v_T[, v_T2])`` in m/s, ``W`` in 1/kg,
impulse ``P`` on body A in N s, ``v_f = v + W P``. Parameters ``params[P_E] = e`` in [0, 1]
and ``params[P_MU] = mu >= 0``. With ``a = v_T`` (initial slip) and ``b = v_fT`` (final)::

    v_fN = -e v_N,     P_T = -mu P_N g,     g = (|a| a + |b| b) / (|a|^2 + |b|^2),  |g| <= 1.

(The seed paper prints the formula without the minus sign; friction opposes sliding.)
Eliminating ``P_N = c / D``, ``c = -(1 + e) v_N > 0``, ``D = W_NN - mu W_NT . g``, leaves
``F(b) = a + c H(g(b)) - b = 0`` with ``H(g) = (W_TN - mu W_TT g) / D``. Physical roots are
those with ``P_N > 0`` (``D > 0``). Facts used below (proved in the comments; DESIGN §4):

* ``dE = P.(v + v_f)/2 <= 0`` at every root with ``P_N >= 0``, so ``v_f`` lies in the energy
  ellipsoid ``x^T W^-1 x <= v^T W^-1 v``: ``|b|`` and ``P_N`` are bounded.
* ``g(b)`` is a monotone map (its Jacobian has a positive semi-definite symmetric part), and
  ``H`` is strictly decreasing in 2D (``dH/dg = -mu det W / D^2``). Hence in **2D** ``F`` is
  strictly decreasing (``F' <= -1``) on the interval of ``b`` where ``D > 0``, running from
  ``+inf`` to ``-inf``: exactly one physical root, always (no root choice needed).
* In **3D** there can be several physical roots (found for large ``mu`` with strongly coupled
  ``W``; e.g. three). For a fixed normal impulse ``p`` the tangential equation
  ``b = a + p (W_TN - mu W_TT g(b))`` has a *unique* solution ``b(p)`` (strongly monotone),
  so the physical roots are exactly the zeros of the scalar ``R(p) = p D(g(b(p))) - c``
  (``R = v_fN(p) + e v_N``), with ``R(p) < 0`` for ``p < c / (W_NN + mu |W_TN|)``.
  **Root choice: the smallest ``P_N``**, i.e. the first ``p`` at which, accumulating normal
  impulse from 0 through Smith-consistent states, the normal velocity reaches ``-e v_N``
  (the same "first time the termination condition holds" reading as Routh's process). In
  every multi-root case we examined it is also the root continued from ``mu -> 0`` and
  from a weak impact ``v_N -> 0``, and the one closest to ``a``. Two roots never share a
  ``P_N``, so the rule is a total order. A physical root always exists for ``a != 0``
  (degree argument: continuation from ``mu = 0``, where the root is unique, with every
  root kept inside the energy bound and away from ``D = 0``), so ``MODE_NO_SOLUTION`` is
  not expected for valid input.

Algorithms and special cases (iteration counts are typical; limits are named below):

* 2D: the forward-slip branch (``b >= 0``, g = 1) is closed form; otherwise, with
  ``t = -b/a``, F = 0 is a cubic in t bracketed on the physical interval and solved by
  safeguarded Halley (3-4 cubic evaluations), then g is polished in g itself. No scan is
  needed: the root is unique. 10-12 M contacts/s per thread in a plain njit loop.
* 3D, planar motion (``W_T2N = W_T1T2 = 0`` once ``a`` lies along t1): reduced exactly to 2D
  (in-plane uniqueness of ``b(p)`` above).
* 3D, uniqueness certified (``_unique_certificate``: ``d^T S d > mu |d . W_TT J W_TN|`` for
  every unit d, ``S = W_NN W_TT - W_TN W_TN^T``, J the 90-degree rotation; then ``H`` is
  strictly anti-monotone and, with ``g`` monotone, two roots cannot exist): damped Newton
  on ``b`` from the 2D solution in the plane of ``(n, a)``, 2-5 iterations.
* 3D otherwise (or if that Newton fails): ``R(p)`` is sampled on a geometric grid (ratio
  ``SCAN_RATIO``) from ``c / (W_NN + mu |W_TN|)`` up to the energy bound, each ``b(p)``
  solved through an exact reduction to one scalar (``_solve_inner_3d``), warm-started along
  the grid with a tangent predictor; the first sign change is refined by safeguarded Newton
  on ``p``. Two roots closer than ``SCAN_RATIO`` in ``P_N`` could be skipped (the next one is
  then returned). About 15 grid points, ~60 scalar evaluations.
* ``a = 0`` (and ``|a|`` below ``A_ZERO_REL`` times the velocity scale): Smith's direction
  is 0/0 only at ``a = b = 0``; we read it as the set-valued sign (the unit ball), which is
  the limit of Smith's law as ``a -> 0`` from every direction. The result is Coulomb's
  inclusion along the final slip: **stick** (``b = 0``, mode ``MODE_STICK``, impulse
  strictly inside the cone) when ``|W_TT^-1 W_TN| <= mu``; otherwise slip along the unique
  direction ``u`` with ``(s I + mu W_TT) u = W_TN``, ``s > 0``, ``|u| = 1`` (2D:
  ``u = sign(W_TN)``), ``D > 0`` guaranteed. The literal "``P_T = 0`` at ``a = b = 0``"
  is rejected: it is not a solution (it gives ``b = W_TN P_N != 0``) and would make the law
  jump at ``a = 0`` (friction would vanish for an exactly non-sliding contact).

Modes: ``MODE_SEPARATING`` (``v_N >= 0``, P = 0); ``MODE_SLIP`` for every ordinary solution
(Smith never truly sticks; ``mu = 0`` is frictionless and also ``MODE_SLIP``); ``MODE_STICK``
only in the set-valued ``a = b = 0`` case; ``MODE_NO_SOLUTION`` for invalid input (non-finite
values, ``W`` not positive definite, ``e <= -1``, ``mu < 0``) or, in 3D, no sign change of
``R`` up to the energy bound (impossible in exact arithmetic); ``MODE_NOT_CONVERGED`` when an
iteration limit is hit. On failure ``P_out`` is zero.

Entry points: ``smith_2d`` / ``smith_3d`` / ``smith`` (the kernel contract of ``common.py``)
and ``smith_2d_scalar`` / ``smith_3d_scalar`` (scalars in, ``(mode, P...)`` out: no arrays,
so callers' loops pay no reference counting). All are ``error_model="numpy"``: a division by
zero can never raise; every non-finite outcome is turned into a failure mode.
"""
import math

from numba import njit

from .common import (MODE_NO_SOLUTION, MODE_NOT_CONVERGED, MODE_SEPARATING, MODE_SLIP,
                     MODE_STICK, P_E, P_MU, solve2)

# ---- named tolerances and limits --------------------------------------------------------------
# The law is homogeneous of degree 1 in v. The 2D solve uses only velocity ratios; the 3D
# kernel divides velocities by s = max(|v_N|, |v_T|). Tolerances are relative (to s, to the
# current iterate, or to the normal impulse) and dimensionless.
A_ZERO_REL = 1e-30
"""|v_T| / s below this is treated as exactly 0 (set-valued case). The induced change of the
final velocity is O((|v_T|/s)^(2/3)) <= 1e-20 relative, far below round-off; above it the
2D cubic in t = -b/a stays far from overflow (t <~ 1e30 W-ratio)."""
TOL_ROOT = 1e-14
"""Newton stops when its step is below TOL_ROOT * max(|b|, |a|) (b in 2D is the scalar final
slip; in 3D the vector): the directions g(b) then hold to ~1e-14, and the quadratic
convergence puts the returned root at round-off level."""
TOL_QUAD = 1e-8
"""3D Newton also stops right after a full step shorter than TOL_QUAD * max(|b|, |a|): by
quadratic convergence the error left is ~TOL_QUAD^2 (times an O(1) curvature factor)."""
TOL_P = 1e-14
"""3D scan path: relative tolerance on the normal impulse p in the outer root refinement."""
TOL_HALLEY = 1e-6
"""2D: the Halley iteration (cubic convergence) stops after a step below TOL_HALLEY * t; the
error left is then ~1e-18 relative, below round-off."""
G_POLISH_T = 4.0
"""2D: for a root t = -b/a <= G_POLISH_T (g >= -0.88) the direction g is polished by one
Newton step in g itself (full relative accuracy when g ~ 0, i.e. near-stick contacts)."""
MAXIT_2D = 100
"""2D safeguarded Halley limit (typically 3-4 evaluations; the bisection fallback halves
the bracket, so 100 is never reached for finite input). Also the 3D secular-equation limit."""
MAXIT_NEWTON_3D = 40
"""3D direct damped Newton (certified-unique case) limit; typically 2-5 iterations. On failure
the scan path takes over."""
MAXIT_INNER = 200
"""3D tangential sub-problem (fixed normal impulse): safeguarded Newton limit on its scalar
reduction (typically 2-4 warm-started; geometric bisection spans 1e+-300 within 200)."""
MAXIT_OUTER = 100
"""3D outer safeguarded Newton/bisection on R(p) limit."""
MAX_LINESEARCH = 40
"""Step halvings in a damped Newton line search before giving up."""
ARMIJO = 1e-4
"""Sufficient-decrease constant for the damped Newton merit |F|^2."""
SCAN_RATIO = 1.125
"""3D scan path: geometric ratio between successive normal impulses at which R(p) is sampled
(root-separation resolution of the smallest-P_N rule)."""
MAX_SCAN = 700
"""3D scan path: maximum number of samples (covers P_max / P_min up to ~1e35)."""
CERT_RTOL = 1e-12
"""Safety margin (relative to trace S) on the 3D uniqueness certificate against round-off."""
CERT_MAXIT = 8
"""Newton steps maximizing the concave certificate function phi(tau) (stops at phi > 0)."""
SECULAR_TOL = 1e-15
"""Set-valued 3D slip: relative tolerance on the secular-equation root s."""


# ================================================================================================
# 2D
# ================================================================================================
@njit(cache=True, error_model="numpy")
def _set_valued_2d(c, Wnn, wnt, Wtt, mu):
    """a = 0: Coulomb inclusion along the final slip (limit a -> 0). Returns mode, P_N, P_T."""
    if wnt > mu * Wtt:                       # normal impulse drives slip forward: g = +1
        PN = c / (Wnn - mu * wnt)            # > 0: Wnn - mu*wnt <= 0 would contradict det > 0
        return MODE_SLIP, PN, -mu * PN
    if wnt < -mu * Wtt:                      # drives it backward: g = -1
        PN = c / (Wnn + mu * wnt)
        return MODE_SLIP, PN, mu * PN
    det = Wnn * Wtt - wnt * wnt              # stick: v_fT = 0, |P_T| < mu P_N
    return MODE_STICK, c * Wtt / det, -c * wnt / det


@njit(cache=True, error_model="numpy")
def _solve_2d(vn, a_in, Wnn, Wnt, Wtt, e, mu):
    """Smith 2D core (v_N < 0, mu > 0, W SPD; any velocity scale: the solve is homogeneous).

    Returns (mode, P_N, P_T, b) with b = v_fT. Works with a >= 0 (tangent flipped if needed).

    With A = W_NN + mu W_NT, B = W_NN - mu W_NT (D at g = -1, +1), C1,2 = W_NT +- mu W_TT:
    * b >= 0 (forward slip, g = 1): F(b) = a + c C2/B - b, closed form; since F decreases on
      the physical interval, a root b+ >= 0 there is *the* root.
    * b < 0: with t = -b/a > 0, g = (1 - t^2)/(1 + t^2) and F = 0 is equivalent (on D > 0)
      to the cubic  q(t) = (1 + t)(A t^2 + B) + k (C1 t^2 + C2) = 0,  k = c/a,
      q = F (A t^2 + B)/a, increasing through its unique root on the physical interval
      {t > 0, A t^2 + B > 0}. Bracket: t > sqrt(-B/A) if B <= 0; t < sqrt(B/-A) if A < 0;
      t >= -(1 + k C1/A) if A > 0 (H(g) <= H(-1)). Safeguarded Halley iteration on q from
      the stick-like (sqrt(-C2/C1)) or reversal-like (-k C1/A) asymptote: typically 3-4
      evaluations of a cubic, one division each.
    """
    c = -(1.0 + e) * vn
    sg = 1.0
    if a_in < 0.0:
        sg = -1.0
    a = sg * a_in
    wnt = sg * Wnt
    if a <= A_ZERO_REL * -vn:
        mode, PN, PT = _set_valued_2d(c, Wnn, wnt, Wtt, mu)
        return mode, PN, sg * PT, sg * (a + wnt * PN + Wtt * PT)
    A = Wnn + mu * wnt
    B = Wnn - mu * wnt
    C1 = wnt + mu * Wtt
    C2 = wnt - mu * Wtt
    if B > 0.0:
        bplus = a + c * C2 / B
        if bplus >= 0.0:
            PN = c / B
            return MODE_SLIP, PN, -sg * mu * PN, sg * bplus
    k = c / a
    c3 = A
    c2 = A + k * C1
    c1 = B
    c0 = B + k * C2
    lo = 0.0
    hi = math.inf
    tb = 0.0
    if A > 0.0:
        if B <= 0.0:
            lo = math.sqrt(-B / A)           # pole; q(lo) < 0
        tb = -(1.0 + k * C1 / A)
        if tb > lo:
            lo = tb
    elif A < 0.0:
        hi = math.sqrt(B / -A)               # pole; q(hi) > 0
    # initial guess from the asymptotes (k -> inf)
    t = 1.0
    if C1 > 0.0 and C2 < 0.0:
        t = math.sqrt(-C2 / C1)
    if A > 0.0 and C1 < 0.0 and tb + 1.0 > t:
        t = tb + 1.0                         # -k C1 / A
    if hi == math.inf:
        h = max(2.0 * t, 2.0 * lo, 1.0)
        for j in range(2100):                # q -> +inf: doubling reaches q > 0
            if c0 + h * (c1 + h * (c2 + h * c3)) > 0.0:
                break
            h *= 2.0
        hi = h
    if not (t > lo and t < hi):
        t = 0.5 * (lo + hi)
    converged = False
    for it in range(MAXIT_2D):
        q = c0 + t * (c1 + t * (c2 + t * c3))
        if q == 0.0:
            converged = True
            break
        dq = c1 + t * (2.0 * c2 + 3.0 * t * c3)
        d2q = 2.0 * c2 + 6.0 * c3 * t
        if q < 0.0:
            lo = t
        else:
            hi = t
        step = -2.0 * q * dq / (2.0 * dq * dq - q * d2q)      # Halley
        tn = t + step
        inside = tn > lo and tn < hi
        if inside and abs(step) <= TOL_HALLEY * t:   # cubic convergence: error << 1e-16
            t = tn
            converged = True
            break
        if not inside:
            tn = 0.5 * (lo + hi)
            if hi - lo <= TOL_ROOT * hi:
                t = tn
                converged = True
                break
        t = tn
    if not converged:
        return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0
    if t <= G_POLISH_T:
        # g = (1 - t^2)/(1 + t^2) loses relative accuracy near g = 0 (t ~ 1), where the
        # root is well conditioned in g itself: one Newton step on
        # E(g) = (1 + t(g)) D(g) + k N(g), t(g) = sqrt((1 - g)/(1 + g)), N = W_NT - mu W_TT g
        # (E = 0 is F = 0 times D/a), from g(t) with 1 - t^2 = (1 - t)(1 + t).
        g = (1.0 - t) * (1.0 + t) / (1.0 + t * t)
        if g > -1.0 + 1e-3 and g < 1.0:
            tg = math.sqrt((1.0 - g) / (1.0 + g))
            Dg = Wnn - mu * wnt * g
            E = (1.0 + tg) * Dg + k * (wnt - mu * Wtt * g)
            dE = -Dg / (tg * (1.0 + g) * (1.0 + g)) - (1.0 + tg) * mu * wnt - k * mu * Wtt
            gn = g - E / dE
            if abs(gn - g) <= 1e-6 * (abs(g) + 1e-300) or abs(gn - g) <= 1e-12:
                g = gn
                t = math.sqrt((1.0 - g) / (1.0 + g))
    else:
        u2 = 1.0 / (t * t)
        g = (u2 - 1.0) / (u2 + 1.0)
    D = Wnn - mu * wnt * g
    if not (D > 0.0):                        # cannot happen: t stays in the physical bracket
        return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0
    PN = c / D
    return MODE_SLIP, PN, -sg * mu * PN * g, -sg * a * t


@njit(cache=True, error_model="numpy")
def smith_2d_scalar(vN, vt, Wnn, Wnt, Wtt, e, mu):
    """Smith 2D on scalars: returns ``(mode, P_N, P_T)``; same contract as ``smith_2d``.

    Scalars only (no arrays), so a caller's loop pays no reference counting for the call.
    The 2D solve is homogeneous in the velocities (it uses c/a and c/B only), so no
    rescaling is needed."""
    if vN >= 0.0:
        return MODE_SEPARATING, 0.0, 0.0
    c = -(1.0 + e) * vN
    if not (c > 0.0 and c < math.inf and abs(vt) < math.inf and mu >= 0.0
            and mu < math.inf and Wnn > 0.0 and Wnn < math.inf
            and Wtt - Wnt * (Wnt / Wnn) > 0.0 and Wtt < math.inf):
        return MODE_NO_SOLUTION, 0.0, 0.0
    if mu == 0.0:                            # frictionless fast path
        return MODE_SLIP, c / Wnn, 0.0
    mode, PN, PT, b = _solve_2d(vN, vt, Wnn, Wnt, Wtt, e, mu)
    if mode < 0 or not (PN < math.inf and abs(PT) < math.inf):
        return min(mode, MODE_NOT_CONVERGED), 0.0, 0.0
    return mode, PN, PT


@njit(cache=True, inline="always", error_model="numpy")
def smith_2d(v, W, params, P_out):
    """Smith's law, 2D contact: ``v = (v_N, v_T)`` (m/s), ``W`` 2x2 SPD (1/kg).

    Writes ``P_out = (P_N, P_T)`` (N s) and returns the mode. The physical root is unique
    (see module docstring): closed form on the forward-slip branch, else safeguarded Halley
    on a cubic in ``t = -v_fT / v_T`` (3-4 evaluations) and one Newton polish of ``g``."""
    mode, PN, PT = smith_2d_scalar(v[0], v[1], W[0, 0], W[0, 1], W[1, 1],
                                   params[P_E], params[P_MU])
    P_out[0] = PN
    P_out[1] = PT
    return mode


# ================================================================================================
# 3D (tangent frame rotated so that a = (alpha, 0))
# ================================================================================================
@njit(cache=True, error_model="numpy")
def _g3(b1, b2, al, al2):
    """g(b) for a = (al, 0), and its Jacobian B = dg/db (2x2, row-major)."""
    r2 = b1 * b1 + b2 * b2
    r = math.sqrt(r2)
    iq = 1.0 / (al2 + r2)
    g1 = (al2 + r * b1) * iq
    g2 = r * b2 * iq
    if r > 0.0:
        ir = 1.0 / r
        # B = (r I + b b^T / r) / Q - 2 g b^T / Q
        B11 = (r + b1 * b1 * ir) * iq - 2.0 * g1 * b1 * iq
        B12 = (b1 * b2 * ir) * iq - 2.0 * g1 * b2 * iq
        B21 = (b1 * b2 * ir) * iq - 2.0 * g2 * b1 * iq
        B22 = (r + b2 * b2 * ir) * iq - 2.0 * g2 * b2 * iq
    else:
        B11 = 0.0
        B12 = 0.0
        B21 = 0.0
        B22 = 0.0
    return g1, g2, B11, B12, B21, B22


@njit(cache=True, error_model="numpy")
def _full_3d(b1, b2, al, al2, c, Wnn, w1, w2, t11, t12, t22, mu):
    """Full residual F(b) = a + c H(g(b)) - b, its Jacobian, and D. D <= 0: not physical."""
    g1, g2, B11, B12, B21, B22 = _g3(b1, b2, al, al2)
    D = Wnn - mu * (w1 * g1 + w2 * g2)
    if not (D > 0.0):
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, D
    iD = 1.0 / D
    H1 = (w1 - mu * (t11 * g1 + t12 * g2)) * iD
    H2 = (w2 - mu * (t12 * g1 + t22 * g2)) * iD
    F1 = al + c * H1 - b1
    F2 = c * H2 - b2
    # dH/dg = (mu / D) (H w^T - T);  J = c (dH/dg) B - I
    k = c * mu * iD
    A11 = k * (H1 * w1 - t11)
    A12 = k * (H1 * w2 - t12)
    A21 = k * (H2 * w1 - t12)
    A22 = k * (H2 * w2 - t22)
    J11 = A11 * B11 + A12 * B21 - 1.0
    J12 = A11 * B12 + A12 * B22
    J21 = A21 * B11 + A22 * B21
    J22 = A21 * B12 + A22 * B22 - 1.0
    return F1, F2, J11, J12, J21, J22, D


@njit(cache=True, error_model="numpy")
def _inner_3d(b1, b2, al, al2, p, w1, w2, t11, t12, t22, mu):
    """Tangential sub-problem at normal impulse p: F = a + p (w - mu T g(b)) - b, Jacobian."""
    g1, g2, B11, B12, B21, B22 = _g3(b1, b2, al, al2)
    k = mu * p
    F1 = al + p * w1 - k * (t11 * g1 + t12 * g2) - b1
    F2 = p * w2 - k * (t12 * g1 + t22 * g2) - b2
    J11 = -k * (t11 * B11 + t12 * B21) - 1.0
    J12 = -k * (t11 * B12 + t12 * B22)
    J21 = -k * (t12 * B11 + t22 * B21)
    J22 = -k * (t12 * B12 + t22 * B22) - 1.0
    return F1, F2, J11, J12, J21, J22, g1, g2


@njit(cache=True, error_model="numpy")
def _lin2(J11, J12, J21, J22, r1, r2):
    """Solve the general 2x2 system J x = r (Cramer). det == 0 gives non-finite x."""
    det = J11 * J22 - J12 * J21
    return (J22 * r1 - J12 * r2) / det, (J11 * r2 - J21 * r1) / det


@njit(cache=True, error_model="numpy")
def _newton_full_3d(b1, b2, al, c, Wnn, w1, w2, t11, t12, t22, mu, maxit):
    """Damped Newton on the full residual from (b1, b2) (merit |F|^2, Armijo backtracking,
    D > 0 kept). Stops when the Newton step is below TOL_ROOT * max(|b|, |a|) (the step is
    then applied), or after a full step below TOL_QUAD * max(|b|, |a|). Returns (ok, b1, b2)."""
    al2 = al * al
    F1, F2, J11, J12, J21, J22, D = _full_3d(b1, b2, al, al2, c, Wnn, w1, w2, t11, t12, t22, mu)
    if not (D > 0.0):
        return False, b1, b2
    f = F1 * F1 + F2 * F2
    for it in range(maxit):
        if f == 0.0:
            return True, b1, b2
        d1, d2 = _lin2(J11, J12, J21, J22, -F1, -F2)
        nd = math.sqrt(d1 * d1 + d2 * d2)
        if not (nd < math.inf):
            return False, b1, b2
        scale = max(math.sqrt(b1 * b1 + b2 * b2), al)
        if nd <= TOL_ROOT * scale:
            return True, b1 + d1, b2 + d2
        t = 1.0
        accepted = False
        for ls in range(MAX_LINESEARCH):
            n1 = b1 + t * d1
            n2 = b2 + t * d2
            G1, G2, K11, K12, K21, K22, Dn = _full_3d(n1, n2, al, al2, c, Wnn, w1, w2,
                                                      t11, t12, t22, mu)
            if Dn > 0.0:
                fn = G1 * G1 + G2 * G2
                if fn <= (1.0 - ARMIJO * t) * f:
                    accepted = True
                    break
            t *= 0.5
        if not accepted:
            return False, b1, b2
        b1, b2 = n1, n2
        F1, F2, J11, J12, J21, J22, f = G1, G2, K11, K12, K21, K22, fn
        if t == 1.0 and nd <= TOL_QUAD * scale:
            return True, b1, b2
    return False, b1, b2


@njit(cache=True, error_model="numpy")
def _solve_inner_3d(b1, b2, al, p, w1, w2, t11, t12, t22, mu):
    """Unique solution of the tangential sub-problem at normal impulse p,

        b + mu p T g(b) = a + p w,    a = (al, 0),

    reduced to one scalar: with sigma = |b| / al, g = (al a + |b| b)/(al^2 + |b|^2) is affine
    in b, so b = al beta(sigma), beta = (I + k1 T)^-1 (e1 + (p/al) w - k2 T e1),
    k1 = (mu p / al) sigma / (1 + sigma^2), k2 = (mu p / al) / (1 + sigma^2); the root of
    psi(sigma) = |beta| / sigma - 1 (positive before it, negative after, unique) is found by
    safeguarded Newton from the warm start |(b1, b2)| / al. Scale-free in al, so a tiny
    initial slip is no harder than a large one.

    Returns (ok, b1, b2, g1, g2, J11, J12, J21, J22), J the sub-problem Jacobian at b."""
    q = p / al
    Pt = mu * q
    r1 = 1.0 + q * w1
    r2 = q * w2
    hi = (1.0 + q * math.sqrt(w1 * w1 + w2 * w2) + Pt * math.sqrt(t11 * t11 + t12 * t12)) \
        * 1.01 + 1.0                         # |beta| <= |rhs| (|(I + k1 T)^-1| <= 1)
    lo = 0.0
    sig = math.sqrt(b1 * b1 + b2 * b2) / al
    if not (sig > 0.0 and sig < hi):
        sig = 1.0 if hi > 2.0 else 0.5 * hi
    ok = False
    be1 = 0.0
    be2 = 0.0
    for it in range(MAXIT_INNER):
        den = 1.0 + sig * sig
        k1 = Pt * sig / den
        k2 = Pt / den
        m11 = 1.0 + k1 * t11
        m12 = k1 * t12
        m22 = 1.0 + k1 * t22
        h1 = r1 - k2 * t11
        h2 = r2 - k2 * t12
        idet = 1.0 / (m11 * m22 - m12 * m12)
        be1 = (m22 * h1 - m12 * h2) * idet
        be2 = (m11 * h2 - m12 * h1) * idet
        nb = math.sqrt(be1 * be1 + be2 * be2)
        psi = nb / sig - 1.0
        if psi == 0.0:
            ok = True
            break
        if psi > 0.0:
            lo = sig
        else:
            hi = sig
        # d beta / d sigma = (I + k1 T)^-1 (-k2' T e1 - k1' T beta)
        iden2 = 1.0 / (den * den)
        dk1 = Pt * (1.0 - sig * sig) * iden2
        dk2 = -2.0 * Pt * sig * iden2
        v1 = -dk2 * t11 - dk1 * (t11 * be1 + t12 * be2)
        v2 = -dk2 * t12 - dk1 * (t12 * be1 + t22 * be2)
        d1 = (m22 * v1 - m12 * v2) * idet
        d2 = (m11 * v2 - m12 * v1) * idet
        dpsi = (be1 * d1 + be2 * d2) / (nb * sig) - nb / (sig * sig)
        step = -psi / dpsi
        sn = sig + step
        inside = sn > lo and sn < hi
        if inside and abs(step) <= TOL_ROOT * sig:
            ok = True
            break
        if not inside:                       # bisection, geometric across scales
            if lo > 0.0 and hi < 4.0 * lo:
                sn = 0.5 * (lo + hi)
            elif lo > 0.0:
                sn = math.sqrt(lo * hi)
            else:
                sn = 1e-3 * hi
            if hi - lo <= TOL_ROOT * hi:
                ok = True
                break
        sig = sn
    b1 = al * be1
    b2 = al * be2
    F1, F2, J11, J12, J21, J22, g1, g2 = _inner_3d(b1, b2, al, al * al, p, w1, w2,
                                                   t11, t12, t22, mu)
    if not (abs(g1) <= 1.0 and abs(g2) <= 1.0 and abs(J11 * J22) < math.inf):
        ok = False
    return ok, b1, b2, g1, g2, J11, J12, J21, J22


@njit(cache=True, error_model="numpy")
def _set_valued_3d(c, Wnn, w1, w2, t11, t12, t22, mu):
    """a = 0 in 3D: stick if |T^-1 w| <= mu, else slip along the unique u with
    (s I + mu T) u = w, s > 0, |u| = 1. Returns (mode, P_N, k1, k2, f) with
    P_T = -f P_N (k1, k2): stick (T^-1 w, 1), slip (u, mu)."""
    y1, y2 = solve2(t11, t12, t22, w1, w2)   # T^-1 w
    if math.hypot(y1, y2) <= mu:              # (hypot: no underflow for tiny mu)
        PN = c / (Wnn - (w1 * y1 + w2 * y2))  # c M_NN (Schur complement > 0)
        return MODE_STICK, PN, y1, y2, 1.0
    # secular equation in the scaled unknowns (w/|w|, s/|w|, m = mu/|w| <= 1/lambda_min(T)):
    # f(s) = 1/|y(s)| - 1 = 0, y(s) = (s I + m T)^-1 w/|w|; f increasing, f(0) < 0 <= f(1).
    # Safeguarded Newton; f' = |y|^-3 y.(s I + m T)^-1 y.
    nw = math.hypot(w1, w2)
    e1 = w1 / nw
    e2 = w2 / nw
    m = mu / nw
    lo = 0.0
    hi = 1.0
    s = 0.5
    ok = False
    for it in range(MAXIT_2D):
        u1, u2 = solve2(s + m * t11, m * t12, s + m * t22, e1, e2)
        ny = math.sqrt(u1 * u1 + u2 * u2)
        f = 1.0 / ny - 1.0
        if f == 0.0:
            ok = True
            break
        if f < 0.0:
            lo = s
        else:
            hi = s
        z1, z2 = solve2(s + m * t11, m * t12, s + m * t22, u1, u2)
        df = (u1 * z1 + u2 * z2) / (ny * ny * ny)
        step = -f / df
        sn = s + step
        inside = sn > lo and sn < hi
        if inside and abs(step) <= SECULAR_TOL * s:
            s = sn
            ok = True
            break
        if not inside:
            sn = 0.5 * (lo + hi)
            if hi - lo <= SECULAR_TOL * hi:
                s = sn
                ok = True
                break
        s = sn
    if not ok:
        return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0, 0.0
    u1, u2 = solve2(s + m * t11, m * t12, s + m * t22, e1, e2)
    ny = math.hypot(u1, u2)
    u1 /= ny
    u2 /= ny
    PN = c / (Wnn - mu * (w1 * u1 + w2 * u2))  # D > 0 proved: Wnn > w.T^-1 w > mu w.u
    return MODE_SLIP, PN, u1, u2, mu


@njit(cache=True, error_model="numpy")
def _unique_certificate(Wnn, w1, w2, t11, t12, t22, mu):
    """True if the 3D Smith equation provably has at most one physical root.

    Two roots b1 != b2 would give (b1 - b2).(G1 - G2) >= 0 (g monotone) and
    (b1 - b2).(G1 - G2) = c (H(G1) - H(G2)).(G1 - G2) = c int d^T (dH/dG) d, with
    D^2/mu d^T (dH/dG) d = -d^T S d + mu (d.x)(JG.d), S = W_NN T - w w^T, x = T J w
    (identity (w.G) I - G w^T = (J w)(J G)^T, J the 90-degree rotation). Since |JG| <= 1,
    uniqueness follows if  d^T S d > mu |d.x|  for every unit d. By trust-region (S-lemma)
    duality that holds iff  phi(tau) = tau - mu^2/4 x^T (S - tau I)^-1 x > 0  for some
    tau < lambda_min(S); phi is concave, maximized by a few Newton steps (any positive
    value is a valid certificate)."""
    s11 = Wnn * t11 - w1 * w1
    s22 = Wnn * t22 - w2 * w2
    s12 = Wnn * t12 - w1 * w2
    tr = s11 + s22
    lmin = 0.5 * (tr - math.sqrt((s11 - s22) * (s11 - s22) + 4.0 * s12 * s12))
    margin = CERT_RTOL * tr
    if not (lmin > margin):
        return False
    x1 = t11 * w2 - t12 * w1
    x2 = t12 * w2 - t22 * w1
    m4 = 0.25 * mu * mu
    if m4 * (x1 * x1 + x2 * x2) == 0.0:
        return True
    tau = 0.5 * lmin
    for it in range(CERT_MAXIT):
        a11 = s11 - tau
        a22 = s22 - tau
        y1, y2 = solve2(a11, s12, a22, x1, x2)           # (S - tau I)^-1 x
        phi = tau - m4 * (x1 * y1 + x2 * y2)
        if phi > margin:
            return True
        z1, z2 = solve2(a11, s12, a22, y1, y2)
        d1 = 1.0 - m4 * (y1 * y1 + y2 * y2)               # phi'
        d2 = -2.0 * m4 * (y1 * z1 + y2 * z2)              # phi'' < 0
        tn = tau - d1 / d2
        if tn >= lmin:
            tn = 0.5 * (tau + lmin)
        if not (tn > -math.inf) or abs(tn - tau) <= 1e-12 * lmin:
            return False
        tau = tn
    return False


@njit(cache=True, error_model="numpy")
def smith_3d_scalar(vN, a1, a2, Wnn, W01, W02, T11, T12, T22, e, mu):
    """Smith 3D on scalars (upper triangle of W): returns ``(mode, P_N, P_T1, P_T2)``.

    Same contract as ``smith_3d``; scalars only, so a caller's loop pays no reference
    counting for the call. W is divided by W_NN (the law is homogeneous of degree -1 in W)
    so that no intermediate over- or underflows for extreme masses."""
    if vN >= 0.0:
        return MODE_SEPARATING, 0.0, 0.0, 0.0
    c = -(1.0 + e) * vN
    if not (c > 0.0 and c < math.inf and abs(a1) < math.inf and abs(a2) < math.inf
            and mu >= 0.0 and mu < math.inf and Wnn > 0.0 and Wnn < math.inf):
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    if mu == 0.0:                            # frictionless fast path
        return MODE_SLIP, c / Wnn, 0.0, 0.0
    iw = 1.0 / Wnn
    W01 *= iw
    W02 *= iw
    T11 *= iw
    T12 *= iw
    T22 *= iw
    # SPD check (W symmetric, upper triangle read): Schur complement of W_NN = 1 is SPD
    s11 = T11 - W01 * W01
    s12 = T12 - W01 * W02
    s22 = T22 - W02 * W02
    if not (s11 > 0.0 and s11 * s22 - s12 * s12 > 0.0 and s22 < math.inf
            and abs(s12) < math.inf):
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    mode, PN, P1, P2, s = _smith_3d_core(vN, a1, a2, 1.0, W01, W02, T11, T12, T22, e, mu)
    fac = s * iw                             # P = P' s / W_NN (P' for normalized v and W)
    PN *= fac
    P1 *= fac
    P2 *= fac
    if mode < 0 or not (PN < math.inf and abs(P1) < math.inf and abs(P2) < math.inf):
        return min(mode, MODE_NOT_CONVERGED), 0.0, 0.0, 0.0
    return mode, PN, P1, P2


@njit(cache=True, error_model="numpy")
def _smith_3d_core(vN, a1, a2, Wnn, W01, W02, T11, T12, T22, e, mu):
    """3D solve on validated input (v_N < 0, mu > 0, W SPD with W_NN = 1). Velocities are
    divided by s = max(|v_N|, |v_T|); returns (mode, P_N', P_T1', P_T2', s) with P' the
    impulse for the normalized velocities (P = P' s)."""
    al2 = a1 * a1 + a2 * a2
    al = math.sqrt(al2) if (al2 > 1e-290 and al2 < 1e290) else math.hypot(a1, a2)
    s = max(-vN, al)
    vn = vN / s
    cn = -(1.0 + e) * vn
    aln = al / s
    if aln <= A_ZERO_REL:
        mode, PN, k1, k2, f = _set_valued_3d(cn, Wnn, W01, W02, T11, T12, T22, mu)
        if mode < 0:
            return mode, 0.0, 0.0, 0.0, s
        return mode, PN, -f * (PN * k1), -f * (PN * k2), s
    # rotate the tangent frame: R a = (al, 0), R = [[cs, sn], [-sn, cs]]
    cs = a1 / al
    sn = a2 / al
    w1 = cs * W01 + sn * W02
    w2 = -sn * W01 + cs * W02
    t11 = cs * cs * T11 + 2.0 * cs * sn * T12 + sn * sn * T22
    t22 = sn * sn * T11 - 2.0 * cs * sn * T12 + cs * cs * T22
    t12 = (cs * cs - sn * sn) * T12 + cs * sn * (T22 - T11)
    if w2 == 0.0 and t12 == 0.0:
        # planar motion (W_T2N = W_T1T2 = 0, a along t1): the tangential sub-problem at every
        # normal impulse p has a unique, hence mirror-symmetric, i.e. in-plane solution, so
        # every 3D root is a root of the 2D law, which has exactly one: solve it in 2D.
        m2d, PN2, PT2, b2d = _solve_2d(vn, aln, Wnn, w1, t11, e, mu)
        if m2d < 0:
            return m2d, 0.0, 0.0, 0.0, s
        return m2d, PN2, cs * PT2, sn * PT2, s
    cert = _unique_certificate(Wnn, w1, w2, t11, t12, t22, mu)
    ok = False
    b1 = 0.0
    b2 = 0.0
    mode = MODE_SLIP
    if cert:
        # start: Smith 2D in the plane of (n, a) (exact when the motion is planar)
        m2d, PN2, PT2, b2d = _solve_2d(vn, aln, Wnn, w1, t11, e, mu)
        if m2d >= 0:
            ok, b1, b2 = _newton_full_3d(b2d, 0.0, aln, cn, Wnn, w1, w2, t11, t12, t22, mu,
                                         MAXIT_NEWTON_3D)
    if not ok:
        # scan path (also the fallback); W rotated consistently for the energy bound
        mode, PN, b1, b2 = _scan_3d_frame(vn, aln, cn, Wnn, w1, w2, t11, t12, t22, mu)
        if mode < 0:
            return mode, 0.0, 0.0, 0.0, s
        # polish on the full residual (keeps the same root: tiny steps only)
        ok2, c1, c2 = _newton_full_3d(b1, b2, aln, cn, Wnn, w1, w2, t11, t12, t22, mu, 3)
        if ok2 and (c1 - b1) ** 2 + (c2 - b2) ** 2 <= 1e-12 * (b1 * b1 + b2 * b2 + aln * aln):
            b1, b2 = c1, c2
    g1, g2, B11, B12, B21, B22 = _g3(b1, b2, aln, aln * aln)
    gn = math.sqrt(g1 * g1 + g2 * g2)
    if gn > 1.0:                             # round-off guard: keep |P_T| <= mu P_N
        g1 /= gn
        g2 /= gn
    D = Wnn - mu * (w1 * g1 + w2 * g2)
    if not (D > 0.0):                        # cannot happen (Newton keeps D > 0; D = c/p)
        return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0, s
    PN = cn / D
    k1 = cs * g1 - sn * g2                   # g back in the caller's tangent basis
    k2 = sn * g1 + cs * g2
    return mode, PN, -mu * (PN * k1), -mu * (PN * k2), s


@njit(cache=True, inline="always", error_model="numpy")
def smith_3d(v, W, params, P_out):
    """Smith's law, 3D contact: ``v = (v_N, v_T1, v_T2)`` (m/s), ``W`` 3x3 SPD (1/kg).

    Writes ``P_out = (P_N, P_T1, P_T2)`` (N s) and returns the mode. Root choice: smallest
    ``P_N`` (see module docstring). If the uniqueness certificate holds, damped Newton on
    ``b = v_fT`` from the 2D solution in the plane of ``(n, a)`` (typically 2-5 iterations);
    otherwise (or if that fails) the ``R(p)`` scan path."""
    mode, PN, P1, P2 = smith_3d_scalar(v[0], v[1], v[2], W[0, 0], W[0, 1], W[0, 2], W[1, 1],
                                       W[1, 2], W[2, 2], params[P_E], params[P_MU])
    P_out[0] = PN
    P_out[1] = P1
    P_out[2] = P2
    return mode


@njit(cache=True, error_model="numpy")
def _scan_3d_frame(vn, al, c, Wnn, w1, w2, t11, t12, t22, mu):
    """Scan path in the rotated frame (builds no array: the energy bound uses cofactors)."""
    # K = v^T W^-1 v and M_NN = (W^-1)_NN via cofactors of the rotated W
    c00 = t11 * t22 - t12 * t12
    c01 = w2 * t12 - w1 * t22
    c02 = w1 * t12 - t11 * w2
    c11 = Wnn * t22 - w2 * w2
    det = Wnn * c00 + w1 * c01 + w2 * c02
    # v = (vn, al, 0)
    K = (c00 * vn * vn + 2.0 * c01 * vn * al + c11 * al * al) / det
    mnn = c00 / det
    return _scan_core(al, c, Wnn, w1, w2, t11, t12, t22, mu, mnn, K)


@njit(cache=True, error_model="numpy")
def _scan_core(al, c, Wnn, w1, w2, t11, t12, t22, mu, mnn, K):
    """Smallest-P_N root via R(p) = p D(g(b(p))) - c: geometric scan + safeguarded Newton.

    Returns (mode, P_N, b1, b2) in the rotated, normalized frame."""
    wn = math.sqrt(w1 * w1 + w2 * w2)
    pmin = c / (Wnn + mu * wn)               # R(p) < 0 below this (D <= Wnn + mu |w|)
    pmax = 2.0 * math.sqrt(abs(mnn * K)) * (1.0 + 1e-6)   # energy bound on any root's P_N
    if not (pmax > pmin):
        pmax = pmin * SCAN_RATIO
    pl = 0.0
    bl1 = al
    bl2 = 0.0
    p = pmin
    # predictor from p = 0 (b = a, g = a/|a| = e1, J = -I): b ~ a + p (w - mu T e1)
    b1 = al + p * (w1 - mu * t11)
    b2 = p * (w2 - mu * t12)
    found = False
    exhausted = False
    R = -c
    g1 = 1.0
    g2 = 0.0
    J11 = -1.0
    J12 = 0.0
    J21 = 0.0
    J22 = -1.0
    for k in range(MAX_SCAN):
        ok, b1, b2, g1, g2, J11, J12, J21, J22 = _solve_inner_3d(b1, b2, al, p, w1, w2,
                                                                 t11, t12, t22, mu)
        if not ok:
            return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0
        R = p * (Wnn - mu * (w1 * g1 + w2 * g2)) - c
        if R >= 0.0:
            found = True
            break
        pl = p
        bl1 = b1
        bl2 = b2
        if p >= pmax:
            exhausted = True
            break
        pn = min(p * SCAN_RATIO, pmax)
        # tangent predictor: db/dp = -J^-1 (w - mu T g)
        db1, db2 = _lin2(J11, J12, J21, J22, -(w1 - mu * (t11 * g1 + t12 * g2)),
                         -(w2 - mu * (t12 * g1 + t22 * g2)))
        if abs(db1) < math.inf and abs(db2) < math.inf:
            b1 += (pn - p) * db1
            b2 += (pn - p) * db2
        p = pn
    if not found:
        if exhausted:
            return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
        return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0
    if R == 0.0:
        return MODE_SLIP, p, b1, b2
    ph = p
    bh1 = b1
    bh2 = b2
    # Safeguarded Newton on R(p) in [pl, ph]; dR/dp = D - p mu w.(B db/dp),
    # db/dp = -J^-1 (w - mu T g), J the sub-problem Jacobian at the solution.
    for it in range(MAXIT_OUTER):
        D = Wnn - mu * (w1 * g1 + w2 * g2)
        r1 = w1 - mu * (t11 * g1 + t12 * g2)
        r2 = w2 - mu * (t12 * g1 + t22 * g2)
        db1, db2 = _lin2(J11, J12, J21, J22, -r1, -r2)
        gg = _g3(b1, b2, al, al * al)
        dg1 = gg[2] * db1 + gg[3] * db2
        dg2 = gg[4] * db1 + gg[5] * db2
        dR = D - p * mu * (w1 * dg1 + w2 * dg2)
        step = -R / dR
        pn = p + step
        if pn > pl and pn < ph and abs(step) <= TOL_P * p:
            # converged: one more inner solve at the corrected p (warm, ~1 iteration)
            p = pn
            ok, b1, b2, g1, g2, J11, J12, J21, J22 = _solve_inner_3d(b1, b2, al, p, w1, w2,
                                                                     t11, t12, t22, mu)
            if not ok:
                return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0
            return MODE_SLIP, p, b1, b2
        if not (pn > pl and pn < ph):
            pn = 0.5 * (pl + ph)
            if ph - pl <= TOL_P * ph:
                return MODE_SLIP, p, b1, b2
        # warm start from the nearer bracket end's solution
        if abs(pn - pl) < abs(ph - pn):
            s1, s2 = bl1, bl2
        else:
            s1, s2 = bh1, bh2
        p = pn
        ok, b1, b2, g1, g2, J11, J12, J21, J22 = _solve_inner_3d(s1, s2, al, p, w1, w2,
                                                                 t11, t12, t22, mu)
        if not ok:
            return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0
        R = p * (Wnn - mu * (w1 * g1 + w2 * g2)) - c
        if R == 0.0:
            return MODE_SLIP, p, b1, b2
        if R > 0.0:
            ph = p
            bh1 = b1
            bh2 = b2
        else:
            pl = p
            bl1 = b1
            bl2 = b2
    return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0


@njit(cache=True, inline="always", error_model="numpy")
def smith(v, W, params, P_out):
    """Smith's law; 2D or 3D chosen by ``v.shape[0]`` (see ``smith_2d`` / ``smith_3d``)."""
    if v.shape[0] == 2:
        return smith_2d(v, W, params, P_out)
    return smith_3d(v, W, params, P_out)
