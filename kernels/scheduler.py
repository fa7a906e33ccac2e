"""Event queue for event-driven molecular dynamics of many bodies: one pending event per
body, kept in a calendar queue (after Smallenburg's EDMD; F. Smallenburg, "Efficient
event-driven simulations of hard spheres", Eur. Phys. J. E 45:22, 2022; the calendar
queue itself is R. Brown, Comm. ACM 31:1220, 1988).

What is stored: for every body ``i`` one key ``qkey[i]`` (the absolute time of its next
event, s). *What* the event is (collision, wall, cell crossing) is the caller's business;
the queue only orders bodies by key. Invalidation is the caller's too: the usual scheme
(used by ``gas_core``) keeps a per-body collision counter, stores with each predicted
collision the partner's counter, and on pop checks that it is unchanged ("validate on
pop"); a stale event is recomputed and pushed again. ``q_remove`` / ``q_update`` move a
body whose event changed (its key is replaced in O(1) on average).

Layout. Time is cut into blocks of width ``dt`` (s); block ``b = floor(t / dt)``.
``nb`` buckets (doubly linked lists threaded through ``qlink``) hold the bodies whose
block lies strictly between the current block ``cur`` and the horizon ``hor`` (at most
``nb`` blocks ahead, so one bucket holds a single block). Bodies in the current block
(or earlier) sit in a small indexed binary heap (exact order); bodies at or beyond the
horizon sit in an overflow list, redistributed once per calendar year (every ``nb``
blocks). Popping the minimum: if the heap is empty, step ``cur`` to the next block and
move that bucket's bodies into the heap. With ``dt`` chosen so that a bucket holds a few
bodies, push, remove and pop are O(1) on average (the heap stays a few entries deep).
If the buckets and the heap are all empty the queue jumps straight to the earliest
overflow block (no scan of empty years).

Arrays (all owned by the caller, nothing is allocated here):

* ``qkey``  float64[n]: event time of each body (s); ``inf`` allowed (never happens).
* ``qlink`` int64[n, 4]: per body ``NEXT``, ``PREV`` (bucket lists), ``WHERE`` (bucket
  index, ``nb`` for overflow, ``IN_HEAP``, or ``OUT``), ``HPOS`` (heap position); the
  row layout keeps one body's links in one cache line.
* ``qheap`` int64[n]: the heap (body ids), ``qhead`` int64[nb + 1]: list heads (the
  last one is the overflow list).
* ``qs``    int64[N_QS]: scalars ``S_HSIZE``, ``S_CUR``, ``S_HOR``, ``S_NB``, ``S_NCAL``
  (bodies in buckets), ``S_NOVER`` (bodies in overflow).
* ``qdt``   float64[2]: ``dt`` (s) and ``1/dt``.

Interface: ``q_init``, ``q_push(i, t)``, ``q_remove(i)``, ``q_update(i, t)`` (remove if
queued, then push), ``q_top()`` (body with the smallest key, -1 if empty; advances the
calendar, never changes the order), ``q_pop()`` (remove and return it), ``q_rebuild``
(new bucket width; a caller whose event rate drifts, e.g. a cooling gas, calls it when
``q_fill_dt`` has moved by more than a factor of 2: a fixed width would leave the bodies
in the overflow list or crowd one bucket). A body with no event for a while (a sleeping
body of ``gas_core``) is simply left out: ``q_remove`` it and set its key to ``inf`` (which
``q_fill_dt`` ignores); ``q_update`` queues it again when it wakes. Every helper is
``inline='always'`` so that a caller's hot loop (compiled with ``_nrt=False``) contains
no call and no reference counting on the arrays (3x measured in a hot loop). Numba inlines
at the IR level, so a caller should have few call sites of them (``gas_core.gas_loop``
has one of each); ``q_*_k`` are standalone entry points for Python callers and tests.
"""
import math

from numba import njit

NEXT = 0
PREV = 1
WHERE = 2
HPOS = 3
N_QLINK = 4

IN_HEAP = -1
OUT = -2

S_HSIZE = 0
S_CUR = 1
S_HOR = 2
S_NB = 3
S_NCAL = 4
S_NOVER = 5
N_QS = 6

