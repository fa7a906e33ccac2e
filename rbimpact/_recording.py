"""What ``Simulation.run`` and ``Simulation3D.run`` keep of a run (issue 15, item 3): the
``record``, ``observer`` and ``snapshot_dt`` arguments, shared by the 2D and 3D front ends.

The compiled loops (``kernels/stepper2d.py``, ``kernels/stepper3d.py``) write events at row
``cnt[CN_EVENTS]`` and trajectory segments at row ``cnt[CN_SEGS]`` of preallocated buffers
(``kernels/evbuf.py``) and never read an earlier row back; when the worst case of one more
instant does not fit they return ``RC_BUFFER_FULL`` and are called again with the same state
arrays (they resume exactly).
``Recorder.on_full`` runs between two such calls:

* ``record="all"``: the new events are handed to the observer and the buffers grow (the
  front end's own growth rule): the run and its ``Result`` are those of a plain ``run``.
* ``record="none"`` or an array of body indices: the filled rows are handed to the observer,
  counted, filtered (events involving a recorded body and those bodies' segments are
  appended to the kept lists), and dropped: ``cnt[CN_EVENTS]`` and ``cnt[CN_SEGS]`` restart
  at 0 and ``toli[TI_MAX_EVENTS]`` is lowered by the number of events dropped, so that
  ``max_events`` still counts every event of the run. Of the segments of the other bodies
  only each body's *tail* is carried on: its last segment starting at or before the current
  time ``glob[0]`` and any later one (a pivot pass records pieces ahead of the loop's time),
  which is all the exact state at any later time needs. The buffers keep their first
  capacity: ``DRAIN_ROWS`` rows (at most ``max_events + 16``) beyond the loop's margins.

Snapshots (``snapshot_dt``): the states of every body at ``0, dt, 2 dt, ...`` up to the end
of the run, evaluated by the result's own ``sample`` on the segments as they pass through:
at a drain, the times before the loop's current time (no segment logged later starts
earlier: checked at every drain), at the end the rest.
"""
import math

import numpy as np

from ._validate import _show, real
from .errors import SimulationError
from .kernels.evbuf import CN_EVENTS, CN_SEGS

__all__ = ["DRAIN_ROWS", "NotRecordedError", "Recorder", "Recording", "check_record_args"]

#: rows of events (and of segments, beyond the loop's own margins) that the buffers of a
#: run with ``record="none"`` or a list of bodies hold between two drains: their memory is
#: fixed (an event row and a segment row take 0.22 KB in 2D, 0.64 KB in 3D: about 4 MB
#: and 11 MB), and the Python cost of a drain (tens of microseconds) is spread over this
#: many events
DRAIN_ROWS = 1 << 14
#: most snapshots a run may ask for (``t_end / snapshot_dt``)
MAX_SNAPSHOTS = 10 ** 8


class NotRecordedError(RuntimeError):
    """A result method needs a part of the run that ``record`` did not keep."""


def check_record_args(who, record, observer, snapshot_dt, n_bodies, t_end):
    """Validate ``run``'s ``record``, ``observer`` and ``snapshot_dt``; returns
    ``(record, observer, snapshot_dt)`` with ``record`` "all", "none" or a sorted int64
    array of distinct body indices, ``snapshot_dt`` a float (s) or None."""
    what = f"{who}.run: record"
    allowed = (f"'all', 'none' or a non-empty 1-D array of body indices (integers in "
               f"0..{n_bodies - 1})")
    if isinstance(record, str):
        if record not in ("all", "none"):
            raise ValueError(f"{what} must be {allowed}, got {_show(record)}")
    else:
        try:
            arr = np.asarray(record)
        except Exception:  # pragma: no cover - an object NumPy cannot take
            arr = np.asarray(None)
        if arr.dtype.kind not in "iu" or arr.ndim != 1 or arr.size == 0:
            if arr.size == 0:
                why = "it is empty (use record='none' to keep no event)"
            elif arr.dtype.kind in "iu":
                why = f"an array of shape {arr.shape} is not 1-D"
            elif arr.dtype.kind == "b":
                why = "booleans are not body indices"
            else:
                why = f"its values are not integers (dtype {arr.dtype})"
            raise ValueError(f"{what} must be {allowed}, got {_show(record)}: {why}")
        bad = arr[(arr < 0) | (arr >= n_bodies)]
        if bad.size:
            raise ValueError(f"{what} must be {allowed}, got {_show(record)}: "
                             f"{int(bad[0])} is not a body index of the scene"
                             + (" (planes are not recorded on their own)"
                                if bad[0] < 0 else ""))
        record = np.unique(arr.astype(np.int64))
        record.flags.writeable = False
    if observer is not None and not callable(observer):
        raise ValueError(f"{who}.run: observer must be a callable (called with each chunk "
                         f"of events) or None, got {_show(observer)}")
    if snapshot_dt is not None:
        dt = real(f"{who}.run: snapshot_dt", snapshot_dt, "s")
        if not dt > 0.0:
            raise ValueError(f"{who}.run: snapshot_dt must be a positive finite time (s) "
                             f"or None, got {_show(snapshot_dt)}")
        if t_end / dt > MAX_SNAPSHOTS:
            raise ValueError(f"{who}.run: snapshot_dt = {dt:g} s would take "
                             f"{t_end / dt:.3g} snapshots of the run to t_end = {t_end:g} "
                             f"s, more than {MAX_SNAPSHOTS:.0e}; choose a larger snapshot_dt")
        snapshot_dt = dt
    return record, observer, snapshot_dt


