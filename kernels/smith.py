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
  Next to the pole of P_N (root with D < DPOLE_REL W_NN, near-singular W or weak impacts
  with large slips) t cannot resolve the root (it can lie within an ulp of the pole) and
  D = W_NN - mu W_NT g cancels: there the equation is solved for D itself
  (``_phi_2d``/``_pole_solve_2d``, det W compensated), and the cubic's bracket stops at
  D = DPOLE_REL W_NN. Small branch denominators A, B and the set-valued case use
  compensated products (``_sub_prod``, ``common.det2k``).
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
* 3D accuracy: W is scaled by a power of two (exact). The scan's normal equation switches to
  the stick-slope form ``R = p sch + z.(b - a) - c`` (``_r_eval``; ``common.schur3`` and a
  refined z = W_TT^-1 w) next to the pole and wherever R is less sensitive to the round-off
  of b(p) in that form (``_stick_form``): for a large normal impulse (p |W| >> |v|) b(p)
  carries eps p (|W_TN| + mu |W_TT|), which the direct form p D(g(b)) - c amplifies by
  ~p mu |W_TN| / |b| (it reported sign changes of R far from any root, where the true D was
  ~1e-9 W_NN, for mu |W_TN| >~ 1e3 W_NN and cond(W) >~ 1e11). Next to the pole
  (D < DPOLE_REL W_NN) or for an ill-conditioned W (away from stick) the root is polished in
  the caller's frame by Newton in (P_N, d = a + b) (``_caller_polish_3d``), with the
  residuals of v_fN = -e v_N and v_fT = b evaluated in Dot2 for the returned float impulse.
  There g (|g| ~ 1 ulp moves D = W_NN - mu w.g by eps mu |w|) and the rotated frame (W off
  by eps |W|) each cost P up to eps cond(W) or eps W_NN / D relative, while (P_N, d)
  resolves P to round-off (before, 5 of the stability suite's 300 random cases returned
  impulses off by up to a factor 3000). Near stick (|g| < G_POLISH_3D, large mu) away from
  the pole the root is polished by damped Newton in g itself, in the caller's frame with
  compensated D and N (``_polish_g_3d``), and the final D is compensated for the returned
  g. Checked against 60-digit references (tests) and on 3e4 draws each of the stability
  suite's stiff (cond(W) 1e8..1e12) and 2e4 of its moderate property: no failure. Weakness
  left: b(p) is still found in the rotated frame (W off by eps |W|), so the sign of R is
  uncertain where |R| is below ~eps p (|W_TN| + mu |W_TT|) |z|: two roots that close in P_N
  could be missed (a later root is then returned, as for roots closer than SCAN_RATIO).
* ``a = 0`` (and ``|a|`` below ``A_ZERO_REL`` times the velocity scale): Smith's direction
  is 0/0 only at ``a = b = 0``; we read it as the set-valued sign (the unit ball), which is
  the limit of Smith's law as ``a -> 0`` from every direction. The result is Coulomb's
  inclusion along the final slip: **stick** (``b = 0``, mode ``MODE_STICK``, impulse
  strictly inside the cone) when ``|W_TT^-1 W_TN| <= mu``; otherwise slip along the unique
  direction ``u`` with ``(s I + mu W_TT) u = W_TN``, ``s > 0``, ``|u| = 1`` (2D:
  ``u = sign(W_TN)``), ``D > 0`` guaranteed. The stick test uses W_TT^-1 W_TN by a refined
  solve; the 3D stick impulse ``P = W^-1 (c, 0, 0)`` comes from ``common.spd3_solve``
  (compensated and refined: ``c / schur3`` lost 2.7e-11 relative at cond(W) = 1e12, an
  energy gain at e = 1); the slip u comes from
  the secular system (scaled only by a power of two, so that a tiny or subnormal W_TN or mu
  neither underflows nor loses digits) refined against its compensated residual, D
  compensated. The literal "``P_T = 0`` at ``a = b = 0``" is rejected: it is not a solution
  (it gives ``b = W_TN P_N != 0``) and would make the law jump at ``a = 0`` (friction would
  vanish for an exactly non-sliding contact).
* 3D near stick with a tiny initial slip (|a| far below eps c mu |W_TT| / D, the round-off
  of the b-residual): the b-root is noise there, so the g-polish starts from the linearized
  stick solution (``_stick_start_3d``) when that has the smaller |E|, and where g cannot
  resolve b at the scale of |a| at all the stick solution is the answer (it tends to the
  set-valued stick as a -> 0), with the impulse ``W^-1 (c, b - a)`` from the linearized
  slip b (``_stick_impulse_3d``, forward accurate).

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

from .cache_guard import guard

# flush stale compiled code before the kernel modules below are imported (cache_guard)
guard(__name__, __file__)

from .common import (MODE_NO_SOLUTION, MODE_NOT_CONVERGED, MODE_SEPARATING, MODE_SLIP,
                     MODE_STICK, P_E, P_MU, det2k, det3s, schur3, solve2, spd3_solve, sub_dot3,
                     two_prod, two_sum)

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
quadratic convergence the error left is ~TOL_QUAD^2 (times an O(1) curvature factor). Not
used next to the pole (D < DPOLE_REL W_NN), where the curvature factor is ~W_NN / D."""
TOL_P = 1e-14
"""3D scan path: relative tolerance on the normal impulse p in the outer root refinement."""
TOL_HALLEY = 1e-6
"""2D: the Halley iteration (cubic convergence) stops after a step below TOL_HALLEY * t; the
error left is then ~1e-18 relative, below round-off."""
G_POLISH_T = 4.0
"""2D: for a root t = -b/a <= G_POLISH_T (g >= -0.88) the direction g is polished by Newton
in g itself, usually one step (full relative accuracy when g ~ 0, i.e. near-stick contacts)."""
MAXIT_POLISH_2D = 8
"""2D: further Newton steps of the g-polish after the first (``_polish_g_2d_more``; 4-6 from
an eps-accurate g to a root with |g| ~ 1e-100, quadratic convergence)."""
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
G_POLISH_3D = 1e-2
"""3D: if |g| < G_POLISH_3D at the root (near stick, large mu), or the root lies next to the
pole (D < DPOLE_REL W_NN), g is polished by Newton in g itself (``_polish_g_3d``): from b it
has ~eps / |g| relative error (|a| a + |b| b cancels for b ~ -a), and P_T = -mu P_N g needs
it relative; above it eps / |g| <= 2e-14."""
MAXIT_POLISH_3D = 12
"""3D: damped Newton steps of the g-polish (near stick, quadratic from an ~eps-absolute start:
1-2; next to the pole from a noisy b-root: a few more)."""
POLISH_SEP = 64.0
"""3D: the g-polish runs only if |a| > POLISH_SEP eps (c/D) mu |T| |g|, i.e. one ulp of g moves
b = a + c N(g)/D by well under |a| (otherwise g cannot represent the root finely enough and
the b-root is kept; its residual is then weighted by the tiny |a| anyway)."""
STICK_START_IT = 4
"""3D near-stick start (``_stick_start_3d``): fixed-point sweeps on D (typically 2-3)."""
UNSCALED_MAX_EXP = 64
"""3D: W is scaled by 2^-ex (W_NN -> [0.5, 1)) unless 1 <= W_NN < 2^UNSCALED_MAX_EXP and the
scaling would push a nonzero off-diagonal entry into the subnormal range (losing its digits)."""
N_REFINE = 3
"""Set-valued 3D: iterative-refinement steps of the 2x2 solves (each gains ~eps cond(T))."""
MAXIT_POLE = 8
"""3D caller-frame polish (``_caller_polish_3d``): Newton step limit; typically 2-3 from the
solver's root, each gaining a factor ~eps cond(W)."""
POLE_ACCEPT = 1e-14
"""3D caller-frame polish: if the line search stalls (round-off), the root is still accepted
when its residuals |F0|, |r| (velocities) are below POLE_ACCEPT times the size of their terms
(~|v| + |W| |P|): a backward error of 1e-14 relative to the velocity scale of v_f = v + W P,
against the stability suite's 1e-12."""
ILLCOND_POLISH = 1e3
"""3D: the caller-frame polish also runs (away from stick) when (trace W)^3 > ILLCOND_POLISH
det W, a cheap bound cond(W) <= (trace W)^3 / det W: the rotated frame (W off by eps |W|)
can then move the root by eps ILLCOND_POLISH ~ 2e-13 relative or more."""
G_PHI_SIGN = 1e-3
"""2D pole test: where |g| at D = DPOLE_REL W_NN is below this, the side of the root is decided
by the D-form Phi (``_phi_2d``) instead of the cubic in t: g from t has eps absolute (eps/|g|
relative) error, so for mu |W_NT| >> W_NN t no longer resolves D near DPOLE_REL W_NN."""
STICK_FORM_SENS = 2.0
"""3D scan: R(p) is evaluated in its stick-slope form where |z| (Q = |a|^2 + |b|^2) is below
STICK_FORM_SENS p mu |w| |b| / Q, a typical size of its sensitivity to b in the direct form
(``_stick_form``; the bound is 4 |b| / Q, the factor only moves the switch by 2x)."""
DPOLE_REL = 1.0 / 64.0
"""2D: a root whose D = W_NN - mu W_NT g is below DPOLE_REL * W_NN lies next to the pole of
P_N(b) (or of a near-pole end of the interval): there D is solved for directly
(``_pole_solve_2d``), since D from g or t cancels (relative error ~eps W_NN / D); above it
that error is <= 2 eps / DPOLE_REL ~ 3e-14. Also the threshold below which the branch
denominators A, B are recomputed compensated."""


