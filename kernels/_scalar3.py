"""Private scalar helpers of the 3D law kernels (kane_levinson, brach, chatterjee_ruina).

Scalar twins of ``common.solve3``: the scalar law cores take the six distinct entries of a
symmetric 3x3 matrix ``[[a, b, c], [b, d, e], [c, e, f]]`` instead of an array, so that a
batch loop can call them without creating array views.
"""
from numba import njit


@njit(cache=True, error_model="numpy", inline="always")
def det3s(a, b, c, d, e, f):
    """Determinant of the symmetric matrix [[a, b, c], [b, d, e], [c, e, f]]."""
    return a * (d * f - e * e) + b * (c * e - b * f) + c * (b * e - c * d)


@njit(cache=True, error_model="numpy", inline="always")
def solve3s(a, b, c, d, e, f, b0, b1, b2):
    """Solve [[a, b, c], [b, d, e], [c, e, f]] x = (b0, b1, b2) (cofactors, as common.solve3)."""
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
