"""Many bodies: granular gases of disks (2D) or spheres (3D) in a box, event-driven.

``random_gas`` builds a state, ``run_gas`` runs it with any collision law (every impact,
body-body or body-wall, is resolved by the law's scalar kernel in contact space, DESIGN
§3) and returns a ``GasResult``. The engine is ``rbimpact.kernels.gas_core`` (cell list,
one event per body in a calendar queue, lazy local times; see its docstring for the
model and ``rbimpact.kernels.scheduler`` for the queue).

Units: SI throughout (m, kg, s; temperature in J, i.e. k_B T as an energy, so that a body
of mass ``m`` has ``<m v_a^2> = T`` per translational component).

Example::

    from rbimpact.manybody import random_gas, run_gas
    s = random_gas(1024, dim=2, packing=0.15, law="kane_levinson", e=1.0)
    res = run_gas(s, max_impacts=10**6)
    res.n_collisions, res.n_wall, res.t
"""
import math
from dataclasses import dataclass, field, replace

import numpy as np

from ._validate import _show, integer, real
from .errors import SimulationError

DIMS = (2, 3)
RECORD_KINDS = ("none", "all")
COLLAPSE_KINDS = ("tc", "none")

# Default TC contact duration, relative to the time a body at the initial rms speed takes
# to cross its own diameter: tc = TC_REL * 2 r / v_rms. Luding & McNamara (1998) take tc
# a few orders of magnitude below the mean free time; 1e-5 of the diameter crossing time
# is far below any gas time scale at packings <= 0.5 and far above round-off.
TC_REL = 1e-5
# Packing fraction limits of random_gas (random sequential insertion jams at about 0.547
# in 2D and 0.38 in 3D; the insertion is slow near the limit, so it is refused before).
MAX_PACKING = {2: 0.5, 3: 0.35}
# Cell side of the cell list in diameters (>= 1: every impact partner of a body is then in
# the 3^dim block of cells around it). Larger cells mean fewer cell crossings and more
# bodies per pair scan; tuned at packing 0.15 (bench manybody).
CELL_DIAMETERS = 1.0     # measured at N = 4096: 1.0 and 1.5 equal, 2.0 8 % slower
BUCKETS_PER_BODY = 1.0    # calendar queue: buckets >= this many per body (power of 2)
QUEUE_INDEX_DTYPE = "int32"   # queue links (bodies < 2^31)
REC_CHUNK = 1 << 16       # records per buffer chunk when recording
SNAP_CHUNK = 64           # snapshots per buffer chunk when t_end is not given (or when an
                          # observer takes them)

# Sleep (run_gas(sleep=...)): every threshold is scaled to the scene's own r and g.
# A body sleeps after SLEEP_IMPACTS consecutive impacts that each left it slower than the
# sleep speed SLEEP_SPEED_REL sqrt(g r) (|v| and r |w|), the last one on the floor or on a
# sleeper. At that speed a free bounce rises sleep_speed^2 / (2 g) = 0.005 r: a body that
# slow is resting to the eye; and the bounces of a body settling with e <= 0.9 take it
# from 1 to 0.001 of that speed in ~65 impacts, so 10 slow impacts in a row happen well
# before the TC model makes its impacts elastic (tc is far below sqrt(r / g)).
SLEEP_SPEED_REL = 0.1
SLEEP_IMPACTS = 10
# A woken body wakes the sleepers within wake_gap of contact: by default
# max(WAKE_GAP_REL r, 2 sleep_speed^2 / g), 4 times the height a body can bounce at the
# sleep speed (the largest gap a sleeper may keep below a body that fell asleep on it);
# both 0.02 r at the default sleep speed.
WAKE_GAP_REL = 0.02

_STATUS_TEXT = {1: "t_end", 2: "max_impacts", 3: "no event left"}


