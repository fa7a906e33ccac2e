"""The exact event-driven 2D simulation (DESIGN §6, issue 3).

    >>> sim = Simulation(scene, Law("kane_levinson", e=0.8, mu=0.3))
    >>> result = sim.run(5.0)

What the stepper does
---------------------
* **Flight** is exact: between events every body moves with constant accelerations
  (gravity in flight), so positions are quadratic and angles linear (or quadratic for a
  disk rolling or sliding) in time. ``Result.sample`` evaluates the same closed forms.
* **Time of impact**: every contact feature (``rbimpact.kernels.toi2d``) has a smooth gap
  function; the earliest root with ``g' < 0`` is found in closed form when the gap is a
  quadratic, else by conservative advancement with a bound on ``|g''|`` (no root is
  skipped, grazing ones included) converging quadratically to ``toi_atol + toi_rtol * t``.
* **Impacts**: at each impact the stepper builds ``n``, ``t = (n_y, -n_x)``, the Delassus
  matrix ``W`` (DESIGN §3; a plane contributes nothing), ``v_i``, calls the pair's law
  kernel through ``rbimpact.kernels.dispatch.resolve_2d`` and applies ``P``. A law's
  failure (mode < 0) raises ``NoSolutionError`` naming body, time and point. An impact that
  leaves the contact approaching (``v_fN < 0``: Brach's perforation, e < 0) disables that
  body-plane (or disk-disk) pair for the rest of the run: the body has gone through.
* **Body-body contacts** (issue 16): every pair of shapes (disk, box/polygon, rod/capsule,
  ellipse). Two disks: closed-form time of impact (``toi2d.disk_disk_toi``); any other
  pair: ``pair2d_toi.pair_toi`` (conservative advancement that never passes a root,
  polished to round-off) and the contact frame of ``pair2d.frame_rel`` at the impact
  instant (normal from B into A, the arms from each centre to its own witness point, so
  ``W`` and ``v`` are those of the pair frame). Two faces touching along a segment (edges
  parallel within ``stepper2d.PAIR_FACE_RTOL``) make a cluster of two contacts, the ends
  of their overlap, resolved by the policy like a flat landing on a plane. Persistent
  contact between bodies is not built: when a pair stays in contact after an impact (its
  impacts would accumulate, or the bodies ride together after a plastic impact), or a
  body held on a plane by an integrated contact has a partner body, the run stops with
  ``SimulationError`` (status "persistent_pair"). A one-body scene has no pair at all (no
  pair search runs). ``ignore_unsupported_pairs=True`` keeps the behaviour from before
  issue 16: only disks collide with each other, other bodies pass through each other (no
  pair law may be given for them).
* **Simultaneous contacts**: all contacts whose impact times lie within ``simul_time`` (s)
  of the earliest one, and the other corners of a body in such an impact whose gap is
  already below ``simul_gap`` (m) and closing, are gathered and grouped into clusters
  sharing a body. A cluster of one contact is resolved by its pair law (if it approaches)
  under both policies. For larger clusters:

  - ``policy="simultaneous"`` (default): one joint solve over the cluster: Newton
    restitution with Coulomb friction, each contact ``k`` taking ``e_k = params[P_E]`` and
    ``mu_k = params[P_MU]`` from its pair law (whatever the law; ``0 <= e <= 1`` is
    required): find ``P`` with ``v_f = v_i + W P`` (``W`` the stacked Delassus matrix over
    all contacts of the cluster) such that for every contact ``0 <= P_N`` complementary
    to ``v_fN >= -e min(v_iN, 0)``, and ``|P_T| <= mu P_N`` with ``P_T`` the box-projected
    value driving ``v_fT`` to 0 (sticking when inside the cone). Solved by projected
    Gauss-Seidel from ``P = 0``, contacts in index order, until no impulse update changes a
    velocity by more than ``simul_tol`` times the largest pre-impact contact speed of the
    cluster in a sweep, at most ``simul_max_iter`` sweeps (else ``SimulationError``).
    Events carry mode 0 (no impulse), 1 (inside the cone) or 2 (on the cone) and
    ``cluster = K``. A symmetric landing stays symmetric. Note: this joint Newton solve
    is not the pair law, and for e > 0 it is not guaranteed to dissipate energy.
  - ``policy="sequential"``: repeatedly take the contact of the cluster whose current
    normal velocity is the most negative (ties: the lowest contact index, i.e. body,
    then plane, then vertex order) and resolve it alone with its pair law, at the current
    velocities; stop when no contact approaches faster than ``seq_vtol`` (m/s); at most
    ``seq_max_steps`` resolutions (else ``SimulationError``). Every resolution is an
    "impact" event.

  ``Result.policy`` reports the policy.
* **Zeno and persistent contact**: after an impact on a plane with gravity pushing into it
  (``g_n = n . g < 0``), the body's *excess energy* ``E_ex`` is computed: kinetic energy
  of the normal motion of its centre of mass, plus (not for a disk) of its rotation, plus
  the potential energy above its nearest resting configuration (a disk: on the plane; a
  polygon or rod: on the face whose two corners are lowest, if the centre of mass lies over
  that face; an ellipse: its minor axis normal to the plane). When
  ``E_ex < m zeno_speed^2 / 2``, with ``zeno_speed`` defaulting to
  ``sqrt(2 |g_n| rest_length)`` (i.e. the body could rise less than ``rest_length``), the
  bounces are taken to accumulate: the run jumps to the accumulation point
  ``t_inf = t_k + 2 v_N / (|g_n| (1 - e_k))`` with ``v_N`` the normal velocity of the
  centre of mass after the impact and ``e_k`` its ratio to the one before (exact for a disk,
  and for a body landing flat under a Newton-type restitution; ``2 v_N / |g_n|`` when
  ``e_k >= 1``), flying the body freely meanwhile, and snaps it onto the plane (normal
  velocity and, for a non-disk, rotation set to zero: event "contact", ``dE`` reports the
  energy removed). Then, with ``mu`` of the pair law and normal force ``m |g_n|``:

  - a disk slides with Coulomb friction until its contact point stops ("roll" event:
    exact closed form), then rolls (or rests, "rest", when nothing moves and the plane is
    level); on an incline where friction cannot hold rolling it keeps sliding;
  - a polygon or rod rests on its face if ``|g_t| <= mu |g_n|`` ("rest"), else slides and
    decelerates (event "rest" when it stops; "slide" if it then slides back down); a slip
    slower than the accumulation speed with friction that holds it sticks at once; when a
    face corner's normal force would turn negative (tipping) the body pivots on the loaded
    corner (event "pivot", below);
  - an ellipse rests (residual tangential speed below ``zeno_speed`` is absorbed), or
    slides if frictionless; a rough sliding ellipse rolls and rocks: it is held on the
    plane and its motion integrated (as below, event "pivot").

  A body in persistent contact hit by an impulse (a wall, another disk) keeps the contact
  when its normal (and, not for a disk, rotational) kinetic energy stays below
  ``m zeno_speed^2 / 2`` (that motion is removed), else it is released ("release") and an
  approach into the plane is then resolved as an impact at the same instant.
  Impacts accumulating at a *single point* (normal speed after impact below
  ``sqrt(2 |g''| rest_length)`` while the gap is accelerating into the plane): at a vertex
  of a box or a rod, or on the boundary of an ellipse, the body is then held there
  ("pivot": mode 2 sticking, i.e. rolling without slip for an ellipse, mode 1 sliding)
  and its motion, which has no closed form, is integrated with Coulomb friction (stick,
  slide, lift-off, landing of another vertex or of the ellipse on another plane;
  ``kernels/pivot2d.py``); a rough ellipse on a level floor rocks for ever (rolling is
  conservative). At a point of a disk (against another disk) the run stops with
  ``SimulationError``.
  A body whose motion is below the accumulation threshold after the impacts of an instant
  and that touches two different planes on which it can rest in static equilibrium with
  Coulomb friction (``kernels/wedge2d.py``: exact two-contact test) rests there (event
  "rest", mode 5): a box wedged in a groove, a disk in a corner.
* **Contact modes** (DESIGN §6a; the README's table says which are built in 2D and 3D):

  ======================  ================================  =================================
  mode                    what is integrated                events that leave it
  ======================  ================================  =================================
  flight                  exact quadratic motion            impact
  impact                  the pair law / the policy         (instantaneous)
  accumulation (Zeno)     jump to t_inf, held on the plane  -> rest, slide or roll
  rest / slide on a face  nothing / constant deceleration   stop, tipping -> pivot
  rest on two planes      nothing (static equilibrium)      an impulse (release)
  disk roll / slide       exact closed form                 slip stops (roll), impact
  pivot: vertex, ellipse  integrated (pivot2d)              lift-off, stick <-> slip, landing
  ======================  ================================  =================================

  Perforation is decided by the law (Brach's e < 0), never by the sign of a round-off
  post-impact normal velocity (``kernels/decisions.py``).
* **Never silently wrong**: non-finite state, a law without solution, a missed event (a gap
  below ``-gap_tol``), a time-of-impact search that does not converge, ``stall_events``
  consecutive passes of the loop at one instant, or ``idle_passes`` passes of the loop in a row that
  record no event raise ``SimulationError`` / ``NoSolutionError``; the exception carries the
  partial ``Result`` as ``exc.result``, whose ``status`` names the failure ("missed",
  "stall", "idle", "no_solution", ...). Reaching ``max_events``
  before ``t_end`` stops early (after the instant in progress), warns, and returns a
  ``Result`` with ``status == "max_events"``.

The event loop is compiled (``rbimpact.kernels.stepper2d``, Numba, cached on disk, with a
guard that flushes that cache when a law kernel it has compiled in changes); event and
trajectory buffers are preallocated and grown by doubling between compiled chunks (or, with
``run(record="none")`` or a list of bodies, drained into fixed-size buffers: see
``run`` and ``rbimpact._recording``). A scene
runs only what it uses: no pair search without disk pairs, no rotation bound for
non-rotating bodies (exact quadratics), the law kernel's own mu = 0 fast path.
"""
import math
import warnings

