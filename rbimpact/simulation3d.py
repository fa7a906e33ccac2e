"""The exact event-driven 3D simulation (DESIGN §6, issue 5).

    >>> sim = Simulation3D(scene, Law("routh", e=0.6, mu=0.4))
    >>> result = sim.run(3.0)

The 3D counterpart of ``rbimpact.Simulation``, with the same keywords, policies, event
kinds, errors and ``Result`` layout (vectors have three components).

What the stepper does
---------------------
* **Flight** is exact: positions are quadratic in time; the torque-free rotation is in
  closed form for spherical and axisymmetric inertia (regular precession) and integrated
  with error control (``rot_tol``) for general inertia (``rbimpact.kernels.flight3d``).
* **Time of impact** (``rbimpact.kernels.toi3d``): the box corners, capsule cap centres and
  sphere centres against every plane, in one conservative-advancement sweep per body with
  a bound on ``|g''|`` (no root skipped, grazing ones included), converging to
  ``toi_atol + toi_rtol * t``; sphere pairs by the cancellation-free quadratic formula.
* **Impacts**: the contact frame is ``n`` with the deterministic tangent basis of DESIGN §3
  (``rbimpact.kernels.toi3d.tangent_basis``: a floor has ``t1 = x, t2 = y``; a normal in the
  x-z plane gives the 2D basis of that plane); ``W`` is built from the world inertia
  tensors and the arms; the pair's law is applied through
  ``rbimpact.kernels.dispatch.resolve_3d`` (Routh's swerve included). A law failure raises
  ``NoSolutionError`` naming body, time and point. A perforating impact (``v_fN < 0``)
  disables that pair for the rest of the run.
* **Body-body contacts** (issue 16): every pair of spheres, boxes and capsules collides.
  Two spheres keep their closed-form time of impact; any other pair is searched by
  ``rbimpact.kernels.pair3d_toi`` (conservative advancement that never passes a root,
  polished to round-off) up to either body's next event. At the impact the contact points
  and their one normal (from B into A) come from ``pair3d_manifold`` (a face, an edge or a
  capsule lying on a face: a cluster of up to 8 points, resolved under the policy with
  the plane contacts of the same instant). Persistent contact between bodies is not built
  yet: the run stops (``SimulationError``, status "persistent_pair") when a pair's impacts
  accumulate, when the bodies ride together after a plastic impact, or when a body held
  by an integrated contact (pivot) has a partner of another shape than two spheres.
  ``ignore_unsupported_pairs=True`` keeps the behaviour from before: only spheres
  collide, other pairs pass through each other.
* **Simultaneous contacts** (a box landing flat): contacts within ``simul_time`` of the
  earliest are clustered by shared bodies; ``policy="simultaneous"`` (default) solves each
  cluster jointly (Newton restitution ``e`` and Coulomb ``mu`` of each contact's pair law,
  projected block Gauss-Seidel with the friction disk, to ``simul_tol``);
  ``policy="sequential"`` resolves the fastest-approaching contact with its pair law until
  none approaches faster than ``seq_vtol``. Same rules as 2D; ``Result3D.policy`` reports it.
* **Zeno, persistent contact, pivoting**: see ``rbimpact.kernels.stepper3d``. A sphere
  slides then rolls; a box or capsule comes to rest on a face or its side (accumulation
  detected from the excess energy, threshold ``m zeno_speed^2 / 2``); impacts that
  accumulate at a corner, an edge or a cap turn into an integrated persistent contact
  (``rbimpact.kernels.pivot3d``: the body pivots, rolls or slides on one or two features,
  stick and slip, to ``contact_tol``; events "pivot", "stick", "slide", "release"), so a
  tumbling die rocks over its corners and edges and comes to rest on a face. A box
  landing on a face while spinning about the normal is snapped onto it with the spin
  removed (event "capture", ``dE`` the energy removed; ``capture=False`` raises instead).
* **Never silently wrong**: non-finite state, a law without solution, a missed event, a
  search or an integration that does not converge, unsupported persistent motion,
  ``stall_events`` passes of the loop at one instant, or ``idle_passes`` passes of the loop in a row
  with no event raise ``SimulationError``/``NoSolutionError`` with
  the partial result as ``exc.result``; ``max_events`` stops early with status
  "max_events" and a ``RuntimeWarning``.
"""
import warnings