@dataclass
class GasState:
    """A gas of ``n`` equal round bodies in the box ``[0, box_0] x ... `` (m).

    ``x`` (n, dim) positions (m), ``v`` (n, dim) velocities (m/s), ``w`` angular
    velocities (rad/s): (n,) in 2D (about z), (n, 3) in 3D; ``radius`` (m), ``mass`` (kg),
    ``inertia`` (kg m^2, central; ``inf`` for smooth bodies, which never spin), ``box``
    (dim,) (m), ``gravity`` (m/s^2, along minus the last axis), ``law`` (a name of
    ``rbimpact.laws.LAWS``) and ``law_params`` (its parameters), ``t`` the time (s);
    ``asleep`` None or (n,) bool: the bodies that sleep (``run_gas(sleep=True)``: static
    until touched; they must be at rest, v = w = 0; ignored when sleep is off)."""

    x: np.ndarray
    v: np.ndarray
    w: np.ndarray
    radius: float
    mass: float
    inertia: float
    box: np.ndarray
    law: str = "kane_levinson"
    law_params: dict = field(default_factory=lambda: {"e": 1.0})
    gravity: float = 0.0
    rough: bool = False
    t: float = 0.0
    asleep: object = None

    @property
    def n(self):
        return self.x.shape[0]

    @property
    def dim(self):
        return self.x.shape[1]

    def kinetic_energy(self):
        """Translational plus rotational kinetic energy (J)."""
        e = 0.5 * self.mass * float(np.sum(self.v * self.v))
        if math.isfinite(self.inertia):
            e += 0.5 * self.inertia * float(np.sum(self.w * self.w))
        return e

    def potential_energy(self):
        """Gravitational energy (J) above the floor (the face at 0 of the last axis)."""
        return self.mass * self.gravity * float(np.sum(self.x[:, -1]))


@dataclass
class GasResult:
    """Outcome of ``run_gas``. ``t`` final time (s); ``x``, ``v``, ``w`` the state there
    (all bodies advanced to ``t``); ``n_collisions`` body-body impacts, ``n_wall`` wall
    impacts, ``n_crossings`` cell crossings, ``n_stale`` stale predictions popped,
    ``n_tc`` impacts made elastic by the TC model; ``snap_t`` (ns,) s, ``snap_v``
    (ns, n, dim) m/s, ``snap_w`` (ns, n) or (ns, n, 3) rad/s; ``events`` None or a dict of
    arrays: ``t`` (s), ``a``, ``b`` (bodies; ``b = -1 - wall`` for a wall,
    ``wall = 2 axis + side``, side 1 the face at ``box[axis]``), ``mode`` (law mode code),
    ``n`` (m, dim) normal from B into A, ``v`` (m, dim) contact-space pre-impact velocity
    (normal first, m/s), ``P`` (m, dim) contact-space impulse on A (N s), ``dE`` (J);
    ``stop`` why the run ended, ``collapse`` the collapse option and ``tc`` (s),
    ``state`` the final ``GasState`` (to continue the run; its ``asleep`` holds the
    sleepers). Sleep: ``sleep`` (the option), ``sleep_speed`` (m/s), ``sleep_impacts``,
    ``wake_gap`` (m) as used (0 when off), ``n_sleeps`` bodies that fell asleep,
    ``n_wakes`` bodies woken (by an impact or touching a woken body), ``n_absorbed``
    impacts on a sleeper that stayed asleep (held fixed by the bed), ``energy_slept`` (J)
    kinetic energy of the bodies as they fell asleep (also in the events' ``dE``),
    ``asleep`` (n,) bool at the end. With an observer and ``keep=False``, ``events`` is
    None and the snapshot arrays are empty (the observer had them)."""

    t: float
    x: np.ndarray
    v: np.ndarray
    w: np.ndarray
    n_collisions: int
    n_wall: int
    n_crossings: int
    n_stale: int
    n_tc: int
    snap_t: np.ndarray
    snap_v: np.ndarray
    snap_w: np.ndarray
    events: object
    stop: str
    collapse: str
    tc: float
    state: GasState
    sleep: bool = False
    sleep_speed: float = 0.0
    sleep_impacts: int = 0
    wake_gap: float = 0.0
    n_sleeps: int = 0
    n_wakes: int = 0
    n_absorbed: int = 0
    energy_slept: float = 0.0
    asleep: np.ndarray = None

    @property
    def n_impacts(self):
        return self.n_collisions + self.n_wall

    @property
    def n_asleep(self):
        """Bodies asleep at the end."""
        return 0 if self.asleep is None else int(np.count_nonzero(self.asleep))


def box_for(n, dim, packing, radius):
    """Side (m) of the square/cube holding ``n`` bodies of radius ``radius`` (m) at the
    packing (area/volume) fraction ``packing``."""
    if dim == 2:
        return math.sqrt(n * math.pi * radius ** 2 / packing)
    return (n * 4.0 / 3.0 * math.pi * radius ** 3 / packing) ** (1.0 / 3.0)


