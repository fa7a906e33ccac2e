"""Warm Numba's on-disk cache for the test suite, one list of compiles per process.

The suite's slowest compiles are independent of one another: the general event loop of
each dimension (``$RBIMPACT_LOOP=general``, set by ``conftest``), the many-body engine's
entries ``gas_entries.entries_for(D, law, sleep)`` the suite runs, the batch kernels of
the laws and the scene loops of ``test_loop_kinds``. One pytest
process compiles them one after the other on one core; ``conftest`` runs this script in
``PREWARM_WORKERS`` processes at once before the first test, each compiling its share
into the cache, where the suite then loads them. It changes no result: a compile the
warm-up misses happens in the test that needs it, as before.

``python tests/_prewarm.py K N`` runs worker K's share of ``TASKS`` among N workers
(``share``: split by each task's measured compile time, so that the shares balance) and
prints one line per task (its wall seconds).
"""
import sys
import time

#: (kind, dimension, argument, seconds): "loop" runs a small scene on the general loop and
#: samples it (the loop, its sampler); "gas" (law, sleep) runs a small gas of that law and
#: sleep option; "batch" resolves a few contacts with every law (``Law.resolve_batch``);
#: "scene" runs scene k of ``test_loop_kinds.SCENES`` on its scene loop; "test" (module,
#: function, arguments) calls a test without fixtures whose compiles are its own (the pair
#: kernels' known poses, the scene loops of the pay-for-what-you-use rows and of the
#: disk-only switch). The seconds are each task's compile time in a clean-clone CI run
#: (session 27, a 2-core machine, two workers): ``share`` splits the tasks between the
#: workers by them (longest first, each to the least loaded worker).
TASKS = (
    ("loop", 3, None, 323),
    ("loop", 2, None, 175),
    ("gas", 3, ("kane_levinson", True), 86),
    ("gas", 2, ("kane_levinson", True), 67),
    ("gas", 2, ("kane_levinson", False), 59),
    ("gas", 3, ("kane_levinson", False), 52),
    ("test", 2, ("test_bench", "test_pay_only_for_what_is_used_a_2d_scene_touches_no_3d_kernel",
                 {}), 50),
    ("test", 3, ("test_pair3d", "test_features_of_known_poses", {}), 49),
    ("scene", 3, 5, 44),
    ("batch", 2, None, 31),
    ("scene", 3, 3, 22),
    ("test", 2, ("test_shapes_switch2d", "test_disk_loop_is_the_general_loop",
                 {"vx": 1.0, "mu": 0.3, "e": 0.8}), 22),
    ("scene", 3, 4, 20),
    ("scene", 2, 2, 20),
    ("batch", 3, None, 19),
    ("scene", 2, 1, 16),
    ("test", 2, ("test_shapes_switch2d", "test_disk_loop_refuses_other_shapes", {}), 15),
    ("scene", 2, 0, 13),
    ("test", 3, ("test_bad_input", "test_resolve_refuses_a_contact_whose_energy_overflows",
                 {"d": 3}), 4),
)


def share(k, n):
    """Worker k's tasks of ``n``: the longest-processing-time split of ``TASKS`` by their
    seconds (each task, longest first, to the worker with the least work so far; ties to
    the lowest worker), in that order."""
    load = [0.0] * n
    mine = []
    for task in sorted(TASKS, key=lambda task: -task[3]):
        w = min(range(n), key=lambda j: (load[j], j))
        load[w] += task[3]
        if w == k:
            mine.append(task)
    return mine


def _loop(dim):
    from rbimpact import Law
    if dim == 2:
        from rbimpact.scene import Scene2D
        from rbimpact.shapes import Disk
        from rbimpact.simulation import Simulation
        sc = Scene2D()
        sc.add_floor()
        sc.add_body(Disk(0.1), 1.0, (0.0, 0.3))
        sim = Simulation(sc, Law("kane_levinson", e=0.5, mu=0.3), loop="general")
    else:
        from rbimpact.scene3d import Scene3D
        from rbimpact.shapes3d import Sphere
        from rbimpact.simulation3d import Simulation3D
        sc = Scene3D()
        sc.add_floor()
        sc.add_body(Sphere(0.1), 1.0, (0.0, 0.0, 0.3))
        sim = Simulation3D(sc, Law("kane_levinson", e=0.5, mu=0.3), loop="general")
    res = sim.run(0.5)
    res.sample([0.0, 0.25])
    res.energy([0.0, 0.25])


def _gas(dim, law, sleep):
    from rbimpact.manybody import random_gas, run_gas
    s = random_gas(8, dim=dim, packing=0.05, law=law, e=0.7, gravity=1.0 if sleep else 0.0,
                   seed=0)
    run_gas(s, max_impacts=50, sleep=sleep)


def _batch(dim):
    import numpy as np
    from rbimpact import Law
    rng = np.random.default_rng(0)
    a = rng.normal(size=(4, dim, dim))
    W = a @ np.transpose(a, (0, 2, 1)) + dim * np.eye(dim)
    v = rng.normal(size=(4, dim))
    v[:, 0] = -np.abs(v[:, 0]) - 0.1
    for name in ("kane_levinson", "brach", "smith", "routh", "chatterjee_ruina"):
        Law(name, e=0.5, mu=0.3).resolve_batch(v, W)


def _scene(k):
    import test_loop_kinds as lk
    dim, bodies, sseed, _ = lk.SCENES[k]
    lk._run(dim, bodies, sseed, "scene")


def _test(module, function, kwargs):
    import importlib
    getattr(importlib.import_module(module), function)(**kwargs)


def main(k, n):
    """Run worker k's share of the tasks (of n workers, ``share``); a task that fails is reported and the next one runs (its
    test, run by pytest afterwards, reports the failure). Returns the number failed."""
    failed = 0
    for kind, dim, arg, _ in share(k, n):
        t0 = time.perf_counter()
        what = "" if arg is None else arg[:2] if kind == "test" else arg
        try:
            if kind == "loop":
                _loop(dim)
            elif kind == "gas":
                _gas(dim, *arg)
            elif kind == "batch":
                _batch(dim)
            elif kind == "scene":
                _scene(arg)
            else:
                _test(*arg)
        except Exception as exc:    # noqa: BLE001 (reported; pytest runs the real tests)
            failed += 1
            print(f"prewarm {kind} {dim}D {what}: failed ({type(exc).__name__}: {exc})",
                  flush=True)
            continue
        print(f"prewarm {kind} {dim}D {what}: {time.perf_counter() - t0:.1f} s", flush=True)
    return failed


if __name__ == "__main__":
    sys.exit(1 if main(int(sys.argv[1]), int(sys.argv[2])) else 0)