import numpy as np

from ._setup import (Arena, call_loop, check_law, check_loop, check_painleve, check_run_args,
                     check_scene, check_tolerances, compiled_loop, pack_laws,
                     idle_message, persistent_pair_message, run_status)
from .kernels import evbuf
from .kernels.codes import PAINLEVE_OPTIONS
from .errors import NoSolutionError, SimulationError
from ._recording import Recorder
from .result import Result, _build_events
from .scene import Plane, Scene2D

__all__ = ["Simulation", "TOLERANCES"]

#: keyword -> (default, unit, meaning)
TOLERANCES = {
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
    "simul_gap": (1e-12, "m", "a corner of a body already in an impact at that instant whose "
                  "gap is below this and closing joins the same cluster"),
    "simul_tol": (1e-14, "-", "joint solve: stop when a sweep changes no contact velocity "
                  "by more than this times the largest pre-impact contact speed (sweeps "
                  "that cycle are accepted after simul_max_iter below 1e-9 of it, "
                  "stepper2d.SIMUL_ACCEPT_RTOL)"),
    "simul_max_iter": (100_000, "-", "joint solve: maximum number of sweeps"),
    "seq_vtol": (1e-12, "m/s", "sequential policy: a contact approaches when v_N < -seq_vtol"),
    "seq_max_steps": (1000, "-", "sequential policy: maximum resolutions at one instant"),
    "stall_events": (10_000, "-", "maximum consecutive passes of the event loop at one instant"),
    "idle_passes": (10_000_000, "-", "maximum consecutive passes of the event loop that "
                    "record no event (integrated motion, bounded searches): beyond it the "
                    "run stops with status 'idle' instead of running on without end; "
                    "raise it for long integrated motions that meet no event"),
    "max_accumulation_impacts": (1_000_000, "-", "a disk whose bounces on a plane would "
                                 "accumulate (or reach t_end) only after more impacts than "
                                 "this (e close to 1) stops the run with an error naming e "
                                 "and the count, instead of stepping through them"),
}
POLICIES = ("simultaneous", "sequential")
#: first capacity (rows beyond the loop's safety margin) of the event and segment buffers;
#: small, so a short run allocates little (the Result keeps views of these buffers) ...
INITIAL_EVENT_ROWS = 256
#: ... and the size they jump to when first full, so long runs grow only a few times
GROWN_EVENT_ROWS = 1 << 14


