"""The result of an event-driven run: events, exact trajectories, energy, export, plot.

``Result.events`` is a structured NumPy array, one row per event, in time order:

=========  ==================================================================================
field      meaning
=========  ==================================================================================
t          time (s)
kind       "impact": a collision resolved by a law (or by the joint solve of the
           simultaneous policy); "contact": impacts accumulated (Zeno) or the body started
           at rest on a plane, and the body is now in persistent contact with it;
           "slide", "roll", "rest": a persistent contact changes mode (slip starts or
           reverses, slip stops and a disk rolls, slip stops and the body rests);
           "release": a body in persistent contact received an impulse that lifts it off,
           or a held vertex's normal force fell to zero; "pivot": impacts accumulated at
           a vertex of a box or a rod, which is now held on the plane (integrated contact,
           ``kernels/pivot2d.py``; mode 2 sticking, 1 sliding); "stick": the held vertex's
           slip stopped and it sticks
a, b       body index of A; B's body index, or ``-1 - plane index`` for a plane
point      contact point (m); for persistent-contact events, the centre of mass projected
           on the plane
normal     unit contact normal, from B into A
v_i, v_f   contact-space velocity (normal first, m/s) of A's contact point minus B's,
           before and after the event
P          impulse on A (N s), normal first; for "contact", ``m (v_f - v_i)`` of the centre
           of mass applied by snapping onto the plane
mode       impact: the law's mode code (``rbimpact.MODE_NAMES``; joint solve: 0 separating,
           1 stick, 2 slip); persistent events: the new mode (1 slide, 2 roll, 3 rest)
dE         energy change (J): impacts ``P . (v_i + v_f) / 2``; "contact": change of kinetic
           plus potential energy by the snap (bounded by ``m g rest_length``); else 0
cluster    number of contacts resolved together at that instant (1: a single contact)
=========  ==================================================================================

Trajectories are stored as segments of exact constant-acceleration motion, so
``sample(times)`` is exact (to round-off) at any time in ``[t_start, t_end]``, except
while a vertex or an ellipse is held on a plane ("pivot" to the next event): that motion
has no closed form, and it is recorded as short constant-acceleration pieces within stated
tolerances of the integrated solution (``pivot2d.PIECE_ETOL`` 1e-13 m V^2 in energy,
``PIECE_ETOL_CURVED`` 1e-11 m V^2 for an ellipse, ``PIECE_LTOL`` 1e-10 L in position,
``PIECE_VTOL`` 1e-9 V in velocity).
"""

import numpy as np

from .result_base import ResultBase, pyplot

__all__ = ["Result", "EVENT_DTYPE"]

EVENT_DTYPE = np.dtype([
    ("t", "f8"), ("kind", "U8"), ("a", "i8"), ("b", "i8"),
    ("point", "f8", (2,)), ("normal", "f8", (2,)), ("v_i", "f8", (2,)), ("v_f", "f8", (2,)),
    ("P", "f8", (2,)), ("mode", "i8"), ("dE", "f8"), ("cluster", "i8"),
])