# ================================================================================================
# 2D
# ================================================================================================
@njit(cache=True, error_model="numpy", inline="always")
def _sub_prod(x, m, y):
    """x - m y, compensated (two_prod, two_sum): a few ulps of the result for exact inputs,
    where the plain formula loses eps |x| / |x - m y| (the denominators D = W_NN - mu W_NT g
    at g = +-1 next to a pole)."""
    p, ep = two_prod(m, y)
    r, er = two_sum(x, -p)
    return r + (er - ep)


@njit(cache=True, error_model="numpy")
def _set_valued_2d(c, Wnn, wnt, Wtt, mu):
    """a = 0: Coulomb inclusion along the final slip (limit a -> 0). Returns mode, P_N, P_T.
    The denominators (W_NN -+ mu W_NT, det W) are compensated: each can cancel for a
    near-singular W (det W << W_NN W_TT) and P_N = c / D would carry eps W_NN / D."""
    # |W_NT| > mu W_TT decides slip; compared as (W_NT, mu) 2^-ex, |W_NT| 2^-ex in [0.5, 1)
    # (exact), since mu W_TT can round in the subnormal range (tiny mu: 1 ulp there is a
    # relative 1) and flip the mode (3D: _set_valued_3d makes the same exact decision)
    ex = math.frexp(wnt)[1] if wnt != 0.0 else 0
    muw = math.ldexp(mu, -ex) * Wtt
    wq = math.ldexp(wnt, -ex)
    if wq > muw:                             # normal impulse drives slip forward: g = +1
        PN = c / _sub_prod(Wnn, mu, wnt)     # > 0: Wnn - mu*wnt <= 0 would contradict det > 0
        return MODE_SLIP, PN, -mu * PN
    if wq < -muw:                            # drives it backward: g = -1
        PN = c / _sub_prod(Wnn, -mu, wnt)
        return MODE_SLIP, PN, mu * PN
    det = det2k(Wnn, Wtt, wnt, wnt)          # stick: v_fT = 0, |P_T| < mu P_N
    return MODE_STICK, c * Wtt / det, -c * wnt / det


@njit(cache=True, error_model="numpy")
def _phi_2d(D, k, Wnn, wnt, det, mu):
    """The 2D root equation in the unknown D = W_NN - mu W_NT g (a > 0, W_NT != 0):

        Phi(D) = D (W_NN (1 + t) + k W_NT) - k mu g det W = W_NN ((1 + t) D + k N(g)),

    g = (W_NN - D) / (mu W_NT), t = sqrt((1 - g)/(1 + g)) = -b/a, N = W_NT - mu W_TT g, using
    W_NN N = W_NT D - mu g det W. sign(Phi) = sign(F(b)); sign(W_NT) Phi < 0 below the root
    and > 0 above it. Every term keeps its relative accuracy for D << W_NN (det W
    compensated), where the t-cubic cancels. Returns (Phi, dPhi/dD, g, t)."""
    g = (Wnn - D) / (mu * wnt)
    g = min(max(g, -1.0), 1.0)
    t = math.sqrt((1.0 - g) / (1.0 + g))
    L = Wnn * (1.0 + t) + k * wnt
    phi = D * L - k * mu * g * det
    # dg/dD = -1/(mu W_NT), dt/dg = -1/(t (1 + g)^2)
    dphi = L + k * det / wnt + D * Wnn / (mu * wnt * t * (1.0 + g) * (1.0 + g))
    return phi, dphi, g, t


@njit(cache=True, error_model="numpy")
def _pole_solve_2d(k, Wnn, wnt, det, mu, Dhi):
    """Root D in (0, Dhi) of Phi (``_phi_2d``), known to lie there (sign(W_NT) Phi(Dhi) >= 0,
    sign(W_NT) Phi(0+) = -k mu |g_p| det < 0): safeguarded Newton from the Newton step at
    D = 0, with bisection (geometric across decades) on the bracket. The root is unique
    (sign(Phi) = sign(F) and F is strictly monotone). Returns (ok, D, g, t)."""
    sw = 1.0 if wnt > 0.0 else -1.0
    gp = min(max(Wnn / (mu * wnt), -1.0), 1.0)       # g at the pole (D = 0)
    tp = math.sqrt((1.0 - gp) / (1.0 + gp))
    lo = 0.0
    hi = Dhi
    D = k * mu * gp * det / (Wnn * (1.0 + tp) + k * wnt + k * det / wnt)
    if not (D > lo and D < hi):
        D = 0.5 * hi
    ok = False
    for it in range(MAXIT_2D):
        phi, dphi, g, t = _phi_2d(D, k, Wnn, wnt, det, mu)
        if phi == 0.0:
            ok = True
            break
        if sw * phi < 0.0:
            lo = D
        else:
            hi = D
        step = -phi / dphi
        Dn = D + step
        inside = Dn > lo and Dn < hi
        if inside and abs(step) <= TOL_ROOT * D:
            D = Dn
            ok = True
            break
        if not inside:
            if lo > 0.0 and hi < 4.0 * lo:
                Dn = 0.5 * (lo + hi)
            elif lo > 0.0:
                Dn = math.sqrt(lo * hi)
            else:
                Dn = 1e-8 * hi
            if hi - lo <= TOL_ROOT * hi:
                D = Dn
                ok = True
                break
        D = Dn
    phi, dphi, g, t = _phi_2d(D, k, Wnn, wnt, det, mu)
    return ok and D > 0.0, D, g, t