import numpy as np

from ._setup import (call_loop, check_law, check_loop, check_painleve, check_run_args,
                     check_scene, check_tolerances, compiled_loop, pack_laws,
                     idle_message, persistent_pair_message, run_status)
from .kernels import evbuf
from .kernels.codes import PAINLEVE_OPTIONS
from .errors import NoSolutionError, SimulationError
from ._recording import Recorder
from .result3d import Result3D, build_events_3d
from .scene3d import Plane3D, Scene3D

__all__ = ["Simulation3D", "TOLERANCES_3D"]

#: keyword -> (default, unit, meaning); the first twelve are those of the 2D Simulation
TOLERANCES_3D = {
    "rest_length": (1e-10, "m", "impacts accumulate (Zeno) when the excess energy of the "
                    "body's normal and rotational motion would lift it less than this"),
    "zeno_speed": (None, "m/s", "accumulation speed; None: sqrt(2 |g_n| rest_length) for each "
                   "plane (and sqrt(2 |g''| rest_length) for a single point)"),
    "gap_tol": (1e-9, "m", "a gap below -gap_tol is a missed event (or a body starting "
                "inside a plane or another body)"),
    "toi_rtol": (1e-14, "-", "relative time tolerance of the time-of-impact search"),
    "toi_atol": (1e-15, "s", "absolute time tolerance of the time-of-impact search"),
    "toi_max_iter": (100_000, "-", "iteration limit of one time-of-impact search"),
    "simul_time": (1e-11, "s", "impacts within this time of the earliest one are "
                   "simultaneous"),
    "simul_tol": (1e-13, "m/s", "joint solve: stop when a sweep changes no contact velocity "
                  "by more than this"),
    "simul_max_iter": (100_000, "-", "joint solve: maximum number of sweeps"),
    "seq_vtol": (1e-12, "m/s", "sequential policy: a contact approaches when v_N < -seq_vtol"),
    "seq_max_steps": (1000, "-", "sequential policy: maximum resolutions at one instant"),
    "stall_events": (10_000, "-", "maximum consecutive passes of the event loop at one instant"),
    "idle_passes": (10_000_000, "-", "maximum consecutive passes of the event loop that "
                    "record no event (integrated motion, bounded searches): beyond it the "
                    "run stops with status 'idle' instead of running on without end; "
                    "raise it for long integrated motions that meet no event"),
    "max_accumulation_impacts": (1_000_000, "-", "a sphere whose bounces on a plane would "
                                 "accumulate (or reach t_end) only after more impacts than "
                                 "this (e close to 1) stops the run with an error naming e "
                                 "and the count, instead of stepping through them"),
    "rot_tol": (1e-12, "-", "error tolerance of the integrated rotation (general inertia; "
                "a sliding sphere's orientation): per step, quaternion components within "
                "rot_tol and body angular velocity within rot_tol |w(0)|"),
    "rot_max_steps": (10_000_000, "-", "step limit of one integrated rotation (or "
                      "integrated contact) segment"),
    "contact_tol": (1e-10, "-", "error tolerance of integrated point/edge contact (a body "
                    "pivoting on a corner, an edge or a cap): per step, relative to the body's "
                    "size, speed scale and 1 for the quaternion"),
    "slip_eps": (1e-6, "m/s", "integrated contact: a sliding contact point sticks when its "
                 "slip speed falls to slip_eps (the rest is removed by an impulse <= m "
                 "slip_eps)"),
}
POLICIES = ("simultaneous", "sequential")
# rotation kinds (kernels/flight3d.py ROT_*)
_ROT_SPHERICAL, _ROT_AXISYM, _ROT_GENERAL = 0, 1, 2


#: first capacity (rows beyond the loop's safety margin) of the event and segment buffers
#: of a run with ``record="all"``; they double when full
INITIAL_EVENT_ROWS_3D = 1 << 14
#: first segment rows for record="all" (grown by doubling): a 3D segment row carries the
#: integrated-contact parameters (``stepper3d.N_SEG`` = 143 floats with ``pivot3d.KMAX`` =
#: 8), so fewer rows than events keep the first allocation, zeroed on every run, small
#: (4.7 MB; 16384 rows cost 2.3 ms per run, measured on a 3-event scene)
INITIAL_SEGMENT_ROWS_3D = 1 << 12


