"""Compiled entries of the many-body engine: ``entries_for(D, law, sleep)`` gives the
set-up, the event loop and the end of a run of ``gas_core`` for one dimension ``D`` (2:
disks, 3: spheres), one law (a ``LAW_*`` id of ``common``) and one sleep option. The
arguments and the model are described in ``gas_core``.

Why a factory (as ``stepper2d.loop_for``): the entries differ only in these three
compile-time constants, so each is built by a memoised function (``functools.lru_cache``)
closing over them as a plain int or bool, and defining the ``@njit`` entry inside:

* only what is called is compiled: Numba prunes the branches on the constants before
  typing (``gas_loop`` and its helpers are inlined into the entry), so a 2D Kane &
  Levinson gas types that law's 2D kernel only, no other law and no 3D code; with
  ``sleep`` False the sleep code is folded away (the loop a gas without gravity always
  ran);
* each (D, law, sleep) has its own on-disk cache entry, loaded by later processes: Numba
  keys the cache of a closure on its cell values (pickled), here ints and bools. A cell
  holding a compiled function (a law chosen in Python) would not do: it pickles with the
  dispatcher's per-process id, so every new process would miss the cache, compile again
  and add one more cache file.

Entries are compiled without Numba reference counting (``_nrt=False``): they only index
the caller's arrays.
"""
import functools

from numba import njit

from .cache_guard import guard

# flush stale compiled code before the kernel modules below are imported (cache_guard)
guard(__name__, __file__)

from .common import (LAW_BRACH, LAW_CHATTERJEE_RUINA, LAW_KANE_LEVINSON, LAW_ROUTH,
                     LAW_SMITH)
from .gas_core import gas_finish, gas_loop, gas_prepare

LAW_IDS = (LAW_KANE_LEVINSON, LAW_BRACH, LAW_SMITH, LAW_ROUTH, LAW_CHATTERJEE_RUINA)


def entries_for(D, law, sleep):
    """``(prepare, run, finish)`` compiled (on first call, or loaded from the cache) for
    dimension ``D`` (2 or 3), law id ``law`` (``LAW_IDS``) and the sleep option ``sleep``
    (True needs gravity). ``prepare`` depends on ``D`` and ``sleep`` only, ``finish`` on
    ``D`` only: laws share them. Raises ``ValueError`` for another ``D`` or ``law``."""
    if D not in (2, 3) or isinstance(D, bool):
        raise ValueError(f"entries_for: D must be 2 or 3, got {D!r}")
    if law not in LAW_IDS or isinstance(law, bool):
        raise ValueError(f"entries_for: law must be one of the ids {LAW_IDS}, got {law!r}")
    D, law, sleep = int(D), int(law), bool(sleep)
    return _prepare_for(D, sleep), _run_for(D, law, sleep), _finish_for(D)


@functools.lru_cache(maxsize=None)
def _run_for(D, LAW, SLEEP):
    """The event loop ``gas_core.gas_loop`` for (D, LAW, SLEEP)."""

    @njit(cache=True, error_model="numpy", _nrt=False)
    def run(x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar, ipar, stats,
            fstats, rec_i, rec_f, rec_mask, snap_t, snap_v, snap_w):
        """Run until t_end, max impacts, a full buffer or a failure; returns the status
        (``gas_core.RUN_*``)."""
        return gas_loop(D, LAW, SLEEP, x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead,
                        qs, qdt, fpar, ipar, stats, fstats, rec_i, rec_f, rec_mask, snap_t,
                        snap_v, snap_w)
    return run


@functools.lru_cache(maxsize=None)
def _prepare_for(D, SLEEP):
    """The set-up ``gas_core.gas_prepare`` for (D, SLEEP)."""

    @njit(cache=True, error_model="numpy", _nrt=False)
    def prepare(x, v, bt, bi, chead, qkey, fpar, ipar, t0):
        """Cells, local times ``t0`` (s) and every prediction; the keys into ``qkey``."""
        gas_prepare(D, SLEEP, x, v, bt, bi, chead, qkey, fpar, ipar, t0)
    return prepare


@functools.lru_cache(maxsize=None)
def _finish_for(D):
    """The end of a run ``gas_core.gas_finish`` for D."""

    @njit(cache=True, error_model="numpy", _nrt=False)
    def finish(t, x, v, bt, bi, g):
        """Every awake body advanced to time ``t`` (s) under gravity ``g`` (m/s^2)."""
        gas_finish(D, t, x, v, bt, bi, g)
    return finish
