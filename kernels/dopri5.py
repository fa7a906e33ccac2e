"""The Dormand-Prince RK5(4)7M step shared by the 3D integrators (``flight3d``: the
torque-free rotation; ``pivot3d``: integrated point/edge contact).

Tableau: Hairer, Norsett & Wanner, *Solving ODEs I*, Table II.5.2; dense output: the
coefficients of their code DOPRI5 (4th order, continuous). Each integrator keeps its
state in one float64 workspace ``w``: ``n`` components at offsets ``Y`` (step start),
``YT`` (stage argument), ``Y1`` (step end), seven stages at ``K + i n`` (i = 0..6) and the
dense-output coefficients at ``RC + r n`` (r = 0..4). The integrator evaluates its own
right-hand side between the stage updates below; everything else of a step is here.
All functions are ``inline="always"``: the compiled steps are those of the hand-written
loops they replace.
"""
from numba import njit

A21 = 1.0 / 5.0
A31, A32 = 3.0 / 40.0, 9.0 / 40.0
A41, A42, A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
A51, A52, A53, A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
A61, A62, A63, A64, A65 = (9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0,
                           -5103.0 / 18656.0)
A71, A73, A74, A75, A76 = (35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0,
                           11.0 / 84.0)
C2, C3, C4, C5 = 0.2, 0.3, 0.8, 8.0 / 9.0
E1, E3, E4, E5, E6, E7 = (71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0,
                          -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0)
D1, D3, D4, D5, D6, D7 = (-12715105075.0 / 11282082432.0, 87487479700.0 / 32700410799.0,
                          -10690763975.0 / 1880347072.0, 701980252875.0 / 199316789632.0,
                          -1453857185.0 / 822651844.0, 69997945.0 / 29380423.0)

# step-size controller (dimensionless): h_new = h * clip(SAFETY * err^(-1/5), FAC_MIN, FAC_MAX)
SAFETY = 0.9
FAC_MIN = 0.2
FAC_MAX = 5.0


@njit(cache=True, inline="always")
def arg2(w, n, Y, K, YT, h):
    """Argument of stage 2 into ``w[YT:YT+n]`` (stage 1 at ``w[K:K+n]``)."""
    for j in range(n):
        w[YT + j] = w[Y + j] + h * A21 * w[K + j]


@njit(cache=True, inline="always")
def arg3(w, n, Y, K, YT, h):
    """Argument of stage 3."""
    for j in range(n):
        w[YT + j] = w[Y + j] + h * (A31 * w[K + j] + A32 * w[K + n + j])


@njit(cache=True, inline="always")
def arg4(w, n, Y, K, YT, h):
    """Argument of stage 4."""
    for j in range(n):
        w[YT + j] = w[Y + j] + h * (A41 * w[K + j] + A42 * w[K + n + j]
                                    + A43 * w[K + 2 * n + j])


@njit(cache=True, inline="always")
def arg5(w, n, Y, K, YT, h):
    """Argument of stage 5."""
    for j in range(n):
        w[YT + j] = w[Y + j] + h * (A51 * w[K + j] + A52 * w[K + n + j]
                                    + A53 * w[K + 2 * n + j] + A54 * w[K + 3 * n + j])


@njit(cache=True, inline="always")
def arg6(w, n, Y, K, YT, h):
    """Argument of stage 6."""
    for j in range(n):
        w[YT + j] = w[Y + j] + h * (A61 * w[K + j] + A62 * w[K + n + j]
                                    + A63 * w[K + 2 * n + j] + A64 * w[K + 3 * n + j]
                                    + A65 * w[K + 4 * n + j])


@njit(cache=True, inline="always")
def solution(w, n, Y, K, Y1, h):
    """The 5th-order step end (also the argument of stage 7, FSAL) into ``w[Y1:Y1+n]``."""
    for j in range(n):
        w[Y1 + j] = w[Y + j] + h * (A71 * w[K + j] + A73 * w[K + 2 * n + j]
                                    + A74 * w[K + 3 * n + j] + A75 * w[K + 4 * n + j]
                                    + A76 * w[K + 5 * n + j])


@njit(cache=True, inline="always")
def error_estimate(w, n, K, h, j):
    """Component ``j`` of the local error estimate (5th minus 4th order) of the step."""
    return h * (E1 * w[K + j] + E3 * w[K + 2 * n + j] + E4 * w[K + 3 * n + j]
                + E5 * w[K + 4 * n + j] + E6 * w[K + 5 * n + j] + E7 * w[K + 6 * n + j])


@njit(cache=True, inline="always")
def step_factor(err):
    """Next step over this one after an accepted step with scaled error ``err <= 1``."""
    if err == 0.0:
        return FAC_MAX
    return min(FAC_MAX, max(FAC_MIN, SAFETY * err ** -0.2))


@njit(cache=True, inline="always")
def reject_factor(err):
    """New step over the rejected one (scaled error ``err > 1``)."""
    return max(FAC_MIN, SAFETY * err ** -0.2)


@njit(cache=True, inline="always")
def dense_store(w, n, Y, Y1, K, RC, h):
    """Store the dense-output coefficients of the accepted step."""
    for j in range(n):
        y0 = w[Y + j]
        ydiff = w[Y1 + j] - y0
        bspl = h * w[K + j] - ydiff
        w[RC + j] = y0
        w[RC + n + j] = ydiff
        w[RC + 2 * n + j] = bspl
        w[RC + 3 * n + j] = ydiff - h * w[K + 6 * n + j] - bspl
        w[RC + 4 * n + j] = h * (D1 * w[K + j] + D3 * w[K + 2 * n + j]
                                 + D4 * w[K + 3 * n + j] + D5 * w[K + 4 * n + j]
                                 + D6 * w[K + 5 * n + j] + D7 * w[K + 6 * n + j])


@njit(cache=True, inline="always")
def dense_eval(w, n, RC, th, j):
    """Component ``j`` of the dense output at ``th = (s - s0) / h`` in [0, 1]."""
    th1 = 1.0 - th
    return w[RC + j] + th * (w[RC + n + j] + th1 * (w[RC + 2 * n + j] + th * (
        w[RC + 3 * n + j] + th1 * w[RC + 4 * n + j])))