def _grow_doubling(arrays, used):
    """Buffers sharing their first dimension, twice as long (zero-filled beyond the old
    rows)."""
    n = 2 * len(arrays[0])
    return tuple(np.concatenate([a, np.zeros((n - len(a),) + a.shape[1:], a.dtype)])
                 for a in arrays)


def _shape_name(body):
    return type(body.shape).__name__


def rotation_kind(inertia):
    """(kind, symmetry axis) of principal moments: 0 spherical (all equal), 1 axisymmetric
    (exactly two equal; axis = the odd one), 2 general."""
    a, b, c = inertia
    if a == b == c:
        return _ROT_SPHERICAL, 2
    if a == b:
        return _ROT_AXISYM, 2
    if a == c:
        return _ROT_AXISYM, 1
    if b == c:
        return _ROT_AXISYM, 0
    return _ROT_GENERAL, 2


def _quat_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _min_gap_plane(body, plane):
    """Smallest gap (m) of a body's contact features to a plane, at the initial state."""
    kind, rad, half, feats = body.shape._kernel()
    R = _quat_matrix(body.orientation)
    n = np.array(plane.normal)
    pts = feats @ R.T + np.array(body.position)
    return float(np.min(pts @ n) - rad - plane.offset)


class Simulation3D:
    """An event-driven 3D simulation of ``scene`` (a ``Scene3D``) with law ``law``.

    ``pair_laws``: optional mapping to other laws: key ``(i, j)`` (two body indices),
    ``(i, plane)`` or ``(plane, i)``, or a ``Plane3D`` alone. Most specific key wins.

    Keywords: ``policy`` ("simultaneous" or "sequential"), ``ignore_unsupported_pairs``
    (bool), ``capture`` (bool, default True: see the module docstring), ``painleve``
    ("impact", default, or "error": as for ``Simulation``; in 3D the impact without
    collision is taken where impacts accumulate at one sliding point), ``loop`` ("scene",
    "general" or None: as for ``Simulation``) and the tolerances
    of ``TOLERANCES_3D`` (name: default, unit): rest_length 1e-10 m; zeno_speed None (m/s);
    gap_tol 1e-9 m; toi_rtol 1e-14; toi_atol 1e-15 s; toi_max_iter 100000; simul_time
    1e-11 s; simul_tol 1e-13 m/s; simul_max_iter 100000; seq_vtol 1e-12 m/s;
    seq_max_steps 1000; stall_events 10000; idle_passes 10000000;
    max_accumulation_impacts 1000000; rot_tol 1e-12; rot_max_steps 1e7;
    contact_tol 1e-10; slip_eps 1e-6 m/s.
    """

    def __init__(self, scene, law, pair_laws=None, *, policy="simultaneous",
                 ignore_unsupported_pairs=False, capture=True, painleve="impact",
                 loop=None, **tolerances):
        if not isinstance(scene, Scene3D):
            raise ValueError(f"Simulation3D: scene must be a Scene3D, got {scene!r}")
        if not scene.bodies:
            raise ValueError("Simulation3D: the scene has no body")
        policy = check_scene("Simulation3D", scene, policy, POLICIES)
        tol = check_tolerances("Simulation3D", TOLERANCES_3D, tolerances)
        if not tol["rot_tol"] > 0:
            raise ValueError("Simulation3D: rot_tol must be > 0")
        self.scene = scene
        self.law = check_law("Simulation3D", law, "law")
        self.policy = policy
        self.capture = bool(capture)
        self.painleve = check_painleve("Simulation3D", painleve)
        self.loop = check_loop("Simulation3D", loop)
        self.tolerances = tol
        self.ignore_unsupported_pairs = bool(ignore_unsupported_pairs)
        self._pack(pair_laws or {})
        self._check_initial()

    # ------------------------------------------------------------ building

    def _pack(self, pair_laws):
        scene = self.scene
        bodies, planes = scene.bodies, scene.planes
        nb, npl = len(bodies), len(planes)
        feats, bint, bflt = [], np.zeros((nb, 5), np.int64), np.zeros((nb, 8))
        self._rot = []
        row = 0
        for i, body in enumerate(bodies):
            kind, rad, half, f = body.shape._kernel()
            rk, axis = rotation_kind(body.inertia)
            self._rot.append((rk, axis))
            bint[i] = (kind, row, len(f), rk, axis)
            bflt[i] = (body.mass, *body.inertia, rad, *half)
            feats.append(f)
            row += len(f)
        self._bint, self._bflt = bint, bflt
        self._feats = np.ascontiguousarray(np.concatenate(feats), dtype=float)
        self._planes = np.array([(*p.normal, p.offset) for p in planes],
                                dtype=float).reshape(npl, 4)
        # every pair of bodies collides (issue 16; pair3d*); ignore_unsupported_pairs=True
        # keeps the sphere pairs only, as before
        collide = (bint[:, 0] == 0) if self.ignore_unsupported_pairs else np.ones(nb, bool)
        table = pack_laws("Simulation3D", scene, self.law, pair_laws, Plane3D,
                          collide, dim="3D", round_name="spheres",
                          ignore_unsupported_pairs=self.ignore_unsupported_pairs)
        self._pairs = table.pairs
        self._bp_law = table.bp_law
        self._laws = table.laws
        self._law_ids = table.law_ids
        self._law_par = table.law_par
        self._grav = np.array(scene.gravity, dtype=float)

    def _check_initial(self):
        gap_tol = self.tolerances["gap_tol"]
        for body in self.scene.bodies:
            for plane in self.scene.planes:
                g = _min_gap_plane(body, plane)
                if g < -gap_tol:
                    raise ValueError(
                        f"Simulation3D: body {body.index} ({_shape_name(body)}) starts inside "
                        f"plane {plane.index} (point {plane.point}, normal {plane.normal}): "
                        f"its lowest point is {-g:.6g} m below the plane's surface")
        if len(self._pairs):
            from .kernels.pair3d import N_FE, N_FR, pair_frame
            fr, fe = np.zeros(N_FR), np.zeros(N_FE, np.int64)
        for i, j, _ in self._pairs:
            bi, bj = self.scene.bodies[i], self.scene.bodies[j]
            rows = []
            for b in (bi, bj):
                row = np.zeros(19)
                row[0:3] = b.position
                row[3:7] = b.orientation
                rows.append(row)
            g = pair_frame(self._bint[i, 0], *self._bflt[i, 4:8], rows[0],
                           self._bint[j, 0], *self._bflt[j, 4:8], rows[1], fr, fe)
            if g < -gap_tol:
                raise ValueError(f"Simulation3D: bodies {i} ({_shape_name(bi)}) and {j} "
                                 f"({_shape_name(bj)}) overlap at the start by {-g:.6g} m "
                                 f"(more than gap_tol = {gap_tol:g} m)")

    # ------------------------------------------------------------ running

    def run(self, t_end, max_events=1_000_000, record="all", observer=None, snapshot_dt=None):
        """Run from t = 0 to ``t_end`` (s) and return a ``Result3D``.

        ``max_events``: stop after the instant at which the number of events of the run
        reaches it (status "max_events", with a ``RuntimeWarning``), whatever ``record``
        keeps.

        ``record`` ("all", "none" or a 1-D array of body indices), ``observer`` (None or a
        callable taking each chunk of events, a read-only array with the columns of
        ``Result3D.events``; its exceptions propagate and stop the run) and
        ``snapshot_dt`` (None or a time step in s: ``result.snapshots == (times,
        states)``, ``states`` a dict like ``sample``'s) are those of ``Simulation.run``:
        "all" keeps everything (memory grows with the events, about 0.6 KB per event with
        its segments), "none" the counts, the final state and the snapshots in buffers of
        fixed size (``_recording.DRAIN_ROWS`` rows beyond the loop's margins), a list of
        bodies their events and trajectories.
        """
        from .kernels import stepper3d as k
        from .kernels.flight3d import N_WS
        from .kernels.pivot3d import N_CP, N_FW, N_PW, NEV_CONTACT
        t_end, max_events = check_run_args(t_end, max_events)
        rec = Recorder.for_run("Simulation3D", k, build_events_3d, self._sampler,
                               len(self.scene.bodies), t_end, max_events, record, observer,
                               snapshot_dt)
        tol = self.tolerances
        nb = len(self.scene.bodies)
        npl = len(self.scene.planes)
        npr = len(self._pairs)
        tolf = np.zeros(k.N_TF)
        tolf[k.TF_REST_LENGTH] = tol["rest_length"]
        tolf[k.TF_ZENO_SPEED] = -1.0 if tol["zeno_speed"] is None else tol["zeno_speed"]
        tolf[k.TF_GAP_TOL] = tol["gap_tol"]
        tolf[k.TF_TOI_RTOL] = tol["toi_rtol"]
        tolf[k.TF_TOI_ATOL] = tol["toi_atol"]
        tolf[k.TF_SIMUL_TIME] = tol["simul_time"]
        tolf[k.TF_SIMUL_TOL] = tol["simul_tol"]
        tolf[k.TF_SEQ_VTOL] = tol["seq_vtol"]
        tolf[k.TF_T_END] = float(t_end)
        tolf[k.TF_ROT_TOL] = tol["rot_tol"]
        tolf[k.TF_CONTACT_TOL] = tol["contact_tol"]
        tolf[k.TF_SLIP_EPS] = tol["slip_eps"]
        tolf[k.TF_PAINLEVE] = PAINLEVE_OPTIONS.index(self.painleve)
        toli = np.zeros(k.N_TI, np.int64)
        toli[k.TI_TOI_MAXIT] = tol["toi_max_iter"]
        toli[k.TI_SIMUL_MAXIT] = tol["simul_max_iter"]
        toli[k.TI_SEQ_MAXSTEPS] = tol["seq_max_steps"]
        toli[k.TI_STALL] = tol["stall_events"]
        toli[k.TI_IDLE] = tol["idle_passes"]
        toli[k.TI_ACC_MAX] = tol["max_accumulation_impacts"]
        toli[k.TI_POLICY] = POLICIES.index(self.policy)
        toli[k.TI_MAX_EVENTS] = max_events
        toli[k.TI_ROT_MAX_STEPS] = tol["rot_max_steps"]
        toli[k.TI_CAPTURE] = 1 if self.capture else 0

        st = np.zeros((nb, 19))
        for i, b in enumerate(self.scene.bodies):
            st[i, 0:3] = b.position
            st[i, 3:7] = b.orientation
            st[i, 7:10] = b.velocity
            st[i, 10:13] = b.angular_velocity
        tref = np.zeros(nb)
        pm = np.zeros((nb, 4), np.int64)      # layout.M_MODE, M_PLANE, M_FEAT, M_AUX
        pm[:, 1:] = -1
        tz = np.full(nb, np.inf)
        zp = np.full(nb, -1, np.int64)
        ttr = np.full(nb, np.inf)
        bt = np.full(nb, np.inf)
        bpl = np.full(nb, -1, np.int64)
        bft = np.full(nb, -1, np.int64)
        bp_off = np.zeros((nb, npl), np.int64)
        pr_t = np.full(npr, np.inf)
        pr_off = np.zeros(npr, np.int64)
        ws = np.zeros((nb, N_WS))
        ws[:, 0] = -1.0
        glob = np.zeros(2)
        cnt = np.zeros(evbuf.N_CNT, np.int64)
        pk = np.zeros((nb, 2), np.int64)
        pv = np.zeros((nb, N_CP))
        pw = np.zeros((nb, N_PW))
        fw = np.zeros(N_FW)
        ybuf = np.zeros(13)
        nv = NEV_CONTACT + max(npl, 1) * int(self._bint[:, 2].max())
        vals = np.zeros(nv)
        vals0 = np.zeros(nv)
        vfl = np.zeros(nv)
        me = k.event_margin(toli, nb)
        ms = k.segment_margin(nb)
        cap_e, cap_s = rec.capacities(me, ms, INITIAL_EVENT_ROWS_3D, INITIAL_SEGMENT_ROWS_3D)
        bufs = (np.zeros(cap_e), np.zeros((cap_e, 5), np.int64), np.zeros((cap_e, k.N_EF)),
                np.zeros(cap_s), np.zeros(cap_s, np.int64), np.zeros((cap_s, k.N_SEG)))
        M = k.MAXC
        c_i = np.zeros((M, k.N_CI), np.int64)
        c_f = np.zeros((M, k.N_CF))
        Wb = np.zeros((3 * M, 3 * M))
        Pb = np.zeros(3 * M)
        vb = np.zeros(3 * M)
        tb = np.zeros(3 * M)
        comp = np.zeros(2 * M, np.int64)
        bmark = np.zeros(nb, np.int64)
        v3 = np.zeros(3)
        W3 = np.zeros((3, 3))
        P3 = np.zeros(3)
        Ii = np.zeros((3, 3))
        skip = np.zeros(max(npl, 1), np.int64)
        pose = np.zeros(19)
        pscr = np.zeros((k.N_PSCR, N_WS))       # the general pair search's scratch rows
        pmf = np.zeros((k.MAX_MF, k.N_MF))     # a pair's contact manifold
        pfe = np.zeros(k.N_FE, np.int64)       # a pair's contact features
        err = np.zeros(k.N_ERR)
        # persistent sphere contact (stepper3d.cluster_sizes): bodies, contacts, work, header
        cb_shape, cc_shape, cw_size, cid_size = k.cluster_sizes(nb)
        cbod, ccon, cwk = np.zeros(cb_shape), np.zeros(cc_shape), np.zeros(cw_size)
        cid = np.zeros(cid_size, np.int64)
        cid[k.CL_PEND] = -1
        cid[k.CL_LEAD] = -1
        scene_arrays = (self._bint, self._bflt, self._feats, self._planes, self._grav,
                        self._law_ids, self._law_par, self._bp_law, self._pairs, tolf, toli)
        state = (st, tref, pm, tz, zp, ttr, bt, bpl, bft, bp_off, pr_t, pr_off, ws, glob, cnt,
                 pk, pv, pw)
        run_loop, (pivot, pair, pgen, joint) = compiled_loop(self, k)
        rc = call_loop(k.init_run, (*scene_arrays, *state, *bufs, c_f, skip, pose, fw, ybuf,
                                    vals, vals0, vfl, pscr, pfe, cid, err, pair, pgen))
        work = (c_i, c_f, Wb, Pb, vb, tb, comp, bmark, v3, W3, P3, Ii, skip, pose, fw, ybuf,
                vals, vals0, vfl, pscr, pmf, pfe, cbod, ccon, cwk, cid, err, pivot, pair, pgen,
                joint)
        if rc == 0:
            rc = call_loop(run_loop, (*scene_arrays, *state, *bufs, *work))
            while rc == k.RC_BUFFER_FULL:
                bufs = rec.on_full(bufs, cnt, glob, toli, me, ms, _grow_doubling)
                rc = run_loop(*scene_arrays, *state, *bufs, *work)
        status = run_status(k, rc)
        *kept, recording = rec.finish(bufs, cnt, glob)
        result = self._result(*kept, glob, status, float(t_end), recording)
        if rc < 0:
            raise self._error(rc, err, result)
        if status == "max_events":
            warnings.warn(f"Simulation3D.run: max_events={max_events} reached at t = "
                          f"{result.t_end:.12g} s, before t_end = {float(t_end):g} s; the "
                          f"result stops there (status 'max_events')", RuntimeWarning,
                          stacklevel=2)
        return result

    def _result(self, ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, glob, status, t_req,
                recording=None):
        from .kernels.stepper3d import EVENT_KINDS
        ev = build_events_3d(ev_t, ev_i, ev_f, EVENT_KINDS)
        bodies = self.scene.bodies
        return Result3D(ev, seg_t.copy(), seg_b.copy(), seg_s.copy(),
                        status=status, policy=self.policy, t_start=0.0, t_end=float(glob[0]),
                        t_requested=t_req, masses=[b.mass for b in bodies],
                        inertias=[b.inertia for b in bodies], rotation=self._rot,
                        gravity=self.scene.gravity,
                        law=getattr(self.law, "name", repr(self.law)),
                        tolerances={**self.tolerances, "policy": self.policy,
                                    "capture": self.capture, "painleve": self.painleve},
                        recording=recording)

    def _sampler(self, seg_t, seg_b, seg_s, times):
        """States at ``times`` (s) from logged segment rows (``Result3D.sample``)."""
        from .kernels.stepper3d import N_EF
        t = float(times.max())
        r = self._result(np.empty(0), np.empty((0, 5), np.int64), np.empty((0, N_EF)), seg_t,
                         seg_b, seg_s, (t,), "done", t)
        return r.sample(times)

    def _where(self, b):
        b = int(b)
        if b < 0:
            p = self.scene.planes[-1 - b]
            return f"plane {p.index} (point {p.point}, normal {p.normal})"
        return f"body {b} ({_shape_name(self.scene.bodies[b])})"

    def _error(self, rc, err, result):
        from .kernels import stepper3d as k
        t, a, b = err[0], int(err[1]), int(err[2])
        at = f"at t = {t:.12g} s"
        if np.all(np.isfinite(err[3:6])):
            pt = f"contact point ({err[3]:.9g}, {err[4]:.9g}, {err[5]:.9g})"
            pos = f"(centre of mass ({err[3]:.9g}, {err[4]:.9g}, {err[5]:.9g}))"
        else:   # the failing step's state diverged: no coordinates to print
            pt = "contact point not finite (the failing step's state diverged)"
            pos = "(centre of mass not finite: the failing step's state diverged)"
        body = self._where(a) if a >= 0 else "the scene"
        if rc == k.ERR_NO_SOLUTION:
            mode = int(err[6])
            law = self._laws[int(err[8])]
            name = getattr(law, "name", "the law")
            exc = NoSolutionError(
                f"impact of {body} on {self._where(b)} {at}, {pt}, has no solution in law "
                f"{name} (mode {mode}); pre-impact v = {err[10:13].tolist()} m/s, W = "
                f"{err[[13, 14, 15, 14, 16, 17, 15, 17, 18]].reshape(3, 3).tolist()} 1/kg",
                mode_code=mode)
        elif rc == k.ERR_NONFINITE:
            exc = SimulationError(f"non-finite state of {body} {at} {pos}")
        elif rc == k.ERR_MISSED:
            exc = SimulationError(f"missed event: {body} is inside {self._where(b)} by more "
                                  f"than gap_tol = {self.tolerances['gap_tol']:g} m {at} "
                                  f"{pos}")
        elif rc == k.ERR_TOI:
            exc = SimulationError(f"the time-of-impact search of {body} did not converge in "
                                  f"toi_max_iter = {self.tolerances['toi_max_iter']} steps, "
                                  f"from {at}")
        elif rc == k.ERR_ROT:
            exc = SimulationError(f"the rotation integrator of {body} exceeded rot_max_steps "
                                  f"= {self.tolerances['rot_max_steps']} steps {at} (rot_tol "
                                  f"= {self.tolerances['rot_tol']:g})")
        elif rc == k.ERR_CHATTER:
            exc = SimulationError(
                f"impacts accumulate at a single contact point of {body} on {self._where(b)} "
                f"{at}, {pt}: normal speed after the impact {err[6]:.3g} m/s while the gap "
                f"accelerates into the contact at {err[7]:.3g} m/s^2: a persistent contact "
                f"there is not supported (sphere pairs; a face landing spinning with "
                f"capture={self.capture})")
        elif rc == k.ERR_SEQ:
            exc = SimulationError(f"sequential policy: contacts of {body} still approach after "
                                  f"seq_max_steps = {int(err[7])} resolutions {at}")
        elif rc == k.ERR_PGS and err[8] == 1.0:
            exc = SimulationError(
                f"simultaneous policy: {int(err[6])} contacts of {body} {at} jam: no "
                f"solution of their joint Newton-restitution/Coulomb impact found (projected "
                f"Gauss-Seidel, the semismooth Newton polish and every sticking set tried), "
                f"while the plastic problem (e = 0) of the same contacts has one: friction "
                f"locks them, where Newton's restitution generally has no solution; "
                f"policy='sequential' resolves them one at a time")
        elif rc == k.ERR_PGS:
            exc = SimulationError(f"simultaneous policy: the joint solve of {int(err[6])} "
                                  f"contacts of {body} {at} did not reach simul_tol in "
                                  f"simul_max_iter sweeps (last change {err[7]:.3g} m/s)")
        elif rc == k.ERR_TIPPING:
            exc = SimulationError(f"{body} in persistent contact with {self._where(b)} {at} "
                                  f"would tip over (friction force {err[6]:.3g} N against "
                                  f"normal force {err[7]:.3g} N at height {err[8]:.3g} m): "
                                  f"not supported")
        elif rc == k.ERR_FAR_ACCUMULATION:
            exc = SimulationError(
                f"{body} bounces on {self._where(b)} with restitution e = {err[6]:.12g} "
                f"{at}: its bounces accumulate (or reach t_end) only after about "
                f"{err[7]:.3g} more impacts, beyond max_accumulation_impacts = "
                f"{self.tolerances['max_accumulation_impacts']}; end the run earlier, lower "
                f"e, or raise max_accumulation_impacts")
        elif rc == k.ERR_NOT_COMPILED:
            exc = SimulationError(
                f"internal error: {body} reached a contact handler ("
                f"{k.FEATURES[int(err[3])]}) that the loop compiled for this scene lacks "
                f"{at} (a bug of stepper3d.scene_features; please report it)")
        elif rc == k.ERR_UNSUPPORTED:
            what = {1.0: "a sphere with non-spherical inertia in persistent contact",
                    3.0: "settling on one plane while touching another (a box or capsule "
                         "on a face or side, or a sphere still bouncing on the second): "
                         "persistent contact with two planes at once",
                    5.0: "motion at three or more features on two planes, or at one "
                         "corner touching both with friction (a corner pinned in a "
                         "groove's crease), faster than the accumulation speed or "
                         "with no rest in the friction cones",
                    4.0: "a sphere slipping along the groove of two planes (rolling on both "
                         "needs more friction, or its contact points slip faster than the "
                         "accumulation speed)"}.get(float(err[6]),
                                                                           "this motion")
            exc = SimulationError(f"{body} on {self._where(b)} {at}: {what} is not supported")
        elif rc == k.ERR_PAINLEVE:
            why = {1.0: "a sliding contact's normal force coefficient is <= 0 (Painleve "
                        "paradox: no consistent contact force)",
                   2.0: "the contact force system is singular",
                   3.0: "no consistent stick/slip/lift-off state was found",
                   4.0: "three or more contact points stick: the body is held still (a "
                        "rest that the integrated contact does not build)"}.get(
                float(err[6]), "the contact forces failed")
            exc = SimulationError(f"integrated contact of {body} with {self._where(b)} {at} "
                                  f"{pos}: {why} (mu = {err[7]:g}, {int(err[8])} contact "
                                  f"point(s))")
        elif rc == k.ERR_CONTACT_STEPS:
            exc = SimulationError(f"the integrated contact of {body} exceeded rot_max_steps "
                                  f"= {self.tolerances['rot_max_steps']} steps {at} "
                                  f"(contact_tol = {self.tolerances['contact_tol']:g})")
        elif rc == k.ERR_PERSISTENT_PAIR:
            held = self._where(int(err[7])) if err[6] == k.PP_HELD else ""
            exc = SimulationError(persistent_pair_message(
                k, err[6], body, self._where(b), held, at, pt, err[7], err[8],
                self.tolerances["rest_length"]))
        elif rc == k.ERR_STALL:
            exc = SimulationError(f"the run stalls {at}: more than stall_events = "
                                  f"{self.tolerances['stall_events']} consecutive passes of "
                                  f"the event loop at one instant")
        elif rc == k.ERR_IDLE:
            exc = SimulationError(idle_message(result, at, self.tolerances["idle_passes"]))
        elif rc == k.ERR_TOO_MANY:
            exc = SimulationError(f"more than {k.MAXC - 1} contacts at one instant {at} "
                                  f"({body})")
        elif rc == k.ERR_JOINT_E:
            exc = SimulationError(f"simultaneous policy needs 0 <= e <= 1 for the joint "
                                  f"Newton solve, but the contact of {body} on "
                                  f"{self._where(b)} {at} has e = {err[6]:g}; use "
                                  f"policy='sequential'")
        else:  # pragma: no cover
            exc = SimulationError(f"stepper error code {rc} {at}")
        exc.result = result
        return exc
