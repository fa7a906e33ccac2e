"""The result of a 3D event-driven run: events, exact trajectories, energy, export, plot.

``Result3D.events`` is a structured NumPy array, one row per event, in time order, with
the fields of the 2D ``Result`` (vectors with three components) plus ``tangent``:

=========  ==================================================================================
field      meaning
=========  ==================================================================================
t          time (s)
kind       "impact", "contact", "slide", "roll", "rest", "release" as in 2D; "pivot":
           impacts accumulated at one or two features (a corner, an edge, a cap), which
           now stay on the plane (integrated contact; mode = number of held features);
           "stick"/"slide": a held feature stops/starts slipping; "release": a held
           feature lifts off; "capture": a box snapped onto a face with its spin about
           the normal removed (``dE``)
a, b       body index of A; B's body index, or ``-1 - plane index`` for a plane
point      contact point (m); for persistent-contact events, the foot of the centre of mass
normal     unit contact normal n, from B into A
tangent    the first tangent t1 of the contact basis (``t2 = n x t1``; DESIGN §3)
v_i, v_f   contact-space velocity (v_N, v_T1, v_T2) in m/s of A's contact point minus B's,
           before and after the event
P          impulse on A (N s), (P_N, P_T1, P_T2); for "contact"/"capture": ``m`` times the
           change of the centre of mass's velocity
mode       impact: the law's mode code (joint solve: 0 separating, 1 stick, 2 slip);
           persistent events: the new mode (1 slide, 2 roll, 3 rest); "pivot": the number
           of held features
dE         energy change (J): impacts ``P . (v_i + v_f) / 2``; "contact"/"capture": change of
           kinetic plus potential energy by the snap; else 0
cluster    number of contacts resolved together at that instant (1: a single contact)
=========  ==================================================================================

Trajectories are stored as segments of exact motion (``rbimpact.kernels.flight3d``):
``sample(times)`` re-evaluates them (exact closed forms; integrated rotations are
re-integrated from the segment start with the run's ``rot_tol``, reproducing the run).
"""

import numpy as np

from .kernels.codes import EVENT_KINDS
from .result_base import ResultBase, pyplot

__all__ = ["Result3D", "EVENT_DTYPE_3D"]

EVENT_DTYPE_3D = np.dtype([
    ("t", "f8"), ("kind", "U8"), ("a", "i8"), ("b", "i8"),
    ("point", "f8", (3,)), ("normal", "f8", (3,)), ("tangent", "f8", (3,)),
    ("v_i", "f8", (3,)), ("v_f", "f8", (3,)), ("P", "f8", (3,)),
    ("mode", "i8"), ("dE", "f8"), ("cluster", "i8"),
])

FIELDS_CSV = ("t", "kind", "a", "b", "point_x", "point_y", "point_z", "normal_x",
               "normal_y", "normal_z", "tangent_x", "tangent_y", "tangent_z", "v_i_N",
               "v_i_T1", "v_i_T2", "v_f_N", "v_f_T1", "v_f_T2", "P_N", "P_T1", "P_T2",
               "mode", "dE", "cluster")


def build_events_3d(ev_t, ev_i, ev_f, kinds):
    """The structured events (``EVENT_DTYPE_3D``) of the raw rows of ``kernels/stepper3d.py``
    (``ev_t`` s, ``ev_i`` kind/a/b/mode/cluster, ``ev_f`` point, normal, tangent, v_i, v_f,
    P, dE); ``kinds``: the names of the kind codes."""
    n = len(ev_t)
    ev = np.zeros(n, dtype=EVENT_DTYPE_3D)
    ev["t"] = ev_t[:n]
    ev["kind"] = np.array(kinds)[ev_i[:n, 0]] if n else []
    ev["a"] = ev_i[:n, 1]
    ev["b"] = ev_i[:n, 2]
    ev["mode"] = ev_i[:n, 3]
    ev["cluster"] = ev_i[:n, 4]
    ev["point"] = ev_f[:n, 0:3]
    ev["normal"] = ev_f[:n, 3:6]
    ev["tangent"] = ev_f[:n, 6:9]
    ev["v_i"] = ev_f[:n, 9:12]
    ev["v_f"] = ev_f[:n, 12:15]
    ev["P"] = ev_f[:n, 15:18]
    ev["dE"] = ev_f[:n, 18]
    return ev


