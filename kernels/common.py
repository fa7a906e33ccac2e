"""Shared contract of every law kernel: parameter layout, mode codes, small linear algebra.

Every law kernel has the signature ``mode = kernel(v, W, params, P_out)``:

* ``v``      float64[d], d = 2 or 3: pre-impact relative velocity of the contact point of
             A minus B, normal first ``(v_N, v_T[, v_T2])`` (m/s). ``v_N < 0`` approaches.
* ``W``      float64[d, d]: contact-space inverse mass (Delassus) matrix, symmetric positive
             definite (1/kg), so that ``v_f = v + W @ P``.
* ``params`` float64[N_PARAMS]: law parameters in the fixed layout below (unused slots ignored).
* ``P_out``  float64[d]: written with the impulse on A (N s), normal first.
* returns    an int mode code (below). Negative codes are failures; ``P_out`` is then zero.

Kernels never allocate, never raise and never return NaN: they report failure by mode code.
"""
import math
from fractions import Fraction

from numba import njit, types
from numba.extending import intrinsic, overload

# ---- parameter layout of ``Law.params`` (float64[N_PARAMS]) --------------------------------
P_E = 0      # normal restitution e (law-dependent range, see DESIGN §4)
P_MU = 1     # Coulomb friction coefficient mu >= 0
P_ET = 2     # tangential restitution e_t in [-1, 1] (Brach, Chatterjee & Ruina)
P_REST = 3   # Routh termination kind: one of REST_* below, stored as a float
P_TOL = 4    # Routh 3D integration tolerance (relative, dimensionless)
N_PARAMS = 5

REST_ENERGETIC = 0   # Stronge: int_0^pf v_N dp = (1 - e^2) W_c
REST_POISSON = 1     # p_f = (1 + e) p_c
REST_NEWTON = 2      # v_N(p_f) = -e v_N(0)

# ---- law ids (used by the dispatchers and by the stepper's per-contact law table) ----------
LAW_KANE_LEVINSON = 0
LAW_BRACH = 1
LAW_SMITH = 2
LAW_ROUTH = 3
LAW_CHATTERJEE_RUINA = 4
N_LAWS = 5

# ---- mode codes ------------------------------------------------------------------------------
MODE_SEPARATING = 0      # v_N >= 0: no impact, P = 0
MODE_STICK = 1           # ends sticking / impulse strictly inside the friction cone
MODE_SLIP = 2            # slides throughout / impulse on the friction cone boundary
MODE_SLIP_STICK = 3      # Routh: slides, then sticks
MODE_SLIP_REVERSE = 4    # Routh: slides, slip stops, slip resumes along the diverging direction
MODE_NO_SOLUTION = -1    # the impact has no solution in this law (Painleve-type jam,
                         # no consistent slip direction, non-positive normal impulse)
MODE_NOT_CONVERGED = -2  # an iteration hit its limit before reaching its tolerance


@njit(cache=True, inline="always")
def zero(P_out):
    for k in range(P_out.shape[0]):
        P_out[k] = 0.0


@njit(cache=True, inline="always")
def solve2(a00, a01, a11, b0, b1):
    """Solve the symmetric 2x2 system [[a00, a01], [a01, a11]] x = b (Cramer's rule)."""
    det = a00 * a11 - a01 * a01
    return (a11 * b0 - a01 * b1) / det, (a00 * b1 - a01 * b0) / det


@njit(cache=True, error_model="numpy", inline="always")
def det3s(a, b, c, d, e, f):
    """Determinant of the symmetric matrix [[a, b, c], [b, d, e], [c, e, f]]."""
    return a * (d * f - e * e) + b * (c * e - b * f) + c * (b * e - c * d)


@njit(cache=True, error_model="numpy", inline="always")
def _cofactors3(a, b, c, d, e, f):
    """Cofactors of the symmetric [[a, b, c], [b, d, e], [c, e, f]] (its adjugate, also
    symmetric) and the determinant by the first row, in plain arithmetic:
    ``(c00, c01, c02, c11, c12, c22, det)``."""
    c00 = d * f - e * e
    c01 = c * e - b * f
    c02 = b * e - c * d
    c11 = a * f - c * c
    c12 = b * c - a * e
    c22 = a * d - b * b
    return c00, c01, c02, c11, c12, c22, a * c00 + b * c01 + c * c02