BIG_BLOCK = 1 << 62       # block of an infinite or absurdly far key
_BIG_F = 4.0e18           # t / dt beyond this counts as BIG_BLOCK

_NJ = dict(cache=True, inline="always", error_model="numpy")
_NJC = dict(cache=True, error_model="numpy", _nrt=False)   # cold paths: not inlined
# (less code for the caller's compile; they run once per calendar year or rarer)


@njit(**_NJ)
def q_block(t, qdt):
    """Block index of time ``t`` (floor(t / dt)); BIG_BLOCK for huge or infinite t."""
    b = t * qdt[1]
    if not (b < _BIG_F):
        return BIG_BLOCK
    return int(math.floor(b))


# ---- indexed binary heap on qkey ---------------------------------------------------------

@njit(**_NJ)
def _sift_up(pos, qkey, qlink, qheap):
    i = qheap[pos]
    k = qkey[i]
    while pos > 0:
        parent = (pos - 1) >> 1
        p = qheap[parent]
        if qkey[p] <= k:
            break
        qheap[pos] = p
        qlink[p, HPOS] = pos
        pos = parent
    qheap[pos] = i
    qlink[i, HPOS] = pos


@njit(**_NJ)
def _sift_down(pos, qkey, qlink, qheap, size):
    i = qheap[pos]
    k = qkey[i]
    while True:
        c = 2 * pos + 1
        if c >= size:
            break
        if c + 1 < size and qkey[qheap[c + 1]] < qkey[qheap[c]]:
            c += 1
        ch = qheap[c]
        if qkey[ch] >= k:
            break
        qheap[pos] = ch
        qlink[ch, HPOS] = pos
        pos = c
    qheap[pos] = i
    qlink[i, HPOS] = pos


@njit(**_NJ)
def _heap_push(i, qkey, qlink, qheap, qs):
    pos = qs[S_HSIZE]
    qs[S_HSIZE] = pos + 1
    qheap[pos] = i
    qlink[i, WHERE] = IN_HEAP
    _sift_up(pos, qkey, qlink, qheap)


@njit(**_NJ)
def _heap_remove(i, qkey, qlink, qheap, qs):
    pos = qlink[i, HPOS]
    size = qs[S_HSIZE] - 1
    qs[S_HSIZE] = size
    qlink[i, WHERE] = OUT
    if pos == size:
        return
    last = qheap[size]
    qheap[pos] = last
    qlink[last, HPOS] = pos
    if pos > 0 and qkey[last] < qkey[qheap[(pos - 1) >> 1]]:
        _sift_up(pos, qkey, qlink, qheap)
    else:
        _sift_down(pos, qkey, qlink, qheap, size)


# ---- bucket lists ----------------------------------------------------------------------

@njit(**_NJ)
def _list_push(i, b, qlink, qhead):
    h = qhead[b]
    qlink[i, NEXT] = h
    qlink[i, PREV] = -1
    if h >= 0:
        qlink[h, PREV] = i
    qhead[b] = i
    qlink[i, WHERE] = b


@njit(**_NJ)
def _list_remove(i, qlink, qhead):
    b = qlink[i, WHERE]
    nx = qlink[i, NEXT]
    pv = qlink[i, PREV]
    if pv >= 0:
        qlink[pv, NEXT] = nx
    else:
        qhead[b] = nx
    if nx >= 0:
        qlink[nx, PREV] = pv
    qlink[i, WHERE] = OUT


@njit(**_NJ)
def _place(i, qkey, qlink, qheap, qhead, qs, qdt):
    """Put body i (not queued) where its key belongs: heap, bucket or overflow."""
    blk = q_block(qkey[i], qdt)
    if blk <= qs[S_CUR]:
        _heap_push(i, qkey, qlink, qheap, qs)
    elif blk < qs[S_HOR]:
        nb = qs[S_NB]
        _list_push(i, blk % nb, qlink, qhead)
        qs[S_NCAL] += 1
    else:
        _list_push(i, qs[S_NB], qlink, qhead)
        qs[S_NOVER] += 1


# ---- public helpers ----------------------------------------------------------------------

@njit(**_NJ)
def q_push(i, t, qkey, qlink, qheap, qhead, qs, qdt):
    """Queue body ``i`` (not queued) with event time ``t`` (s)."""
    qkey[i] = t
    _place(i, qkey, qlink, qheap, qhead, qs, qdt)


