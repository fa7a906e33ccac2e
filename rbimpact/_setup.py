"""Setup shared by ``Simulation`` (2D) and ``Simulation3D``: validation of the keywords and
of ``run``'s arguments, and the packing of the law table (default law, ``pair_laws``).

Every function takes ``who`` ("Simulation" or "Simulation3D"), the prefix of its error
messages, so both front ends raise the same errors with their own name.
"""
import contextlib
import gc
import math

import numpy as np

from ._validate import choice, scene_energy_check, validate_run_args, validate_tolerances
from .kernels import codes
from .laws import N_PARAMS

__all__ = ["call_loop", "check_loop", "compiled_loop", "loop_kind", "check_tolerances", "check_law", "check_run_args", "check_scene", "pack_laws", "run_status"]


def check_tolerances(who, table, tolerances):
    """The tolerance dict: ``table`` (keyword -> (default, unit, meaning)) defaults updated
    with ``tolerances``, each checked (``_validate.validate_tolerances``: a number, finite,
    >= 0; iteration limits positive integers; ``zeno_speed`` may be None). Unknown keywords
    raise ``TypeError``."""
    return validate_tolerances(who, table, tolerances)


def check_law(who, law, what):
    """``law`` if it looks like an ``rbimpact.Law`` (``law_id`` and finite ``params`` of
    length N_PARAMS), else ``ValueError`` naming ``what``."""
    ok = hasattr(law, "law_id") and hasattr(law, "params")
    if ok:
        p = np.asarray(law.params, dtype=float)
        ok = p.shape == (N_PARAMS,) and bool(np.all(np.isfinite(p)))
    if not ok:
        raise ValueError(f"{who}: {what} must be an rbimpact.Law, got {law!r}")
    return law


def check_run_args(t_end, max_events):
    """Validate ``run(t_end, max_events)``; returns ``(float(t_end), int(max_events))``
    (``_validate.validate_run_args``: t_end positive and finite in s, max_events a whole
    number from 1 to the int64 limit)."""
    return validate_run_args(t_end, max_events)


def check_scene(who, scene, policy, policies):
    """The scene's energy is representable (``_validate.scene_energy_check``) and
    ``policy`` is one of ``policies``; returns ``policy``."""
    scene_energy_check(who, scene)
    return choice(f"{who}: policy", policy, policies)


def check_painleve(who, painleve):
    """``painleve`` is one of ``kernels.codes.PAINLEVE_OPTIONS`` ("error", "impact");
    returns it."""
    from .kernels.codes import PAINLEVE_OPTIONS
    return choice(f"{who}: painleve", painleve, PAINLEVE_OPTIONS)


def _check_body(who, scene, i):
    if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)) \
            or not 0 <= int(i) < len(scene.bodies):
        raise ValueError(f"{who}: {i!r} is not a body index of the scene "
                         f"(0..{len(scene.bodies) - 1})")
    return int(i)


def _check_plane(who, scene, plane):
    if not (0 <= plane.index < len(scene.planes) and scene.planes[plane.index] is plane):
        raise ValueError(f"{who}: {plane!r} is not a plane of this scene")


class LawTable:
    """The packed law table of a scene: ``laws`` (list, row 0 the default law),
    ``law_ids`` int64[nl], ``law_par`` float64[nl, N_PARAMS], ``bp_law`` int64[nb, np]
    (law row of each body-plane contact) and ``pairs`` int64[npr, 3] (body pairs that can
    collide: ``(a, b, law row)``)."""

    __slots__ = ("laws", "law_ids", "law_par", "bp_law", "pairs")


