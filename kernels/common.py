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
from numba import njit

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
def solve3s(a, b, c, d, e, f, b0, b1, b2):
    """Solve the symmetric system [[a, b, c], [b, d, e], [c, e, f]] x = (b0, b1, b2) by
    cofactors. Scalars in and out (the 3D law cores take W by its upper triangle)."""
    c00 = d * f - e * e
    c01 = c * e - b * f
    c02 = b * e - c * d
    c11 = a * f - c * c
    c12 = b * c - a * e
    c22 = a * d - b * b
    det = a * c00 + b * c01 + c * c02
    x0 = (c00 * b0 + c01 * b1 + c02 * b2) / det
    x1 = (c01 * b0 + c11 * b1 + c12 * b2) / det
    x2 = (c02 * b0 + c12 * b1 + c22 * b2) / det
    return x0, x1, x2


# ---- error-free transformations (compensated determinants) -----------------------------------
# Dekker/Knuth: two_sum and two_prod return (s, err) with s + err == a + b (a * b) exactly
# (barring overflow; two_prod's Veltkamp split needs |a|, |b| < 2**996). They let the stick
# slopes W_NN - W_TN W_TT^-1 W_TN = det(W) / det(W_TT) be computed to a few ulps with W taken
# as exact, instead of losing eps cond(W) to cancellation. Ref: Ogita, Rump & Oishi, SIAM J.
# Sci. Comput. 26:1955 (2005).
_SPLIT = 134217729.0     # 2**27 + 1 (Veltkamp split of a float64)


@njit(cache=True, error_model="numpy", inline="always")
def two_sum(a, b):
    """(s, err): s = fl(a + b) and s + err == a + b exactly."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@njit(cache=True, error_model="numpy", inline="always")
def two_prod(a, b):
    """(p, err): p = fl(a * b) and p + err == a * b exactly (no underflow)."""
    p = a * b
    t = _SPLIT * a
    ah = t - (t - a)
    al = a - ah
    t = _SPLIT * b
    bh = t - (t - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


@njit(cache=True, error_model="numpy", inline="always")
def _det2dd(a, d, b, c):
    """a d - b c as an unevaluated double-double (hi, lo), |error| <~ eps^2 (|a d| + |b c|)."""
    p1, e1 = two_prod(a, d)
    p2, e2 = two_prod(b, c)
    s, es = two_sum(p1, -p2)
    lo = es + (e1 - e2)
    hi = s + lo
    return hi, lo - (hi - s)


@njit(cache=True, error_model="numpy", inline="always")
def det2c(a, d, b, c):
    """a d - b c, compensated: correct to a few ulps of the result for exact inputs."""
    hi, lo = _det2dd(a, d, b, c)
    return hi + lo


@njit(cache=True, error_model="numpy", inline="always")
def det3sc(a, b, c, d, e, f):
    """Determinant of the symmetric [[a, b, c], [b, d, e], [c, e, f]], compensated (cofactor
    expansion in double-double): a few ulps of the result plus eps^2 sum |terms|, where
    ``det3s`` loses eps cond."""
    h0, l0 = _det2dd(d, f, e, e)            # c00 = d f - e^2
    h1, l1 = _det2dd(c, e, b, f)            # c01 = c e - b f
    h2, l2 = _det2dd(b, e, c, d)            # c02 = b e - c d
    p0, q0 = two_prod(a, h0)
    p1, q1 = two_prod(b, h1)
    p2, q2 = two_prod(c, h2)
    s, r1 = two_sum(p0, p1)
    s, r2 = two_sum(s, p2)
    return s + ((r1 + r2) + (q0 + q1 + q2) + (a * l0 + b * l1 + c * l2))


@njit(cache=True, error_model="numpy", inline="always")
def schur2(a, b, c):
    """Stick slope a - b^2 / c of the SPD [[a, b], [b, c]] (= det / c), compensated."""
    return det2c(a, c, b, b) / c


@njit(cache=True, error_model="numpy", inline="always")
def schur3(a, b, c, d, e, f):
    """Normal stick slope W_NN - W_TN . W_TT^-1 W_TN = det(W) / det(W_TT) of the symmetric
    W = [[a, b, c], [b, d, e], [c, e, f]] (normal first), compensated."""
    return det3sc(a, b, c, d, e, f) / det2c(d, f, e, e)