class Result3D(ResultBase):
    """Outcome of ``Simulation3D.run``.

    Attributes: ``events`` (see the module docstring), ``status`` ("done",
    "max_events", or on the partial result an exception carries, the failure: "missed",
    "no_solution", "stall", "painleve", ... from ``_setup.run_status``), ``policy``, ``t_start``, ``t_end`` (s: the time reached),
    ``t_requested`` (s), ``n_bodies``, ``masses`` (kg), ``inertias`` (principal moments,
    kg m^2, shape (n_bodies, 3)), ``gravity`` (m/s^2), ``law``, ``tolerances``,
    ``n_impacts``; what the run kept (``run``'s ``record``): ``record``, ``n_events``,
    ``event_counts``, ``snapshots``, ``kept_from(i)`` (``ResultBase``).
    """

    _kinds = EVENT_KINDS        # the stepper's event kinds (event_counts' keys)

    def __init__(self, events, seg_t, seg_b, seg_s, *, status, policy, t_start, t_end,
                 t_requested, masses, inertias, rotation, gravity, law, tolerances,
                 recording=None):
        self._events = events
        self.status = status
        self.policy = policy
        self.t_start = float(t_start)
        self.t_end = float(t_end)
        self.t_requested = float(t_requested)
        self.masses = np.asarray(masses, dtype=float)
        self.inertias = np.asarray(inertias, dtype=float).reshape(-1, 3)
        self.n_bodies = len(self.masses)
        self.gravity = np.asarray(gravity, dtype=float)
        self.law = law
        self.tolerances = dict(tolerances)
        self._rotation = [tuple(map(int, r)) for r in rotation]
        order = np.argsort(seg_b, kind="stable")
        self._seg_t = np.ascontiguousarray(seg_t[order])
        self._seg_s = np.ascontiguousarray(seg_s[order])
        counts = np.bincount(seg_b, minlength=self.n_bodies)
        self._seg_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        self._init_recording(recording)

    @property
    def events(self):
        """The events (structured array, see the module docstring); with ``record`` a list
        of bodies, the events involving one of them; ``record="none"`` raises
        ``NotRecordedError``."""
        if self._events is None:
            self._require_events("events")
        return self._events

    @events.setter
    def events(self, value):
        self._events = value

    @property
    def n_impacts(self):
        """Number of "impact" events of the whole run (whatever ``record`` kept)."""
        if self._rec is not None:
            return int(self._rec.counts[self._rec.kinds.index("impact")])
        return int(np.count_nonzero(self.events["kind"] == "impact"))

    def __repr__(self):
        return (f"Result3D(status={self.status!r}, policy={self.policy!r}, "
                f"t_end={self.t_end:g}, {self.n_events} events, {self.n_impacts} impacts)")

    def sample(self, times, bodies=None):
        """State at ``times`` (s): dict of arrays "position" (m) and "velocity" (m/s) of
        shape ``(len(times), n_bodies, 3)``, "orientation" (unit quaternion (w, x, y, z),
        ``(len(times), n_bodies, 4)``) and "angular_velocity" (rad/s, world frame,
        ``(len(times), n_bodies, 3)``); with ``bodies`` (body indices) the second axis holds
        those bodies, in that order. At an event time the state just after the event is
        returned. A time before ``kept_from(i)`` of a body asked for (a run made with
        ``record="none"`` or a list of bodies) raises ``NotRecordedError``."""
        from rbimpact.kernels.flight3d import N_WS
        from rbimpact.kernels.pivot3d import N_FW, N_PW, sample_segments
        from .errors import SimulationError
        t = self._times(times)
        idx = self._body_indices(bodies, "Result3D.sample")
        self._check_kept(t, idx, "sample")
        out = np.empty((t.size, idx.size, 13))
        order = np.argsort(t, kind="stable")
        fw = np.zeros(N_FW)
        pose = np.zeros(19)
        rot_tol = float(self.tolerances.get("rot_tol", 1e-12))
        contact_tol = float(self.tolerances.get("contact_tol", 1e-10))
        max_steps = int(self.tolerances.get("rot_max_steps", 10_000_000))
        # each body's integrators are kept between calls: sampling a held (integrated)
        # motion one time after another, as a minimiser does, steps on instead of
        # re-integrating its segment from the start every call (the same values)
        keep = self.__dict__.setdefault("_integrators", {})
        for col, i in enumerate(idx):
            rk, axis = self._rotation[i]
            I1, I2, I3 = self.inertias[i]
            if i not in keep:
                keep[i] = (np.zeros(N_WS), np.zeros(N_PW), np.zeros(N_PW),
                           np.full(1, -1, np.int64))
            ws, pw, pwck, cur = keep[i]
            rc = sample_segments(self._seg_t, self._seg_s, self._seg_start[i],
                                 self._seg_start[i + 1], rk, axis, I1, I2, I3, rot_tol,
                                 contact_tol, max_steps, t, order, out, col, ws, pw, pwck, fw,
                                 pose, cur)
            if rc != 0:
                raise SimulationError(f"sample: the integrator of body {i} failed (step "
                                      f"limit rot_max_steps = {max_steps})")
        return {"position": out[:, :, 0:3].copy(), "orientation": out[:, :, 3:7].copy(),
                "velocity": out[:, :, 7:10].copy(), "angular_velocity": out[:, :, 10:13].copy()}

    def energy(self, times, per_body=False):
        """Total mechanical energy (J, kinetic + gravitational, potential zero at the
        origin) at ``times`` (s): shape ``(len(times),)``, or ``(len(times), n_bodies)``
        with ``per_body=True``."""
        s = self.sample(times)
        q = s["orientation"]
        w = s["angular_velocity"]
        wb = _rotate_inv(q, w)
        rot = 0.5 * np.sum(self.inertias[None, :, :] * wb * wb, axis=-1)
        e = (0.5 * self.masses * np.sum(s["velocity"] ** 2, axis=-1) + rot
             - self.masses * (s["position"] @ self.gravity))
        return e if per_body else e.sum(axis=1)

    def angular_momentum(self, times):
        """Angular momentum (kg m^2/s, world frame) of each body about its own centre of
        mass at ``times``: shape ``(len(times), n_bodies, 3)``."""
        s = self.sample(times)
        q = s["orientation"]
        wb = _rotate_inv(q, s["angular_velocity"])
        return _rotate(q, self.inertias[None, :, :] * wb)

    # ---------------------------------------------------------------- export

    FIELDS_CSV = FIELDS_CSV
    _EVENT_VECTORS = ("point", "normal", "tangent", "v_i", "v_f", "P")

    def _json_bodies(self):
        return {"masses": self.masses.tolist(), "inertias": self.inertias.tolist()}

    def plot(self, path, n=2000):
        """Save a figure to ``path``: centre-of-mass trajectories seen from above (x, y) and
        from the side (x, z) with impact markers, and total energy against time. Needs
        matplotlib (the ``plot`` extra)."""
        self._require_full("plot")
        plt = pyplot("Result3D.plot")
        t = np.linspace(self.t_start, self.t_end, n)
        ev_t = self.events["t"]
        t = np.union1d(t, ev_t[(ev_t >= self.t_start) & (ev_t <= self.t_end)])
        s = self.sample(t)
        x = s["position"]
        fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
        imp = self.events[self.events["kind"] == "impact"]
        for ax, (a, b), title in ((axes[0], (0, 1), "from above"),
                                  (axes[1], (0, 2), "from the side")):
            for i in range(self.n_bodies):
                ax.plot(x[:, i, a], x[:, i, b], lw=1, label=f"body {i}")
            if len(imp):
                ax.plot(imp["point"][:, a], imp["point"][:, b], "k.", ms=3, label="impacts")
            ax.set_xlabel("xyz"[a] + " (m)")
            ax.set_ylabel("xyz"[b] + " (m)")
            ax.set_title(f"centre-of-mass trajectories, {title}")
            ax.axis("equal")
        axes[0].legend(fontsize=8)
        axes[2].plot(t, self.energy(t), lw=1)
        for te in imp["t"]:
            axes[2].axvline(te, color="0.85", lw=0.5, zorder=0)
        axes[2].set_xlabel("t (s)")
        axes[2].set_ylabel("energy (J)")
        axes[2].set_title(f"total energy ({self.law}, {len(imp)} impacts)")
        fig.tight_layout()
        fig.savefig(path, dpi=120)
        plt.close(fig)


def _rotate(q, v):
    """Rotate vectors v (..., 3) by unit quaternions q (..., 4)."""
    w = q[..., :1]
    u = q[..., 1:]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def _rotate_inv(q, v):
    qc = q.copy()
    qc[..., 1:] *= -1.0
    return _rotate(qc, v)