def pack_laws(who, scene, law, pair_laws, plane_type, round_body, *, dim, round_name,
              ignore_unsupported_pairs):
    """Resolve ``pair_laws`` against ``scene`` and pack the law table (``LawTable``).

    ``pair_laws`` keys: ``(i, j)`` (two body indices), ``(i, plane)`` or ``(plane, i)``
    (a ``plane_type`` of the scene), or a plane alone; the most specific key wins.
    ``round_body[i]``: body ``i`` can take part in a body-body contact (a disk in 2D, a
    sphere in 3D, named ``round_name``); another pair of bodies raises ``ValueError``
    unless ``ignore_unsupported_pairs`` (then it gets no pair, and no pair law may be
    given for it). A one-body scene has no pair (no pair search runs)."""
    check_law(who, law, "law")
    bodies = scene.bodies
    nb, npl = len(bodies), len(scene.planes)
    laws = [law]

    def law_index(x):
        for k, y in enumerate(laws):
            if y is x:
                return k
        laws.append(x)
        return len(laws) - 1

    by_pair, by_body_plane, by_plane = {}, {}, {}
    for key, x in dict(pair_laws or {}).items():
        check_law(who, x, f"pair_laws[{key!r}]")
        if isinstance(key, plane_type):
            _check_plane(who, scene, key)
            by_plane[key.index] = x
            continue
        if not (isinstance(key, tuple) and len(key) == 2):
            raise ValueError(f"{who}: pair_laws keys are (i, j), (i, plane), (plane, i) or a "
                             f"plane; got {key!r}")
        a, b = key
        if isinstance(a, plane_type):
            a, b = b, a
        if isinstance(b, plane_type):
            _check_plane(who, scene, b)
            by_body_plane[(_check_body(who, scene, a), b.index)] = x
        else:
            i, j = _check_body(who, scene, a), _check_body(who, scene, b)
            if i == j:
                raise ValueError(f"{who}: pair_laws key {key!r} pairs a body with itself")
            by_pair[(min(i, j), max(i, j))] = x

    bp_law = np.zeros((nb, npl), np.int64)
    for i in range(nb):
        for p in range(npl):
            bp_law[i, p] = law_index(by_body_plane.get((i, p), by_plane.get(p, law)))
    pairs = []
    for i in range(nb):
        for j in range(i + 1, nb):
            if round_body[i] and round_body[j]:
                pairs.append((i, j, law_index(by_pair.get((i, j), law))))
            elif (i, j) in by_pair or not ignore_unsupported_pairs:
                raise ValueError(
                    f"{who}: bodies {i} ({type(bodies[i].shape).__name__}) and {j} "
                    f"({type(bodies[j].shape).__name__}) could collide, but the {dim} "
                    f"stepper only handles body-body contacts between {round_name}; pass "
                    f"ignore_unsupported_pairs=True to let such bodies pass through each "
                    f"other (and give no pair law for them)")
    table = LawTable()
    table.laws = laws
    table.law_ids = np.array([int(x.law_id) for x in laws], dtype=np.int64)
    table.law_par = np.array([np.asarray(x.params, dtype=float) for x in laws]
                             ).reshape(len(laws), N_PARAMS)
    table.bp_law = bp_law
    table.pairs = np.array(pairs, dtype=np.int64).reshape(len(pairs), 3)
    return table


class Arena:
    """The arrays of one run of a compiled event loop, allocated once per simulation: views
    into one float64 and one int64 buffer, reset before each run from a template by two
    copies (instead of some forty small allocations per run).

    ``spec``: ``(name, shape, dtype, initial value)`` per array, in the loop's argument
    order. ``reset()`` returns the views (a tuple, spec order); ``named[name]`` is a view.
    """

    def __init__(self, spec):
        sizes = {np.float64: 0, np.int64: 0}
        layout = []
        for name, shape, dtype, value in spec:
            dtype = np.float64 if dtype is float else np.int64
            size = math.prod(shape)
            layout.append((name, shape, dtype, value, sizes[dtype], size))
            sizes[dtype] += size
        self.fbuf = np.zeros(sizes[np.float64])
        self.ibuf = np.zeros(sizes[np.int64], np.int64)
        views, self.named = [], {}
        for name, shape, dtype, value, start, size in layout:
            buf = self.fbuf if dtype is np.float64 else self.ibuf
            view = buf[start:start + size].reshape(shape)
            if not (isinstance(value, (int, float)) and value == 0):
                view[...] = value
            views.append(view)
            self.named[name] = view
        self.views = tuple(views)
        self.fbuf0 = self.fbuf.copy()
        self.ibuf0 = self.ibuf.copy()

    def reset(self):
        np.copyto(self.fbuf, self.fbuf0)
        np.copyto(self.ibuf, self.ibuf0)
        return self.views


def run_status(k, rc):
    """The ``Result.status`` of a run of stepper module ``k`` that returned ``rc``: "done",
    "max_events", or for an error the lowercase name of its ``ERR_*`` code ("missed",
    "no_solution", "stall", "painleve", ...), so that the partial result carried by the
    exception (``exc.result``) names the failure instead of saying "done"."""
    if rc == k.RC_MAX_EVENTS:
        return "max_events"
    if rc >= 0:
        return "done"
    for name in dir(k):
        if name.startswith("ERR_") and getattr(k, name) == rc:
            return name[4:].lower()
    return f"error {rc}"



