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