@njit(cache=True, error_model="numpy")
def _polish_g_2d_more(g, t, k, Wnn, wnt, Wtt, mu):
    """Further Newton steps of the 2D g-polish (rare: after a first step that moved g by more
    than 1e-8 of itself). From g(t) (eps absolute error) a root with |g| << eps (mu |W_NT| or
    mu W_TT k >> W_NN, e.g. g = 1.4e-100 for mu = 1e100, where t = 1 - 1.4e-100 rounds to 1)
    is reached quadratically (g -> ~mu W_NT g^2 / |E'|), with the terms linear in g of
    E(g) = (1 + t) D + k N cancelled analytically,

        g - E/E' = (g t'(g) D(g) - (1 + t) W_NN - k W_NT) / E',

    since g - E/E' in floating point keeps only ~eps |g| absolute accuracy. Same acceptance
    rule as the first step (small moves only). Returns (g, t)."""
    for ip in range(MAXIT_POLISH_2D):
        if not (g > -1.0 + 1e-3 and g < 1.0):
            break
        tg = math.sqrt((1.0 - g) / (1.0 + g))
        Dg = Wnn - mu * wnt * g
        dtg = -1.0 / (tg * (1.0 + g) * (1.0 + g))
        dE = Dg * dtg - (1.0 + tg) * mu * wnt - k * mu * Wtt
        gn = (g * dtg * Dg - (1.0 + tg) * Wnn - k * wnt) / dE
        if not (abs(gn - g) <= 1e-6 * (abs(g) + 1e-300) or abs(gn - g) <= 1e-12):
            break
        small = abs(gn - g) <= 1e-8 * abs(gn)
        g = gn
        t = math.sqrt((1.0 - g) / (1.0 + g))
        if small:
            break
    return g, t


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
    dthr = DPOLE_REL * Wnn
    if abs(A) < dthr:                        # cancels: compensated (sign and P_N = c / A)
        A = _sub_prod(Wnn, -mu, wnt)
    if abs(B) < dthr:
        B = _sub_prod(Wnn, mu, wnt)
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
    tth = 0.0
    pole = B <= 0.0 or A < 0.0
    if pole:
        # The interval ends at a pole of P_N (D = 0). If the root's D is below dthr, the cubic
        # cannot resolve it (t within ulps of the pole, D = (A t^2 + B)/(1 + t^2) cancels):
        # solve for D itself. Otherwise the bracket stops at D = dthr, away from the pole.
        # The sign test uses the cubic q at t(dthr) (sign q = sign Phi, and q is accurate
        # there, away from the pole); a wrong sign where the root sits at dthr itself only
        # picks the other, equally valid, solver. If g(dthr) is tiny (mu |W_NT| >> W_NN),
        # t(dthr) rounds to ~1 (g from t has eps absolute error: q could even be evaluated
        # on the wrong side of the root) and Phi(dthr) itself decides (its g is exact there).
        gth = min(max((Wnn - dthr) / (mu * wnt), -1.0), 1.0)
        tth = math.sqrt((1.0 - gth) / (1.0 + gth))
        det = 0.0
        if abs(gth) < G_PHI_SIGN:
            det = det2k(Wnn, Wtt, wnt, wnt)
            qth = _phi_2d(dthr, k, Wnn, wnt, det, mu)[0]
        else:
            qth = c0 + tth * (c1 + tth * (c2 + tth * c3))
        if qth * wnt >= 0.0:
            if det == 0.0:
                det = det2k(Wnn, Wtt, wnt, wnt)
            ok, D, g, t = _pole_solve_2d(k, Wnn, wnt, det, mu, dthr)
            if not ok:
                return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0
            PN = c / D
            return MODE_SLIP, PN, -sg * mu * PN * g, -sg * a * t
    if A > 0.0:
        if B <= 0.0:
            lo = tth                         # D = dthr, between the pole and the root
        tb = -(1.0 + k * C1 / A)
        if tb > lo:
            lo = tb
    elif A < 0.0:
        hi = tth                             # D = dthr; q(hi) > 0
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
        # Usually one step; more (_polish_g_2d_more) only if it moved g by more than 1e-8 of
        # itself (a root with |g| << eps, e.g. 1.4e-100 for mu = 1e100).
        if g > -1.0 + 1e-3 and g < 1.0:
            tg = math.sqrt((1.0 - g) / (1.0 + g))
            Dg = Wnn - mu * wnt * g
            E = (1.0 + tg) * Dg + k * (wnt - mu * Wtt * g)
            dE = -Dg / (tg * (1.0 + g) * (1.0 + g)) - (1.0 + tg) * mu * wnt - k * mu * Wtt
            gn = g - E / dE
            if abs(gn - g) <= 1e-6 * (abs(g) + 1e-300) or abs(gn - g) <= 1e-12:
                more = abs(gn - g) > 1e-8 * abs(gn)    # else quadratic: next step < eps
                g = gn
                t = math.sqrt((1.0 - g) / (1.0 + g))
                if more:
                    g, t = _polish_g_2d_more(g, t, k, Wnn, wnt, Wtt, mu)
    else:
        u2 = 1.0 / (t * t)
        g = (u2 - 1.0) / (u2 + 1.0)
    D = Wnn - mu * wnt * g
    if D < dthr and not pole:
        # near an end where A or B is small (g -> -1 or 1): the sum of positive terms keeps
        # full relative accuracy where Wnn - mu wnt g cancels
        D = (A * t * t + B) / (1.0 + t * t) if t < math.inf else A
    if not (D > 0.0):                        # cannot happen: t stays in the physical bracket
        return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0
    PN = c / D
    return MODE_SLIP, PN, -sg * mu * PN * g, -sg * a * t


@njit(cache=True, error_model="numpy")
def smith_2d_scalar(vN, vt, Wnn, Wnt, Wtt, e, mu):
    """Smith 2D on scalars: returns ``(mode, P_N, P_T)``; same contract as ``smith_2d``.

    Scalars only (no arrays), so a caller's loop pays no reference counting for the call.
    The 2D solve is homogeneous in the velocities (it uses c/a and c/B only), so no
    rescaling is needed. (W is not rescaled either: extreme masses, W_NN ~ 1e-200, can
    underflow det W; rescaling by a power of two here cost ~10% of the 2D kernel's time.)
    |P_T| = fl(fl(mu P_N) |g|) <= fl(mu P_N) holds by monotone rounding."""
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
        if t == 1.0 and nd <= TOL_QUAD * scale and Dn >= DPOLE_REL * Wnn:
            # (not next to the pole: there the quadratic-convergence constant ~ W_NN / D
            # is too large for this shortcut; iterate to TOL_ROOT)
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


@njit(cache=True, error_model="numpy", inline="always")
def _res_comp(r, t1, y1, t2, y2):
    """r - t1 y1 - t2 y2, compensated (two_prod / two_sum): the residual of an iterative
    refinement step must be accurate where it cancels."""
    p1, e1 = two_prod(t1, y1)
    p2, e2 = two_prod(t2, y2)
    q, eq = two_sum(p1, p2)
    d, ed = two_sum(r, -q)
    return d + (ed - eq - e1 - e2)


@njit(cache=True, error_model="numpy")
def _solve2_refined(a00, a01, a11, b0, b1):
    """Solve the SPD 2x2 system [[a00, a01], [a01, a11]] x = b: Cramer's rule with a
    compensated determinant, plus N_REFINE steps of iterative refinement with a compensated
    residual, so that x is right to ~eps relative for cond up to ~1e11 (Cramer's rule alone
    loses eps cond: the set-valued stick needs v_fT = P_N (w - T x) ~ 0 and
    P_N (W_NN - w.x) = c with P_N from the exact Schur complement)."""
    det = det2k(a00, a11, a01, a01)
    x0 = (a11 * b0 - a01 * b1) / det
    x1 = (a00 * b1 - a01 * b0) / det
    for it in range(N_REFINE):
        r0 = _res_comp(b0, a00, x0, a01, x1)
        r1 = _res_comp(b1, a01, x0, a11, x1)
        x0 += (a11 * r0 - a01 * r1) / det
        x1 += (a00 * r1 - a01 * r0) / det
    return x0, x1