def _grow(a, used):
    """A buffer at least twice as long (and at least ``GROWN_EVENT_ROWS`` rows) holding the
    first ``used`` rows of ``a``."""
    out = np.empty((max(2 * len(a), GROWN_EVENT_ROWS),) + a.shape[1:], dtype=a.dtype)
    out[:used] = a[:used]
    return out


def _grow_all(arrays, used):
    """``_grow`` of each of ``arrays`` (buffers sharing their first dimension)."""
    return tuple(_grow(a, used) for a in arrays)


def _shape_name(body):
    return type(body.shape).__name__


def _min_gap_plane(body, plane):
    """Smallest gap (m) of a body's contact features to a plane, at the initial state."""
    kind, rad, ea, eb, verts = body.shape._kernel()
    n = np.array(plane.normal)
    d = plane.offset
    x = np.array(body.position)
    c, s = math.cos(body.angle), math.sin(body.angle)
    if kind == 2:  # ellipse
        nb = np.array([c * n[0] + s * n[1], -s * n[0] + c * n[1]])
        h = math.sqrt(ea * ea * nb[0] ** 2 + eb * eb * nb[1] ** 2)
        return float(n @ x - h - d)
    R = np.array([[c, -s], [s, c]])
    w = verts @ R.T
    return float(np.min(w @ n) + n @ x - rad - d)