class Recording:
    """What a run kept, handed to its ``Result`` (``ResultBase._init_recording``).

    ``record`` ("all", "none" or the recorded body indices), ``counts`` (events of the whole
    run per kind code), ``kinds`` (names of the codes), ``cover`` (float[n_bodies]: the
    earliest time from which each body's trajectory is kept, or None when all of it is),
    ``snapshots`` (None or ``(times, states)``)."""

    def __init__(self, record, counts, kinds, cover, snapshots):
        self.record = record
        self.counts = counts
        self.kinds = tuple(kinds)
        self.cover = cover
        self.snapshots = snapshots


class Recorder:
    """The drains of one run (see the module docstring).

    ``who``: "Simulation" or "Simulation3D"; ``record``, ``observer``, ``snapshot_dt``: from
    ``check_record_args``; ``n_bodies``; ``max_events``; ``kinds``: the stepper's
    ``EVENT_KINDS``; ``ti_max_events``: the index of ``max_events`` in ``toli``;
    ``build_events(ev_t, ev_i, ev_f)``: the structured events of raw rows (the observer's
    chunks); ``sampler(seg_t, seg_b, seg_s, times)``: the states at ``times`` (the dict of
    the result's ``sample``) from logged segment rows.
    """

    @classmethod
    def for_run(cls, who, k, build_events, sampler, n_bodies, t_end, max_events, record,
                observer, snapshot_dt):
        """The recorder of one ``run()`` of a stepper module ``k`` (``stepper2d`` or
        ``stepper3d``: its ``EVENT_KINDS`` and ``TI_MAX_EVENTS``), its recording arguments
        checked first (``check_record_args``); ``build_events(ev_t, ev_i, ev_f, kinds)``."""
        kinds = k.EVENT_KINDS
        return cls(who, *check_record_args(who, record, observer, snapshot_dt, n_bodies,
                                           t_end),
                   n_bodies=n_bodies, max_events=max_events, kinds=kinds,
                   ti_max_events=k.TI_MAX_EVENTS,
                   build_events=lambda t, i, f: build_events(t, i, f, kinds),
                   sampler=sampler)

    def __init__(self, who, record, observer, snapshot_dt, *, n_bodies, max_events, kinds,
                 ti_max_events, build_events, sampler):
        self.who = who
        self.record = record
        self.keep_all = isinstance(record, str) and record == "all"
        # the default run (everything kept, nothing streamed, no snapshot) pays nothing
        # beyond the growth of its buffers: its result counts events from the events
        self.plain = self.keep_all and observer is None and snapshot_dt is None
        self.max_events = max_events
        self.kinds = tuple(kinds)
        self.nb = n_bodies
        if self.plain:
            return
        self.bodies = None if isinstance(record, str) else record
        self.observer = observer
        self.dt = snapshot_dt
        self.ti_max_events = ti_max_events
        self.build_events = build_events
        self.sampler = sampler
        self.counts = np.zeros(len(self.kinds), np.int64)
        self.observed = 0              # rows of the event buffer already observed
        self.dropped = 0               # events dropped from the buffer so far
        self.kept_ev = []              # (ev_t, ev_i, ev_f) of recorded events, in order
        self.kept_seg = []             # (seg_t, seg_b, seg_s) of recorded bodies' past rows
        self.carry = None              # the segment rows still needed (tails), or None
        self.cut = np.zeros(n_bodies, bool)   # bodies whose early segments were dropped
        self.snap_k = 0                # next snapshot index (time snap_k * dt)
        self.snap_t = []
        self.snap_s = []
        self.t_safe = -math.inf        # no segment logged after the last drain starts earlier
        if self.bodies is not None:
            self.keep_body = np.zeros(n_bodies, bool)
            self.keep_body[self.bodies] = True

    # ------------------------------------------------------------ capacity

    def capacities(self, margin_e, margin_s, initial_rows, initial_seg_rows=None):
        """``(cap_e, cap_s)``: the first lengths of the event and segment buffers, given the
        loop's margins and the front end's first capacities for ``record="all"`` (events;
        segments, when their rows are wider: ``initial_seg_rows``, default the same)."""
        rows = initial_rows if self.keep_all else DRAIN_ROWS
        rows = min(self.max_events + 16, rows)
        srows = rows
        if self.keep_all and initial_seg_rows is not None:
            srows = min(rows, initial_seg_rows)
        return margin_e + rows, margin_s + self.nb + srows

    # ------------------------------------------------------------ drains

    def _observe(self, ev_t, ev_i, ev_f, n, final=False):
        """Count the event rows ``observed:n`` and hand them to the observer (mid-run only
        when there are some; at the end always)."""
        if self.plain:
            return
        a = self.observed
        self.observed = n
        if n > a:
            self.counts += np.bincount(ev_i[a:n, 0], minlength=len(self.kinds))
        if self.observer is not None and (n > a or final):
            chunk = self.build_events(ev_t[a:n].copy(), ev_i[a:n].copy(), ev_f[a:n].copy())
            chunk.flags.writeable = False
            self.observer(chunk)

    def _segments(self, seg_t, seg_b, seg_s, m):
        """The carried tails followed by the buffer's rows ``:m`` (copies), log order."""
        new = (seg_t[:m].copy(), seg_b[:m].copy(), seg_s[:m].copy())
        if self.carry is None:
            return new
        return tuple(np.concatenate([c, x]) for c, x in zip(self.carry, new))

    def _snapshots(self, segs, t_stop, final):
        """Evaluate the pending snapshot times: before ``t_stop`` (a drain: segments logged
        later start at ``t_stop`` or after), or at the end (``final``) up to ``t_stop``
        within the result's time slack (``ResultBase.TIME_SLACK``)."""
        if self.dt is None:
            return
        if final:
            limit = t_stop + 1e-12 * max(1.0, abs(t_stop))
            within = lambda k: k * self.dt <= limit             # noqa: E731
            if not np.all(np.bincount(segs[1], minlength=self.nb) > 0):
                return          # a run that failed before every body had a trajectory
        else:
            within = lambda k: k * self.dt < t_stop             # noqa: E731
        k = math.floor(t_stop / self.dt)
        while within(k + 1):
            k += 1
        while k >= self.snap_k and not within(k):
            k -= 1
        if k < self.snap_k:
            return
        times = np.arange(self.snap_k, k + 1) * self.dt
        self.snap_k = k + 1
        self.snap_t.append(times)
        self.snap_s.append(self.sampler(*segs, times))

    def on_full(self, bufs, cnt, glob, toli, margin_e, margin_s, grow):
        """The loop returned ``RC_BUFFER_FULL``: observe, then grow (``record="all"``) or
        drain the buffers. ``bufs``: ``(ev_t, ev_i, ev_f, seg_t, seg_b, seg_s)``;
        ``grow(arrays, used)``: the front end's growth rule. Returns the buffers to pass to
        the loop's next call."""
        ev_t, ev_i, ev_f, seg_t, seg_b, seg_s = bufs
        n, m = int(cnt[CN_EVENTS]), int(cnt[CN_SEGS])
        self._observe(ev_t, ev_i, ev_f, n)
        if self.keep_all:
            if n + margin_e > len(ev_t):
                ev_t, ev_i, ev_f = grow((ev_t, ev_i, ev_f), n)
            if m + margin_s > len(seg_t):
                seg_t, seg_b, seg_s = grow((seg_t, seg_b, seg_s), m)
            return ev_t, ev_i, ev_f, seg_t, seg_b, seg_s
        # ---- events: keep those involving a recorded body, drop the rest
        if self.bodies is not None and n:
            a, b = ev_i[:n, 1], ev_i[:n, 2]
            sel = self.keep_body[a] | ((b >= 0) & self.keep_body[np.maximum(b, 0)])
            if sel.any():
                self.kept_ev.append((ev_t[:n][sel], ev_i[:n][sel], ev_f[:n][sel]))
        self.dropped += n
        toli[self.ti_max_events] = self.max_events - self.dropped
        cnt[CN_EVENTS] = 0
        self.observed = 0
        # ---- segments
        t_now = float(glob[0])
        if m and self.dt is not None and float(seg_t[:m].min()) < self.t_safe:
            raise SimulationError(   # pragma: no cover - an internal contract of the loops
                f"{self.who}.run: internal error: a trajectory segment logged after t = "
                f"{self.t_safe:.17g} s starts at {float(seg_t[:m].min()):.17g} s, before "
                f"snapshots already evaluated; please report it")
        segs = self._segments(seg_t, seg_b, seg_s, m)
        self._snapshots(segs, t_now, final=False)
        self.t_safe = t_now
        st, sb, ss = segs
        idx = np.arange(len(st))
        last = np.full(self.nb, -1, np.int64)
        le = st <= t_now
        np.maximum.at(last, sb[le], idx[le])
        tail = idx >= last[sb]              # per body: the last row <= t_now and later ones
        past = ~tail
        if self.bodies is not None:
            rec = self.keep_body[sb] & past
            if rec.any():
                self.kept_seg.append((st[rec], sb[rec], ss[rec]))
            past &= ~self.keep_body[sb]
        self.cut[np.unique(sb[past])] = True
        self.carry = (st[tail], sb[tail], ss[tail])
        cnt[CN_SEGS] = 0
        return bufs

    def finish(self, bufs, cnt, glob):
        """The loop ended (done, max_events or an error): observe the last rows, evaluate
        the last snapshots; returns ``(ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, recording)``
        for the result (``record="all"``: the buffers' filled rows as views)."""
        ev_t, ev_i, ev_f, seg_t, seg_b, seg_s = bufs
        n, m = int(cnt[CN_EVENTS]), int(cnt[CN_SEGS])
        if self.plain:
            return ev_t[:n], ev_i[:n], ev_f[:n], seg_t[:m], seg_b[:m], seg_s[:m], None
        self._observe(ev_t, ev_i, ev_f, n, final=True)
        if self.keep_all:
            out_ev = (ev_t[:n], ev_i[:n], ev_f[:n])
            out_seg = (seg_t[:m], seg_b[:m], seg_s[:m])
        else:
            if self.bodies is not None:
                a, b = ev_i[:n, 1], ev_i[:n, 2]
                sel = self.keep_body[a] | ((b >= 0) & self.keep_body[np.maximum(b, 0)])
                parts = self.kept_ev + [(ev_t[:n][sel], ev_i[:n][sel], ev_f[:n][sel])]
            else:
                parts = [(ev_t[:0], ev_i[:0], ev_f[:0])]
            out_ev = tuple(np.concatenate(c) for c in zip(*parts))
            last = self._segments(seg_t, seg_b, seg_s, m)
            out_seg = tuple(np.concatenate(c) for c in zip(*self.kept_seg, last))
        self._snapshots(out_seg, float(glob[0]), final=True)
        cover = None
        if self.cut.any():
            cover = np.zeros(self.nb)
            bodies, first = np.unique(out_seg[1], return_index=True)
            cover[bodies] = np.where(self.cut[bodies], out_seg[0][first], 0.0)
        snapshots = None
        if self.dt is not None:
            times = np.concatenate(self.snap_t) if self.snap_t else np.zeros(0)
            states = {}
            if self.snap_s:
                for key in self.snap_s[0]:
                    states[key] = np.concatenate([s[key] for s in self.snap_s])
            times.flags.writeable = False
            snapshots = (times, states)
        rec = Recording(self.record, self.counts.copy(), self.kinds, cover, snapshots)
        return (*out_ev, *out_seg, rec)