@njit(**_NJ)
def q_remove(i, qkey, qlink, qheap, qhead, qs):
    """Take body ``i`` out of the queue (no-op if it is not queued)."""
    w = qlink[i, WHERE]
    if w == IN_HEAP:
        _heap_remove(i, qkey, qlink, qheap, qs)
    elif w >= 0:
        _list_remove(i, qlink, qhead)
        if w == qs[S_NB]:
            qs[S_NOVER] -= 1
        else:
            qs[S_NCAL] -= 1


@njit(**_NJ)
def q_update(i, t, qkey, qlink, qheap, qhead, qs, qdt):
    """Give body ``i`` the event time ``t`` (s), queued or not."""
    q_remove(i, qkey, qlink, qheap, qhead, qs)
    qkey[i] = t
    _place(i, qkey, qlink, qheap, qhead, qs, qdt)


@njit(**_NJC)
def _redistribute(qkey, qlink, qheap, qhead, qs, qdt):
    """New calendar year: horizon = cur + nb; overflow bodies now inside it are placed."""
    nb = qs[S_NB]
    qs[S_HOR] = qs[S_CUR] + nb
    i = qhead[nb]
    while i >= 0:
        nx = qlink[i, NEXT]
        if q_block(qkey[i], qdt) < qs[S_HOR]:
            _list_remove(i, qlink, qhead)
            qs[S_NOVER] -= 1
            _place(i, qkey, qlink, qheap, qhead, qs, qdt)
        i = nx


@njit(**_NJC)
def _jump(qkey, qlink, qheap, qhead, qs, qdt):
    """Heap and buckets empty: set the calendar just before the earliest overflow block
    (or, if only infinite keys are left, move them all into the heap)."""
    nb = qs[S_NB]
    m = BIG_BLOCK
    i = qhead[nb]
    while i >= 0:
        b = q_block(qkey[i], qdt)
        if b < m:
            m = b
        i = qlink[i, NEXT]
    if m >= BIG_BLOCK:
        # only infinite (or absurdly far) keys left: the heap takes them all and
        # every later push (the calendar then degenerates into a binary heap)
        i = qhead[nb]
        while i >= 0:
            nx = qlink[i, NEXT]
            _list_remove(i, qlink, qhead)
            qs[S_NOVER] -= 1
            _heap_push(i, qkey, qlink, qheap, qs)
            i = nx
        qs[S_CUR] = BIG_BLOCK
        qs[S_HOR] = BIG_BLOCK + nb
        return
    qs[S_CUR] = m - 1
    qs[S_HOR] = m


@njit(**_NJ)
def q_top(qkey, qlink, qheap, qhead, qs, qdt):
    """Body with the smallest key (-1 if the queue is empty). Advances the calendar to
    the block of that key (bodies of the new block move into the heap); the set of queued
    bodies and their keys are unchanged."""
    while qs[S_HSIZE] == 0:
        nb = qs[S_NB]
        if qs[S_NCAL] == 0:
            if qs[S_NOVER] == 0:
                return -1
            # nothing before the horizon: jump to the earliest overflow block
            _jump(qkey, qlink, qheap, qhead, qs, qdt)
            if qs[S_HSIZE] > 0:
                continue
        cur = qs[S_CUR] + 1
        qs[S_CUR] = cur
        if cur >= qs[S_HOR]:
            _redistribute(qkey, qlink, qheap, qhead, qs, qdt)
        b = cur % nb
        i = qhead[b]
        while i >= 0:
            nx = qlink[i, NEXT]
            _heap_push(i, qkey, qlink, qheap, qs)
            qs[S_NCAL] -= 1
            i = nx
        qhead[b] = -1
    return qheap[0]


@njit(**_NJ)
def q_pop(qkey, qlink, qheap, qhead, qs, qdt):
    """Remove and return the body with the smallest key (-1 if empty)."""
    i = q_top(qkey, qlink, qheap, qhead, qs, qdt)
    if i >= 0:
        _heap_remove(i, qkey, qlink, qheap, qs)
    return i


