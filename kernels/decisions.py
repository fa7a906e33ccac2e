"""Decisions the steppers take on a contact, stated once for 2D and 3D (issue 13 item 2).

No decision is taken on the sign of round-off: a quantity that is zero up to rounding
(a plastic impact's post-impact normal velocity of -1e-15 m/s) is zero here, and what
counts as "zero" is either a property of the law and its parameters or a tolerance scaled
to the contact's own speed.
"""
import math

from numba import njit

from .common import P_E


@njit(cache=True, _nrt=False, inline="always")
def perforates(law_par_row, vfN):
    """True when an impact resolved by a law with parameters ``law_par_row`` leaves the
    contact approaching at normal velocity ``vfN`` (m/s) *because the law says so*: only a
    negative restitution (Brach's ``e < 0``: the body goes through a barrier) perforates.
    Every other law ends an impact with ``v_fN = -e v_N >= 0`` in exact arithmetic, so a
    negative ``vfN`` from them is round-off of a plastic (``e = 0``) impact: the body stays
    on the plane (its contact is then handled as resting or accumulating)."""
    return law_par_row[P_E] < 0.0 and vfN < 0.0


@njit(cache=True, _nrt=False)
def impacts_before_rest(after, before, gn, t, t_end, eex, thr):
    """Number of further impacts (a float, >= 0) of a round body bouncing on a plane before
    its bounces accumulate onto it (Zeno) or the run ends, whichever comes first.

    A disk's or sphere's normal impulse exerts no moment about its centre (``W_NT = 0``), so
    every law gives the same normal restitution ratio ``e = -after / before`` (the centre's
    normal velocity after / before the impact, m/s) at every later bounce: the bounces are
    geometric. Its excess energy ``eex`` (J) falls by ``e^2`` per bounce to the accumulation
    threshold ``thr`` = m zeno_speed^2 / 2 (J) after ``ln(eex / thr) / (2 ln(1/e))`` bounces;
    its flight times ``f0 e^j`` (``f0 = 2 after / |g_n|``, s) reach the end of the run
    ``t_end - t`` (s) after ``ln(1 - (t_end - t)(1 - e) / f0) / ln e`` bounces (never when
    the logarithm's argument is <= 0). Returns 0 for a body not bouncing back
    (``after <= 0``) or an elastic one (``e >= 1``: no accumulation; ``max_events`` bounds
    it)."""
    if not (before < 0.0 and after > 0.0 and gn < 0.0):
        return 0.0
    e = -after / before
    if not e < 1.0:
        return 0.0
    n_thr = 0.0
    if eex > thr > 0.0:
        n_thr = 0.5 * math.log(eex / thr) / -math.log(e)
    f0 = 2.0 * after / -gn
    x = 1.0 - (t_end - t) * (1.0 - e) / f0
    if x > 0.0:
        return min(n_thr, math.log(x) / math.log(e))
    return n_thr


@njit(cache=True, _nrt=False, inline="always")
def accumulation_time(after, before, gn):
    """Time (s) from an impact of a body bouncing on a plane to the accumulation point of
    its bounces: the flight times ``2 after / |g_n|`` (s) shrink by ``e = -after / before``
    per bounce (centre's normal velocity after / before the impact, m/s; ``gn < 0`` the
    normal gravity, m/s^2) and sum to ``2 after / (|g_n| (1 - e))``; 0 for a body not
    bouncing back (``after <= 0``), a single flight when e is not below 1."""
    dt = 0.0
    if after > 0.0:
        dt = 2.0 * after / (-gn)
        if before < 0.0:
            ek = -after / before
            if ek < 1.0:
                dt = dt / (1.0 - ek)
    return dt


#: a touching contact (gap <= 0, within gap_tol) approaches only when its normal rate is
#: below -TOUCH_RTOL times the speed it is computed from (m/s: the bodies' centre speeds
#: plus |w| r): an impact resolved to v_N = 0 leaves a rate of that speed's round-off
#: (-2.8e-17 m/s at 0.5 m/s), which read as a new approach at the same instant stalled runs
#: (3:3811175237, two spheres; 3:2310587818, a box corner on a wall) (dimensionless)
TOUCH_RTOL = 1e-12


@njit(cache=True, _nrt=False, inline="always")
def touching_rate(rate, speed):
    """The normal rate (m/s) of a touching contact with its round-off removed: 0 when
    ``|rate| <= TOUCH_RTOL speed`` (``speed`` m/s, the scale the rate is computed from),
    else ``rate``."""
    return 0.0 if abs(rate) <= TOUCH_RTOL * speed else rate
