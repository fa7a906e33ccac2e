"""Exact 2D motion between events: constant linear and angular acceleration.

A body's state is a float64[9] row ``(x, y, angle, vx, vy, omega, ax, ay, alpha)`` valid
from a reference time ``t_ref`` (s). Between events every body moves with constant
accelerations, so its motion is exactly quadratic in ``s = t - t_ref``:

* free flight:            ``(ax, ay) = gravity``, ``alpha = 0`` (angle linear in time);
* persistent contact:     the constant accelerations of sliding, rolling or rest on a plane
                          (set by the stepper, see ``stepper2d``).

Units: m, rad, s. Every function is ``@njit(cache=True, _nrt=False)`` and allocation-free.
"""

from numba import njit

N_STATE = 9
X, Y, ANGLE, VX, VY, OMEGA, AX, AY, ALPHA = range(9)


@njit(cache=True, _nrt=False, inline="always")
def fly_into(st, s, out):
    """Write into ``out`` (float64[9]) the state ``st`` (float64[9]) advanced by ``s`` (s)."""
    h = 0.5 * s * s
    out[0] = st[0] + st[3] * s + st[6] * h
    out[1] = st[1] + st[4] * s + st[7] * h
    out[2] = st[2] + st[5] * s + st[8] * h
    out[3] = st[3] + st[6] * s
    out[4] = st[4] + st[7] * s
    out[5] = st[5] + st[8] * s
    out[6] = st[6]
    out[7] = st[7]
    out[8] = st[8]


@njit(cache=True, _nrt=False, inline="always")
def fly_row(st, i, s):
    """Advance row ``i`` of the state table ``st`` (float64[n, 9]) in place by ``s`` (s)."""
    if s == 0.0:
        return
    h = 0.5 * s * s
    st[i, 0] = st[i, 0] + st[i, 3] * s + st[i, 6] * h
    st[i, 1] = st[i, 1] + st[i, 4] * s + st[i, 7] * h
    st[i, 2] = st[i, 2] + st[i, 5] * s + st[i, 8] * h
    st[i, 3] = st[i, 3] + st[i, 6] * s
    st[i, 4] = st[i, 4] + st[i, 7] * s
    st[i, 5] = st[i, 5] + st[i, 8] * s


@njit(cache=True, _nrt=False)
def rotate(c, s, px, py):
    """``R(angle) p`` with ``c = cos(angle)``, ``s = sin(angle)``."""
    return c * px - s * py, s * px + c * py


@njit(cache=True, _nrt=False)
def sample_segments(seg_t, seg_s, start, stop, times, out_x, out_y, out_a, out_vx, out_vy,
                    out_w, col):
    """Evaluate one body's piecewise-quadratic motion at sorted or unsorted ``times``.

    ``seg_t[start:stop]`` are the body's segment start times (non-decreasing) and
    ``seg_s[start:stop]`` the state rows at those times. For each time the last segment
    starting at or before it is used (times before the first segment use the first).
    Results go to column ``col`` of the ``out_*`` arrays (shape ``(len(times), n)``).
    """
    n = stop - start
    for k in range(times.shape[0]):
        t = times[k]
        # binary search: last j with seg_t[start + j] <= t
        lo = 0
        hi = n - 1
        if seg_t[start] > t:
            j = 0
        else:
            while lo < hi:
                mid = (lo + hi + 1) // 2
                if seg_t[start + mid] <= t:
                    lo = mid
                else:
                    hi = mid - 1
            j = lo
        r = start + j
        s = t - seg_t[r]
        h = 0.5 * s * s
        out_x[k, col] = seg_s[r, 0] + seg_s[r, 3] * s + seg_s[r, 6] * h
        out_y[k, col] = seg_s[r, 1] + seg_s[r, 4] * s + seg_s[r, 7] * h
        out_a[k, col] = seg_s[r, 2] + seg_s[r, 5] * s + seg_s[r, 8] * h
        out_vx[k, col] = seg_s[r, 3] + seg_s[r, 6] * s
        out_vy[k, col] = seg_s[r, 4] + seg_s[r, 7] * s
        out_w[k, col] = seg_s[r, 5] + seg_s[r, 8] * s


@njit(cache=True, _nrt=False)
def body_energy(st_row, m, inertia, gx, gy):
    """Kinetic plus gravitational energy (J) of one body state row (potential 0 at x = 0)."""
    return (0.5 * m * (st_row[3] * st_row[3] + st_row[4] * st_row[4])
            + 0.5 * inertia * st_row[5] * st_row[5]
            - m * (gx * st_row[0] + gy * st_row[1]))