@njit(cache=True, error_model="numpy")
def q_init(qkey, qlink, qheap, qhead, qs, qdt, nb, dt, t0):
    """Empty queue with ``nb`` buckets of width ``dt`` (s) starting at time ``t0`` (s).
    ``qhead`` must hold ``nb + 1`` entries. Keys already in ``qkey`` are not queued:
    push every body afterwards (``q_push``)."""
    qdt[0] = dt
    qdt[1] = 1.0 / dt
    for i in range(qlink.shape[0]):
        qlink[i, NEXT] = -1
        qlink[i, PREV] = -1
        qlink[i, WHERE] = OUT
        qlink[i, HPOS] = -1
    for b in range(nb + 1):
        qhead[b] = -1
    qs[S_HSIZE] = 0
    qs[S_NB] = nb
    qs[S_CUR] = q_block(t0, qdt)
    qs[S_HOR] = qs[S_CUR] + nb
    qs[S_NCAL] = 0
    qs[S_NOVER] = 0


@njit(**_NJC)
def q_rebuild(qkey, qlink, qheap, qhead, qs, qdt, dt, t0):
    """Re-bucket every queued body with the new bucket width ``dt`` (s), the calendar
    restarting at time ``t0`` (s, no key earlier). O(n); for a caller whose event rate
    drifts (a cooling gas): see ``q_fill_dt``."""
    n = qkey.shape[0]
    nb = qs[S_NB]
    qdt[0] = dt
    qdt[1] = 1.0 / dt
    queued = 0
    for i in range(n):
        if qlink[i, WHERE] != OUT:
            qlink[i, WHERE] = 1      # mark: queued
            queued += 1
    for b in range(nb + 1):
        qhead[b] = -1
    qs[S_HSIZE] = 0
    qs[S_CUR] = q_block(t0, qdt)
    qs[S_HOR] = qs[S_CUR] + nb
    qs[S_NCAL] = 0
    qs[S_NOVER] = 0
    for i in range(n):
        if qlink[i, WHERE] != OUT:
            qlink[i, WHERE] = OUT
            _place(i, qkey, qlink, qheap, qhead, qs, qdt)


@njit(**_NJC)
def q_fill_dt(qkey, t0, fill):
    """Bucket width (s) that puts about ``fill`` bodies in a bucket: ``fill`` times the
    mean time to the next event (over finite keys, from ``t0``) divided by the number of
    bodies; 0 when no key is finite."""
    tot = 0.0
    m = 0
    for i in range(qkey.shape[0]):
        k = qkey[i]
        if k < math.inf:
            tot += k - t0
            m += 1
    if m == 0 or not tot > 0.0:
        return 0.0
    return fill * tot / (m * qkey.shape[0])


# ---- standalone wrappers (tests, Python callers) -----------------------------------------

@njit(cache=True, error_model="numpy")
def q_push_k(i, t, qkey, qlink, qheap, qhead, qs, qdt):
    q_push(i, t, qkey, qlink, qheap, qhead, qs, qdt)


@njit(cache=True, error_model="numpy")
def q_update_k(i, t, qkey, qlink, qheap, qhead, qs, qdt):
    q_update(i, t, qkey, qlink, qheap, qhead, qs, qdt)


@njit(cache=True, error_model="numpy")
def q_remove_k(i, qkey, qlink, qheap, qhead, qs):
    q_remove(i, qkey, qlink, qheap, qhead, qs)


@njit(cache=True, error_model="numpy")
def q_pop_k(qkey, qlink, qheap, qhead, qs, qdt):
    return q_pop(qkey, qlink, qheap, qhead, qs, qdt)


def q_alloc(n, nb, index_dtype="int64"):
    """NumPy arrays of a queue for ``n`` bodies and ``nb`` buckets (Python helper):
    ``(qkey, qlink, qheap, qhead, qs, qdt)``. ``index_dtype``: of the body links
    ("int32" halves their memory; n and nb must then be < 2^31). ``qs`` holds block
    numbers: always int64."""
    import numpy as np
    return (np.full(n, np.inf), np.full((n, N_QLINK), -1, index_dtype),
            np.full(n, -1, index_dtype), np.full(nb + 1, -1, index_dtype),
            np.zeros(N_QS, np.int64), np.zeros(2))
