"""What 2D and 3D results share: sample-time checks, writing the event log as CSV, JSON or
Parquet, the events as a pandas DataFrame, and loading pyplot.

A result class deriving from ``ResultBase`` defines ``FIELDS_CSV`` (the flat column names),
``_EVENT_VECTORS`` (the vector fields of its events record, in column order) and
``_json_bodies()`` (its body properties for the JSON header).

The CSV is written by one compiled pass (``_csv_rows``): every float is printed as its
shortest round-trip decimal (Ryu, Adams 2018, PLDI), in the layout of Python's ``repr``,
so the file is byte for byte what ``csv.writer`` with ``repr(float)`` wrote, about 20 times
faster. NumPy's own formatting (``astype(str)``, ``np.savetxt``) costs as much per number
as ``repr``. pandas and pyarrow are needed only by ``to_pandas`` and ``to_parquet`` (the
``sweep`` extra).
"""
import csv
import functools
import json
import math

import numba
import numpy as np

from ._recording import NotRecordedError

#: rows formatted per compiled call of ``to_csv`` (bounds its buffer to ~35 MB)
CSV_CHUNK = 65536
_SWEEP_EXTRA = "pip install 'rbimpact[sweep]'"


def require(module, what):
    """Import the optional ``module`` (pandas, pyarrow, dask...) or raise an ImportError
    naming the ``sweep`` extra."""
    import importlib
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise ImportError(f"{what} needs {module.split('.')[0]}: {_SWEEP_EXTRA}") from exc


