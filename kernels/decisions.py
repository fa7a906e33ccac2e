"""Decisions the steppers take on a contact, stated once for 2D and 3D (issue 13 item 2).

No decision is taken on the sign of round-off: a quantity that is zero up to rounding
(a plastic impact's post-impact normal velocity of -1e-15 m/s) is zero here, and what
counts as "zero" is either a property of the law and its parameters or a tolerance scaled
to the contact's own speed.
"""
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