@njit(cache=True, error_model="numpy", inline="always")
def solve3s(a, b, c, d, e, f, b0, b1, b2):
    """Solve the symmetric system [[a, b, c], [b, d, e], [c, e, f]] x = (b0, b1, b2) by
    cofactors. Scalars in and out (the 3D law cores take W by its upper triangle)."""
    c00, c01, c02, c11, c12, c22, det = _cofactors3(a, b, c, d, e, f)
    x0 = (c00 * b0 + c01 * b1 + c02 * b2) / det
    x1 = (c01 * b0 + c11 * b1 + c12 * b2) / det
    x2 = (c02 * b0 + c12 * b1 + c22 * b2) / det
    return x0, x1, x2


# ---- error-free transformations (FMA) and compensated determinants --------------------------
# two_sum and two_prod return (s, err) with s + err == a + b (a * b) exactly (Knuth; the
# product's error is one fused multiply-add, fma(a, b, -a b), barring over- and underflow).
# They let the stick slopes W_NN - W_TN W_TT^-1 W_TN = det(W) / det(W_TT) and the residuals
# of refined solves be computed to a few ulps with W taken as exact, instead of losing
# eps cond(W) to cancellation. Ref: Ogita, Rump & Oishi, SIAM J. Sci. Comput. 26:1955 (2005).
# With a hardware FMA the compensated 2x2/3x3 solves below cost about as much as the plain
# cofactor formulas. (Without one, LLVM calls the C library's correctly rounded fma: same
# results, slower.)
def fma(a, b, c):
    """a * b + c with a single rounding. Called from compiled code this is the LLVM
    ``llvm.fma.f64`` intrinsic (one instruction); called from Python (e.g. the stability
    suite's shadow run of a kernel) it is evaluated in exact rational arithmetic."""
    if math.isfinite(a) and math.isfinite(b) and math.isfinite(c):
        return float(Fraction(a) * Fraction(b) + Fraction(c))
    return a * b + c


@intrinsic
def _fma_f64(typingctx, a, b, c):
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        return builder.fma(args[0], args[1], args[2])
    return sig, codegen


@overload(fma, inline="always")
def _fma_overload(a, b, c):
    def impl(a, b, c):
        return _fma_f64(a, b, c)
    return impl