#: the environment variable that selects the event loop simulations run (``loop_kind``)
LOOP_ENV = "RBIMPACT_LOOP"
#: the event loops: "scene" (the default) is compiled for the scene's law and the modes it
#: can reach, the least a new process compiles (issue 14); "general" has every law
#: (dispatched per contact) and every mode: one compile serves every scene of a process
#: or of a warm cache (the test suite, whose scenes reach 45 2D and 21 3D scene loops).
#: Both give the same results, bit for bit (``tests/test_loop_kinds.py``).
LOOP_KINDS = ("scene", "general")


def loop_kind():
    """The event loop simulations run, from ``$RBIMPACT_LOOP`` ("scene" when unset);
    ``ValueError`` for any other value than those of ``LOOP_KINDS``."""
    import os
    return choice(f"${LOOP_ENV}", os.environ.get(LOOP_ENV, "scene"), LOOP_KINDS)


def check_loop(who, loop):
    """``loop`` (None, or one of ``LOOP_KINDS``) for the ``loop`` keyword of ``who``."""
    return None if loop is None else choice(f"{who}: loop", loop, LOOP_KINDS)


def compiled_loop(sim, k):
    """``(run_loop, switches)`` of a ``Simulation`` or ``Simulation3D`` ``sim`` with stepper
    module ``k``, found once per simulation (at its first run): of kind ``sim.loop``, or
    ``loop_kind()`` when that is None. The scene loop is compiled for the
    scene's one law (``k.loop_for``; every law when its contacts have different laws) and
    the scene's feature switches (``k.scene_features``: the modes the loop compiles); the
    general loop for ``LAW_ANY`` and ``k.ALL_FEATURES``. A stepper whose loop takes the
    switches as compile-time constants (``k.SWITCHES_IN_LOOP``, 2D) gets them in
    ``loop_for``, and ``switches`` is empty; otherwise they are the loop's last arguments
    (3D)."""
    loop = sim.__dict__.get("_loop_switches")
    if loop is None:
        from .kernels.dispatch import LAW_ANY
        if (sim.loop or loop_kind()) == "general":
            law, switches = LAW_ANY, k.ALL_FEATURES
        else:
            laws = {int(x) for x in sim._law_ids}
            law = laws.pop() if len(laws) == 1 else LAW_ANY
            switches = k.scene_features(sim._bint, sim._planes, sim._grav, len(sim._pairs))
        if getattr(k, "SWITCHES_IN_LOOP", False):
            loop = (k.loop_for(law, *switches), ())
        else:
            loop = (k.loop_for(law), switches)
        sim._loop_switches = loop
    return loop


#: Python's generation-2 collection threshold while Numba compiles (or loads from its disk
#: cache) an event loop, on its first call in a process: full collections are deferred
#: (each one walks the compiler's whole heap: about 3 s, a fifth, of the 15 s cold compile
#: of ``rbimpact run bouncing_ball``, issue 14). Generations 0 and 1 are still collected;
#: the heap grows by about 100 MB during that compile. The thresholds are restored after.
GC_GEN2_WHILE_COMPILING = 1_000_000


@contextlib.contextmanager
def _full_gc_deferred():
    """No full garbage collection within (``GC_GEN2_WHILE_COMPILING``)."""
    old = gc.get_threshold()
    gc.set_threshold(old[0], old[1], GC_GEN2_WHILE_COMPILING)
    try:
        yield
    finally:
        gc.set_threshold(*old)


def call_loop(loop, args):
    """``loop(*args)`` for a Numba dispatcher; its first call in a process (which compiles
    it, or loads it from the cache) with full garbage collections deferred. Checking
    ``overloads`` costs well under a microsecond (``signatures`` cost 13 us per run)."""
    if loop.overloads:
        return loop(*args)
    with _full_gc_deferred():
        return loop(*args)


def _cluster_kernel(k):
    """The name of the cluster kernel of stepper module ``k``."""
    return k.cl.__name__.rsplit(".", 1)[-1]


def idle_message(result, at, idle_passes):
    """The message of a run stopped by ``ERR_IDLE`` (2D and 3D): ``idle_passes`` passes of
    the event loop in a row recorded no event, up to ``at``; ``result`` the partial result
    (its last recorded event, if any, says where the idle stretch began)."""
    ev = result.events
    since = (f" since the last event at t = {float(ev['t'][-1]):.12g} s" if len(ev)
             else " since the start")
    return (f"the run makes no progress {at}: {int(idle_passes)} consecutive passes of the event "
            f"loop recorded no event{since} (integrated motion, or a bound between two "
            f"bodies that crawls, reaching no event: please report the scene); raise "
            f"idle_passes if the scene's motion really needs more")