def _build_events(ev_t, ev_i, ev_f, kinds):
    """Fill the structured event array column by column (all fields are 8-byte aligned)."""
    n = len(ev_t)
    ev = np.empty(n, dtype=EVENT_DTYPE)
    if n == 0:
        return ev
    off = {k: v[1] // 8 for k, v in EVENT_DTYPE.fields.items()}
    w = EVENT_DTYPE.itemsize // 8
    F = ev.view(np.float64).reshape(n, w)
    I = ev.view(np.int64).reshape(n, w)
    codes = np.array(kinds, dtype="U8").view(np.uint32).reshape(len(kinds), 8)
    U = ev.view(np.uint32).reshape(n, 2 * w)
    F[:, off["t"]] = ev_t
    U[:, 2 * off["kind"]:2 * off["kind"] + 8] = codes[ev_i[:, 0]]
    I[:, off["a"]] = ev_i[:, 1]
    I[:, off["b"]] = ev_i[:, 2]
    I[:, off["mode"]] = ev_i[:, 3]
    I[:, off["cluster"]] = ev_i[:, 4]
    p = off["point"]
    F[:, p:p + 10] = ev_f[:, 0:10]      # point, normal, v_i, v_f, P are contiguous
    F[:, off["dE"]] = ev_f[:, 10]
    return ev


FIELDS_CSV = ("t", "kind", "a", "b", "point_x", "point_y", "normal_x", "normal_y",
               "v_i_N", "v_i_T", "v_f_N", "v_f_T", "P_N", "P_T", "mode", "dE", "cluster")


class Result(ResultBase):
    """Outcome of ``Simulation.run``.

    Attributes: ``events`` (see the module docstring), ``status`` ("done",
    "max_events", or on the partial result an exception carries, the failure: "missed",
    "no_solution", "stall", "painleve", ... from ``_setup.run_status``), ``policy`` ("simultaneous" or "sequential": the simultaneous-contact
    policy that ran), ``t_start`` and ``t_end`` (s: the time reached; earlier than the
    requested end when status is "max_events"), ``t_requested`` (s), ``n_bodies``,
    ``masses`` (kg), ``moments`` (kg m^2), ``gravity`` (m/s^2), ``law`` (name of the default
    law), ``tolerances`` (the Simulation keywords used), ``n_impacts``; what the run kept
    (``run``'s ``record``): ``record``, ``n_events``, ``event_counts``, ``snapshots``,
    ``kept_from(i)`` (``ResultBase``).
    """

    def __init__(self, ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, *, status, policy, t_start,
                 t_end, t_requested, masses, moments, gravity, law, tolerances, kinds,
                 recording=None):
        # raw event columns (see kernels/stepper2d.py); the structured array is built lazily
        self._ev_t, self._ev_i, self._ev_f = ev_t, ev_i, ev_f
        self._kinds = tuple(kinds)
        self._events = None
        self._raw_seg = (seg_t, seg_b, seg_s)
        self._seg_t = None
        self.status = status
        self.policy = policy
        self.t_start = float(t_start)
        self.t_end = float(t_end)
        self.t_requested = float(t_requested)
        self.masses = np.asarray(masses, dtype=float)
        self.moments = np.asarray(moments, dtype=float)
        self.n_bodies = len(self.masses)
        self.gravity = np.asarray(gravity, dtype=float)
        self.law = law
        self.tolerances = dict(tolerances)
        self._init_recording(recording)

    @property
    def events(self):
        """The events as a structured array (built on first access, then cached); with
        ``record`` a list of bodies, the events involving one of them; ``record="none"``
        raises ``NotRecordedError``."""
        if self._events is None:
            self._require_events("events")
            self._events = _build_events(self._ev_t, self._ev_i, self._ev_f, self._kinds)
        return self._events

    @property
    def n_impacts(self):
        """Number of "impact" events of the whole run (whatever ``record`` kept)."""
        if self._rec is not None:
            return int(self._rec.counts[self._kinds.index("impact")])
        return int(np.count_nonzero(self._ev_i[:, 0] == self._kinds.index("impact")))

    @property
    def n_events(self):
        """Number of events of the whole run (whatever ``record`` kept)."""
        if self._rec is not None:
            return int(self._rec.counts.sum())
        return len(self._ev_t)

    def __repr__(self):
        return (f"Result(status={self.status!r}, policy={self.policy!r}, t_end={self.t_end:g}, "
                f"{self.n_events} events, {self.n_impacts} impacts)")

    def _segments(self):
        if self._seg_t is None:
            seg_t, seg_b, seg_s = self._raw_seg
            order = np.argsort(seg_b, kind="stable")
            self._seg_t = np.ascontiguousarray(seg_t[order])
            self._seg_s = np.ascontiguousarray(seg_s[order])
            counts = np.bincount(seg_b, minlength=self.n_bodies)
            self._seg_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
            self._raw_seg = None
        return self._seg_t, self._seg_s, self._seg_start

    def sample(self, times, bodies=None):
        """Exact state at ``times`` (s): dict of arrays "x", "y" (m), "angle" (rad), "vx",
        "vy" (m/s), "omega" (rad/s), each of shape ``(len(times), n_bodies)`` (or
        ``(len(times), len(bodies))``: the columns of ``bodies``, body indices, in that
        order). At an event time the state just after the event is returned. A time before
        ``kept_from(i)`` of a body asked for (a run made with ``record="none"`` or a list
        of bodies) raises ``NotRecordedError``."""
        from rbimpact.kernels.flight2d import sample_segments
        t = self._times(times)
        idx = self._body_indices(bodies, "Result.sample")
        self._check_kept(t, idx, "sample")
        shape = (t.size, idx.size)
        out = {k: np.empty(shape) for k in ("x", "y", "angle", "vx", "vy", "omega")}
        seg_t, seg_s, start = self._segments()
        for col, i in enumerate(idx):
            sample_segments(seg_t, seg_s, start[i], start[i + 1], t, out["x"], out["y"],
                            out["angle"], out["vx"], out["vy"], out["omega"], col)
        return out

    def energy(self, times, per_body=False):
        """Total mechanical energy (J, kinetic + gravitational, potential zero at the
        origin) at ``times`` (s): shape ``(len(times),)``, or ``(len(times), n_bodies)``
        with ``per_body=True``."""
        s = self.sample(times)
        g = self.gravity
        e = (0.5 * self.masses * (s["vx"] ** 2 + s["vy"] ** 2)
             + 0.5 * self.moments * s["omega"] ** 2
             - self.masses * (g[0] * s["x"] + g[1] * s["y"]))
        return e if per_body else e.sum(axis=1)

    # ---------------------------------------------------------------- export

    FIELDS_CSV = FIELDS_CSV
    _EVENT_VECTORS = ("point", "normal", "v_i", "v_f", "P")

    def _json_bodies(self):
        return {"masses": self.masses.tolist(), "moments": self.moments.tolist()}

    def plot(self, path, n=2000):
        """Save a figure to ``path``: trajectories of the centres of mass with impact
        markers, height against time, and total energy against time. Needs matplotlib
        (the ``plot`` extra)."""
        self._require_full("plot")
        plt = pyplot("Result.plot")
        t = np.linspace(self.t_start, self.t_end, n)
        ev_t = self.events["t"]
        t = np.union1d(t, ev_t[(ev_t >= self.t_start) & (ev_t <= self.t_end)])
        s = self.sample(t)
        fig, (ax1, ax3, ax2) = plt.subplots(1, 3, figsize=(15, 4.5))
        for i in range(self.n_bodies):
            ax1.plot(s["x"][:, i], s["y"][:, i], lw=1, label=f"body {i}")
        imp = self.events[self.events["kind"] == "impact"]
        if len(imp):
            ax1.plot(imp["point"][:, 0], imp["point"][:, 1], "k.", ms=3, label="impacts")
        other = self.events[self.events["kind"] != "impact"]
        if len(other):
            ax1.plot(other["point"][:, 0], other["point"][:, 1], "rx", ms=5,
                     label="contact switches")
        ax1.set_xlabel("x (m)")
        ax1.set_ylabel("y (m)")
        ax1.set_title("centre-of-mass trajectories")
        ax1.axis("equal")
        ax1.legend(fontsize=8)
        for i in range(self.n_bodies):
            ax3.plot(t, s["y"][:, i], lw=1, label=f"body {i}")
        if len(imp):
            ax3.plot(imp["t"], self.sample(imp["t"])["y"][np.arange(len(imp)), imp["a"]],
                     "k.", ms=3, label="impacts")
        ax3.set_xlabel("t (s)")
        ax3.set_ylabel("y (m)")
        ax3.set_title("height of the centres of mass")
        ax3.legend(fontsize=8)
        ax2.plot(t, self.energy(t), lw=1)
        for te in imp["t"]:
            ax2.axvline(te, color="0.85", lw=0.5, zorder=0)
        ax2.set_xlabel("t (s)")
        ax2.set_ylabel("energy (J)")
        ax2.set_title(f"total energy ({self.law}, {len(imp)} impacts)")
        fig.tight_layout()
        fig.savefig(path, dpi=120)
        plt.close(fig)