def random_gas(n, dim=2, packing=0.15, radius=0.5, mass=1.0, law="kane_levinson", seed=0,
               temperature=1.0, gravity=0.0, rough=False, **law_params):
    """A random gas: ``n`` bodies (disks if ``dim`` = 2, spheres if 3) of radius
    ``radius`` (m) and mass ``mass`` (kg) at non-overlapping uniformly random positions
    (random sequential insertion) in a square/cubic box sized for the packing fraction
    ``packing``; Maxwellian velocities with zero total momentum, rescaled so that the
    kinetic energy is exactly ``dim * temperature / 2`` per body (``temperature`` in J);
    ``rough``: spinning bodies (solid disk ``I = m r^2 / 2``, solid sphere
    ``I = 2 m r^2 / 5``) with Maxwellian spins of the same temperature per rotational
    degree of freedom; else smooth (``I = inf``, no spin). ``gravity`` (m/s^2, >= 0)
    acts along minus the last axis. ``law`` and ``law_params`` as ``rbimpact.Law``
    (``e`` defaults to 1); checked here. ``seed``: integer >= 0."""
    from .laws import Law
    dim = _dim(dim)
    n = integer("random_gas: n", n, lo=2)
    packing = real("random_gas: packing", packing, "dimensionless")
    if not 0.0 < packing <= MAX_PACKING[dim]:
        raise ValueError(f"random_gas: packing must be in (0, {MAX_PACKING[dim]}] for "
                         f"dim = {dim}, got {packing!r}")
    radius = _positive("random_gas: radius", radius, "m")
    mass = _positive("random_gas: mass", mass, "kg")
    temperature = _positive("random_gas: temperature", temperature, "J")
    gravity = _gravity("random_gas", gravity)
    seed = integer("random_gas: seed", seed, lo=0)
    rough = _flag("random_gas: rough", rough)
    params = _law_params(law, law_params, "random_gas")
    Law(law, **params)                       # validates the law and its parameters
    L = box_for(n, dim, packing, radius)
    rng = np.random.default_rng(seed)
    x = np.empty((n, dim))
    got = 0
    for _ in range(200):
        cand = rng.uniform(radius, L - radius, size=(max(4 * n, 1024), dim))
        got = _place(cand, x, got, radius, L)
        if got == n:
            break
    if got < n:
        raise ValueError(f"random_gas: could not place {n} bodies at packing {packing} "
                         f"(placed {got}); use a lower packing")
    v = rng.normal(0.0, math.sqrt(temperature / mass), size=(n, dim))
    v -= v.mean(axis=0)
    v *= math.sqrt(n * dim * temperature / (mass * float(np.sum(v * v))))
    nw = 1 if dim == 2 else 3
    if rough:
        inertia = (0.5 if dim == 2 else 0.4) * mass * radius ** 2
        w = rng.normal(0.0, math.sqrt(temperature / inertia), size=(n, nw))
        w *= math.sqrt(n * nw * temperature / (inertia * float(np.sum(w * w))))
    else:
        inertia = math.inf
        w = np.zeros((n, nw))
    if dim == 2:
        w = w[:, 0].copy()
    return GasState(x=x, v=v, w=w, radius=radius, mass=mass, inertia=inertia,
                    box=np.full(dim, L), law=law, law_params=params, gravity=gravity,
                    rough=rough)


def _place(cand, x, got, radius, L):
    from .kernels.gas_rsa import rsa_place
    return int(rsa_place(cand, x, got, radius, L))