@njit(cache=True, error_model="numpy")
def _set_valued_3d(c, Wnn, w1, w2, t11, t12, t22, mu):
    """a = 0 in 3D: stick if |T^-1 w| <= mu, else slip along the unique u with
    (s I + mu T) u = w, s > 0, |u| = 1. Returns (mode, P_N, k1, k2, f) with
    P_T = -f P_N (k1, k2): stick (T^-1 w, 1), slip (u, mu).

    The stick test and the secular system are homogeneous of degree 1 in (w, mu, sigma):
    they are solved for w and mu scaled by the power of two 2^-ex, |w| 2^-ex in [0.5, 1)
    (exact). Unscaled, a tiny coupling (|w| ~ 1e-195, mu ~ 1e-219) under- or overflows:
    det(sigma I + mu T) ~ |w|^2 underflows to 0 and the iteration never converged, and a
    subnormal w or mu loses its digits in T^-1 w and in the stick test."""
    nw = math.hypot(w1, w2)
    if nw == 0.0:                             # T^-1 w = 0: stick (friction not needed)
        return MODE_STICK, c / Wnn, 0.0, 0.0, 1.0
    ex = math.frexp(nw)[1]
    q1 = math.ldexp(w1, -ex)                  # w 2^-ex, |q| in [0.5, 1): exact unless a
    q2 = math.ldexp(w2, -ex)                  # component drops below 2^-1022 |q| (moot)
    muq = math.ldexp(mu, -ex)                 # mu 2^-ex (may be +inf: then stick)
    y1, y2 = _solve2_refined(t11, t12, t22, q1, q2)   # T^-1 w 2^-ex
    if math.hypot(y1, y2) <= muq:
        # c M_NN: the Schur complement W_NN - w.T^-1 w = det W / det T, compensated (by
        # Cramer's rule it cancels for near-singular W and can even come out negative);
        # _smith_3d_core replaces this impulse by a refined solve (spd3_solve) where it can
        PN = c / schur3(Wnn, w1, w2, t11, t12, t22)
        return MODE_STICK, PN, math.ldexp(y1, ex), math.ldexp(y2, ex), 1.0
    # secular equation in the scaled unknown s = sigma/|w| (m = mu/|w| <= 1/lambda_min(T)):
    # f(s) = 1/|u(s)| - 1 = 0, u(s) = (s I + m T)^-1 w/|w|; f increasing, f(0) < 0 <= f(1).
    # Safeguarded Newton; f' = |u|^-3 u.(s I + m T)^-1 u.
    nq = math.hypot(q1, q2)
    m = muq / nq
    lo = 0.0
    hi = 1.0
    s = 0.5
    ok = False
    for it in range(MAXIT_2D):
        # u(sigma) from the (power-of-two scaled, so exact) refined solve: the root must be
        # that of the exact system (the normalized one is off by eps cond(T), which moves |u|
        # next to the pole)
        u1, u2 = _solve_secular_u(s * nq, muq, q1, q2, t11, t12, t22)
        ny = math.sqrt(u1 * u1 + u2 * u2)
        f = 1.0 / ny - 1.0
        if f == 0.0:
            ok = True
            break
        if f < 0.0:
            lo = s
        else:
            hi = s
        # (s I + m T) u = e is the same system scaled by 1/|w|: f' = |u|^-3 u.(s I + m T)^-1 u
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
    # u from the unscaled system (sigma I + mu T) u = w, sigma = s |w|, refined against its
    # exact residual and not renormalized (|u| = 1 to the secular tolerance): next to the
    # pole (D << W_NN) both v_fN = v_N + P_N (W_NN - mu w.u) and the energy,
    # dE = -P_N^2 mu u.(w - mu T u) / 2 at e = 1, hinge on that residual, which the scaled
    # and normalized u leaves at eps cond(T).
    sig = s * nq                              # sigma 2^-ex
    u1, u2 = _solve_secular_u(sig, muq, q1, q2, t11, t12, t22)
    # D = W_NN - mu w.u > 0, compensated for this u (P_N D = c holds for the returned
    # impulse; unscaled: where mu w.u underflows it is below eps W_NN). The identity
    # D = (W_NN - w.T^-1 w) + sigma mu + sigma^2 u.T^-1 u (all terms positive; schur3
    # compensated) is the fallback.
    D = _sub_mu_dot(Wnn, mu, w1, u1, w2, u2)
    if not (D > 0.0):
        z1, z2 = _solve2_refined(t11, t12, t22, u1, u2)
        D = schur3(Wnn, w1, w2, t11, t12, t22) + math.ldexp(
            sig * muq + sig * sig * (u1 * z1 + u2 * z2), 2 * ex)
    PN = c / D
    return MODE_SLIP, PN, u1, u2, mu


@njit(cache=True, error_model="numpy")
def _sub_mu_dot(x, mu, w1, u1, w2, u2):
    """x - mu (w1 u1 + w2 u2), compensated (double-double dot product, then the product with
    mu): a few ulps of the result for exact inputs."""
    p1, e1 = two_prod(w1, u1)
    p2, e2 = two_prod(w2, u2)
    d, ed = two_sum(p1, p2)
    lo = ed + (e1 + e2)
    q, eq = two_prod(mu, d)
    eq += mu * lo
    r, er = two_sum(x, -q)
    return r + (er - eq)


@njit(cache=True, error_model="numpy", inline="always")
def _res_secular(w, sig, mu, ta, ua, tb, ub):
    """w - sig ua - mu ta ua - mu tb ub, compensated (mu t formed exactly as q + eq)."""
    p1, e1 = two_prod(sig, ua)
    q, eq = two_prod(mu, ta)
    p2, e2 = two_prod(q, ua)
    e2 += eq * ua
    q, eq = two_prod(mu, tb)
    p3, e3 = two_prod(q, ub)
    e3 += eq * ub
    r, er1 = two_sum(w, -p1)
    r, er2 = two_sum(r, -p2)
    r, er3 = two_sum(r, -p3)
    return r + ((er1 + er2 + er3) - (e1 + e2 + e3))


