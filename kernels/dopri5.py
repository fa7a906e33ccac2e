"""The Dormand-Prince RK5(4)7M step shared by the integrators (``flight3d``: the
torque-free rotation; ``pivot2d``, ``pivot3d``: integrated point/edge contact;
``cluster2d``, ``cluster3d``: persistent contact between several bodies).

Tableau: Hairer, Norsett & Wanner, *Solving ODEs I*, Table II.5.2; dense output: the
coefficients of their code DOPRI5 (4th order, continuous). Each integrator keeps its
state in one float64 workspace ``w``: ``n`` components at offsets ``Y`` (step start),
``YT`` (stage argument), ``Y1`` (step end), seven stages at ``K + i n`` (i = 0..6) and the
dense-output coefficients at ``RC + r n`` (r = 0..4). The integrator evaluates its own
right-hand side between the stage updates below; everything else of a step is here:
``dopri5_step`` (one error-controlled step around a given right-hand side, used by
``pivot2d``, ``pivot3d``, ``cluster2d`` and ``cluster3d``) and ``dense_out``. ``flight3d``
calls the pieces itself (its right-hand side depends on time, never fails and its error norm
skips zero scales).

All functions are ``inline="always"``: the compiled steps are those of the hand-written
loops they replace. A right-hand side passed to ``dopri5_step`` is a module-level jitted
function of the caller: the generic step is inlined into the caller's own cached ``_step``,
so the call is resolved when that one compiles and it is cached on disk like any other
(a jitted function passed to a function that is not inlined, or closed over by a factory,
compiles in every process).
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

STEP_OK = 0             # the status of an accepted step and of a right-hand side that succeeded
MAX_TRIES = 1000        # attempts of one step at most (pivot2d, cluster2d, cluster3d)


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


@njit(cache=True, _nrt=False, inline="always")
def stage_arg(w, n, Y, K, YT, Y1, h, i):
    """Argument of stage ``i + 1`` (i = 1..6) into ``w``; returns its offset (``YT``, or
    ``Y1`` for the 5th-order step end that is the argument of stage 7)."""
    if i == 1:
        arg2(w, n, Y, K, YT, h)
    elif i == 2:
        arg3(w, n, Y, K, YT, h)
    elif i == 3:
        arg4(w, n, Y, K, YT, h)
    elif i == 4:
        arg5(w, n, Y, K, YT, h)
    elif i == 5:
        arg6(w, n, Y, K, YT, h)
    else:
        solution(w, n, Y, K, Y1, h)
        return Y1
    return YT


@njit(cache=True, _nrt=False, inline="always")
def dopri5_step(rhs, args, w, n, Y, YT, Y1, K, RC, SC, H, HNEXT, tol, h, max_tries,
                check_h, shrink, hmin, too_many):
    """One error-controlled step of ``n`` components from ``w[Y:Y+n]`` with first trial
    ``h`` (s; stage 1 already at ``w[K:K+n]``). Stage ``i`` is ``rhs(*args, w, yo, ko)``:
    dy/ds at ``w[yo:yo+n]`` into ``w[ko:ko+n]``, returning ``STEP_OK`` or a failure status.
    The scaled error is ``max_j |err_j| / (tol w[SC+j])``; an accepted step stores its dense
    output at ``RC``, its length at ``w[H]`` and the next trial at ``w[HNEXT]``.

    A failing stage ends the step with its status when ``shrink`` is 0; otherwise the step
    is retried with ``h * shrink`` unless that is below ``hmin`` (s). After ``max_tries``
    attempts (or, with ``check_h``, at a trial step that is not positive) the status is
    ``too_many``. Returns (status, attempts)."""
    att = 0
    while True:
        att += 1
        if att > max_tries or (check_h and not h > 0.0):
            return too_many, att
        st = STEP_OK
        for i in range(1, 7):
            yo = stage_arg(w, n, Y, K, YT, Y1, h, i)
            st = rhs(*args, w, yo, K + i * n)
            if st != STEP_OK:
                break
        if st != STEP_OK:
            if not shrink > 0.0:
                return st, att
            h *= shrink
            if h < hmin:
                return st, att
            continue
        err = 0.0
        for j in range(n):
            r = abs(error_estimate(w, n, K, h, j)) / (tol * w[SC + j])
            if r > err:
                err = r
        if err <= 1.0:
            dense_store(w, n, Y, Y1, K, RC, h)
            w[H] = h
            w[HNEXT] = h * step_factor(err)
            return STEP_OK, att
        h = h * reject_factor(err)


@njit(cache=True, _nrt=False, inline="always")
def dense_out(w, n, RC, S0, H, s, out, oo):
    """Dense output at ``s`` (s, within the step of length ``w[H]`` from ``w[S0]``) into
    ``out[oo:oo+n]``."""
    th = (s - w[S0]) / w[H]
    for j in range(n):
        out[oo + j] = dense_eval(w, n, RC, th, j)