@njit(cache=True, error_model="numpy", inline="always")
def two_sum(a, b):
    """(s, err): s = fl(a + b) and s + err == a + b exactly (Knuth, 6 flops)."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@njit(cache=True, error_model="numpy", inline="always")
def two_prod(a, b):
    """(p, err): p = fl(a * b) and p + err == a * b exactly (FMA; barring underflow of err)."""
    p = a * b
    return p, fma(a, b, -p)


@njit(cache=True, error_model="numpy", inline="always")
def det2k(a, d, b, c):
    """a d - b c by Kahan's FMA algorithm: within 2 ulps of the exact result (relative, for
    exact inputs, barring underflow; Jeannerod, Louvet & Muller, Math. Comp. 82:2245, 2013),
    so its sign is always right. 4 flops."""
    w = b * c
    err = fma(-b, c, w)          # w - b c exactly
    return fma(a, d, -w) + err


@njit(cache=True, error_model="numpy", inline="always")
def _dd_det2(a, d, b, c):
    """a d - b c as an unevaluated sum (hi, lo), |error| <~ 2 eps^2 (|a d| + |b c|) (FMA)."""
    p1 = a * d
    p2 = b * c
    s, es = two_sum(p1, -p2)
    return s, es + (fma(a, d, -p1) - fma(b, c, -p2))


@njit(cache=True, error_model="numpy", inline="always")
def _dd_dot3(h0, l0, r0, h1, l1, r1, h2, l2, r2):
    """sum_i (h_i + l_i) r_i rounded once more (Ogita-Rump-Oishi Dot2 with FMA): as if
    computed in twice the working precision, error <~ eps |sum| + 3 eps^2 sum |terms|."""
    p0 = h0 * r0
    p1 = h1 * r1
    p2 = h2 * r2
    s, t1 = two_sum(p0, p1)
    s, t2 = two_sum(s, p2)
    q = fma(h0, r0, -p0) + fma(h1, r1, -p1) + fma(h2, r2, -p2)
    return s + ((t1 + t2) + q + (l0 * r0 + l1 * r1 + l2 * r2))


@njit(cache=True, error_model="numpy", inline="always")
def schur3(a, b, c, d, e, f):
    """Normal stick slope W_NN - W_TN . W_TT^-1 W_TN = det(W) / det(W_TT) of the symmetric
    W = [[a, b, c], [b, d, e], [c, e, f]] (normal first), compensated: det W by cofactors in
    double-double and Dot2 (FMA; a few ulps plus 3 eps^2 sum |terms|, where ``det3s`` loses
    eps cond), det W_TT by Kahan's ``det2k`` (2 ulps). Relative error of the slope therefore
    ~eps^2 |W|^3 / det W: 3e-11 at cond(W) = 1e12 (Smith's set-valued stick uses
    ``spd3_solve`` instead)."""
    h00, l00 = _dd_det2(d, f, e, e)
    h01, l01 = _dd_det2(c, e, b, f)
    h02, l02 = _dd_det2(b, e, c, d)
    return _dd_dot3(h00, l00, a, h01, l01, b, h02, l02, c) / det2k(d, f, e, e)


SPD3_FAST = 16.0
"""``spd3_solve`` takes its plain cofactor path when ``W_00 W_11 W_22 <= SPD3_FAST det W``
(dimensionless; Hadamard: the ratio is >= 1 for SPD W and bounds the cancellation of every
term of the cofactor expansion, each at most ``W_00 W_11 W_22`` once the 2x2 minors are
positive): the rounding of det W is then below ``18 SPD3_FAST eps`` relative and x is
accurate to ~1e2 ulps normwise. Larger ratios (ill-conditioned W) take the compensated
path."""


@njit(cache=True, error_model="numpy", inline="always")
def spd3_solve(a, b, c, d, e, f, r0, r1, r2):
    """Positive-definiteness test and solve of the symmetric W x = r (3x3), backward stable.

    ``W = [[a, b, c], [b, d, e], [c, e, f]]`` (upper triangle). Returns ``(ok, x0, x1, x2)``:
    ``ok`` is ``W`` positive definite, ``x = W^-1 r`` (``x = 0`` when not ``ok``).

    Well-conditioned ``W`` (``a d f <= SPD3_FAST det W``, all 2x2 principal minors > 0):
    plain cofactors ``x = adj(W) r / det W``; the bound certifies ``det W > 0`` and ``x``
    to ~1e2 ulps normwise. Otherwise ``_spd3_solve_dd``: Sylvester's criterion with
    compensated minors and the cofactor solve in double-double (FMA) plus one step of
    iterative refinement, so every SPD W up to cond ~1e15 is accepted, an indefinite one
    rejected, and x is correct to a few ulps normwise up to cond ~1e14. Either way the
    residual is ~eps (|r| + |W| |x|) row by row (componentwise backward stable)."""
    c00, c01, c02, c11, c12, c22, det = _cofactors3(a, b, c, d, e, f)
    if (a > 0.0 and c00 > 0.0 and c11 > 0.0 and c22 > 0.0
            and a * d * f <= SPD3_FAST * det):
        idet = 1.0 / det
        x0 = (c00 * r0 + c01 * r1 + c02 * r2) * idet
        x1 = (c01 * r0 + c11 * r1 + c12 * r2) * idet
        x2 = (c02 * r0 + c12 * r1 + c22 * r2) * idet
        return True, x0, x1, x2
    return _spd3_solve_dd(a, b, c, d, e, f, r0, r1, r2)


@njit(cache=True, error_model="numpy", inline="always")
def sub_dot3(r, w0, w1, w2, x0, x1, x2):
    """r - (w0 x0 + w1 x1 + w2 x2) as if in twice the working precision (Dot2 with FMA):
    error <~ eps |result| + 4 eps^2 (|r| + sum |w_i x_i|)."""
    p0 = w0 * x0
    p1 = w1 * x1
    p2 = w2 * x2
    s, t0 = two_sum(r, -p0)
    s, t1 = two_sum(s, -p1)
    s, t2 = two_sum(s, -p2)
    q = fma(w0, x0, -p0) + fma(w1, x1, -p1) + fma(w2, x2, -p2)
    return s + ((t0 + t1 + t2) - q)


@njit(cache=True, error_model="numpy")
def _spd3_solve_dd(a, b, c, d, e, f, r0, r1, r2):
    """The compensated path of ``spd3_solve`` (same contract), for ill-conditioned W.

    Sylvester's criterion ``a > 0``, ``a d - b^2 > 0``, ``det W > 0`` with the minors from
    double-double cofactors (FMA), exact unless ``det W`` is within ~eps^2 of its terms.
    ``x = adj(W) r / det W`` with the cofactors and the dot products in double-double is
    componentwise backward stable, with a forward error ~eps^2 cond(W)^2 (the cofactors of
    two small eigenvalues lose eps^2 ||W||^2); one step of iterative refinement (residual
    ``r - W x`` in Dot2, correction by the same factorization) squares that, so x is
    correct to a few ulps normwise up to cond ~1e14 (the energy of the laws that never
    create energy depends on this forward accuracy, not only on the residual)."""
    h00, l00 = _dd_det2(d, f, e, e)
    h01, l01 = _dd_det2(c, e, b, f)
    h02, l02 = _dd_det2(b, e, c, d)
    h22, l22 = _dd_det2(a, d, b, b)
    det = _dd_dot3(h00, l00, a, h01, l01, b, h02, l02, c)
    if not (a > 0.0 and h22 + l22 > 0.0 and det > 0.0):
        return False, 0.0, 0.0, 0.0
    h11, l11 = _dd_det2(a, f, c, c)
    h12, l12 = _dd_det2(b, c, a, e)
    x0 = _dd_dot3(h00, l00, r0, h01, l01, r1, h02, l02, r2) / det
    x1 = _dd_dot3(h01, l01, r0, h11, l11, r1, h12, l12, r2) / det
    x2 = _dd_dot3(h02, l02, r0, h12, l12, r1, h22, l22, r2) / det
    # one step of iterative refinement
    g0 = sub_dot3(r0, a, b, c, x0, x1, x2)
    g1 = sub_dot3(r1, b, d, e, x0, x1, x2)
    g2 = sub_dot3(r2, c, e, f, x0, x1, x2)
    y0 = x0 + _dd_dot3(h00, l00, g0, h01, l01, g1, h02, l02, g2) / det
    y1 = x1 + _dd_dot3(h01, l01, g0, h11, l11, g1, h12, l12, g2) / det
    y2 = x2 + _dd_dot3(h02, l02, g0, h12, l12, g1, h22, l22, g2) / det
    return True, y0, y1, y2


@njit(cache=True, error_model="numpy", inline="always")
def finite3(mode, p0, p1, p2):
    """``(mode, p0, p1, p2)`` if the impulse is finite, else ``(MODE_NO_SOLUTION, 0, 0, 0)``."""
    if p0 - p0 == 0.0 and p1 - p1 == 0.0 and p2 - p2 == 0.0:
        return mode, p0, p1, p2
    return MODE_NO_SOLUTION, 0.0, 0.0, 0.0


_HYPOT_LO = 1e-150   # |q| (any unit) below which q1^2 + q2^2 may underflow: use math.hypot
_HYPOT_HI = 1e150    # |q| above which q1^2 + q2^2 may overflow: use math.hypot


@njit(cache=True, error_model="numpy", inline="always")
def cone_slip3(a, mu, wnn, w1, w2, q1, q2):
    """3D impulse on the friction cone along a tangential direction: the shared slip tail
    of Brach and Chatterjee & Ruina. ``P_T = r P_N`` with ``r = mu q / |q|`` (``r = 0`` when
    ``q = 0``) and ``P_N = a / (W_NN + W_NT . r)`` (so that ``v_fN = v_N + a``). Returns
    ``(mode, P_N, P_T1, P_T2)``: ``MODE_SLIP``, or ``MODE_NO_SOLUTION`` with zeros when
    ``q`` is not finite, the denominator is not positive or the result is not finite."""
    st = math.sqrt(q1 * q1 + q2 * q2)
    if not (_HYPOT_LO < st < _HYPOT_HI):
        st = math.hypot(q1, q2)          # squares under- or overflowed (or q = 0, NaN)
    r1 = 0.0
    r2 = 0.0
    if st > 0.0:
        g = mu / st
        r1 = g * q1
        r2 = g * q2
    elif st != 0.0:                    # NaN
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    den = wnn + w1 * r1 + w2 * r2
    if not (den > 0.0):
        return MODE_NO_SOLUTION, 0.0, 0.0, 0.0
    p0 = a / den
    return finite3(MODE_SLIP, p0, r1 * p0, r2 * p0)


@njit(cache=True, error_model="numpy", inline="always")
def store3(P_out, mode, p0, p1, p2):
    """Write a 3D impulse into ``P_out`` and return ``mode`` (the array kernels' tail)."""
    P_out[0] = p0
    P_out[1] = p1
    P_out[2] = p2
    return mode