@njit(cache=True, error_model="numpy")
def _solve_secular_u(sig, mu, w1, w2, t11, t12, t22):
    """Solve (sig I + mu T) u = w: Cramer's rule with a compensated determinant, then
    N_REFINE steps of iterative refinement against the compensated residual of the
    unrounded matrix (each step gains a factor ~eps cond; 3 reach round-off for cond
    up to ~1e11)."""
    a00 = sig + mu * t11
    a01 = mu * t12
    a11 = sig + mu * t22
    det = det2k(a00, a11, a01, a01)
    u1 = (a11 * w1 - a01 * w2) / det
    u2 = (a00 * w2 - a01 * w1) / det
    for it in range(N_REFINE):
        r1 = _res_secular(w1, sig, mu, t11, u1, t12, u2)
        r2 = _res_secular(w2, sig, mu, t22, u2, t12, u1)
        u1 += (a11 * r1 - a01 * r2) / det
        u2 += (a00 * r2 - a01 * r1) / det
    return u1, u2


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
    counting for the call. W is scaled by the power of two 2^-ex nearest 1/W_NN (the law
    is homogeneous of degree -1 in W; the scaling is exact) so that no intermediate over- or
    underflows for extreme masses."""
    if vN >= 0.0:
        return MODE_SEPARATING, 0.0, 0.0, 0.0
    c = -(1.0 + e) * vN
    if not (c > 0.0 and c < math.inf and abs(a1) < math.inf and abs(a2) < math.inf
            and mu >= 0.0 and mu < math.inf and Wnn > 0.0 and Wnn < math.inf):
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    if mu == 0.0:                            # frictionless fast path
        return MODE_SLIP, c / Wnn, 0.0, 0.0
    # exact scaling by a power of two (W_NN -> m in [0.5, 1)): an inexact division would
    # perturb W by eps relative per entry, i.e. det W by eps cond(W)
    m, ex = math.frexp(Wnn)
    if ex > 0 and ex <= UNSCALED_MAX_EXP:
        # scaling down would round a tiny coupling into the subnormal range (W_TN = 5e-323
        # with W_NN = 100 became 0, turning a set-valued slip into a stick): keep W as is
        # (W_NN < 2^UNSCALED_MAX_EXP is still far from over- or underflow)
        tiny = math.ldexp(1.0, ex - 1022)
        if ((W01 != 0.0 and abs(W01) < tiny) or (W02 != 0.0 and abs(W02) < tiny)
                or (T12 != 0.0 and abs(T12) < tiny)):
            m = Wnn
            ex = 0
    if ex > -1000 and ex < 1000:             # 2^-ex is a normal number: multiply (exact)
        sc = math.ldexp(1.0, -ex)
        W01 *= sc
        W02 *= sc
        T11 *= sc
        T12 *= sc
        T22 *= sc
    else:
        W01 = math.ldexp(W01, -ex)
        W02 = math.ldexp(W02, -ex)
        T11 = math.ldexp(T11, -ex)
        T12 = math.ldexp(T12, -ex)
        T22 = math.ldexp(T22, -ex)
    # SPD check (W symmetric, upper triangle read): the Schur complement of W_NN is SPD
    s11 = T11 - W01 * (W01 / m)
    s12 = T12 - W01 * (W02 / m)
    s22 = T22 - W02 * (W02 / m)
    if not (s11 > 0.0 and s11 * s22 - s12 * s12 > 0.0 and s22 < math.inf
            and abs(s12) < math.inf):
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    mode, PN, P1, P2, s = _smith_3d_core(vN, a1, a2, m, W01, W02, T11, T12, T22, e, mu)
    tiny = mu * PN < 1e-290                  # P_T' = -mu P_N' g formed near/below subnormal
    # P = P' s 2^-ex (P' for the normalized v and W)
    if ex > -1000 and ex < 1000:
        sc = math.ldexp(s, -ex)
        PN *= sc
        P1 *= sc
        P2 *= sc
    else:
        PN = math.ldexp(PN * s, -ex)
        P1 = math.ldexp(P1 * s, -ex)
        P2 = math.ldexp(P2 * s, -ex)
    if mode < 0 or not (PN < math.inf and abs(P1) < math.inf and abs(P2) < math.inf):
        return min(mode, MODE_NOT_CONVERGED), 0.0, 0.0, 0.0
    cone = mu * PN
    if tiny and math.hypot(P1, P2) > cone:
        # round-off: for a tiny mu, P_T = -mu P_N g is formed in the normalized units in the
        # subnormal range (one ulp is a large relative error) and then scaled: pull it back
        # into the cone (|P_T| <= mu P_N is part of the law), by ulps where subnormal. Its
        # direction keeps only the few bits of the subnormal P_T' (mu < ~1e-290 only).
        # (Elsewhere the cone holds to round-off: no hypot on the hot path.)
        r = cone / math.hypot(P1, P2)
        P1 *= r
        P2 *= r
        for it in range(8):
            if not (math.hypot(P1, P2) > cone):
                break
            if abs(P1) >= abs(P2):
                P1 -= math.copysign(5e-324, P1)
            else:
                P2 -= math.copysign(5e-324, P2)
    return mode, PN, P1, P2


@njit(cache=True, error_model="numpy")
def _smith_3d_core(vN, a1, a2, Wnn, W01, W02, T11, T12, T22, e, mu):
    """3D solve on validated input (v_N < 0, mu > 0, W SPD with W_NN in [0.5, 1)). Velocities are
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
        if mode == MODE_STICK:
            # stick: P = W^-1 (c, 0, 0) by the refined compensated solve (few ulps normwise
            # up to cond(W) ~1e14). c / schur3 loses ~eps^2 |W|^3 / det W relative (2.7e-11 at
            # cond(W) = 1e12): at e = 1 the energy error is v_fN dP_N, i.e. a gain.
            okr, x0, x1, x2 = spd3_solve(Wnn, W01, W02, T11, T12, T22, cn, 0.0, 0.0)
            if okr and x0 > 0.0 and x0 < math.inf and math.hypot(x1, x2) <= mu * x0:
                return mode, x0, x1, x2, s
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
    Tn = abs(T11) + abs(T22) + 2.0 * abs(T12)
    if aln * Wnn < POLISH_SEP * 2.2e-16 * cn * mu * Tn:
        # (cheap pre-test, |g| <= 1, D >= W_NN for the stick-like roots it is meant for)
        # a slip so small that one ulp of a near-stick g moves b by more than |a|: every
        # b- or p-based residual is round-off noise (the scan once found a spurious sign
        # change of R at P_N ~ 1e-77 for mu |W_TN| = 1e92 W_NN), and a is in effect 0. If
        # the linearized stick solution exists, is near stick and cannot be resolved
        # further (the polish gate below fails), it is the answer (the set-valued stick
        # as a -> 0).
        ao1 = cs * aln
        ao2 = sn * aln
        oks, h1, h2 = _stick_start_3d(Wnn, ao1, ao2, aln, cn, Wnn, W01, W02, T11, T12, T22,
                                      mu)
        if oks and h1 * h1 + h2 * h2 < G_POLISH_3D * G_POLISH_3D:
            D = _sub_mu_dot(Wnn, mu, W01, h1, W02, h2)
            if aln * D <= POLISH_SEP * cn * mu * Tn * (abs(h1) + abs(h2)) * 2.2e-16:
                okp, PN, P1, P2 = _stick_impulse_3d(h1, h2, ao1, ao2, aln, cn, Wnn, W01, W02,
                                                    T11, T12, T22, mu)
                if okp:
                    return MODE_SLIP, PN, P1, P2, s
                PN = cn / D
                return MODE_SLIP, PN, -mu * (PN * h1), -mu * (PN * h2), s
    cert = _unique_certificate(Wnn, w1, w2, t11, t12, t22, mu)
    ok = False
    b1 = 0.0
    b2 = 0.0
    PN = 0.0                                 # P_N of the scan path (0: not taken)
    sch = 0.0                                # stick slope and z = W_TT^-1 w (caller's frame)
    zo1 = 0.0
    zo2 = 0.0
    mode = MODE_SLIP
    if cert:
        # start: Smith 2D in the plane of (n, a) (exact when the motion is planar)
        m2d, PN2, PT2, b2d = _solve_2d(vn, aln, Wnn, w1, t11, e, mu)
        if m2d >= 0:
            ok, b1, b2 = _newton_full_3d(b2d, 0.0, aln, cn, Wnn, w1, w2, t11, t12, t22, mu,
                                         MAXIT_NEWTON_3D)
    if not ok:
        # scan path (also the fallback). Its normal equation next to the pole uses the stick
        # slope and z = W_TT^-1 w, formed in the caller's frame (scaled by a power of two
        # only, hence exact; the rotated W is off by eps |W|, i.e. eps cond W in det W), z
        # then rotated like w.
        sch = schur3(Wnn, W01, W02, T11, T12, T22)
        zo1, zo2 = _solve2_refined(T11, T12, T22, W01, W02)
        zr1 = cs * zo1 + sn * zo2
        zr2 = -sn * zo1 + cs * zo2
        ao1 = cs * aln
        ao2 = sn * aln
        ya1, ya2 = _solve2_refined(T11, T12, T22, ao1, ao2)
        # energy K = v.W^-1 v = a.T^-1 a + (v_N - z.a)^2 / schur (positive terms)
        dv = vn - (zo1 * ao1 + zo2 * ao2)
        K = (ao1 * ya1 + ao2 * ya2) + dv * dv / sch
        mode, PN, b1, b2 = _scan_core(aln, cn, Wnn, w1, w2, t11, t12, t22, mu, 1.0 / sch, K,
                                      sch, zr1, zr2)
        if mode < 0:
            return mode, 0.0, 0.0, 0.0, s
        # polish on the full residual (keeps the same root: tiny steps only). It makes the
        # impulse self-consistent (P_N = c / D(g), v_fT = b): the root of the Smith
        # equations for W perturbed by round-off, which the residual checks measure
        ok2, c1, c2 = _newton_full_3d(b1, b2, aln, cn, Wnn, w1, w2, t11, t12, t22, mu, 3)
        if ok2 and (c1 - b1) ** 2 + (c2 - b2) ** 2 <= 1e-12 * (b1 * b1 + b2 * b2 + aln * aln):
            b1, b2 = c1, c2
    g1, g2, B11, B12, B21, B22 = _g3(b1, b2, aln, aln * aln)
    k1 = cs * g1 - sn * g2                   # g back in the caller's tangent basis
    k2 = sn * g1 + cs * g2
    ao1 = cs * aln
    ao2 = sn * aln
    Dg = Wnn - mu * (w1 * g1 + w2 * g2)
    near = g1 * g1 + g2 * g2 < G_POLISH_3D * G_POLISH_3D
    if (Dg < DPOLE_REL * Wnn or cn < DPOLE_REL * Wnn * PN
            or (not near and (Wnn + T11 + T22) ** 3 > ILLCOND_POLISH * det3s(
                Wnn, W01, W02, T11, T12, T22))):
        # next to the pole (D from this g, or from the scan's P_N = c / D, which the stick-slope
        # form of R keeps accurate) or W ill-conditioned: Newton in (P_N, d = a + b) in the
        # caller's frame, from the solver's root
        if not (sch > 0.0):
            sch = schur3(Wnn, W01, W02, T11, T12, T22)
            zo1, zo2 = _solve2_refined(T11, T12, T22, W01, W02)
        okp, PNp, h1, h2 = _caller_polish_3d(PN, cs * b1 - sn * b2, sn * b1 + cs * b2, ao1,
                                             ao2, aln, cn, Wnn, W01, W02, T11, T12, T22, mu,
                                             sch, zo1, zo2)
        if okp:
            gn = math.sqrt(h1 * h1 + h2 * h2)
            if gn > 1.0:                     # round-off guard: keep |P_T| <= mu P_N
                h1 /= gn
                h2 /= gn
            return mode, PNp, -mu * (PNp * h1), -mu * (PNp * h2), s
    oks = False
    h1 = k1
    h2 = k2
    if near:
        # near stick the b-root itself can be noise: its residual carries eps c mu |T| / D
        # absolute (g from b has eps absolute error), which can swamp a tiny initial slip
        # (b came out ~1e6 |a| for mu = 1e8, T ~ 1e-6, |a| = 1e-20 |v_N|, and g off by 1e86
        # for mu = 1e100): the linearized stick solution has no such floor
        oks, h1, h2 = _stick_start_3d(Dg, ao1, ao2, aln, cn, Wnn, W01, W02, T11, T12, T22,
                                      mu)
        if oks:
            Dg = Wnn - mu * (W01 * h1 + W02 * h2)
        else:
            h1 = k1
            h2 = k2
    if ((near or Dg < DPOLE_REL * Wnn)
            and aln * abs(Dg) > POLISH_SEP * cn * mu * (abs(t11) + abs(t22) + 2.0 * abs(t12))
            * (abs(h1) + abs(h2)) * 2.2e-16):
        # near stick (b ~ -a, large mu: g from b has ~eps absolute, eps/|g| relative error,
        # and P_T = -mu P_N g needs it relative) or next to the pole (D = W_NN - mu w.g
        # << W_NN: the b-residual is lost to cancellation): Newton in g itself, in the
        # caller's frame with compensated D and N (see _polish_g_3d), from whichever of the
        # b-root and the stick start has the smaller |E|. Only where float g resolves b at
        # the scale of |a| (POLISH_SEP): else |E| is round-off noise.
        if oks:
            E1, E2, J11, J12, J21, J22, D1 = _eg_3d(k1, k2, ao1, ao2, aln, cn, Wnn, W01, W02,
                                                    T11, T12, T22, mu)
            F1, F2, J11, J12, J21, J22, D2 = _eg_3d(h1, h2, ao1, ao2, aln, cn, Wnn, W01, W02,
                                                    T11, T12, T22, mu)
            if D1 > 0.0 and E1 * E1 + E2 * E2 <= F1 * F1 + F2 * F2:
                h1 = k1
                h2 = k2
        k1, k2 = _polish_g_3d(h1, h2, ao1, ao2, aln, cn, Wnn, W01, W02, T11, T12, T22, mu)
    elif oks:
        # near stick, and g cannot resolve b at the scale of |a| (a tiny initial slip
        # against eps c mu |T| / D): both the b-root and E are noise there; the impulse is
        # stick-like and fixed by g to ~|g| relative, which the stick solution gives
        okp, PNp, P1, P2 = _stick_impulse_3d(h1, h2, ao1, ao2, aln, cn, Wnn, W01, W02, T11,
                                             T12, T22, mu)
        if okp:
            return mode, PNp, P1, P2, s
        k1 = h1
        k2 = h2
    gn = math.sqrt(k1 * k1 + k2 * k2)
    if gn > 1.0:                             # round-off guard: keep |P_T| <= mu P_N
        k1 /= gn
        k2 /= gn
    # D for this g, compensated, in the caller's frame (exactly scaled W): P_N D = c, i.e.
    # v_fN = -e v_N, holds for the returned impulse to round-off even next to the pole
    D = _sub_mu_dot(Wnn, mu, W01, k1, W02, k2)
    if D > 0.0:
        PN = cn / D
    else:
        # g unphysical (D <= 0): the root was lost to round-off (extreme ratios, e.g. a weak
        # impact with |a| ~ 1e8 |v_N| and mu |W_TN| >> W_NN). Falling back on the scan's P_N
        # with this g gave v_fN wrong by orders of magnitude: report failure instead.
        return MODE_NOT_CONVERGED, 0.0, 0.0, 0.0, s
    return mode, PN, -mu * (PN * k1), -mu * (PN * k2), s