def persistent_pair_message(k, why, body, other, third, at, pt, v, s, rest_length):
    """The message of a run stopped by ``ERR_PERSISTENT_PAIR`` (2D and 3D; ``k`` the stepper
    module): reason ``why`` (``codes.PP_*``), the pair's bodies as text, ``third`` the body
    the reason names (the held body of ``PP_HELD``, the other member of ``PP_SHAPES`` and
    ``PP_TWO``; else unused), the time and point texts, the reason's number ``v`` (the post-impact normal speed,
    m/s; a cluster2d / cluster3d ``CS_*`` status; a count of mode events) and ``s`` (the next impact,
    s after it)."""
    if why == codes.PP_NO_MODE:
        return (f"Painleve: {body} and {other} in persistent contact {at}: no consistent "
                f"stick/slip/lift-off mode of their cluster exists (every combination of "
                f"{_cluster_kernel(k)}'s enumeration has a pulling normal force, a force "
                f"outside its friction cone or a contact accelerating into another, to the "
                f"tolerances "
                f"FORCE_TOL and ACC_TOL); the impact without collision that would resolve it "
                f"is not built for clusters")
    if why == codes.PP_HELD:
        detail = (f"{third} is held by an integrated (pivot) contact or in a moving cluster "
                  f"of bodies in persistent contact {at} while it can meet the other body of "
                  f"the pair, {body} and {other}; body-body contact with a body in an "
                  f"integrated contact")
    elif why == codes.PP_TOGETHER:
        detail = (f"{body} and {other} stay together after their impact {at}, {pt} (normal "
                  f"speed {v:.3g} m/s, the round-off of a plastic impact; no separation "
                  f"found)")
    elif why == codes.PP_CLUSTER:
        detail = (f"the persistent contact of {body} and {other} {at} failed in "
                  f"{_cluster_kernel(k)} "
                  f"(status CS {int(v)}: 2 singular, 3 Painleve, 4 step limit, 6 too many "
                  f"contacts, 7 inconsistent modes)")
    elif why == codes.PP_SHAPES:
        detail = (f"{body} and {other} stay in contact {at} with {third} in the cluster: "
                  f"persistent contact is built for disks, rods, capsules and polygons (2D; "
                  f"not ellipses) and spheres of spherical inertia (3D) only")
    elif why == codes.PP_FEATURE:
        detail = (f"a contact point of the cluster of {body} leaves its feature {at}, and the "
                  f"contacts gathered again there leave theirs at once, three times (no "
                  f"feature switch found)")
    elif why == codes.PP_REENTRY:
        detail = (f"the persistent contact of {body} and {other} ends and starts again "
                  f"{int(v)} times {at}, each within {k.CL_CHAT_RTOL:g} sqrt(L / |g|) of the "
                  f"one before (no lasting contact mode found)")
    elif why == codes.PP_UNWATCHED:
        detail = (f"{body} and {other}, in one cluster without touching at its entry, "
                  f"overlap by {-v:.3g} m {at} (a pair of the cluster not touching at its "
                  f"entry has no contact row; its meeting is not located)")
    elif why == codes.PP_CORNER:
        detail = (f"{body} and {other} touch {at} by two sharp corners, or by features "
                  f"the cluster's contact rows cannot describe (cluster2d_rows status "
                  f"{int(v)})")
    elif why == codes.PP_TWO:
        detail = (f"{body} and {other} stay in contact {at} while {third} is in another "
                  f"cluster or held by an integrated contact (one cluster at a time)")
    elif why == codes.PP_STICK_SLIP:
        detail = (f"the stick-slip events of the cluster of {body} accumulate {at} "
                  f"({int(v)} mode changes closer than {k.CL_CHAT_RTOL:g} sqrt(L / |g|) "
                  f"apart; no consistent lasting mode found)")
    elif why == codes.PP_SPLIT:
        detail = (f"{body} leaves the cluster {at} while other bodies stay in contact "
                  f"(splitting a cluster is not built)")
    else:
        detail = (f"impacts accumulate at a single contact point of {body} on {other} {at}, "
                  f"{pt}: normal speed after the impact {v:.3g} m/s, next impact of the pair "
                  f"{s:.3g} s later (the bodies part by less than rest_length = "
                  f"{rest_length:g} m)")
    return (f"persistent body-body contact (resting, sliding, pivoting or rolling on another "
            f"body) is not supported yet (issue 16): {detail}")