def run_gas(state, t_end=None, max_impacts=None, record="none", snapshot_dt=None,
            collapse="tc", tc=None, sleep=None, sleep_speed=None, sleep_impacts=None,
            wake_gap=None, observer=None, keep=None):
    """Run the gas ``state`` (a ``GasState``, not modified) until ``t_end`` (s, absolute
    time) or until ``max_impacts`` impacts (body-body plus wall), whichever comes first
    (at least one must be given).

    ``record``: "none" (counts and final state only; memory independent of the number of
    events), "all" (every impact), or an array of body indices (the impacts involving one
    of them). ``snapshot_dt`` (s): also keep all velocities every ``snapshot_dt`` from
    the start time. ``collapse``: "tc" (default: the TC model of Luding & McNamara 1998,
    an impact of a body whose previous impact is less than ``tc`` seconds old is resolved
    by the same law with e = 1, mu = 0) or "none" (the law as given; an inelastic gas may
    then collapse, which ends the run with a SimulationError after
    ``gas_core.STALL_IMPACTS`` impacts at one instant). ``tc`` (s, > 0): default
    ``TC_REL * 2 r / v_rms`` of the initial state.

    Sleep (``sleep``: True, False, or None = True exactly when gravity > 0; it needs
    gravity). Under gravity an inelastic gas settles, and a settled body would keep
    bouncing on the floor, its impacts made elastic by the TC model: about one impact per
    ``tc`` per resting body, so that simulated time nearly stops (200 disks with the
    default tc advanced 0.5 s in 1.6 10^6 impacts; ``rbimpact bench manybody``, bed rows,
    compares a bed with and without sleep). With sleep a body at rest costs no event:

    * it falls asleep after ``sleep_impacts`` (default ``SLEEP_IMPACTS`` = 10, at most
      ``gas_core.STALL_IMPACTS / 10``) consecutive impacts that each left it slower than
      ``sleep_speed`` (m/s; |v| and r |w|; default ``SLEEP_SPEED_REL sqrt(g r)`` =
      0.1 sqrt(g r), the speed of a bounce 0.005 r high), the last one on the floor (the
      face at 0 of the last axis) or on a sleeper. Asleep it is static (v = w = 0, not
      under gravity, no event of its own) and stays in the cell list; its kinetic energy
      at that moment is removed and counted (``energy_slept``, and in that impact's
      ``dE``: the recorded dE still sum to the change of kinetic plus potential energy);
    * an awake body's impact on a sleeper is resolved by the law with the sleeper's true
      mass and v = w = 0. If the sleeper would leave slower than ``sleep_speed`` the bed
      holds it: it stays asleep and the impact is resolved again with the sleeper held
      fixed (as a wall), the awake body rebounding. Else it wakes with that velocity, and
      every sleeper within ``wake_gap`` (m, default ``max(WAKE_GAP_REL r,
      2 sleep_speed^2 / g)`` = 0.02 r, four times the highest bounce at the sleep speed)
      of contact with a woken body wakes too, from rest, recursively: nothing floats
      when its support moves;
    * a rebound on a static support (the floor, a held sleeper) slower than
      ``g_n tc / 2`` (``g_n`` the part of gravity pressing the body on it: the TC
      model's steady bounce) is raised to that, the normal speed taken from the body's
      tangential velocity (its energy unchanged): a body sliding over a sleeper with zero
      normal speed would otherwise meet it again at the same instant for ever;
    * an awake body and a sleeper meet when the awake body's parabola reaches distance
      2r from the static one: the earliest root of a quartic, found exactly
      (``gas_core.sleeper_toi``); awake pairs stay linear, sleepers are never paired.

    A settled bed then advances in time at no cost (once every body sleeps the run jumps
    to ``t_end``, stop "no event left"). What sleep gives up: a body may fall asleep on an
    unstable perch (10 slow impacts take far less time than sliding off a slope; it
    stays until something touches it), a slow push on a sleeper is held by the bed rather
    than passed on through it, and a strong impact on a bed wakes every sleeper connected
    to it (the bed then settles again). ``state.asleep`` starts bodies asleep (continuing
    a run); the final state carries the sleepers. Without sleep the engine is the one
    before sleep existed, bit for bit (its loop is compiled without the sleep code).

    ``observer``: a callable taking ``(kind, chunk)``, handed every non-empty chunk of
    recorded events (``kind`` "events", ``chunk`` a dict as ``GasResult.events``) each
    time the record buffer (``REC_CHUNK`` events) fills and once at the end, and of
    snapshots (``kind`` "snapshots", ``chunk`` a dict ``t``, ``v``, ``w`` as ``snap_t``,
    ``snap_v``, ``snap_w``; ``SNAP_CHUNK`` at most) as they come: memory then stays flat
    however long the run. ``keep``: also keep them in the result (default: False with an
    observer, True without).

    The bodies must not overlap initially (not checked: O(N^2)); ``random_gas``
    places them without overlap.

    Raises ``ValueError`` for bad arguments, ``SimulationError`` if the law has no
    solution for an impact or the run stalls."""
    from .laws import Law
    if not isinstance(state, GasState):
        raise ValueError(f"run_gas: state must be a GasState (from random_gas), got "
                         f"{type(state).__name__}")
    n, dim = _check_state(state)
    params = _law_params(state.law, state.law_params, "run_gas")
    law = Law(state.law, **params)
    t0 = real("run_gas: state.t", state.t, "s")
    if t_end is None and max_impacts is None:
        raise ValueError("run_gas: give t_end (s) or max_impacts (or both)")
    if t_end is not None:
        t_end = real("run_gas: t_end", t_end, "s")
        if not t_end >= t0:
            raise ValueError(f"run_gas: t_end must be >= the state's time {t0}, got {t_end}")
    max_imp = (np.iinfo(np.int64).max if max_impacts is None
               else integer("run_gas: max_impacts", max_impacts, lo=0))
    mask = None
    if isinstance(record, str):
        if record not in RECORD_KINDS:
            raise ValueError(f"run_gas: record must be 'none', 'all' or an array of body "
                             f"indices, got {record!r}")
    else:
        try:
            idx = np.asarray(record)
        except Exception:       # noqa: BLE001
            idx = None
        if idx is None or idx.ndim != 1 or idx.dtype.kind not in "iu":
            raise ValueError(f"run_gas: record must be 'none', 'all' or a 1-D array of body "
                             f"indices (integers), got {_show(record)}")
        if idx.size and (idx.min() < 0 or idx.max() >= n):
            raise ValueError(f"run_gas: record indices must be in [0, {n - 1}]")
        mask = np.zeros(n, np.uint8)
        mask[idx] = 1
    if snapshot_dt is not None:
        snapshot_dt = _positive("run_gas: snapshot_dt", snapshot_dt, "s")
    if not (isinstance(collapse, str) and collapse in COLLAPSE_KINDS):
        raise ValueError(f"run_gas: collapse must be one of {COLLAPSE_KINDS}, got "
                         f"{_show(collapse)}")
    vrms = math.sqrt(float(np.mean(np.sum(state.v ** 2, axis=1)))) if n else 0.0
    if tc is None:
        tc = TC_REL * 2.0 * state.radius / vrms if vrms > 0 else 0.0
    else:
        tc = _positive("run_gas: tc", tc, "s")
    sleep, sleep_speed, sleep_impacts, wake_gap = _sleep_options(
        state, sleep, sleep_speed, sleep_impacts, wake_gap)
    asleep0 = _asleep_flags(state, n) if sleep else np.zeros(n, bool)
    if observer is not None and not callable(observer):
        raise ValueError(f"run_gas: observer must be callable (kind, chunk), got "
                         f"{_show(observer)}")
    if keep is None:
        keep = observer is None
    else:
        keep = _flag("run_gas: keep", keep)

    from .kernels import gas_core as gc
    from .kernels.gas_entries import entries_for
    # compiled for this dimension, law and sleep option only (without sleep the loop is
    # the plain one)
    prepare, run, finish = entries_for(dim, law.law_id, sleep)
    r = float(state.radius)
    L = np.asarray(state.box, float)
    nc = np.ones(3, np.int64)
    cs = np.ones(3)
    for a in range(dim):
        nc[a] = max(1, int(L[a] / (CELL_DIAMETERS * 2.0 * r * (1.0 + gc.CELL_MARGIN))))
        cs[a] = L[a] / nc[a]
    # one row per body holding x, v and the event times (views): the fields a pair
    # scan reads sit in one or two cache lines
    rows = np.zeros((n, 2 * dim + gc.N_BT))
    x = rows[:, :dim]
    v = rows[:, dim:2 * dim]
    bt = rows[:, 2 * dim:]
    x[:] = state.x
    v[:] = state.v
    w = np.ascontiguousarray(state.w, float).reshape(n, -1).copy()
    bi = np.zeros((n, gc.N_BI), np.int32)
    bi[:, gc.SLP] = asleep0
    chead = np.full(int(np.prod(nc)), -1, np.int32)
    fpar = np.zeros(gc.N_FPAR)
    fpar[gc.F_R] = r
    fpar[gc.F_SIG2] = (2.0 * r) ** 2
    fpar[gc.F_INVM] = 1.0 / state.mass
    fpar[gc.F_INVI] = 1.0 / state.inertia if math.isfinite(state.inertia) else 0.0
    fpar[gc.F_G] = state.gravity
    fpar[gc.F_E:gc.F_E + 5] = law.params
    fpar[gc.F_TC] = tc
    fpar[gc.F_TEND] = math.inf if t_end is None else t_end
    fpar[gc.F_L:gc.F_L + dim] = L
    fpar[gc.F_CS:gc.F_CS + 3] = cs
    fpar[gc.F_SNAP_DT] = snapshot_dt or 0.0
    fpar[gc.F_SNAP_T0] = t0
    fpar[gc.F_FILL] = gc.BUCKET_FILL
    fpar[gc.F_SLEEP_V] = sleep_speed
    fpar[gc.F_WAKE_GAP] = wake_gap
    ipar = np.zeros(gc.N_IPAR, np.int64)
    ipar[gc.I_NC:gc.I_NC + 3] = nc
    ipar[gc.I_COLLAPSE] = gc.COLLAPSE_TC if collapse == "tc" else gc.COLLAPSE_NONE
    ipar[gc.I_RECORD] = (gc.REC_MASK if mask is not None else
                         gc.REC_ALL if record == "all" else gc.REC_NONE)
    ipar[gc.I_MAXIMP] = max_imp
    ipar[gc.I_SLEEP] = 1 if sleep else 0
    ipar[gc.I_SLEEP_N] = sleep_impacts
    from .kernels import scheduler as sch
    nb = 16
    while nb < BUCKETS_PER_BODY * n:
        nb *= 2
    qkey, qlink, qheap, qhead, qs, qdt = sch.q_alloc(n, nb, QUEUE_INDEX_DTYPE)
    prepare(x, v, bt, bi, chead, qkey, fpar, ipar, t0)
    if not np.all(np.isfinite(x)) or not np.all(np.isfinite(v)):
        raise ValueError("run_gas: the state holds non-finite values")
    fin = qkey[np.isfinite(qkey)] - t0
    tau = float(np.mean(fin)) if fin.size else 1.0
    dt = max(tau * fpar[gc.F_FILL] / n, 1e-300) if tau > 0 else 1.0
    keys = qkey.copy()
    sch.q_init(qkey, qlink, qheap, qhead, qs, qdt, nb, dt, t0)
    for i in range(n):
        if not asleep0[i]:                     # a sleeper has no event
            sch.q_push_k(i, keys[i], qkey, qlink, qheap, qhead, qs, qdt)

    stats = np.zeros(gc.N_ST, np.int64)
    fstats = np.zeros(gc.N_FS)
    fstats[gc.FS_T] = -math.inf
    nrf = 2 + 3 * dim
    recording = ipar[gc.I_RECORD] != gc.REC_NONE
    cap = REC_CHUNK if recording else 1
    rec_i = np.zeros((cap, 3), np.int64)
    rec_f = np.zeros((cap, nrf))
    rec_parts = []
    if mask is None:
        mask = np.zeros(1, np.uint8)
    if snapshot_dt:
        ns = (int(math.floor((t_end - t0) / snapshot_dt)) + 1
              if t_end is not None and observer is None else SNAP_CHUNK)
    else:
        ns = 0
    snap_t = np.zeros(max(ns, 1))
    snap_v = np.zeros((max(ns, 1), n if ns else 1, dim))
    snap_w = np.zeros((max(ns, 1), n if ns else 1, w.shape[1]))
    snap_parts = []

    def events_dict(ri, rf):
        return {"t": rf[:, 0].copy(), "a": ri[:, 0].copy(), "b": ri[:, 1].copy(),
                "mode": ri[:, 2].copy(), "dE": rf[:, 1].copy(),
                "n": rf[:, 2:2 + dim].copy(), "v": rf[:, 2 + dim:2 + 2 * dim].copy(),
                "P": rf[:, 2 + 2 * dim:2 + 3 * dim].copy()}

    def snaps_dict(k):
        sw = snap_w[:k].copy()
        return {"t": snap_t[:k].copy(), "v": snap_v[:k].copy(),
                "w": sw[:, :, 0] if dim == 2 else sw}

    def hand_events(k):
        if k == 0:
            return
        if observer is not None:
            observer("events", events_dict(rec_i[:k], rec_f[:k]))
        if keep:
            rec_parts.append((rec_i[:k].copy(), rec_f[:k].copy()))

    def hand_snaps(k):
        if k == 0:
            return
        if observer is not None:
            observer("snapshots", snaps_dict(k))
        if keep:
            snap_parts.append((snap_t[:k].copy(), snap_v[:k].copy(), snap_w[:k].copy()))

    while True:
        status = run(x, v, w, bt, bi, chead, qkey, qlink, qheap, qhead, qs, qdt, fpar, ipar,
                     stats, fstats, rec_i, rec_f, mask, snap_t, snap_v, snap_w)
        if status == gc.RUN_REC_FULL:
            hand_events(int(stats[gc.ST_NREC]))
            stats[gc.ST_NREC] = 0
            continue
        if status == gc.RUN_SNAP_FULL:
            k = int(stats[gc.ST_NSNAP])
            hand_snaps(k)
            # the kernel indexes snapshots from 0 in each buffer: shift the origin
            fpar[gc.F_SNAP_T0] += k * snapshot_dt
            stats[gc.ST_NSNAP] = 0
            continue
        break
    if status < 0:
        t_fail = float(fstats[gc.FS_T])
        if status == gc.RUN_LAW_FAILED:
            a, b = int(stats[gc.ST_FAIL_A]), int(stats[gc.ST_FAIL_B])
            what = f"body {a} and body {b}" if b >= 0 else f"body {a} and wall {-1 - b}"
            raise SimulationError(
                f"run_gas: law {state.law!r} has no solution (mode {int(stats[gc.ST_FAIL_MODE])})"
                f" for the impact of {what} after t = {t_fail} s")
        raise SimulationError(
            f"run_gas: {gc.STALL_IMPACTS} impacts at t = {t_fail} s without time advancing "
            f"(inelastic collapse; collapse={collapse!r}, tc={tc} s): use collapse='tc' or "
            f"a larger tc")
    if status == gc.RUN_DONE_TEND or (status == gc.RUN_EMPTY and t_end is not None):
        t_fin = t_end
    else:
        t_fin = max(float(fstats[gc.FS_T]), t0)
    finish(t_fin, x, v, bt, bi, state.gravity)
    events = None
    if recording:
        hand_events(int(stats[gc.ST_NREC]))
        if keep:
            ri = (np.concatenate([p[0] for p in rec_parts]) if rec_parts
                  else np.zeros((0, 3), np.int64))
            rf = np.concatenate([p[1] for p in rec_parts]) if rec_parts else np.zeros((0, nrf))
            events = events_dict(ri, rf)
    if ns:
        hand_snaps(int(stats[gc.ST_NSNAP]))
    if ns and keep and snap_parts:
        st = np.concatenate([p[0] for p in snap_parts])
        sv = np.concatenate([p[1] for p in snap_parts])
        sw = np.concatenate([p[2] for p in snap_parts])
    else:
        st, sv, sw = np.zeros(0), np.zeros((0, n, dim)), np.zeros((0, n, w.shape[1]))
    if dim == 2:
        w = w[:, 0].copy()
        sw = sw[:, :, 0]
    stop = {gc.RUN_DONE_TEND: "t_end", gc.RUN_DONE_MAX: "max_impacts",
            gc.RUN_EMPTY: "no event left"}[status]
    x, v = x.copy(), v.copy()
    asleep = bi[:, gc.SLP] != 0
    final = replace(state, x=x, v=v, w=w, t=t_fin, law_params=dict(params),
                    asleep=asleep.copy() if sleep else None)
    return GasResult(t=t_fin, x=x, v=v, w=w, n_collisions=int(stats[gc.ST_NCOLL]),
                     n_wall=int(stats[gc.ST_NWALL]), n_crossings=int(stats[gc.ST_NCROSS]),
                     n_stale=int(stats[gc.ST_NSTALE]), n_tc=int(stats[gc.ST_NTC]),
                     snap_t=st, snap_v=sv, snap_w=sw, events=events, stop=stop,
                     collapse=collapse, tc=tc, state=final, sleep=sleep,
                     sleep_speed=sleep_speed, sleep_impacts=sleep_impacts,
                     wake_gap=wake_gap, n_sleeps=int(stats[gc.ST_NSLEEP]),
                     n_wakes=int(stats[gc.ST_NWAKE]), n_absorbed=int(stats[gc.ST_NABSORB]),
                     energy_slept=float(fstats[gc.FS_SLEPT]), asleep=asleep)