@njit(cache=True, error_model="numpy", inline="always")
def _g_jac(b1, b2, a1, a2, na):
    """Smith's direction g(a, b) = (|a| a + |b| b) / (|a|^2 + |b|^2) for a general a
    (``na = |a| > 0``, caller's frame) and its Jacobian B = dg/db (row-major; 0 at b = 0).
    Returns (g1, g2, B11, B12, B21, B22)."""
    nb = math.sqrt(b1 * b1 + b2 * b2)
    iq = 1.0 / (na * na + nb * nb)
    g1 = (na * a1 + nb * b1) * iq
    g2 = (na * a2 + nb * b2) * iq
    if nb > 0.0:
        # B = (|b| I + b b^T / |b|) / Q - 2 g b^T / Q,  Q = |a|^2 + |b|^2
        inb = 1.0 / nb
        B11 = (nb + b1 * b1 * inb) * iq - 2.0 * g1 * b1 * iq
        B12 = (b1 * b2 * inb) * iq - 2.0 * g1 * b2 * iq
        B21 = (b1 * b2 * inb) * iq - 2.0 * g2 * b1 * iq
        B22 = (nb + b2 * b2 * inb) * iq - 2.0 * g2 * b2 * iq
        return g1, g2, B11, B12, B21, B22
    return g1, g2, 0.0, 0.0, 0.0, 0.0


@njit(cache=True, error_model="numpy")
def _eg_3d(g1, g2, a1, a2, na, c, Wnn, W01, W02, T11, T12, T22, mu):
    """E(g) = g(a, b(g)) - g and its Jacobian (general a, caller's frame), with
    b(g) = a + c N(g) / D(g), D = W_NN - mu w.g, N = w - mu T g both compensated
    (_sub_mu_dot: exact to round-off for the float g, where they cancel next to the pole).
    Jacobian B (c mu / D)(H w^T - T) - I, H = N / D, B = dg/db. Returns (E1, E2, J11, J12,
    J21, J22, D); D <= 0: not physical."""
    D = _sub_mu_dot(Wnn, mu, W01, g1, W02, g2)
    if not (D > 0.0):
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, D
    iD = 1.0 / D
    H1 = _sub_mu_dot(W01, mu, T11, g1, T12, g2) * iD
    H2 = _sub_mu_dot(W02, mu, T12, g1, T22, g2) * iD
    gb1, gb2, B11, B12, B21, B22 = _g_jac(a1 + c * H1, a2 + c * H2, a1, a2, na)
    k = c * mu * iD
    A11 = k * (H1 * W01 - T11)
    A12 = k * (H1 * W02 - T12)
    A21 = k * (H2 * W01 - T12)
    A22 = k * (H2 * W02 - T22)
    J11 = B11 * A11 + B12 * A21 - 1.0
    J12 = B11 * A12 + B12 * A22
    J21 = B21 * A11 + B22 * A21
    J22 = B21 * A12 + B22 * A22 - 1.0
    return gb1 - g1, gb2 - g2, J11, J12, J21, J22, D


@njit(cache=True, error_model="numpy")
def _stick_start_3d(D, a1, a2, na, c, Wnn, W01, W02, T11, T12, T22, mu):
    """Linearized near-stick root g (caller's frame). Near stick, b = -a + d with |d| << |a|,
    and g = (|a| a + |b| b)/(|a|^2 + |b|^2) = (I + u u^T) d / (2 |a|) + O(|d|^2/|a|^2),
    u = a/|a|. With d = 2 a + c N(g)/D, N = w - mu T g, times D = W_NN - mu w.g:

        (2 |a| D (I - u u^T / 2) + c mu T + 2 mu a w^T) g = 2 W_NN a + c w,

    linear in g but for the D of the first term, taken from the previous sweep (from the
    given D; STICK_START_IT sweeps). That term is the small one (2 |a| D << c mu |T| near
    stick), so the sweeps contract fast, while D's dependence on g (strong next to the pole,
    mu |w| >> W_NN) sits in the exact linear terms. The solution is right to O(|g|)
    relative, independently of the noise of the b-root (eps c mu |T| / D absolute, which
    can exceed |a| by orders of magnitude); as a -> 0 it tends to the set-valued stick.
    Returns (ok, g1, g2); ok requires |g| < 1 and D(g) > 0."""
    u1 = a1 / na
    u2 = a2 / na
    Dh = D if D > 0.0 else Wnn
    h1 = 0.0
    h2 = 0.0
    cm = c * mu
    m1 = 2.0 * mu * a1
    m2 = 2.0 * mu * a2
    for it in range(STICK_START_IT):
        q = 2.0 * na * Dh
        h1, h2 = _lin2(q * (1.0 - 0.5 * u1 * u1) + cm * T11 + m1 * W01,
                       -0.5 * q * u1 * u2 + cm * T12 + m1 * W02,
                       -0.5 * q * u1 * u2 + cm * T12 + m2 * W01,
                       q * (1.0 - 0.5 * u2 * u2) + cm * T22 + m2 * W02,
                       2.0 * Wnn * a1 + c * W01, 2.0 * Wnn * a2 + c * W02)
        if not (h1 * h1 + h2 * h2 < 1.0):
            return False, 0.0, 0.0
        Dn = _sub_mu_dot(Wnn, mu, W01, h1, W02, h2)
        if not (Dn > 0.0):
            return False, 0.0, 0.0
        if abs(Dn - Dh) <= 1e-15 * Dn:
            break
        Dh = Dn
    return True, h1, h2


