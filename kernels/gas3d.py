"""Granular gas of spheres in a box (3D): compiled entries of ``gas_core`` with ``D = 3``.

One ``run_<law>`` entry per law (a two-line ``@njit(cache=True)`` function calling the
inline generic loop ``gas_core.gas_loop`` with that law's adapters, module-level compiled
functions): calling one law compiles and caches that law only (its 2D and 3D scalar
kernels: the dimension branches are typed, then folded by LLVM). ``run_<law>_sleep`` is
the same loop with the sleep option compiled in (``SLEEP = True``, a constant: with False
the sleep code is folded away, and a gas without gravity runs the loop it always ran);
``prepare_sleep`` is the set-up that knows sleepers. All arguments and the model are
described in ``gas_core``. Entries are compiled without Numba reference
counting (``_nrt=False``): the loop only indexes the caller's arrays.
"""
from numba import njit

from .cache_guard import guard

# flush stale compiled code before the kernel modules below are imported (cache_guard)
guard(__name__, __file__)

from .gas_core import (brach_2d, brach_3d, cr_2d, cr_3d, gas_finish, gas_loop, gas_prepare,
                       kl_2d, kl_3d, routh_2d, routh_3d, smith_2d, smith_3d)

D = 3
_OPT = dict(cache=True, error_model="numpy", _nrt=False)


@njit(**_OPT)
def prepare(x, v, bt, bi, chead, qkey, fpar, ipar, t0):
    gas_prepare(D, False, x, v, bt, bi, chead, qkey, fpar, ipar, t0)


@njit(**_OPT)
def prepare_sleep(x, v, bt, bi, chead, qkey, fpar, ipar, t0):
    gas_prepare(D, True, x, v, bt, bi, chead, qkey, fpar, ipar, t0)


@njit(**_OPT)
def finish(t, x, v, bt, bi, g):
    gas_finish(D, t, x, v, bt, bi, g)


@njit(**_OPT)
def run_kane_levinson(x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar, ipar,
                      stats, fstats, rec_i, rec_f, rec_mask, snap_t, snap_v, snap_w):
    return gas_loop(D, kl_2d, kl_3d, False, x, v, w, bt, bi, chead, qkey, qlink, qheap,
                    qhead, qs, qdt, fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask,
                    snap_t, snap_v, snap_w)


@njit(**_OPT)
def run_kane_levinson_sleep(x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar,
                            ipar, stats, fstats, rec_i, rec_f, rec_mask, snap_t, snap_v,
                            snap_w):
    return gas_loop(D, kl_2d, kl_3d, True, x, v, w, bt, bi, chead, qkey, qlink, qheap,
                    qhead, qs, qdt, fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask,
                    snap_t, snap_v, snap_w)


@njit(**_OPT)
def run_chatterjee_ruina(x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar,
                         ipar, stats, fstats, rec_i, rec_f, rec_mask, snap_t, snap_v, snap_w):
    return gas_loop(D, cr_2d, cr_3d, False, x, v, w, bt, bi, chead, qkey, qlink, qheap,
                    qhead, qs, qdt, fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask,
                    snap_t, snap_v, snap_w)


@njit(**_OPT)
def run_chatterjee_ruina_sleep(x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt,
                               fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask, snap_t,
                               snap_v, snap_w):
    return gas_loop(D, cr_2d, cr_3d, True, x, v, w, bt, bi, chead, qkey, qlink, qheap,
                    qhead, qs, qdt, fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask,
                    snap_t, snap_v, snap_w)


@njit(**_OPT)
def run_brach(x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar, ipar, stats,
              fstats, rec_i, rec_f, rec_mask, snap_t, snap_v, snap_w):
    return gas_loop(D, brach_2d, brach_3d, False, x, v, w, bt, bi, chead, qkey, qlink, qheap,
                    qhead, qs, qdt, fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask,
                    snap_t, snap_v, snap_w)


@njit(**_OPT)
def run_brach_sleep(x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar, ipar,
                    stats, fstats, rec_i, rec_f, rec_mask, snap_t, snap_v, snap_w):
    return gas_loop(D, brach_2d, brach_3d, True, x, v, w, bt, bi, chead, qkey, qlink, qheap,
                    qhead, qs, qdt, fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask,
                    snap_t, snap_v, snap_w)


@njit(**_OPT)
def run_routh(x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar, ipar, stats,
              fstats, rec_i, rec_f, rec_mask, snap_t, snap_v, snap_w):
    return gas_loop(D, routh_2d, routh_3d, False, x, v, w, bt, bi, chead, qkey, qlink, qheap,
                    qhead, qs, qdt, fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask,
                    snap_t, snap_v, snap_w)


@njit(**_OPT)
def run_routh_sleep(x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar, ipar,
                    stats, fstats, rec_i, rec_f, rec_mask, snap_t, snap_v, snap_w):
    return gas_loop(D, routh_2d, routh_3d, True, x, v, w, bt, bi, chead, qkey, qlink, qheap,
                    qhead, qs, qdt, fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask,
                    snap_t, snap_v, snap_w)


@njit(**_OPT)
def run_smith(x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar, ipar, stats,
              fstats, rec_i, rec_f, rec_mask, snap_t, snap_v, snap_w):
    return gas_loop(D, smith_2d, smith_3d, False, x, v, w, bt, bi, chead, qkey, qlink, qheap,
                    qhead, qs, qdt, fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask,
                    snap_t, snap_v, snap_w)


@njit(**_OPT)
def run_smith_sleep(x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar, ipar,
                    stats, fstats, rec_i, rec_f, rec_mask, snap_t, snap_v, snap_w):
    return gas_loop(D, smith_2d, smith_3d, True, x, v, w, bt, bi, chead, qkey, qlink, qheap,
                    qhead, qs, qdt, fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask,
                    snap_t, snap_v, snap_w)
