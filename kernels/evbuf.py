"""Output buffers of the steppers (events and trajectory segments), shared by ``stepper2d``
and ``stepper3d``.

The compiled loops write events and segments into preallocated arrays and never allocate.
Before handling one more instant they check that the worst case of that instant fits
(``has_room``); if not they return ``RC_BUFFER_FULL`` and the Python front end enlarges the
buffers (``grow``) and calls the loop again, which resumes where it stopped.

Worst case of one instant (rows): events ``seq_max_steps`` sequential resolutions plus
``8 maxc + 6 nb + 16`` (impacts, persistent-contact and mode events of every body);
segments ``6 nb + 4 maxc + 16``.
"""
import numpy as np
from numba import njit

# The loops' counters (``cnt``, int64, ``N_CNT`` slots), shared by 2D and 3D:
CN_EVENTS = 0   # event rows used (the Python front end drains them: not a run total)
CN_SEGS = 1     # segment rows used (drained likewise)
CN_STALL = 2    # consecutive passes of the loop at one instant (``stall_events``)
CN_STARTED = 3  # 0 until the run's first pass has initialised it
CN_IDLE = 4     # consecutive passes since the last event was logged (``idle_passes``)
N_CNT = 5


@njit(cache=True, inline="always")
def event_margin(seq_max_steps, maxc, nb):
    """Free event rows a loop needs before it handles one more instant."""
    return seq_max_steps + 8 * maxc + 6 * nb + 16


@njit(cache=True, inline="always")
def segment_margin(maxc, nb):
    """Free segment rows a loop needs before it handles one more instant."""
    return 6 * nb + 4 * maxc + 16


# the same margins for the Python front ends (no dispatch; also under NUMBA_DISABLE_JIT)
event_margin_py = getattr(event_margin, "py_func", event_margin)
segment_margin_py = getattr(segment_margin, "py_func", segment_margin)


@njit(cache=True, inline="always")
def has_room(cnt, margin_e, margin_s, cap_e, cap_s):
    """Do ``margin_e`` more events and ``margin_s`` more segments fit (``cnt[CN_EVENTS]``,
    ``cnt[CN_SEGS]`` rows used of ``cap_e``, ``cap_s``)?"""
    return cnt[CN_EVENTS] + margin_e <= cap_e and cnt[CN_SEGS] + margin_s <= cap_s


def grow(arrays, used, need):
    """Enlarge buffers sharing their first dimension (Python side, between loop calls).

    ``arrays``: the buffers (same length); ``used``: rows filled; ``need``: free rows
    required. Returns the buffers unchanged when they have room, else new ones of at least
    twice the length holding the first ``used`` rows.
    """
    n = len(arrays[0])
    if used + need <= n:
        return tuple(arrays)
    m = max(2 * n, used + need)
    out = []
    for a in arrays:
        b = np.empty((m,) + a.shape[1:], dtype=a.dtype)
        b[:used] = a[:used]
        out.append(b)
    return tuple(out)