@njit(cache=True, error_model="numpy")
def _polish_g_3d(g1, g2, a1, a2, na, c, Wnn, W01, W02, T11, T12, T22, mu):
    """Damped Newton on the root equation written in g, E(g) = g(a, b(g)) - g (``_eg_3d``),
    from the g of the b-solution, in the caller's frame (W scaled by a power of two only:
    exact, where the rotated frame perturbs W by eps |W|, i.e. the energy by eps W_NN / D
    next to the pole).

    Why in g: near stick (mu large, |g| ~ 1/mu, b ~ -a) g(a, b) cancels to ~eps absolute,
    but the Jacobian is ~mu c |T| / (D |a|), so a step leaves ~eps |g| relative error in g,
    where the b-iteration leaves eps / |g|. Next to the pole (D << W_NN) D(g(b)) loses
    eps W_NN / D and the b-residual is noise, while E(g) with D, N compensated stays exact
    to round-off for the float g. Merit |E|^2 with Armijo backtracking keeping D > 0; stops
    at a step below TOL_ROOT |g| or after MAXIT_POLISH_3D steps. Returns the input g
    unless |E| decreased (a failed polish never makes the result worse)."""
    E1, E2, J11, J12, J21, J22, D = _eg_3d(g1, g2, a1, a2, na, c, Wnn, W01, W02, T11, T12,
                                           T22, mu)
    if not (D > 0.0):
        return g1, g2
    f0 = E1 * E1 + E2 * E2
    f = f0
    h1 = g1
    h2 = g2
    for it in range(MAXIT_POLISH_3D):
        if f == 0.0:
            break
        d1, d2 = _lin2(J11, J12, J21, J22, -E1, -E2)
        nd = d1 * d1 + d2 * d2
        if not (nd < math.inf):
            break
        t = 1.0
        accepted = False
        for ls in range(MAX_LINESEARCH):
            n1 = h1 + t * d1
            n2 = h2 + t * d2
            F1, F2, K11, K12, K21, K22, Dn = _eg_3d(n1, n2, a1, a2, na, c, Wnn, W01, W02,
                                                    T11, T12, T22, mu)
            if Dn > 0.0:
                fn = F1 * F1 + F2 * F2
                if fn <= (1.0 - ARMIJO * t) * f:
                    accepted = True
                    break
            t *= 0.5
        if not accepted:
            break
        h1, h2 = n1, n2
        E1, E2, J11, J12, J21, J22, f = F1, F2, K11, K12, K21, K22, fn
        if nd * t * t <= TOL_ROOT * TOL_ROOT * (h1 * h1 + h2 * h2):
            break
    if f < f0:
        return h1, h2
    return g1, g2


@njit(cache=True, error_model="numpy")
def _caller_eval_3d(p, d1, d2, a1, a2, na, c, Wnn, W01, W02, T11, T12, T22, mu):
    """Residuals of the Smith equations at (P_N, d) = (p, d1, d2), d = a + b (b = v_fT),
    caller's frame, exactly scaled W, for the impulse as returned, ``P = (p, -mu p g)``:
    ``F0 = W_N.P - c`` (``v_fN + e v_N``) and ``r = (b - a) - W_T P`` (``b - v_fT``), in
    Dot2 (exact to round-off for the float P, where their terms, ~|W| |P| >> |v| next to the
    pole, cancel). g(a, b) is formed from d, ``g = (|a| d + (|b| - |a|) b) / Q``,
    ``|b| - |a| = (b - a).d / (|a| + |b|)``: relative accuracy near stick (b ~ -a, |g| << 1),
    where |a| a + |b| b cancels. Returns (g1, g2, B11, B12, B21, B22, F0, r1, r2, |terms|),
    B = dg/db."""
    b1 = d1 - a1
    b2 = d2 - a2
    s1, e1 = two_sum(d1, -2.0 * a1)          # b - a, exact as s + e
    s2, e2 = two_sum(d2, -2.0 * a2)
    nb = math.sqrt(b1 * b1 + b2 * b2)
    dn = (s1 * d1 + s2 * d2) / (na + nb)     # |b| - |a|
    iq = 1.0 / (na * na + nb * nb)
    g1 = (na * d1 + dn * b1) * iq
    g2 = (na * d2 + dn * b2) * iq
    h1, h2, B11, B12, B21, B22 = _g_jac(b1, b2, a1, a2, na)
    P1 = -mu * (p * g1)                      # as returned (_smith_3d_core)
    P2 = -mu * (p * g2)
    F0 = -sub_dot3(c, Wnn, W01, W02, p, P1, P2)
    r1 = sub_dot3(s1, W01, T11, T12, p, P1, P2) + e1
    r2 = sub_dot3(s2, W02, T12, T22, p, P1, P2) + e2
    size = (c + abs(s1) + abs(s2) + (Wnn + abs(W01) + abs(W02)) * p
            + (abs(W01) + abs(W02) + abs(T11) + 2.0 * abs(T12) + abs(T22))
            * (abs(P1) + abs(P2)))
    return g1, g2, B11, B12, B21, B22, F0, r1, r2, size


@njit(cache=True, error_model="numpy", inline="always")
def _polish_step(F0, r1, r2, K11, K12, K21, K22, n1, n2, den, z1, z2):
    """Newton correction (dP_N, dd) of ``_caller_polish_3d`` for residuals (F0, r), with the
    Jacobian factors K, n = K^-1 N and den = sch + z.n of the point it was formed at."""
    u1, u2 = _lin2(K11, K12, K21, K22, r1, r2)
    dp = ((z1 * u1 + z2 * u2) - (F0 + (z1 * r1 + z2 * r2))) / den
    return dp, n1 * dp - u1, n2 * dp - u2