class Simulation:
    """An event-driven simulation of ``scene`` with collision law ``law``.

    ``pair_laws``: optional mapping to other laws: key ``(i, j)`` (two body indices), ``(i,
    plane)`` or ``(plane, i)`` (a body and a ``Plane`` returned by ``add_plane``), or a
    ``Plane`` alone (every body against it). Most specific key wins.

    Keywords: ``policy`` ("simultaneous" or "sequential", see the module docstring),
    ``ignore_unsupported_pairs`` (bool: only disks collide with each other, the other
    bodies pass through each other, as before issue 16; default False: every pair of
    shapes collides), ``painleve`` ("impact", default: a body whose impacts leave a
    contact sliding at v_N = 0 where sliding has no consistent force -- the Painleve
    paradox, ``W_NN - mu s W_NT <= 0`` -- takes an impact without collision, event
    "painleve"; "error": the run stops with status "painleve"; a
    Painleve state met otherwise, e.g. during an integrated slide, always stops the run),
    ``loop`` (the compiled event loop, ``_setup.LOOP_KINDS``: "scene", compiled for this
    scene's law and the contact modes it can reach, the fewest compiles for one scene;
    "general", every law and mode, one compile for every scene of a process or of the warm
    disk cache; both give the same results bit for bit; None, the default: the
    ``RBIMPACT_LOOP`` environment variable, else "scene"; read at the first ``run``),
    and the tolerances of ``TOLERANCES`` (name: default, unit):
    rest_length 1e-10 m; zeno_speed None (m/s); gap_tol 1e-9 m; toi_rtol 1e-14;
    toi_atol 1e-15 s; toi_max_iter 100000; simul_time 1e-11 s; simul_gap 1e-12 m;
    simul_tol 1e-14 (relative);
    simul_max_iter 100000; seq_vtol 1e-12 m/s; seq_max_steps 1000; stall_events 10000;
    idle_passes 10000000; max_accumulation_impacts 1000000.
    """

    def __new__(cls, scene=None, *args, **kwargs):
        """A ``Scene3D`` gets a ``Simulation3D`` (same arguments, see its docstring)."""
        if cls is Simulation and type(scene).__name__ == "Scene3D":
            from .simulation3d import Simulation3D
            return Simulation3D(scene, *args, **kwargs)
        return super().__new__(cls)

    def __init__(self, scene, law, pair_laws=None, *, policy="simultaneous",
                 ignore_unsupported_pairs=False, painleve="impact", loop=None,
                 **tolerances):
        if not isinstance(scene, Scene2D):
            raise ValueError(f"Simulation: scene must be a Scene2D or a Scene3D, got {scene!r}")
        if not scene.bodies:
            raise ValueError("Simulation: the scene has no body")
        policy = check_scene("Simulation", scene, policy, POLICIES)
        tol = check_tolerances("Simulation", TOLERANCES, tolerances)
        self.scene = scene
        self.law = check_law("Simulation", law, "law")
        self.policy = policy
        self.tolerances = tol
        self.ignore_unsupported_pairs = bool(ignore_unsupported_pairs)
        self.painleve = check_painleve("Simulation", painleve)
        self.loop = check_loop("Simulation", loop)
        self._pack(pair_laws or {})
        self._check_initial()

    # ------------------------------------------------------------ building

    def _pack(self, pair_laws):
        scene = self.scene
        bodies, planes = scene.bodies, scene.planes
        nb, npl = len(bodies), len(planes)
        verts, bint, bflt = [], np.zeros((nb, 3), np.int64), np.zeros((nb, 5))
        row = 0
        for i, body in enumerate(bodies):
            kind, rad, ea, eb, v = body.shape._kernel()
            bint[i] = (kind, row, len(v))
            bflt[i] = (body.mass, body.moment, rad, ea, eb)
            verts.append(v)
            row += len(v)
        self._bint, self._bflt = bint, bflt
        self._verts = np.ascontiguousarray(np.concatenate(verts), dtype=float)
        self._planes = np.array([(p.normal[0], p.normal[1], p.offset) for p in planes],
                                dtype=float).reshape(npl, 3)
        # every pair of bodies can collide (issue 16: pair2d, pair2d_toi for each shape
        # pair); ignore_unsupported_pairs=True keeps the disk pairs only, as before issue 16
        collide = (bint[:, 0] == 0) if self.ignore_unsupported_pairs else np.ones(nb, bool)
        table = pack_laws("Simulation", scene, self.law, pair_laws, Plane, collide, dim="2D",
                          round_name="disks",
                          ignore_unsupported_pairs=self.ignore_unsupported_pairs)
        self._pairs = table.pairs
        self._bp_law = table.bp_law
        self._laws = table.laws
        self._law_ids = table.law_ids
        self._law_par = table.law_par
        self._grav = np.array(scene.gravity, dtype=float)
        # what every run's Result shares (read-only)
        self._masses = np.array([b.mass for b in bodies], dtype=float)
        self._moments = np.array([b.moment for b in bodies], dtype=float)
        self._masses.flags.writeable = False
        self._moments.flags.writeable = False
        self._law_name = getattr(self.law, "name", repr(self.law))
        self._result_tol = {**self.tolerances, "policy": self.policy,
                            "painleve": self.painleve}
        from .kernels import stepper2d
        self._arena = self._make_arena(stepper2d)     # the run's arrays, reset per run

    def _check_initial(self):
        gap_tol = self.tolerances["gap_tol"]
        for body in self.scene.bodies:
            for plane in self.scene.planes:
                g = _min_gap_plane(body, plane)
                if g < -gap_tol:
                    raise ValueError(
                        f"Simulation: body {body.index} ({_shape_name(body)}) starts inside "
                        f"plane {plane.index} (point {plane.point}, normal {plane.normal}): "
                        f"its lowest point is {-g:.6g} m below the plane's surface")
        for i, j, _ in self._pairs:
            g = self._pair_gap(int(i), int(j))
            if g < -gap_tol:
                bi, bj = self.scene.bodies[i], self.scene.bodies[j]
                raise ValueError(f"Simulation: bodies {i} ({_shape_name(bi)}) and {j} "
                                 f"({_shape_name(bj)}) overlap at the start by {-g:.6g} m "
                                 f"(more than gap_tol = {gap_tol:g} m)")

    def _pair_gap(self, i, j):
        """Signed gap (m) of bodies i and j at their initial state: the distance of their
        boundaries, minus the penetration depth when they overlap (``kernels.pair2d``)."""
        bi, bj = self.scene.bodies[i], self.scene.bodies[j]
        if self._bint[i, 0] == 0 and self._bint[j, 0] == 0:       # two disks
            dist = math.hypot(bi.position[0] - bj.position[0], bi.position[1] - bj.position[1])
            return dist - self._bflt[i, 2] - self._bflt[j, 2]
        from .kernels.pair2d import frame_rel
        bint, bflt, V = self._bint, self._bflt, self._verts
        out = frame_rel(int(bint[i, 0]), bflt[i, 2], bflt[i, 3], bflt[i, 4], V,
                        int(bint[i, 1]), int(bint[i, 2]), float(bi.angle), int(bint[j, 0]),
                        bflt[j, 2], bflt[j, 3], bflt[j, 4], V, int(bint[j, 1]),
                        int(bint[j, 2]), bj.position[0] - bi.position[0],
                        bj.position[1] - bi.position[1], float(bj.angle))
        return float(out[0])

    # ------------------------------------------------------------ running

    def _make_arena(self, k):
        """The arrays of a run (see ``rbimpact.kernels.stepper2d``): tolerances, dynamic
        state and workspaces, allocated once and reset from a template before each run."""
        tol = self.tolerances
        nb, npl, npr = len(self.scene.bodies), len(self.scene.planes), len(self._pairs)
        tolf = np.zeros(k.N_TF)
        tolf[k.TF_REST_LENGTH] = tol["rest_length"]
        tolf[k.TF_ZENO_SPEED] = -1.0 if tol["zeno_speed"] is None else tol["zeno_speed"]
        tolf[k.TF_GAP_TOL] = tol["gap_tol"]
        tolf[k.TF_TOI_RTOL] = tol["toi_rtol"]
        tolf[k.TF_TOI_ATOL] = tol["toi_atol"]
        tolf[k.TF_SIMUL_TIME] = tol["simul_time"]
        tolf[k.TF_SIMUL_TOL] = tol["simul_tol"]
        tolf[k.TF_SIMUL_GAP] = tol["simul_gap"]
        tolf[k.TF_SEQ_VTOL] = tol["seq_vtol"]
        tolf[k.TF_PAINLEVE] = PAINLEVE_OPTIONS.index(self.painleve)
        toli = np.zeros(k.N_TI, np.int64)
        toli[k.TI_TOI_MAXIT] = tol["toi_max_iter"]
        toli[k.TI_SIMUL_MAXIT] = tol["simul_max_iter"]
        toli[k.TI_SEQ_MAXSTEPS] = tol["seq_max_steps"]
        toli[k.TI_STALL] = tol["stall_events"]
        toli[k.TI_IDLE] = tol["idle_passes"]
        toli[k.TI_ACC_MAX] = tol["max_accumulation_impacts"]
        toli[k.TI_POLICY] = POLICIES.index(self.policy)
        st = np.zeros((nb, 9))
        for i, b in enumerate(self.scene.bodies):
            st[i, :6] = (*b.position, b.angle, *b.velocity, b.angular_velocity)
        pm = np.zeros((nb, k.N_PM), np.int64)
        pm[:, 1:] = -1
        M = k.MAXC
        F, I = float, int
        cb_shape, cc_shape, cw_size, cid_size = k.cluster_sizes(nb)
        cid0 = np.zeros(cid_size, np.int64)
        cid0[k.CL_PEND] = -1
        cid0[k.CL_LEAD] = -1
        return Arena([
            ("tolf", (k.N_TF,), F, tolf), ("toli", (k.N_TI,), I, toli),
            # dynamic state
            ("st", (nb, 9), F, st), ("tref", (nb,), F, 0.0), ("pm", (nb, k.N_PM), I, pm),
            ("tz", (nb,), F, np.inf), ("zp", (nb,), I, -1), ("ttr", (nb,), F, np.inf),
            ("bp_t", (nb, npl), F, np.inf), ("bp_off", (nb, npl), I, 0),
            ("pr_t", (npr,), F, np.inf), ("pr_off", (npr,), I, 0), ("glob", (2,), F, 0.0),
            ("cnt", (evbuf.N_CNT,), I, 0),
            # workspaces
            ("c_i", (M, k.N_CI), I, 0), ("c_f", (M, k.N_CF), F, 0.0),
            ("Wb", (2 * M, 2 * M), F, 0.0), ("Pb", (2 * M,), F, 0.0),
            ("vb", (2 * M,), F, 0.0), ("tb", (2 * M,), F, 0.0), ("comp", (2 * M,), I, 0),
            ("bmark", (nb,), I, 0), ("v2", (2,), F, 0.0), ("W2", (2, 2), F, 0.0),
            ("P2", (2,), F, 0.0), ("tmp", (2, 9), F, 0.0), ("err", (8,), F, 0.0),
            # persistent body-body contact (stepper2d.cluster_sizes)
            ("cbod", cb_shape, F, 0.0), ("ccon", cc_shape, F, 0.0), ("cw", (cw_size,), F, 0.0),
            ("cid", (cid_size,), I, cid0)])

    def run(self, t_end, max_events=1_000_000, record="all", observer=None, snapshot_dt=None):
        """Run from t = 0 to ``t_end`` (s) and return a ``Result``.

        ``max_events``: stop after the instant at which the number of events of the run
        reaches it (status "max_events", with a ``RuntimeWarning``), whatever ``record``
        keeps.

        ``record``: what the result keeps.

        * ``"all"`` (default): every event and the whole trajectory of every body; memory
          grows with the number of events (about 0.2 KB per event with its segments).
        * ``"none"``: the event counts (``n_events``, ``event_counts``, ``n_impacts``), the
          status and the final state (``sample`` at and after ``kept_from(i)``, the start of
          each body's last trajectory segment; always at ``t_end``), and the snapshots. The
          event and segment buffers keep a fixed size (``_recording.DRAIN_ROWS`` rows
          beyond the loop's margins): memory does not grow with the number of events.
          ``events``, the exports, ``plot`` and earlier samples raise ``NotRecordedError``.
        * a 1-D array of body indices: the events involving one of those bodies (``a`` or
          ``b``; a plane is never recorded on its own) and those bodies' whole
          trajectories (``sample(times, bodies=...)``); the other bodies as with "none".
          Memory grows with the recorded bodies' events only.

        ``observer``: None or a callable, called with each chunk of events as the buffers
        are drained (every ``DRAIN_ROWS`` events or so with ``record`` "none" or a list, at
        each growth of the buffers with "all"), then once at the end with the last chunk
        (possibly empty): a read-only structured array with the columns of
        ``Result.events``, in time order; every event of the run (not only the recorded
        ones) is passed exactly once. An exception raised by the observer propagates out
        of ``run`` and stops the run (no result is returned).

        ``snapshot_dt``: None or a time step (s, positive, finite): the states of every body
        at ``0, dt, 2 dt, ...`` up to the end of the run, evaluated from the exact
        trajectory as the run goes (any ``record``), are ``result.snapshots == (times,
        states)``, ``states`` a dict like ``sample``'s (arrays of shape ``(len(times),
        n_bodies)``). They take ``48 n_bodies`` bytes per snapshot.

        The fixed cost of a call is small (tens of microseconds): the scene is packed once
        when the ``Simulation`` is built and the run's arrays once on its first run; event
        buffers start small and double as needed (``record="all"``).
        """
        from .kernels import stepper2d as k
        t_end, max_events = check_run_args(t_end, max_events)
        rec = Recorder.for_run("Simulation", k, _build_events, self._sampler,
                               len(self.scene.bodies), t_end, max_events, record, observer,
                               snapshot_dt)
        # one set of run arrays per Simulation, taken for the duration of the run (a
        # concurrent run of the same Simulation from another thread allocates its own)
        arena = self.__dict__.pop("_arena", None) or self._make_arena(k)
        try:
            return self._run(k, arena, t_end, max_events, rec)
        finally:
            self._arena = arena

    def _run(self, k, arena, t_end, max_events, rec):
        (tolf, toli, st, tref, pm, tz, zp, ttr, bp_t, bp_off, pr_t, pr_off, glob, cnt,
         c_i, c_f, Wb, Pb, vb, tb, comp, bmark, v2, W2, P2, tmp, err, *clu) = arena.reset()
        tolf[k.TF_T_END] = t_end
        toli[k.TI_MAX_EVENTS] = max_events
        nb = st.shape[0]
        me = k.event_margin(toli, nb)
        ms = k.segment_margin(nb)
        cap_e, cap_s = rec.capacities(me, ms, INITIAL_EVENT_ROWS)
        bufs = (np.empty(cap_e), np.empty((cap_e, 5), np.int64), np.empty((cap_e, 11)),
                np.empty(cap_s), np.empty(cap_s, np.int64), np.empty((cap_s, 9)))
        run_loop, switches = compiled_loop(self, k)
        scene_arrays = (self._bint, self._bflt, self._verts, self._planes, self._grav,
                        self._law_ids, self._law_par, self._bp_law, self._pairs, tolf, toli)
        args = (*scene_arrays, st, tref, pm, tz, zp, ttr, bp_t, bp_off, pr_t, pr_off, glob,
                cnt, *bufs, c_i, c_f, Wb, Pb, vb, tb, comp, bmark, v2, W2, P2, tmp, err,
                *clu, *switches)
        rc = call_loop(run_loop, args)
        while rc == k.RC_BUFFER_FULL:
            bufs = rec.on_full(bufs, cnt, glob, toli, me, ms, _grow_all)
            rc = run_loop(*scene_arrays, st, tref, pm, tz, zp, ttr, bp_t, bp_off, pr_t,
                          pr_off, glob, cnt, *bufs, c_i, c_f, Wb, Pb, vb, tb, comp, bmark,
                          v2, W2, P2, tmp, err, *clu, *switches)
        status = run_status(k, rc)
        *kept, recording = rec.finish(bufs, cnt, glob)
        result = self._result(*kept, glob, status, t_end, recording)
        if rc < 0:
            raise self._error(rc, err, result)
        if status == "max_events":
            warnings.warn(f"Simulation.run: max_events={max_events} reached at t = "
                          f"{result.t_end:.12g} s, before t_end = {t_end:g} s; the "
                          f"result stops there (status 'max_events')", RuntimeWarning,
                          stacklevel=3)
        return result

    def _result(self, ev_t, ev_i, ev_f, seg_t, seg_b, seg_s, glob, status, t_req,
                recording=None):
        from .kernels.stepper2d import EVENT_KINDS
        return Result(ev_t, ev_i, ev_f, seg_t, seg_b, seg_s,
                      status=status, policy=self.policy, t_start=0.0, t_end=float(glob[0]),
                      t_requested=t_req, masses=self._masses, moments=self._moments,
                      gravity=self.scene.gravity, law=self._law_name,
                      tolerances=self._result_tol, kinds=EVENT_KINDS, recording=recording)

    def _sampler(self, seg_t, seg_b, seg_s, times):
        """States at ``times`` (s) from logged segment rows (``Result.sample``)."""
        ev = np.empty(0)
        r = self._result(ev, np.empty((0, 5), np.int64), np.empty((0, 11)), seg_t, seg_b,
                         seg_s, (float(times.max()),), "done", float(times.max()))
        return r.sample(times)

    def _where(self, b):
        b = int(b)
        if b < 0:
            p = self.scene.planes[-1 - b]
            return f"plane {p.index} (point {p.point}, normal {p.normal})"
        return f"body {b} ({_shape_name(self.scene.bodies[b])})"

    def _error(self, rc, err, result):
        from .kernels import stepper2d as k
        t, a, b = err[0], int(err[1]), int(err[2])
        at = f"at t = {t:.12g} s"
        pt = f"contact point ({err[3]:.9g}, {err[4]:.9g})"
        body = self._where(a) if a >= 0 else "the scene"
        if rc == k.ERR_NO_SOLUTION:
            mode = int(err[5])
            if b < 0:
                law = self._laws[int(self._bp_law[a, -1 - b])]
            else:
                rows = [q for q in self._pairs if {int(q[0]), int(q[1])} == {a, b}]
                law = self._laws[int(rows[0][2])] if rows else self.law
            name = getattr(law, "name", repr(law))
            exc = NoSolutionError(
                f"impact of {body} on {self._where(b)} {at}, {pt}, has no solution in law "
                f"{name} (mode {mode}); pre-impact v = ({err[6]:.9g}, {err[7]:.9g}) m/s",
                mode_code=mode)
        elif rc == k.ERR_NONFINITE:
            exc = SimulationError(f"non-finite state of {body} {at} (position ({err[3]:g}, "
                                  f"{err[4]:g}))")
        elif rc == k.ERR_MISSED:
            exc = SimulationError(f"missed event: {body} is inside {self._where(b)} by more "
                                  f"than gap_tol = {self.tolerances['gap_tol']:g} m {at} "
                                  f"(body position ({err[3]:.9g}, {err[4]:.9g}))")
        elif rc == k.ERR_TOI:
            exc = SimulationError(f"the time-of-impact search of {body} against "
                                  f"{self._where(b)} did not converge in toi_max_iter = "
                                  f"{self.tolerances['toi_max_iter']} steps, from {at}")
        elif rc == k.ERR_CHATTER:
            exc = SimulationError(
                f"impacts accumulate at a single contact point of {body} on {self._where(b)} "
                f"{at}, {pt}: normal speed after the impact {err[5]:.3g} m/s while the gap "
                f"accelerates into the contact at {err[6]:.3g} m/s^2. The body would roll on "
                f"that point in persistent contact: integrated at a vertex of a box or a rod "
                f"and on an ellipse (pivot), not supported for a disk")
        elif rc == k.ERR_PERSISTENT_PAIR:
            named = err[5] in (k.PP_HELD, k.PP_SHAPES, k.PP_TWO)
            third = self._where(int(err[6])) if named else ""
            exc = SimulationError(persistent_pair_message(
                k, err[5], body, self._where(b), third, at, pt, err[6], err[7],
                self.tolerances["rest_length"]))
        elif rc == k.ERR_PAINLEVE:
            exc = SimulationError(
                f"Painleve: {body} held on a vertex (or its boundary) on {self._where(b)} {at} "
                f"(centre of mass "
                f"({err[3]:.9g}, {err[4]:.9g})) has no consistent contact force with friction "
                f"mu = {err[5]:g}: sliding needs W_NN - mu s W_NT > 0")
        elif rc == k.ERR_CONTACT_STEPS:
            exc = SimulationError(
                f"{body} held on a vertex on {self._where(b)}: the pivot integrator reached "
                f"its step limit {at} (centre of mass ({err[3]:.9g}, {err[4]:.9g}))")
        elif rc == k.ERR_TWO_PLANES:
            exc = SimulationError(
                f"{body} is held by {self._where(b)} and plane {int(err[5])} {at} and has "
                f"no consistent motion on both: it cannot rest there (static equilibrium "
                f"with friction), nor slide on both with non-negative normal forces")
        elif rc == k.ERR_FAR_ACCUMULATION:
            exc = SimulationError(
                f"{body} bounces on {self._where(b)} with restitution e = {err[5]:.12g} "
                f"{at}: its bounces accumulate (or reach t_end) only after about "
                f"{err[6]:.3g} more impacts, beyond max_accumulation_impacts = "
                f"{self.tolerances['max_accumulation_impacts']}; end the run earlier, lower "
                f"e, or raise max_accumulation_impacts")
        elif rc == k.ERR_NOT_COMPILED:
            exc = SimulationError(
                f"internal error: {body} reached a contact handler ("
                f"{k.FEATURES[int(err[3])]}) "
                f"that the loop compiled for this scene lacks {at} (a bug of "
                f"stepper2d.scene_features; please report it)")
        elif rc == k.ERR_SEQ:
            exc = SimulationError(f"sequential policy: contacts of {body} still approach after "
                                  f"seq_max_steps = {int(err[6])} resolutions {at}")
        elif rc == k.ERR_PGS and err[7] == 1.0:
            exc = SimulationError(
                f"Painleve-type jam: simultaneous policy: the joint Newton-restitution/Coulomb "
                f"impact of {int(err[5])} contacts of {body} {at} has no solution (every "
                f"stick/slip/lift-off combination of the contacts checked: a jam of redundant "
                f"frictional contacts); use policy='sequential'")
        elif rc == k.ERR_PGS:
            exc = SimulationError(f"simultaneous policy: the joint solve of {int(err[5])} "
                                  f"contacts of {body} {at} did not reach simul_tol in "
                                  f"simul_max_iter sweeps (last change {err[6]:.3g} m/s)")
        elif rc == k.ERR_TIPPING:
            exc = SimulationError(f"{body} in persistent contact with {self._where(b)} {at} "
                                  f"would tip over (face normal forces {err[6]:.3g} N, "
                                  f"{err[7]:.3g} N): not supported")
        elif rc == k.ERR_STALL:
            exc = SimulationError(f"the run stalls {at}: more than stall_events = "
                                  f"{self.tolerances['stall_events']} consecutive passes of "
                                  f"the event loop at one instant")
        elif rc == k.ERR_IDLE:
            exc = SimulationError(idle_message(result, at, self.tolerances["idle_passes"]))
        elif rc == k.ERR_TOO_MANY:
            exc = SimulationError(f"more than {k.MAXC} contacts at one instant {at} "
                                  f"({body})")
        elif rc == k.ERR_JOINT_E:
            exc = SimulationError(f"simultaneous policy needs 0 <= e <= 1 for the joint "
                                  f"Newton solve, but the contact of {body} on "
                                  f"{self._where(b)} {at} has e = {err[5]:g}; use "
                                  f"policy='sequential'")
        else:  # pragma: no cover
            exc = SimulationError(f"stepper error code {rc} {at}")
        exc.result = result
        return exc
