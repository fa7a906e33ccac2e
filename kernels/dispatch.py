"""Law dispatch by integer id, for compiled callers that hold a per-contact law table.

``resolve_2d`` references only the 2D kernels and ``resolve_3d`` only the 3D ones, so a
2D caller never compiles 3D code. Law ids are the ``LAW_*`` constants of ``common``.
"""
from numba import njit

from .brach import brach_2d, brach_3d
from .chatterjee_ruina import chatterjee_ruina_2d, chatterjee_ruina_3d
from .common import (LAW_BRACH, LAW_CHATTERJEE_RUINA, LAW_KANE_LEVINSON, LAW_ROUTH,
                     LAW_SMITH, MODE_NO_SOLUTION, zero)
from .kane_levinson import kane_levinson_2d, kane_levinson_3d
from .routh import routh_2d, routh_3d
from .smith import smith_2d, smith_3d


@njit(cache=True)
def resolve_2d(law_id, v, W, params, P_out):
    """Apply law ``law_id`` to a 2D contact; same contract as every law kernel."""
    if law_id == LAW_KANE_LEVINSON:
        return kane_levinson_2d(v, W, params, P_out)
    if law_id == LAW_BRACH:
        return brach_2d(v, W, params, P_out)
    if law_id == LAW_CHATTERJEE_RUINA:
        return chatterjee_ruina_2d(v, W, params, P_out)
    if law_id == LAW_ROUTH:
        return routh_2d(v, W, params, P_out)
    if law_id == LAW_SMITH:
        return smith_2d(v, W, params, P_out)
    zero(P_out)
    return MODE_NO_SOLUTION


@njit(cache=True)
def resolve_3d(law_id, v, W, params, P_out):
    """Apply law ``law_id`` to a 3D contact; same contract as every law kernel."""
    if law_id == LAW_KANE_LEVINSON:
        return kane_levinson_3d(v, W, params, P_out)
    if law_id == LAW_BRACH:
        return brach_3d(v, W, params, P_out)
    if law_id == LAW_CHATTERJEE_RUINA:
        return chatterjee_ruina_3d(v, W, params, P_out)
    if law_id == LAW_ROUTH:
        return routh_3d(v, W, params, P_out)
    if law_id == LAW_SMITH:
        return smith_3d(v, W, params, P_out)
    zero(P_out)
    return MODE_NO_SOLUTION
