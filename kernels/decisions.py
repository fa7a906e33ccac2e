"""Decisions the steppers take on a contact, stated once for 2D and 3D (issue 13 item 2).

No decision is taken on the sign of round-off: a quantity that is zero up to rounding
(a plastic impact's post-impact normal velocity of -1e-15 m/s) is zero here, and what
counts as "zero" is either a property of the law and its parameters or a tolerance scaled
to the contact's own speed.
"""
import math

from numba import njit

from .codes import PP_CHATTER, PP_TOGETHER
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


@njit(cache=True, _nrt=False, inline="always")
def touching_speed(speed, accel, reach):
    """The speed scale (m/s) of a touching contact's rate, for ``touching_rate``: the speed
    it is computed from (``speed``, m/s), and at least ``sqrt(|accel| reach)``, the speed
    the body's acceleration (``accel``, m/s^2: gravity in flight) gives it over the contact
    point's reach from its centre (``reach``, m). A body brought to rest within one instant
    by alternating impacts has no speed of its own left to scale the round-off: a polygon
    face flat against a wall (2:937134506) went on to 1e-323 m/s and stalled."""
    return speed + math.sqrt(abs(accel) * reach)


@njit(cache=True, _nrt=False, inline="always")
def touching_accel(accel, body_accel, omega, reach):
    """The normal acceleration (m/s^2) of a touching contact's gap with its round-off
    removed: 0 when ``|accel| <= TOUCH_RTOL (|body_accel| + omega^2 reach)`` (the body's
    centre acceleration, m/s^2; its angular speed, rad/s; the contact point's reach from
    the centre, m: the terms the gap acceleration is computed from), else ``accel``. A rod
    or capsule flat against a wall that gravity does not push has a gap acceleration of
    ``omega^2`` times the round-off of its tilt (-1.4e-20 m/s^2 at 2:441169314): read for
    its sign, the end was held as if pushed and refused as an accumulation."""
    return 0.0 if abs(accel) <= TOUCH_RTOL * (abs(body_accel) + omega * omega * reach) else accel


#: a body pair's normal speed at most PAIR_VN_RTOL times the speed it is computed from
#: (|v_A| + |v_B| + |w_A| |r_A| + |w_B| |r_B|, m/s: the round-off of ``v_A - v_B``), or at
#: most the joint solve's ``simul_tol`` (the residual it leaves at a contact), is zero:
#: never read for its sign (``pair_zero_speed``, ``pair_persistence``) (dimensionless)
PAIR_VN_RTOL = 1e-12


@njit(cache=True, _nrt=False, inline="always")
def pair_zero_speed(speed, residual):
    """The normal speed (m/s) below which a pair's contact rate is zero: the larger of
    ``PAIR_VN_RTOL speed`` (``speed`` m/s, the absolute speeds the rate is computed from)
    and ``residual`` (m/s), the joint solve's stopping tolerance (3D ``simul_tol``; 2D
    ``simul_tol`` times the speed, its ``simul_tol`` being relative)."""
    return max(PAIR_VN_RTOL * speed, residual)


#: a re-contact of a pair ``s`` after an impact that left its contact separating at ``v``
#: is the same contact turning back only if its gap could: a parabola through ``v`` that
#: closes at ``s`` needs ``|g''| = 2 v / s``; when that exceeds PAIR_RECONTACT_SLACK times
#: the bound ``G`` of the pair's ``|g''|`` (``pair_accel_bound``) the re-contact is another
#: contact of the pair (the far end of an edge, a second corner: a near-simultaneous
#: impact the contact frame did not name), resolved as an impact, not an accumulation
#: (a box pair under Brach's law: v = 2.17 m/s, s = 1.8e-17 s) (dimensionless)
PAIR_RECONTACT_SLACK = 10.0