@njit(cache=True, error_model="numpy")
def _caller_polish_3d(p, b1, b2, a1, a2, na, c, Wnn, W01, W02, T11, T12, T22, mu, sch, z1,
                      z2):
    """Newton on the Smith equations in the unknowns (P_N, d), d = a + b (b = v_fT), in the
    caller's frame (W scaled by a power of two only, hence exact), from the solver's root
    (P_N, b) = (p, b1, b2).

    For roots next to the pole of P_N (D = W_NN - mu w.g << W_NN) or an ill-conditioned W,
    where the solver's root, in the rotated frame (W off by eps |W|: P by eps cond(W)) with
    P_N = c / D(g) (D cancels: eps W_NN / D relative), is off by far more than round-off.
    The unknowns are well scaled there (d rather than b keeps g, hence P_T, relatively
    accurate near stick), and the equations linear in P_N: P = (P_N, -mu P_N g) with
    ``F0 = W_N.P - c = 0``, ``r = (b - a) - W_T P = 0`` evaluated exactly
    (``_caller_eval_3d``). The step uses the normal equation in its stick-slope form
    ``F0 + z.r = P_N sch + z.(b - a) - c`` (``sch = W_NN - w.z``, ``z = W_TT^-1 w``, from the
    caller; no cancelling D in the Jacobian): with ``K = I + mu P_N T B`` (B = dg/db),
    ``dP_N = (z.K^-1 r - F0 - z.r) / (sch + z.K^-1 N)``, ``dd = K^-1 (N dP_N - r)``,
    ``N = W_T P / P_N`` (``_polish_step``). ``p <= 0``: start from ``P_N = (c - z.(b - a)) /
    sch`` (= [W^-1 (v_f - v)]_N).

    Damping by Deuflhard's natural monotonicity test (the residuals' scales differ by the
    huge mu P_N |T| |B| next to the pole and for large mu, so a residual-norm merit rejects
    good steps): a step t is accepted when the simplified correction at the trial point,
    with the same Jacobian, is below (1 - t/4) times the full correction, measured relative
    to P_N and |d|. Stops after a correction below TOL_ROOT (then applied) or, if the
    damping stalls, at residuals below POLE_ACCEPT times their terms. Returns
    (ok, P_N, g1, g2)."""
    if not (p > 0.0):
        p = (c - (z1 * (b1 - a1) + z2 * (b2 - a2))) / sch
        if not (p > 0.0 and p < math.inf):
            return False, 0.0, 0.0, 0.0
    d1 = a1 + b1
    d2 = a2 + b2
    g1, g2, B11, B12, B21, B22, F0, r1, r2, size = _caller_eval_3d(
        p, d1, d2, a1, a2, na, c, Wnn, W01, W02, T11, T12, T22, mu)
    for it in range(MAXIT_POLE):
        k = mu * p
        K11 = 1.0 + k * (T11 * B11 + T12 * B21)
        K12 = k * (T11 * B12 + T12 * B22)
        K21 = k * (T12 * B11 + T22 * B21)
        K22 = 1.0 + k * (T12 * B12 + T22 * B22)
        ip = 1.0 / p
        n1, n2 = _lin2(K11, K12, K21, K22, (d1 - 2.0 * a1 - r1) * ip,
                       (d2 - 2.0 * a2 - r2) * ip)
        den = sch + (z1 * n1 + z2 * n2)
        dp, s1, s2 = _polish_step(F0, r1, r2, K11, K12, K21, K22, n1, n2, den, z1, z2)
        # correction size relative to P_N and |d| (|d| floored at eps |a|: d = 0 is stick)
        isd = 1.0 / max(d1 * d1 + d2 * d2, 4.9e-32 * na * na)
        nu = (dp * ip) ** 2 + (s1 * s1 + s2 * s2) * isd
        if not (nu < math.inf):
            break
        if nu <= TOL_ROOT * TOL_ROOT:
            g1, g2, B11, B12, B21, B22, F0, r1, r2, size = _caller_eval_3d(
                p + dp, d1 + s1, d2 + s2, a1, a2, na, c, Wnn, W01, W02, T11, T12, T22, mu)
            return p + dp > 0.0, p + dp, g1, g2
        t = 1.0
        accepted = False
        for ls in range(MAX_LINESEARCH):
            pn = p + t * dp
            if pn > 0.0:
                m1 = d1 + t * s1
                m2 = d2 + t * s2
                h1, h2, C11, C12, C21, C22, G0, q1, q2, sn = _caller_eval_3d(
                    pn, m1, m2, a1, a2, na, c, Wnn, W01, W02, T11, T12, T22, mu)
                ep, e1, e2 = _polish_step(G0, q1, q2, K11, K12, K21, K22, n1, n2, den, z1,
                                          z2)
                if (ep * ip) ** 2 + (e1 * e1 + e2 * e2) * isd <= (1.0 - 0.25 * t) ** 2 * nu:
                    accepted = True
                    break
            t *= 0.5
        if not accepted:
            break
        p, d1, d2 = pn, m1, m2
        g1, g2, B11, B12, B21, B22, F0, r1, r2, size = (h1, h2, C11, C12, C21, C22, G0, q1,
                                                        q2, sn)
    if F0 * F0 + r1 * r1 + r2 * r2 <= (POLE_ACCEPT * size) ** 2:
        return True, p, g1, g2
    return False, 0.0, 0.0, 0.0


@njit(cache=True, error_model="numpy")
def _stick_impulse_3d(h1, h2, a1, a2, na, c, Wnn, W01, W02, T11, T12, T22, mu):
    """Impulse of a near-stick root whose slip b = -a + d cannot be resolved by a float g at
    the scale of |a| (tiny initial slip): from the linearized root h (``_stick_start_3d``),
    ``d = 2 |a| (I - u u^T / 2) h`` (u = a/|a|) and ``P = W^-1 (c, b - a)`` by
    ``common.spd3_solve`` (forward accurate up to cond(W) ~1e14). The alternative
    ``P_N = c / D(h)``, ``P_T = -mu P_N h`` fixes P only to the accuracy of h in D and in the
    direction of P_T: next to the pole that cost P a relative 4e-11 and the energy check
    (an elastic impact, which conserves energy at stick). Returns (ok, P_N, P_T1, P_T2); ok
    requires P inside the friction cone."""
    u1 = a1 / na
    u2 = a2 / na
    hu = 0.5 * (u1 * h1 + u2 * h2)
    d1 = 2.0 * na * (h1 - hu * u1)
    d2 = 2.0 * na * (h2 - hu * u2)
    ok, PN, P1, P2 = spd3_solve(Wnn, W01, W02, T11, T12, T22, c, d1 - 2.0 * a1,
                                d2 - 2.0 * a2)
    ok = ok and PN > 0.0 and PN < math.inf and math.hypot(P1, P2) <= mu * PN
    return ok, PN, P1, P2


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


@njit(cache=True, error_model="numpy", inline="always")
def _stick_form(p, b1, b2, D, al, Wnn, mu, wn, zn):
    """True if R(p) is better evaluated in its stick-slope form (``_r_eval``): next to the
    pole (D < DPOLE_REL W_NN, where p D cancels), or where R is less sensitive to an error
    db of the tangential solution b(p) in that form. Sensitivities: direct form
    ``p mu w.(dg/db) db`` with ``|dg/db| <= 4 |b| / Q`` (Q = |a|^2 + |b|^2), stick-slope form
    ``z.db``. For a large normal impulse (p |W| >> |v|) b(p) carries the round-off
    eps p (|w| + mu |T|) of the tangential equation; through g it moved the direct R by
    p mu |w| times that over |b| (sign changes of R far from any root for mu |W_TN| ~ 1e3..1e5
    W_NN and cond(W) ~ 1e11..1e12, where the true D was ~1e-9 W_NN)."""
    if D < DPOLE_REL * Wnn:
        return True
    nb2 = b1 * b1 + b2 * b2
    return zn * (al * al + nb2) < STICK_FORM_SENS * p * mu * wn * math.sqrt(nb2)


@njit(cache=True, error_model="numpy", inline="always")
def _r_eval(p, b1, b2, g1, g2, al, c, Wnn, w1, w2, mu, sch, z1, z2, wn, zn):
    """R(p) = v_fN(p) + e v_N = p D - c at the tangential solution b(p) (rotated frame).
    With P_T = W_TT^-1 (b - a - p w) from the tangential equation, also
    R = p sch + z.(b - a) - c (sch = W_NN - w.z, z = W_TT^-1 w): next to the pole
    (D < DPOLE_REL W_NN) that form keeps its accuracy (sch compensated, b accurate) where
    p (W_NN - mu w.g) carries eps W_NN / D relative error; it is also taken wherever it is
    the less sensitive to the error of b (``_stick_form``; ``wn = |w|``, ``zn = |z|``)."""
    D = Wnn - mu * (w1 * g1 + w2 * g2)
    if _stick_form(p, b1, b2, D, al, Wnn, mu, wn, zn):
        return p * sch + (z1 * (b1 - al) + z2 * b2) - c
    return p * D - c


@njit(cache=True, error_model="numpy")
def _scan_core(al, c, Wnn, w1, w2, t11, t12, t22, mu, mnn, K, sch, z1, z2):
    """Smallest-P_N root via R(p) = p D(g(b(p))) - c: geometric scan + safeguarded Newton.
    ``mnn = (W^-1)_NN``, ``K = v.W^-1 v`` (energy bound), ``sch`` the stick slope and
    ``z = W_TT^-1 w`` (rotated frame) for the near-pole form of R (``_r_eval``).

    Returns (mode, P_N, b1, b2) in the rotated, normalized frame."""
    wn = math.sqrt(w1 * w1 + w2 * w2)
    zn = math.sqrt(z1 * z1 + z2 * z2)
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
        R = _r_eval(p, b1, b2, g1, g2, al, c, Wnn, w1, w2, mu, sch, z1, z2, wn, zn)
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
        if _stick_form(p, b1, b2, D, al, Wnn, mu, wn, zn):
            dR = sch + z1 * db1 + z2 * db2   # derivative of the stick-slope form of R
        else:
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
        R = _r_eval(p, b1, b2, g1, g2, al, c, Wnn, w1, w2, mu, sch, z1, z2, wn, zn)
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
