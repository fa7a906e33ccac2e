"""Shared reference of the slope tests (``test_sphere_slope``, ``test_face_slope``): the
classical sliding-puck-on-an-incline solution.

A slip ``u`` obeying ``du/dt = a e_s - k u/|u|`` (``a`` m/s^2 down the slope ``e_s``, ``k``
m/s^2 the friction deceleration, ``q = k / a``): with ``phi`` the angle from ``e_s`` to
``u`` and ``tau = tan(phi / 2)``, ``|u| = (C / 2) tau^(q-1) (1 + tau^2)`` and ``t(tau) =
(C / 2a) [T(tau0) - T(tau)]``, ``T(tau) = tau^(q-1)/(q-1) + tau^(q+1)/(q+1)``,
``C = |u0| sin(phi0) / tau0^q``; for q > 1 the slip stops.
"""
import math

import numpy as np


def slip_stop_time(u0, es, a, q, eps):
    """Time (s) at which the slip from ``u0`` (m/s) has fallen to ``eps`` (m/s), for q > 1
    (bisection in tau: ``|u|(tau)`` increases with tau on (0, tau0])."""
    U0 = np.linalg.norm(u0)
    phi0 = math.acos(max(-1.0, min(1.0, (u0 @ es) / U0)))
    tau0 = math.tan(phi0 / 2.0)
    C = U0 * math.sin(phi0) / tau0 ** q

    def T(tau):
        return tau ** (q - 1) / (q - 1) + tau ** (q + 1) / (q + 1)

    lo, hi = 0.0, tau0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if 0.5 * C * mid ** (q - 1) * (1 + mid * mid) > eps:
            hi = mid
        else:
            lo = mid
    return C / (2.0 * a) * (T(tau0) - T(hi))