def _sleep_options(state, sleep, sleep_speed, sleep_impacts, wake_gap):
    """Checked ``(sleep, sleep_speed, sleep_impacts, wake_gap)`` of ``run_gas``; zeros when
    sleep is off."""
    g = float(state.gravity)
    if sleep is None:
        sleep = g > 0.0
    else:
        sleep = _flag("run_gas: sleep", sleep)
    if not sleep:
        given = [k for k, val in (("sleep_speed", sleep_speed), ("sleep_impacts", sleep_impacts),
                                  ("wake_gap", wake_gap)) if val is not None]
        if given:
            raise ValueError(f"run_gas: {', '.join(given)} given but sleep is off")
        return False, 0.0, 0, 0.0
    if not g > 0.0:
        raise ValueError("run_gas: sleep needs gravity > 0 (bodies sleep on the floor or on "
                         "sleepers); this state has gravity 0")
    r = float(state.radius)
    if sleep_speed is None:
        sleep_speed = SLEEP_SPEED_REL * math.sqrt(g * r)
    else:
        sleep_speed = _positive("run_gas: sleep_speed", sleep_speed, "m/s")
    if sleep_impacts is None:
        sleep_impacts = SLEEP_IMPACTS
    else:
        from .kernels.gas_core import STALL_IMPACTS
        # a body resting from zero speed sleeps after sleep_impacts impacts at one
        # instant: far fewer than the stall guard's
        sleep_impacts = integer("run_gas: sleep_impacts", sleep_impacts, lo=1,
                                hi=STALL_IMPACTS // 10)
    if wake_gap is None:
        wake_gap = max(WAKE_GAP_REL * r, 2.0 * sleep_speed ** 2 / g)
    else:
        wake_gap = real("run_gas: wake_gap", wake_gap, "m")
        if not wake_gap >= 0.0:
            raise ValueError(f"run_gas: wake_gap must be >= 0 (m), got {_show(wake_gap)}")
    return True, sleep_speed, sleep_impacts, wake_gap


def _asleep_flags(state, n):
    """``state.asleep`` checked: (n,) bool, the flagged bodies at rest."""
    if state.asleep is None:
        return np.zeros(n, bool)
    a = state.asleep
    if not (isinstance(a, np.ndarray) and a.shape == (n,) and a.dtype == bool):
        raise ValueError(f"run_gas: state.asleep must be None or a ({n},) bool array")
    if a.any():
        w = np.asarray(state.w).reshape(n, -1)
        moving = a & ((np.abs(state.v).max(axis=1) > 0) | (np.abs(w).max(axis=1) > 0))
        if moving.any():
            k = int(np.nonzero(moving)[0][0])
            raise ValueError(f"run_gas: body {k} is asleep (state.asleep) but moves: a sleeper "
                             f"must have v = w = 0 (set state.asleep[{k}] = False to wake it)")
    return a.copy()


def contact_W(state, wall=False):
    """Diagonal of the contact-space Delassus matrix of an impact (1/kg):
    ``(W_NN, W_TT)`` for a pair (``wall=False``) or a body on a wall."""
    k = 1.0 if wall else 2.0
    invi = 1.0 / state.inertia if math.isfinite(state.inertia) else 0.0
    return k / state.mass, k * (1.0 / state.mass + state.radius ** 2 * invi)


# ---- helpers ------------------------------------------------------------------------------

def _dim(dim):
    if isinstance(dim, bool) or dim not in DIMS:
        raise ValueError(f"dim must be 2 (disks) or 3 (spheres), got {_show(dim)}")
    return int(dim)


def _positive(what, value, unit):
    x = real(what, value, unit)
    if not x > 0.0:
        raise ValueError(f"{what} must be > 0 ({unit}), got {_show(value)}")
    return x


def _gravity(who, g):
    g = real(f"{who}: gravity", g, "m/s^2")
    if g < 0.0:
        raise ValueError(f"{who}: gravity must be >= 0 (m/s^2, acting along minus the last "
                         f"axis), got {g!r}")
    return g


def _flag(what, value):
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise ValueError(f"{what} must be True or False, got {_show(value)}")


def _law_params(law, params, who):
    from .laws import LAWS
    if not isinstance(law, str) or law not in LAWS:
        raise ValueError(f"{who}: law must be one of {', '.join(LAWS)}, got {_show(law)}")
    params = dict(params)
    params.setdefault("e", 1.0)
    return params


def _check_state(s):
    dim = s.x.shape[1] if (isinstance(s.x, np.ndarray) and s.x.ndim == 2) else None
    if dim not in DIMS:
        raise ValueError("run_gas: state.x must be an (n, 2) or (n, 3) array of positions (m)")
    n = s.x.shape[0]
    if n < 1:
        raise ValueError("run_gas: the gas needs at least one body")
    if not (isinstance(s.v, np.ndarray) and s.v.shape == (n, dim)):
        raise ValueError(f"run_gas: state.v must be an ({n}, {dim}) array of velocities (m/s)")
    wshape = (n,) if dim == 2 else (n, 3)
    if not (isinstance(s.w, np.ndarray) and s.w.shape == wshape):
        raise ValueError(f"run_gas: state.w must be an array of shape {wshape} (rad/s)")
    _positive("run_gas: state.radius", s.radius, "m")
    _positive("run_gas: state.mass", s.mass, "kg")
    if not (s.inertia == math.inf or (real("run_gas: state.inertia", s.inertia, "kg m^2")
                                      > 0.0)):
        raise ValueError(f"run_gas: state.inertia must be > 0 (kg m^2) or inf (smooth), "
                         f"got {s.inertia!r}")
    _gravity("run_gas", s.gravity)
    box = np.asarray(s.box, float)
    if box.shape != (dim,) or not np.all(np.isfinite(box)) or np.any(box < 2 * s.radius):
        raise ValueError(f"run_gas: state.box must hold {dim} finite lengths >= 2 radius (m)")
    for name, arr in (("x", s.x), ("v", s.v), ("w", s.w)):
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"run_gas: state.{name} holds non-finite values")
    # inside the box (round-off allowed: POS_RTOL of the box side)
    tol = POS_RTOL * float(box.max())
    if np.any(s.x < s.radius - tol) or np.any(s.x > box - s.radius + tol):
        raise ValueError("run_gas: every centre must lie in [radius, box - radius]")
    return n, dim


# Positions may sit outside [r, L - r] by this fraction of the box side (round-off).
POS_RTOL = 1e-12