@njit(cache=True, _nrt=False, inline="always")
def pair_accel_bound(da, alA, rA, alB, rB, wA, wB, speed):
    """A bound (m/s^2) of ``|g''|`` of a contact between two bodies in free flight or in a
    closed-form motion: ``|a_A - a_B|`` (``da``) plus the angular accelerations times the
    arms (``alA rA + alB rB``) plus ``4 (|w_A| + |w_B|) speed`` (rad/s, m/s), which covers
    the centripetal terms ``|w|^2 r <= |w| speed``, the normal's turning ``2 |w| |v_rel|`` and
    the torque-free ``|dw/dt| <= |w|^2`` of any rigid body (``|I2 - I3| <= I1``)."""
    return da + alA * rA + alB * rB + 4.0 * (wA + wB) * speed


@njit(cache=True, _nrt=False, inline="always")
def pair_persistence(v, s, converged, vzero, accel, rest_length):
    """Whether two bodies that had an impact stay in contact (2D and 3D; persistent
    body-body contact is not built, issue 16 item 2): 0 (they part) or the reason
    ``codes.PP_CHATTER`` / ``codes.PP_TOGETHER``.

    ``v`` (m/s) is the gap rate just after the impact, ``s`` (s) the pair's next time of
    impact from there (``inf``: none), ``converged`` whether that search converged,
    ``vzero`` (m/s) the rate that is zero (``pair_zero_speed``), ``accel`` (m/s^2) a bound
    of the contact's ``|g''|`` (``pair_accel_bound``), ``rest_length`` (m) the scene's. In
    free flight the gap rises to about ``v s / 4`` before it closes again (exact for a
    parabola ``g = v s' - |g''| s'^2 / 2``, whose root is ``s = 2 v / |g''|``): below
    ``rest_length`` the impacts accumulate at that contact (``PP_CHATTER``; the rule of a
    single point on a plane, ``v^2 < 2 |g''| rest_length``, without needing ``g''``),
    unless the re-contact is too early to be that contact's (``PAIR_RECONTACT_SLACK``) or
    the frame's contact approaches (``v < -vzero``: the laws leave a resolved contact at
    ``v >= 0``, so this is another contact of the pair that the instant did not resolve,
    the closest features having been tied with it: an impact at once). A search that does
    not converge from the touching state while ``|v| <= vzero`` (the bodies ride together:
    zero gravity, plastic impact) is ``PP_TOGETHER``."""
    if v < -vzero:
        return 0.0
    if not converged:
        return PP_TOGETHER if v <= vzero else 0.0
    vp = max(v, 0.0)
    if s < math.inf and vp * s < 4.0 * rest_length:
        if 2.0 * vp > PAIR_RECONTACT_SLACK * accel * s:
            return 0.0      # another contact of the pair, not this one turning back
        return PP_CHATTER
    return 0.0


@njit(cache=True, _nrt=False)
def pair_crawl_chatters(v, accel, rest_length):
    """Whether a touching pair (its gap within ``gap_tol``) whose time-of-impact search did
    not converge (the conservative advancement crawls: the gap moves at a rate far below
    the points' speeds) is an accumulation: its gap rate ``v`` (m/s) at most
    ``sqrt(2 accel rest_length)`` (``accel`` m/s^2 the bound of ``|g''|``, ``rest_length`` m),
    the speed below which a parabola of that curvature rises less than ``rest_length``
    before it closes (``pair_persistence``'s rule without the re-contact time, and the
    single point's on a plane). 2D: the pair then enters a cluster, whose mode selection
    lets the contact lift at once if it parts."""
    return v * v <= 2.0 * accel * rest_length


#: a pair released from persistent contact (``codes.PR_REL``: its contact lifted at a
#: tangency of order three) is searched from the first offset ``REL_S0 T 2^k`` (T =
#: sqrt(R / |a_rel|), or R / |v_rel|; R the sum of the radii) where its gap exceeds gap_tol
#: and grows: searched from a gap of zero, the conservative advancement would crawl
#: (dimensionless; a re-contact within that offset of the release is not seen)
REL_S0 = 1e-7