class ResultBase:
    """Base of ``Result`` and ``Result3D``: ``_times`` (sample-time check), what the run
    kept (``record``, ``n_events``, ``event_counts``, ``snapshots``), and the exports of
    ``self.events``: ``to_csv``, ``to_json``, ``to_pandas``, ``to_parquet``.

    What a run made with ``record="none"`` or a list of bodies (``run``'s ``record``) can
    give: ``status``, ``t_end``, ``n_events``, ``event_counts``, ``n_impacts`` (the whole
    run's), ``snapshots``, and ``sample`` / ``energy`` at the times whose states were kept
    (from ``kept_from(i)`` for body i: the final state at ``t_end`` always; a recorded
    body's whole trajectory). ``events`` and the exports (``record="none"``: no event was
    kept), ``plot`` and earlier samples raise ``NotRecordedError`` (a ``RuntimeError``)
    saying so; with a list of bodies ``events`` holds the events involving those bodies.
    """

    FIELDS_CSV = ()
    _EVENT_VECTORS = ()
    # what the run kept (``_init_recording``); these defaults describe a full record
    record = "all"
    snapshots = None
    _rec = None
    _cover = None

    def _init_recording(self, recording):
        """Take a ``_recording.Recording`` (None: the whole run was kept)."""
        self._rec = recording
        if recording is None:
            return
        self.record = recording.record
        self.snapshots = recording.snapshots
        self._cover = recording.cover

    def _record_text(self):
        r = self.record
        return f"record={r!r}" if isinstance(r, str) else f"record={[int(i) for i in r]}"

    def _require_events(self, what):
        """Raise ``NotRecordedError`` when the run kept no event (``record="none"``)."""
        if isinstance(self.record, str) and self.record == "none":
            raise NotRecordedError(
                f"{type(self).__name__}.{what}: the run was made with record='none', which "
                f"keeps only the event counts (n_events, event_counts, n_impacts), the "
                f"final state and the snapshots; run with record='all' (or a list of body "
                f"indices), or pass an observer to see the events as they happen")

    def _require_full(self, what):
        """Raise ``NotRecordedError`` unless the whole run was kept."""
        self._require_events(what)
        if not (isinstance(self.record, str) and self.record == "all"):
            raise NotRecordedError(
                f"{type(self).__name__}.{what} needs the whole run, but it was made with "
                f"{self._record_text()} (only the events and trajectories of those bodies "
                f"were kept); run with record='all'")

    @property
    def n_events(self):
        """Number of events of the whole run (whatever ``record`` kept)."""
        if self._rec is None:
            return len(self.events)
        return int(self._rec.counts.sum())

    @property
    def event_counts(self):
        """Events of the whole run per kind: dict kind -> count (whatever ``record`` kept;
        every kind of the stepper is a key)."""
        if self._rec is None:
            kinds, counts = np.unique(np.asarray(self.events["kind"]), return_counts=True)
            out = {k: 0 for k in getattr(self, "_kinds", ())}
            out.update({str(k): int(c) for k, c in zip(kinds, counts)})
            return out
        return {k: int(c) for k, c in zip(self._rec.kinds, self._rec.counts)}

    def kept_from(self, body):
        """The earliest time (s) at which ``sample`` can give body ``body``'s state: the
        run's start when its whole trajectory was kept (``record="all"``, a recorded body),
        else the start of its last trajectory segment kept (at or before ``t_end``)."""
        b = self._body_indices([body], "kept_from")[0]
        return self.t_start if self._cover is None else max(self.t_start,
                                                             float(self._cover[b]))

    def _body_indices(self, bodies, what):
        """``bodies`` (None: all) as an int64 array of body indices, checked."""
        if bodies is None:
            return np.arange(self.n_bodies)
        b = np.atleast_1d(np.asarray(bodies))
        if b.ndim != 1 or (b.size and b.dtype.kind not in "iu"):
            raise ValueError(f"{what}: bodies must be None or a 1-D sequence of body "
                             f"indices (0..{self.n_bodies - 1}), got {bodies!r}")
        b = b.astype(np.int64)
        if b.size and (b.min() < 0 or b.max() >= self.n_bodies):
            raise ValueError(f"{what}: bodies must be body indices (0..{self.n_bodies - 1}), "
                             f"got {bodies!r}")
        return b

    def _check_kept(self, t, bodies, what):
        """Raise ``NotRecordedError`` if a time of ``t`` precedes the kept part of the
        trajectory of one of ``bodies``."""
        if self._cover is None or not t.size:
            return
        cover = self._cover[bodies]
        lo = float(t.min())
        bad = bodies[cover > lo]
        if bad.size:
            b = int(bad[0])
            raise NotRecordedError(
                f"{type(self).__name__}.{what}: the run was made with {self._record_text()}: "
                f"body {b}'s state is kept only from t = {float(self._cover[b]):.12g} s on "
                f"(its final trajectory segment), and a time {lo:.12g} s was asked; "
                f"use the snapshots (run's snapshot_dt), record the body, or record='all'"
                + ("" if isinstance(self.record, str) else
                   f"; sample(times, bodies=...) gives the recorded bodies alone"))

    def _rows(self):
        for ev in self.events:
            vectors = [float(x) for name in self._EVENT_VECTORS for x in ev[name]]
            yield (float(ev["t"]), str(ev["kind"]), int(ev["a"]), int(ev["b"]), *vectors,
                   int(ev["mode"]), float(ev["dE"]), int(ev["cluster"]))

    def _json_bodies(self):
        raise NotImplementedError

    #: slack (relative to max(1 s, |t_end|)) on the simulated interval for sample times
    TIME_SLACK = 1e-12

    def _times(self, times):
        """``times`` (s) as a finite 1-D float array inside [t_start, t_end]."""
        t = np.atleast_1d(np.asarray(times, dtype=float))
        if t.ndim != 1:
            raise ValueError("times must be a scalar or a 1-D array of times (s)")
        if not np.all(np.isfinite(t)):
            raise ValueError("times must be finite")
        slack = self.TIME_SLACK * max(1.0, abs(self.t_end))
        if t.size and (t.min() < self.t_start - slack or t.max() > self.t_end + slack):
            raise ValueError(f"times must lie in the simulated interval [{self.t_start:g}, "
                             f"{self.t_end:g}] s, got [{t.min():g}, {t.max():g}]")
        return t

    def _columns(self):
        """The events as flat columns in ``FIELDS_CSV`` order: list of (name, 1-D array);
        the vector fields are split into their components, ``kind`` stays a str array."""
        ev = self.events
        cols = []
        names = iter(self.FIELDS_CSV)
        for field in ("t", "kind", "a", "b", *self._EVENT_VECTORS, "mode", "dE", "cluster"):
            x = ev[field]
            if x.ndim == 1:
                cols.append((next(names), x))
            else:
                cols += [(next(names), x[:, k]) for k in range(x.shape[1])]
        return cols

    def _kind_codes(self):
        """(codes, names): ``kind`` as int64 codes into the sorted list of its values."""
        k = np.ascontiguousarray(self.events["kind"])
        chars = k.view(np.uint32).reshape(len(k), k.dtype.itemsize // 4)
        if chars.shape[1] > 8 or chars.max(initial=0) > 127:
            raise ValueError("event kinds must be ASCII of at most 8 characters")
        codes, keys = _ascii_codes(chars)
        names = [b.decode() for b in keys.view("S8")]
        order = np.argsort(names)                  # categories in alphabetical order
        rank = np.empty(len(names), dtype=np.int64)
        rank[order] = np.arange(len(names))
        return rank[codes], [names[i] for i in order]

    def to_csv(self, path):
        """Write the events to ``path`` as CSV (one header line, ``FIELDS_CSV``; rows end in
        CRLF like ``csv.writer``; contact-space columns normal first; ``b < 0`` is plane
        ``-1 - b``; floats are their shortest round-trip text, as ``repr``). Needs only
        NumPy and Numba."""
        self._require_events("to_csv")
        cols = self._columns()
        n = len(self.events)
        floats = [x for name, x in cols if x.dtype.kind == "f"]
        ints = [x for name, x in cols if x.dtype.kind in "iu"]
        F = np.empty((n, len(floats)))
        for k, x in enumerate(floats):
            F[:, k] = x
        I = np.empty((n, len(ints)), dtype=np.int64)
        for k, x in enumerate(ints):
            I[:, k] = x
        codes, kinds = self._kind_codes()
        table = np.zeros((max(len(kinds), 1), 8), dtype=np.uint8)
        lens = np.zeros(max(len(kinds), 1), dtype=np.int64)
        for k, s in enumerate(kinds):
            b = s.encode()
            if any(c in b for c in b',"\r\n'):
                raise ValueError(f"to_csv: event kind {s!r} would need quoting")
            table[k, :len(b)] = np.frombuffer(b, dtype=np.uint8)
            lens[k] = len(b)
        # column plan: 0 float (index into F), 1 int (into I), 2 kind
        plan_kind, plan_idx, nf, ni = [], [], 0, 0
        for name, x in cols:
            if x.dtype.kind == "f":
                plan_kind.append(0)
                plan_idx.append(nf)
                nf += 1
            elif x.dtype.kind in "iu":
                plan_kind.append(1)
                plan_idx.append(ni)
                ni += 1
            else:
                plan_kind.append(2)
                plan_idx.append(0)
        plan_kind = np.array(plan_kind, dtype=np.int64)
        plan_idx = np.array(plan_idx, dtype=np.int64)
        inv, pow5 = _ryu_tables()
        width = 25 * nf + 21 * ni + 9 * int((plan_kind == 2).sum()) + 2
        buf = np.empty(min(n, CSV_CHUNK) * width, dtype=np.uint8)
        with open(path, "wb") as f:
            f.write((",".join(self.FIELDS_CSV) + "\r\n").encode())
            for r0 in range(0, n, CSV_CHUNK):
                r1 = min(n, r0 + CSV_CHUNK)
                m = _csv_rows(F, I, codes, table, lens, plan_kind, plan_idx, r0, r1, buf,
                              inv, pow5)
                f.write(memoryview(buf[:m]))

    def to_pandas(self):
        """The events as a pandas DataFrame, one row per event, columns ``FIELDS_CSV``
        (vectors split into components, contact space normal first: ``v_i_N``, ``v_i_T``
        in 2D, ``v_i_N``, ``v_i_T1``, ``v_i_T2`` in 3D; units as in ``events``); ``kind``
        is categorical. ``df.attrs`` holds status, policy, law, t_start, t_end (s),
        n_bodies. Needs pandas (the ``sweep`` extra)."""
        self._require_events("to_pandas")
        pd = require("pandas", f"{type(self).__name__}.to_pandas")
        data = {}
        for name, x in self._columns():
            if name == "kind":
                codes, kinds = self._kind_codes()
                data[name] = pd.Categorical.from_codes(codes, categories=kinds)
            else:
                data[name] = np.ascontiguousarray(x)
        df = pd.DataFrame(data)
        df.attrs = {"status": self.status, "policy": self.policy, "law": self.law,
                    "t_start": self.t_start, "t_end": self.t_end, "n_bodies": self.n_bodies}
        return df

    def to_parquet(self, path):
        """Write ``to_pandas()`` to ``path`` as Parquet (needs pandas and pyarrow: the
        ``sweep`` extra)."""
        require("pyarrow", f"{type(self).__name__}.to_parquet")
        self.to_pandas().to_parquet(path, index=False)

    def to_json(self, path):
        """Write the run's metadata and events to ``path`` as JSON (a run made with a list
        of bodies as ``record`` adds ``"record"``: those bodies, whose events are the ones
        written)."""
        self._require_events("to_json")
        doc = {
            "status": self.status, "policy": self.policy, "law": self.law,
            "t_start": self.t_start, "t_end": self.t_end, "t_requested": self.t_requested,
            "n_bodies": self.n_bodies, **self._json_bodies(),
            "gravity": self.gravity.tolist(),
            "tolerances": {k: (v if not isinstance(v, float) or math.isfinite(v) else str(v))
                           for k, v in self.tolerances.items()},
            "fields": list(self.FIELDS_CSV),
            "events": [dict(zip(self.FIELDS_CSV, row)) for row in self._rows()],
        }
        if not isinstance(self.record, str):
            doc["record"] = [int(i) for i in self.record]
        with open(path, "w") as f:
            json.dump(doc, f, indent=1)


def pyplot(what):
    """matplotlib.pyplot on the Agg backend, or an ImportError naming the ``plot`` extra."""
    try:
        import matplotlib
        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError(f"{what} needs matplotlib: pip install 'rbimpact[plot]'") from exc
    return plt


# ------------------------------------------------------------------ CSV formatting (Numba)
# Shortest round-trip decimal of a double: Ryu (U. Adams, "Ryu: fast float-to-string
# conversion", PLDI 2018), the d2s algorithm with its full 128-bit tables, computed here
# with exact integers; 64 x 64 -> 128-bit products from 32-bit halves.

_POW5_INV_BITCOUNT = 125
_POW5_BITCOUNT = 125
_M32 = np.uint64(0xFFFFFFFF)
_U0 = np.uint64(0)
_U1 = np.uint64(1)
_U2 = np.uint64(2)
_U4 = np.uint64(4)
_U5 = np.uint64(5)
_U10 = np.uint64(10)
_U100 = np.uint64(100)
_U32 = np.uint64(32)
_U64 = np.uint64(64)


@functools.lru_cache(maxsize=1)
def _ryu_tables():
    """(inv, pow5): the 2 x 64-bit halves (low, high) of Ryu's double tables (exact
    big-integer arithmetic): ``inv[q] = floor(2^(bitlen(5^q) - 1 + 125) / 5^q) + 1`` for
    q < 342, ``pow5[i]`` = the top 125 bits of 5^i for i < 326."""
    inv = np.empty((342, 2), dtype=np.uint64)
    pow5 = np.empty((326, 2), dtype=np.uint64)
    mask = (1 << 64) - 1
    for q in range(342):
        p = 5 ** q
        v = (1 << (p.bit_length() - 1 + _POW5_INV_BITCOUNT)) // p + 1
        inv[q] = (v & mask, v >> 64)
    for i in range(326):
        p = 5 ** i
        s = p.bit_length() - _POW5_BITCOUNT
        v = p >> s if s >= 0 else p << -s
        pow5[i] = (v & mask, v >> 64)
    return inv, pow5


@numba.njit(cache=True, inline="always")
def _umul128_hi_lo(a, b):
    a_lo = a & _M32
    a_hi = a >> _U32
    b_lo = b & _M32
    b_hi = b >> _U32
    b00 = a_lo * b_lo
    b01 = a_lo * b_hi
    b10 = a_hi * b_lo
    b11 = a_hi * b_hi
    mid1 = b10 + (b00 >> _U32)
    mid2 = b01 + (mid1 & _M32)
    hi = b11 + (mid1 >> _U32) + (mid2 >> _U32)
    lo = (mid2 << _U32) | (b00 & _M32)
    return hi, lo


@numba.njit(cache=True)
def _mul_shift64(m, mul_lo, mul_hi, j):
    high1, low1 = _umul128_hi_lo(m, mul_hi)
    high0, _ = _umul128_hi_lo(m, mul_lo)
    s = high0 + low1
    if s < high0:
        high1 += _U1
    dist = np.uint64(j - 64)
    return (high1 << (_U64 - dist)) | (s >> dist)


@numba.njit(cache=True)
def _pow5_factor(v):
    c = 0
    while v % _U5 == _U0:
        v //= _U5
        c += 1
    return c


@numba.njit(cache=True)
def _pow5bits(e):
    return ((e * 1217359) >> 19) + 1


@numba.njit(cache=True)
def _d2d(ieee_m, ieee_e, inv, pow5):
    """Ryu's shortest decimal (digits as an integer, exponent of 10) of a finite nonzero
    double given its mantissa and biased exponent fields."""
    if ieee_e == 0:
        e2 = 1 - 1023 - 52 - 2
        m2 = ieee_m
    else:
        e2 = ieee_e - 1023 - 52 - 2
        m2 = (_U1 << np.uint64(52)) | ieee_m
    even = (m2 & _U1) == _U0
    accept = even
    mv = _U4 * m2
    mm_shift = _U1 if (ieee_m != _U0 or ieee_e <= 1) else _U0
    vm_tz = False
    vr_tz = False
    if e2 >= 0:
        q = ((e2 * 78913) >> 18) - (1 if e2 > 3 else 0)
        e10 = q
        k = _POW5_INV_BITCOUNT + _pow5bits(q) - 1
        i = -e2 + q + k
        vr = _mul_shift64(_U4 * m2, inv[q, 0], inv[q, 1], i)
        vp = _mul_shift64(_U4 * m2 + _U2, inv[q, 0], inv[q, 1], i)
        vm = _mul_shift64(_U4 * m2 - _U1 - mm_shift, inv[q, 0], inv[q, 1], i)
        if q <= 21:
            if mv % _U5 == _U0:
                vr_tz = _pow5_factor(mv) >= q
            elif accept:
                vm_tz = _pow5_factor(mv - _U1 - mm_shift) >= q
            else:
                if _pow5_factor(mv + _U2) >= q:
                    vp -= _U1
    else:
        q = (((-e2) * 732923) >> 20) - (1 if -e2 > 1 else 0)
        e10 = q + e2
        i = -e2 - q
        k = _pow5bits(i) - _POW5_BITCOUNT
        j = q - k
        vr = _mul_shift64(_U4 * m2, pow5[i, 0], pow5[i, 1], j)
        vp = _mul_shift64(_U4 * m2 + _U2, pow5[i, 0], pow5[i, 1], j)
        vm = _mul_shift64(_U4 * m2 - _U1 - mm_shift, pow5[i, 0], pow5[i, 1], j)
        if q <= 1:
            vr_tz = True
            if accept:
                vm_tz = mm_shift == _U1
            else:
                vp -= _U1
        elif q < 63:
            vr_tz = (mv & ((_U1 << np.uint64(q)) - _U1)) == _U0
    removed = 0
    last = _U0
    if vm_tz or vr_tz:
        while vp // _U10 > vm // _U10:
            vm_tz = vm_tz and (vm % _U10 == _U0)
            vr_tz = vr_tz and (last == _U0)
            last = vr % _U10
            vr //= _U10
            vp //= _U10
            vm //= _U10
            removed += 1
        if vm_tz:
            while vm % _U10 == _U0:
                vr_tz = vr_tz and (last == _U0)
                last = vr % _U10
                vr //= _U10
                vp //= _U10
                vm //= _U10
                removed += 1
        if vr_tz and last == _U5 and vr % _U2 == _U0:
            last = np.uint64(4)
        up = (vr == vm and (not accept or not vm_tz)) or last >= _U5
        out = vr + (_U1 if up else _U0)
    else:                          # the common case: remove two digits at a time first
        round_up = False
        vp100 = vp // _U100
        vm100 = vm // _U100
        if vp100 > vm100:
            vr100 = vr // _U100
            round_up = vr - _U100 * vr100 >= np.uint64(50)
            vr = vr100
            vp = vp100
            vm = vm100
            removed += 2
        while vp // _U10 > vm // _U10:
            round_up = vr % _U10 >= _U5
            vr //= _U10
            vp //= _U10
            vm //= _U10
            removed += 1
        out = vr + (_U1 if (vr == vm or round_up) else _U0)
    return out, e10 + removed


@numba.njit(cache=True)
def _write_float(x, bits, buf, pos, inv, pow5, tmp):
    """Write ``repr(float(x))`` into the uint8 array ``buf`` at ``pos`` (``bits``: the
    IEEE bits of ``x`` as uint64; ``tmp``: 20 bytes of scratch); return the new position
    (at most 24 bytes are written)."""
    if x != x:
        buf[pos] = 110; buf[pos + 1] = 97; buf[pos + 2] = 110   # nan
        return pos + 3
    sign = (bits >> np.uint64(63)) != _U0
    ieee_m = bits & ((_U1 << np.uint64(52)) - _U1)
    ieee_e = np.int64((bits >> np.uint64(52)) & np.uint64(0x7FF))
    if sign:
        buf[pos] = 45
        pos += 1
    if ieee_e == 0x7FF:
        buf[pos] = 105; buf[pos + 1] = 110; buf[pos + 2] = 102   # inf
        return pos + 3
    if ieee_e == 0 and ieee_m == _U0:
        buf[pos] = 48; buf[pos + 1] = 46; buf[pos + 2] = 48      # 0.0
        return pos + 3
    digits, e10 = _d2d(ieee_m, ieee_e, inv, pow5)
    # the decimal digits, least significant first
    nd = 0
    while digits > _U0:
        tmp[nd] = np.uint8(48 + np.int64(digits % _U10))
        digits //= _U10
        nd += 1
    x10 = nd + e10 - 1             # value = d.ddd x 10^x10
    if x10 < -4 or x10 >= 16:      # Python repr: scientific
        buf[pos] = tmp[nd - 1]
        pos += 1
        if nd > 1:
            buf[pos] = 46
            pos += 1
            for k in range(nd - 2, -1, -1):
                buf[pos] = tmp[k]
                pos += 1
        buf[pos] = 101
        buf[pos + 1] = 45 if x10 < 0 else 43
        pos += 2
        ax = -x10 if x10 < 0 else x10
        if ax >= 100:
            buf[pos] = 48 + ax // 100
            pos += 1
        buf[pos] = 48 + (ax // 10) % 10
        buf[pos + 1] = 48 + ax % 10
        return pos + 2
    if x10 < 0:                    # 0.000ddd
        buf[pos] = 48
        buf[pos + 1] = 46
        pos += 2
        for k in range(-x10 - 1):
            buf[pos] = 48
            pos += 1
        for k in range(nd - 1, -1, -1):
            buf[pos] = tmp[k]
            pos += 1
        return pos
    # x10 >= 0: integer part has x10 + 1 digits
    for k in range(x10 + 1):
        idx = nd - 1 - k
        buf[pos] = tmp[idx] if idx >= 0 else 48
        pos += 1
    buf[pos] = 46
    pos += 1
    if nd > x10 + 1:
        for k in range(nd - x10 - 2, -1, -1):
            buf[pos] = tmp[k]
            pos += 1
    else:
        buf[pos] = 48
        pos += 1
    return pos




@numba.njit(cache=True)
def _write_int(v, buf, pos, tmp):
    if v < 0:
        buf[pos] = 45
        pos += 1
        v = -v
    nd = 0
    while True:
        tmp[nd] = 48 + v % 10
        v //= 10
        nd += 1
        if v == 0:
            break
    for k in range(nd - 1, -1, -1):
        buf[pos] = tmp[k]
        pos += 1
    return pos


@numba.njit(cache=True)
def _csv_rows(F, I, codes, table, lens, plan_kind, plan_idx, r0, r1, buf, inv, pow5):
    """Rows ``r0:r1`` as CSV text (comma separated, CRLF) into ``buf``; returns its length.
    Columns follow the plan: kind 0 float ``F[:, idx]``, 1 int ``I[:, idx]``, 2 the string
    ``table[codes[r], :lens[codes[r]]]``. A float equal (bit for bit) to the one above it
    in its column is copied from that row's text (normals and tangents of a floor, zeros)."""
    pos = 0
    nc = plan_kind.shape[0]
    B = F.view(np.uint64)
    tmp = np.empty(24, dtype=np.uint8)
    last_start = np.zeros(nc, dtype=np.int64)
    last_len = np.zeros(nc, dtype=np.int64)
    for r in range(r0, r1):
        for c in range(nc):
            if c > 0:
                buf[pos] = 44
                pos += 1
            k = plan_kind[c]
            if k == 0:
                j = plan_idx[c]
                b = B[r, j]
                if r > r0 and b == B[r - 1, j]:
                    s0 = last_start[c]
                    for q in range(last_len[c]):
                        buf[pos + q] = buf[s0 + q]
                    last_start[c] = pos
                    pos += last_len[c]
                else:
                    last_start[c] = pos
                    pos = _write_float(F[r, j], b, buf, pos, inv, pow5, tmp)
                    last_len[c] = pos - last_start[c]
            elif k == 1:
                pos = _write_int(I[r, plan_idx[c]], buf, pos, tmp)
            else:
                s = codes[r]
                for q in range(lens[s]):
                    buf[pos] = table[s, q]
                    pos += 1
        buf[pos] = 13
        buf[pos + 1] = 10
        pos += 2
    return pos


@numba.njit(cache=True)
def _ascii_codes(chars):
    """Codes of the rows of ``chars`` (n, <= 8) uint32 (a "U8" array's code points, ASCII)
    into the list of distinct rows in order of first appearance: (codes, distinct rows
    packed as uint64, one byte per character)."""
    n = chars.shape[0]
    codes = np.empty(n, dtype=np.int64)
    seen = np.empty(64, dtype=np.uint64)
    ns = 0
    for i in range(n):
        key = np.uint64(0)
        for q in range(chars.shape[1]):
            key |= np.uint64(chars[i, q] & 0xFF) << np.uint64(8 * q)
        c = -1
        for k in range(ns):
            if seen[k] == key:
                c = k
                break
        if c < 0:
            if ns == seen.shape[0]:
                grown = np.empty(2 * ns, dtype=np.uint64)
                grown[:ns] = seen
                seen = grown
            seen[ns] = key
            c = ns
            ns += 1
        codes[i] = c
    return codes, seen[:ns].copy()
