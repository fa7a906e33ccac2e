"""Benchmarks: every figure is a median of repeats, judged by a ratio measured in the same run.

``rbimpact bench laws``        batched law throughput (contacts/s), 2D and 3D, one thread
                               and all threads, against NumPy Kane & Levinson 2D and a plain
                               copy; per-call cost of ``Law.resolve`` against ``Law.kernel``
                               called from a user's njit loop.
``rbimpact bench routh3d``     error of Routh 3D against run time on the DESIGN §5 swerve case.
``rbimpact bench rotation3d``  torque-free 3D rotation: integrator error against ``rot_tol``.
``rbimpact bench stepper``     impacts per second of the 2D stepper (elastic bouncing_ball,
                               falling_rod, ...) and the 3D one (die_toss, die_toss batch), per
                               impact against the elastic ball; fixed cost of a run.
``rbimpact bench crosscheck``  rbimpact against pymunk on bouncing_ball: time and error ratios.
``rbimpact bench compile``     start-up in a new process, empty and warm Numba cache.
``rbimpact bench pay``         pay only for what is used: a frictionless one-ball scene against a
                               rough two-ball scene, compile (new process, empty cache) and run.
``rbimpact bench sweep``       ``rbimpact.sweep("die_toss", seeds=400)`` with 1 and 2 workers, and
                               ``to_csv`` per 1e6 events against the former row-by-row writer.
``rbimpact bench all``         all of the above.
"""
import json
import time

import numpy as np

LAW_SETTINGS = {  # the parameters every law is benchmarked with
    "kane_levinson": {"e": 0.5, "mu": 0.3},
    "brach": {"e": 0.5, "mu": 0.3, "e_t": 0.2},
    "smith": {"e": 0.5, "mu": 0.3},
    "routh": {"e": 0.5, "mu": 0.3, "restitution": "energetic", "tol": 1e-10},
    "chatterjee_ruina": {"e": 0.5, "mu": 0.3, "e_t": 0.2},
}
SWERVE = {  # DESIGN §5, 3D swerve case
    "v": [-4.0, -2.0, 1.0],
    "W": [[5.0, 1.0, -1.0], [1.0, 8.0, -2.0], [-1.0, -2.0, 3.0]],
    "e": 0.2, "mu": 0.2,
}


def random_contacts(n, d, seed=0):
    """n random contacts of a rigid body (unit mass scale) hitting a static plane.

    ``W = 1/m I + (r x t_i)(r x t_j)/I`` per DESIGN §3, with masses in [0.5, 2] kg, arms up
    to 1 m and gyration radii in [0.1, 1] m; ``v_N`` in [-2, -0.1] m/s, ``v_T`` in [-2, 2].
    """
    rng = np.random.default_rng(seed)
    m = rng.uniform(0.5, 2.0, n)
    W = np.zeros((n, d, d))
    W[:, range(d), range(d)] = 1.0 / m[:, None]
    if d == 2:
        r = rng.uniform(-1.0, 1.0, (n, 2))
        inertia = m * rng.uniform(0.1, 1.0, n) ** 2
        # arm cross basis vector e_i: n = (0, 1) -> r x n = r_x ; t = (1, 0) -> r x t = -r_y
        c = np.stack([r[:, 0], -r[:, 1]], axis=1)
        W += c[:, :, None] * c[:, None, :] / inertia[:, None, None]
    else:
        r = rng.uniform(-1.0, 1.0, (n, 3))
        k = rng.uniform(0.1, 1.0, (n, 3)) ** 2 * m[:, None]  # principal inertias, body = world
        basis = np.eye(3)[[2, 0, 1]]  # n = z, t1 = x, t2 = y
        c = np.cross(r[:, None, :], basis[None, :, :])  # (n, 3 dirs, 3 comps)
        W += np.einsum("nik,nk,njk->nij", c, 1.0 / k, c)
    v = np.empty((n, d))
    v[:, 0] = rng.uniform(-2.0, -0.1, n)
    v[:, 1:] = rng.uniform(-2.0, 2.0, (n, d - 1))
    return v, W


def _median_time(fn, repeat):
    fn()  # warm-up (compilation, page faults)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def bench_laws(n=1_000_000, repeat=7):
    """Rows of batched throughput per law and dimension (contacts/s).

    Per law: a minimal Numba loop on the same data (one thread: read ``v`` and the upper
    triangle of ``W``, call the law's scalar core, store ``P`` and the mode; no
    validation, no ``v_f``, ``dE`` or energy flag) and the public ``Law.resolve_batch``
    (validation, ``v_f``, ``dE``, energy flags, output allocation), one thread and all
    threads. Ratios: against a plain copy of the arrays, NumPy Kane & Levinson 2D, and
    (``vs_minimal``) the minimal loop, all measured in this run."""
    import numba
    from numba import njit
    from .kernels.batch import CORES_2D, CORES_3D
    from .laws import Law
    from .numpy_laws import kane_levinson_2d_numpy

    def minimal_loop(core, d):
        """The reference: the law's core in a plain loop (compiled here, not cached)."""
        if d == 2:
            @njit(error_model="numpy")
            def loop(v, W, prm, P, mode):
                e, mu, et, rest, tol = prm[0], prm[1], prm[2], prm[3], prm[4]
                for i in range(v.shape[0]):
                    m, p0, p1 = core(v[i, 0], v[i, 1], W[i, 0, 0], W[i, 0, 1], W[i, 1, 1],
                                     e, mu, et, rest, tol)
                    mode[i] = m
                    P[i, 0] = p0
                    P[i, 1] = p1
            return loop

        @njit(error_model="numpy")
        def loop3(v, W, prm, P, mode):
            e, mu, et, rest, tol = prm[0], prm[1], prm[2], prm[3], prm[4]
            for i in range(v.shape[0]):
                m, p0, p1, p2 = core(v[i, 0], v[i, 1], v[i, 2], W[i, 0, 0], W[i, 0, 1],
                                     W[i, 0, 2], W[i, 1, 1], W[i, 1, 2], W[i, 2, 2],
                                     e, mu, et, rest, tol)
                mode[i] = m
                P[i, 0] = p0
                P[i, 1] = p1
                P[i, 2] = p2
        return loop3

    rows = []
    threads_all = numba.config.NUMBA_NUM_THREADS
    for d, cores in ((2, CORES_2D), (3, CORES_3D)):
        nd = n if d == 2 else n // 4
        v, W = random_contacts(nd, d)
        P, vf = np.empty((nd, d)), np.empty((nd, d))
        mode = np.empty(nd, dtype=np.int64)
        vc, Wc = np.empty_like(v), np.empty_like(W)

        def copy():
            np.copyto(vc, v)
            np.copyto(Wc, W)
            np.copyto(P, v)
            np.copyto(vf, v)

        t_copy = _median_time(copy, repeat)
        rows.append({"item": f"plain copy of the arrays {d}D", "dim": d, "threads": 1,
                     "contacts_per_s": nd / t_copy})
        if d == 2:
            t_np = _median_time(lambda: kane_levinson_2d_numpy(v, W, 0.5, 0.3), repeat)
            rows.append({"item": "NumPy kane_levinson 2D", "dim": 2, "threads": 1,
                         "contacts_per_s": nd / t_np, "vs_copy": t_copy / t_np,
                         "vs_numpy_kl2d": 1.0})

        def row(item, threads, t, t_min=None):
            r = {"item": item, "dim": d, "threads": threads, "contacts_per_s": nd / t,
                 "vs_copy": t_copy / t}
            if d == 2:
                r["vs_numpy_kl2d"] = t_np / t
            if t_min is not None:
                r["vs_minimal"] = t_min / t
            return r

        for name, params in LAW_SETTINGS.items():
            law = Law(name, **params)
            loop = minimal_loop(cores[law.law_id], d)
            numba.set_num_threads(1)
            try:
                t_min = _median_time(lambda: loop(v, W, law.params, P, mode), repeat)
                rows.append(row(f"minimal loop {name} {d}D", 1, t_min))
                for threads in sorted({1, threads_all}):
                    numba.set_num_threads(threads)
                    t = _median_time(lambda: law.resolve_batch(v, W), repeat)
                    rows.append(row(f"{name} {d}D", threads, t, t_min))
            finally:
                numba.set_num_threads(threads_all)
    return rows


def bench_routh3d(repeat=7, n=2000):
    """Rows of (tol, error of v_f against tol = 1e-14, run time per impact) on the swerve
    case, through ``Law.resolve_batch`` (one thread). ``error`` is the max-norm error of
    v_f (m/s); ``rel_error`` divides it by |v| (the scale tol is relative to)."""
    from .laws import Law
    import numba

    v = np.repeat(np.array([SWERVE["v"]]), n, axis=0)
    W = np.repeat(np.array([SWERVE["W"]]), n, axis=0)
    ref = Law("routh", e=SWERVE["e"], mu=SWERVE["mu"], tol=1e-14).resolve(v[0], W[0]).v_f
    vscale = float(np.linalg.norm(SWERVE["v"]))
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    rows = []
    try:
        for k in range(3, 13):
            law = Law("routh", e=SWERVE["e"], mu=SWERVE["mu"], tol=10.0 ** -k)
            out = []
            t = _median_time(lambda: out.append(law.resolve_batch(v, W)), repeat)
            err = float(np.abs(out[-1].v_f - ref).max())
            rows.append({"tol": 10.0 ** -k, "error": err, "rel_error": err / vscale,
                         "time_per_impact_s": t / n, "impacts_per_s": n / t})
    finally:
        numba.set_num_threads(threads)
    return rows


def bench_overhead(repeat=7, n=20000, laws=None):
    """Per-call cost of one 2D impact: ``Law.resolve`` from Python, and ``Law.kernel`` called
    from a user's njit loop (the way a user's own stepper would call it)."""
    from numba import njit
    from .laws import Law

    v, W = random_contacts(n, 2, seed=1)
    rows = []
    for name, params in LAW_SETTINGS.items():
        if laws is not None and name not in laws:
            continue
        law = Law(name, **params)
        kernel, table = law.kernel, law.params

        @njit
        def user_loop(v, W, P):
            acc = 0
            for i in range(v.shape[0]):
                acc += kernel(v[i], W[i], table, P)
            return acc

        P = np.zeros(2)
        t_njit = _median_time(lambda: user_loop(v, W, P), repeat)
        m = min(2000, n)

        def python_loop():
            for i in range(m):
                law.resolve(v[i], W[i])

        t_py = _median_time(python_loop, max(3, repeat // 2))
        rows.append({"item": name, "resolve_us": 1e6 * t_py / m,
                     "njit_kernel_ns": 1e9 * t_njit / n, "ratio": (t_py / m) / (t_njit / n)})
    return rows


_COLD_SCRIPT = """
import time, numpy as np
t0 = time.perf_counter()
import rbimpact
t_import = time.perf_counter() - t0
t0 = time.perf_counter()
for name, p in {settings!r}.items():
    rbimpact.Law(name, **p).resolve([-1.0, 1.0], [[2.5, -1.5], [-1.5, 2.5]])
print(t_import, time.perf_counter() - t0)
"""


def bench_compile():
    """Start-up: ``import rbimpact`` and the first 2D resolve of every law in a new process,
    with an empty Numba cache (compilation) and then with the warm on-disk cache."""
    import subprocess
    import sys
    import tempfile
    import os

    rows = []
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        code = _COLD_SCRIPT.format(settings=LAW_SETTINGS)
        for label in ("empty cache", "warm cache"):
            t0 = time.perf_counter()
            out = subprocess.run([sys.executable, "-c", code], env=env, check=True,
                                 capture_output=True, text=True).stdout.split()
            wall = time.perf_counter() - t0
            rows.append({"item": f"first resolve of the 5 laws, {label}", "import_s": float(out[0]),
                         "first_calls_s": float(out[1]), "process_wall_s": wall})
    for r in rows:  # ratio: against the empty cache (compilation)
        r["vs_empty_cache"] = r["first_calls_s"] / rows[0]["first_calls_s"]
    from .bench_compile import bench_compile_scenes
    return rows + bench_compile_scenes()


#: the stepper's target rate on the elastic bouncing ball (impacts per second)
STEPPER_TARGET = 1e6


def bench_stepper(repeat=5, n_elastic=100_000, tosses=200, with_3d=True):
    """Warm event rates of the 2D stepper (elastic bouncing_ball with ``n_elastic`` impacts,
    falling_rod, ...) and, with ``with_3d``, of the 3D stepper (die_toss, and the die_toss
    batch over ``tosses`` random tosses). Ratios: ``vs_target`` (elastic ball against 1 M
    impacts/s) and ``per_impact_vs_elastic`` (time per impact against the elastic ball's);
    the last 2D row is the fixed cost of one ``run()`` call (a run with no event) and of
    building the ``Simulation``, against one impact of the elastic ball."""
    import warnings
    from . import scenarios

    rows = []
    cases = [
        (f"bouncing_ball elastic, {n_elastic:.0e} impacts", dict(elastic=True), 1e9, n_elastic),
        ("bouncing_ball e=0.8 to rest", {}, None, None),
        ("falling_rod (routh)", {}, None, None),
        ("falling_rod (kane_levinson)", dict(law="kane_levinson"), None, None),
        ("spinning_ball (two balls, rough)", {}, None, None),
    ]
    for label, params, t_end, max_events in cases:
        name = label.split()[0]
        sc = scenarios.get(name, **params)
        sim = sc.simulation()
        kw = {"max_events": max_events or sc.max_events}

        def run():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                return sim.run(t_end or sc.t_end, **kw)

        t0 = time.perf_counter()
        res = run()
        first = time.perf_counter() - t0
        t = _median_time(run, repeat)
        rows.append({"item": label, "impacts": int(res.n_impacts), "events": len(res.events),
                     "run_s": t, "impacts_per_s": res.n_impacts / t, "first_call_s": first})
    per_impact = rows[0]["run_s"] / max(rows[0]["impacts"], 1)
    rows[0]["vs_target"] = rows[0]["impacts_per_s"] / STEPPER_TARGET
    for r in rows:
        r["per_impact_vs_elastic"] = r["run_s"] / max(r["impacts"], 1) / per_impact
    # fixed cost: a run that ends before the first event, and building the Simulation
    sc = scenarios.get("bouncing_ball", law="kane_levinson")
    sim = sc.simulation()
    t_run = _median_time(lambda: sim.run(1e-3), max(repeat, 20))
    t_build = _median_time(sc.simulation, max(repeat, 20))
    rows.append({"item": "fixed cost of run() (no event)", "impacts": 0, "events": 0,
                 "run_s": t_run, "build_s": t_build, "per_impact_vs_elastic": t_run / per_impact})
    if with_3d:
        from .bench3d import bench_stepper3d
        for r in bench_stepper3d(repeat=max(1, repeat // 2), tosses=tosses):
            if "time_s" in r:
                r["run_s"] = r.pop("time_s")
                r["first_call_s"] = r.pop("first_run_s")
                r["per_impact_vs_elastic"] = r["run_s"] / max(r["impacts"], 1) / per_impact
            else:
                r["per_impact_vs_elastic"] = 1.0 / r["impacts_per_s"] / per_impact
            rows.append(r)
    return rows


def bench_rotation3d(repeat=5):
    """``bench3d.bench_rotation3d`` rows, with the ratio each is judged by: the orientation
    error over ``rot_tol`` (integrator ladder) and the run time against the tightest
    tolerance's."""
    from .bench3d import bench_rotation3d as rot
    rows = rot(repeat=repeat)
    ladder = [r for r in rows if r["rot_tol"] > 0]
    t_ref = ladder[-1]["time_s"] if ladder else 1.0
    for r in rows:
        if r["rot_tol"] > 0:
            r["error_over_tol"] = r["orientation_error_rad"] / r["rot_tol"]
        r["time_vs_tightest"] = r["time_s"] / t_ref
    return rows


def bench_pymunk(repeat=3, dt=1e-4, dts=None):
    """rbimpact against pymunk on bouncing_ball (first 5 impacts): pymunk at ``dt`` and at
    its neighbours on the ladder, rbimpact exact; time and error ratios (pymunk over
    rbimpact) from one run, stored in each row."""
    from .crosscheck import crosscheck_report
    _, rows = crosscheck_report("bouncing_ball", dts=dts or (1e-3, dt, 1e-5), repeat=repeat)
    exact = next(r for r in rows if r["engine"] == "rbimpact")
    for r in rows:
        r["time_ratio"] = r["run_time_s"] / exact["run_time_s"]
        r["error_ratio"] = r["error_m"] / max(exact["error_m"], 1e-300)
    return rows


PAY_SCENES = {  # label -> (scenario, parameters): what "pay only for what is used" compares
    "one ball, frictionless": ("bouncing_ball", {}),
    "two balls, rough (pair search, friction)": ("spinning_ball", {}),
}

_PAY_SCRIPT = """
import sys, time, json
t0 = time.perf_counter()
from rbimpact import scenarios
sc = scenarios.get({name!r}, **{params!r})
sim = sc.simulation()
r = sim.run(sc.t_end, max_events=sc.max_events)
first = time.perf_counter() - t0
mods = sorted(m for m in sys.modules if m.startswith("rbimpact.kernels.")
              and m.rsplit(".", 1)[1] in ("stepper3d", "flight3d", "toi3d", "pivot3d"))
import numba
from numba.core.registry import CPUDispatcher
compiled_3d = 0
for m in list(sys.modules.values()):
    if getattr(m, "__name__", "").startswith("rbimpact.kernels."):
        for k, f in vars(m).items():
            if isinstance(f, CPUDispatcher) and ("3d" in k) and f.py_func.__module__ == m.__name__:
                compiled_3d += len(f.signatures)
print(json.dumps({{"first_s": first, "impacts": int(r.n_impacts), "modules_3d": mods,
                   "compiled_3d": compiled_3d}}))
"""


def bench_pay(repeat=5, cold=True):
    """Pay only for what is used: a frictionless one-ball scene (mu = 0: the law's
    frictionless path; one body: no pair search) against a rough two-ball scene. For each:
    a new process with an empty Numba cache (``cold``; else the current cache) times the
    first run (compilation included) and counts the 3D kernels it compiled or imported (a
    2D scene: none); then warm runs in this process give the time per impact. Ratios:
    one ball over the full scene."""
    import os
    import subprocess
    import sys
    import tempfile
    import warnings
    from . import scenarios

    rows = []
    with tempfile.TemporaryDirectory() as cache:
        for label, (name, params) in PAY_SCENES.items():
            env = {**os.environ, "RBIMPACT_LOOP": "scene"}     # what a user's scene runs
            if cold:
                env["NUMBA_CACHE_DIR"] = os.path.join(cache, name)  # empty
            code = _PAY_SCRIPT.format(name=name, params=params)
            t0 = time.perf_counter()
            out = subprocess.run([sys.executable, "-c", code], env=env, check=True,
                                 capture_output=True, text=True).stdout
            wall = time.perf_counter() - t0
            info = json.loads(out.strip().splitlines()[-1])
            sc = scenarios.get(name, **params)
            sim = sc.simulation()
            sim.loop = "scene"

            def run():
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    return sim.run(sc.t_end, max_events=sc.max_events)

            res = run()
            t = _median_time(run, repeat)
            rows.append({"item": f"{label} ({name})", "cache": "empty" if cold else "warm",
                         "first_run_s": info["first_s"], "process_wall_s": wall,
                         "compiled_3d_kernels": info["compiled_3d"],
                         "modules_3d_imported": len(info["modules_3d"]),
                         "impacts": int(res.n_impacts), "run_s": t,
                         "per_impact_s": t / max(res.n_impacts, 1)})
    one, full = rows
    for r in rows:
        r["first_run_vs_full"] = r["first_run_s"] / full["first_run_s"]
        r["per_impact_vs_full"] = r["per_impact_s"] / full["per_impact_s"]
    return rows


def _print_stepper(rows):
    print("Stepper, warm (median of repeats; first call includes loading or compiling code);")
    print(f"ratios: elastic ball against the target {STEPPER_TARGET:.0e} impacts/s, and time per "
          f"impact against the elastic ball's")
    print(f"{'scene':<52}{'impacts':>9}{'run ms':>10}{'M impacts/s':>13}{'per impact':>12}"
          f"{'first s':>9}")
    for r in rows:
        rate = f"{r['impacts_per_s'] / 1e6:.3f}" if "impacts_per_s" in r else ""
        ms = f"{1e3 * r['run_s']:.3f}" if "run_s" in r else ""
        first = f"{r['first_call_s']:.2f}" if "first_call_s" in r else ""
        extra = ""
        if "vs_target" in r:
            extra = f"  ({r['vs_target']:.2f} x target)"
        if "build_s" in r:
            extra = f"  (building the Simulation: {1e6 * r['build_s']:.0f} us)"
        if "tosses_per_s" in r:
            extra = (f"  ({r['tosses_per_s']:.1f} tosses/s, {r['unresolved']} unresolved, "
                     f"faces {r['faces']})")
        print(f"{r['item']:<52}{r.get('impacts', ''):>9}{ms:>10}{rate:>13}"
              f"{r['per_impact_vs_elastic']:>11.2f}x{first:>9}{extra}")


def _print_pymunk(rows):
    print("rbimpact against pymunk, bouncing_ball (first 5 impacts; error: max distance of the")
    print("centre of mass from the exact trajectory, m; run time median of repeats)")
    print(f"{'engine':<10}{'setting':<14}{'run time s':>12}{'error m':>11}{'time ratio':>12}"
          f"{'error ratio':>13}")
    for r in rows:
        print(f"{r['engine']:<10}{r['setting']:<14}{r['run_time_s']:>12.3g}{r['error_m']:>11.2e}"
              f"{r['time_ratio']:>12.0f}{r['error_ratio']:>13.1e}")
    print("(ratios: pymunk / rbimpact; rbimpact's error is round-off against the exact solution)")


def _print_rotation3d(rows):
    from .bench3d import format_rows
    print("Torque-free 3D rotation: integrator error against rot_tol (reference rot_tol = "
          "1e-14), energy and momentum drift; closed form against the integrator")
    print(format_rows(rows))


def _print_pay(rows):
    print("Pay only for what is used: first run in a new process (compilation included), 3D "
          "kernels it compiled/imported, warm time per impact; ratios against the full scene")
    print(f"{'scene':<58}{'cache':>7}{'first s':>9}{'x full':>8}{'3D kernels':>12}"
          f"{'us/impact':>11}{'x full':>8}")
    for r in rows:
        print(f"{r['item']:<58}{r['cache']:>7}{r['first_run_s']:>9.2f}"
              f"{r['first_run_vs_full']:>8.2f}"
              f"{r['compiled_3d_kernels'] + r['modules_3d_imported']:>12}"
              f"{1e6 * r['per_impact_s']:>11.2f}{r['per_impact_vs_full']:>8.2f}")


def _print_overhead(rows):
    print("Per-call cost of one 2D impact (median): Law.resolve from Python against")
    print("Law.kernel called from a user's njit loop")
    print(f"{'law':<20}{'Law.resolve us':>16}{'njit kernel ns':>16}{'ratio':>10}")
    for r in rows:
        print(f"{r['item']:<20}{r['resolve_us']:>16.2f}{r['njit_kernel_ns']:>16.1f}"
              f"{r['ratio']:>10.0f}")


def _print_compile(rows):
    print("Start-up in a new process (s)")
    print(f"{'what':<44}{'import':>9}{'first calls':>13}{'process':>10}")
    for r in rows:
        if "import_s" in r:
            print(f"{r['item']:<44}{r['import_s']:>9.3f}{r['first_calls_s']:>13.3f}"
                  f"{r['process_wall_s']:>10.2f}  ({r['vs_empty_cache']:.3f} x empty cache)")
    print("\nA scene's first run in a new process: empty cache (cold) and warm (s, whole "
          "command); functions compiled cold")
    print(f"{'what':<30}{'cold':>7}{'cold CPU':>10}{'warm':>7}{'warm CPU':>10}"
          f"{'functions':>11}{'3D':>5}  laws")
    for r in rows:
        if "cold_s" in r:
            print(f"{r['item']:<30}{r['cold_s']:>7.1f}{r['cold_cpu_s']:>10.1f}"
                  f"{r['warm_s']:>7.2f}{r['warm_cpu_s']:>10.2f}{r['functions']:>11d}"
                  f"{r['functions_3d']:>5d}  {r['laws']}")


def _print_laws(rows):
    print("Batched law throughput (median of repeats; ratios measured in this run).")
    print("'<law> <d>D' is the public Law.resolve_batch (validation, v_f, dE, energy flags);")
    print("'of minimal' compares it with the minimal Numba loop over the same law core")
    print(f"{'item':<36}{'threads':>8}{'M contacts/s':>14}{'x NumPy KL2D':>14}{'of copy':>10}"
          f"{'of minimal':>12}")
    for r in rows:
        ratio = f"{r['vs_numpy_kl2d']:.1f}" if "vs_numpy_kl2d" in r else ""
        copy = f"{100 * r['vs_copy']:.0f}%" if "vs_copy" in r else ""
        mini = f"{100 * r['vs_minimal']:.0f}%" if "vs_minimal" in r else ""
        print(f"{r['item']:<36}{r['threads']:>8}{r['contacts_per_s'] / 1e6:>14.2f}"
              f"{ratio:>14}{copy:>10}{mini:>12}")


def _print_routh3d(rows):
    print("Routh 3D, DESIGN §5 swerve case: error of v_f (max abs, m/s; and relative to |v|)")
    print("against tol = 1e-14, run time per impact (Law.resolve_batch, median, one thread)")
    print(f"{'tol':>8}{'error':>12}{'rel error':>12}{'us/impact':>12}{'impacts/s':>12}")
    for r in rows:
        print(f"{r['tol']:>8.0e}{r['error']:>12.2e}{r['rel_error']:>12.2e}"
              f"{1e6 * r['time_per_impact_s']:>12.3f}{r['impacts_per_s']:>12.3g}")


def _csv_rowwise(res, path):
    """The CSV writer as it was before ``to_csv`` was vectorized (csv.writer over rows,
    ``repr`` of floats): the reference ``bench sweep`` times ``to_csv`` against."""
    import csv
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(res.FIELDS_CSV)
        for ev in res.events:
            vectors = [float(x) for name in res._EVENT_VECTORS for x in ev[name]]
            row = (float(ev["t"]), str(ev["kind"]), int(ev["a"]), int(ev["b"]), *vectors,
                   int(ev["mode"]), float(ev["dE"]), int(ev["cluster"]))
            w.writerow([repr(x) if isinstance(x, float) else x for x in row])


def bench_sweep(repeat=3, seeds=400, workers=(1, 2), csv_events=1_000_000,
                old_events=100_000, tosses=100, pairs=None):
    """The command ``rbimpact sweep die_toss --seeds SEEDS --workers W --out T.parquet``
    for each ``W`` in ``workers``, timed as a whole new process (interpreter start,
    imports, Numba cache load, the LocalCluster's start and stop, the table written):
    ``pairs`` rounds (default ``max(3, repeat)``), the commands in turn within a round, the
    median wall time of each and the median of the per-round ratios against the first;
    start-up and runs (``setup_s``, ``compute_s``) are the medians of what the command
    prints; whether the tables (``run_s`` aside) are identical; the 1-minute load average
    before and after. Then ``to_csv`` per 1e6 events against the former row-by-row
    writer, on a 3D log of ``csv_events`` events (the events of ``tosses`` die tosses,
    repeated with shifted times); the former writer is timed on ``old_events`` of them and
    scaled (its cost is linear), after checking that both write the same bytes. Needs the
    sweep extra."""
    import copy
    import os
    import re
    import subprocess
    import sys
    import tempfile
    from . import scenarios
    from .result_base import require
    pd = require("pandas", "bench sweep")

    pairs = max(3, repeat) if pairs is None else max(1, int(pairs))
    load = [os.getloadavg()[0]]
    walls = {w: [] for w in workers}
    split = {w: [] for w in workers}
    tables, same_runs = {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(pairs):
            for w in workers:
                out = os.path.join(tmp, f"w{w}_{k}.parquet")
                cmd = [sys.executable, "-m", "rbimpact.cli", "sweep", "die_toss", "--seeds",
                       str(seeds), "--workers", str(w), "--out", out]
                t0 = time.perf_counter()
                proc = subprocess.run(cmd, capture_output=True, text=True,
                                      env={**os.environ, "RBIMPACT_PROGRESS": "0"})
                walls[w].append(time.perf_counter() - t0)
                if proc.returncode != 0:
                    raise RuntimeError(f"bench sweep: {' '.join(cmd[1:])} failed: "
                                       f"{proc.stderr.strip()[-500:]}")
                m = re.search(r"start-up ([0-9.]+) s, runs ([0-9.]+) s", proc.stdout)
                split[w].append((float(m[1]), float(m[2])) if m else (np.nan, np.nan))
                df = pd.read_parquet(out).drop(columns="run_s")
                tables.setdefault(w, df)
                same_runs[w] = same_runs.get(w, True) and bool(df.equals(tables[w]))
    load.append(os.getloadavg()[0])
    first = workers[0]
    rows = []
    for w in workers:
        t = tables[w]
        rows.append({"item": f"sweep die_toss --seeds {seeds} --workers {w}", "workers": w,
                     "wall_s": float(np.median(walls[w])), "wall_min_s": min(walls[w]),
                     "wall_max_s": max(walls[w]), "runs": len(walls[w]),
                     "setup_s": float(np.median([x[0] for x in split[w]])),
                     "compute_s": float(np.median([x[1] for x in split[w]])),
                     "speedup": float(np.median([a / b for a, b in
                                                 zip(walls[first], walls[w])])),
                     "identical_table": same_runs[w] and same_runs[first]
                     and bool(t.equals(tables[first])),
                     "errors": int((t["status"] == "error").sum()),
                     "load_before": load[0], "load_after": load[1]})
    for r in rows:
        r["compute_speedup"] = rows[0]["compute_s"] / r["compute_s"]

    logs = [scenarios.get("die_toss", seed=k).simulate() for k in range(tosses)]
    base = np.concatenate([r.events for r in logs])
    span = max(r.t_end for r in logs)
    base["t"] += np.repeat(np.arange(tosses) * span, [len(r.events) for r in logs])
    k = -(-csv_events // len(base))
    big = np.tile(base, k)[:csv_events].copy()
    big["t"] += np.repeat(np.arange(k) * span * tosses, len(base))[:csv_events]
    res = copy.copy(logs[0])
    with tempfile.TemporaryDirectory() as tmp:
        new_path, old_path = os.path.join(tmp, "new.csv"), os.path.join(tmp, "old.csv")
        res.events = big[:old_events]
        _csv_rowwise(res, old_path)
        res.to_csv(new_path)
        same = open(old_path, "rb").read() == open(new_path, "rb").read()
        t_old = _median_time(lambda: _csv_rowwise(res, old_path), max(1, repeat)) \
            * 1e6 / old_events
        res.events = big
        t_new = _median_time(lambda: res.to_csv(new_path), max(1, repeat)) * 1e6 / csv_events
        size = os.path.getsize(new_path)
    rows.append({"item": f"to_csv, 3D die_toss log ({len(big):.0e} events, "
                         f"{size / 1e6:.0f} MB)", "old_s_per_1e6": t_old,
                 "new_s_per_1e6": t_new, "speedup": t_old / t_new, "same_bytes": same})
    return rows


def _print_sweep(rows):
    r0 = next((r for r in rows if "wall_s" in r), None)
    if r0 is not None:
        print(f"Sweeps: die_toss over seeds, each a whole command in a new process (start-up, "
              f"imports, Numba cache load, the LocalCluster's start and stop, the table "
              f"written), {r0['runs']} runs each, in turn; median wall time (min-max), "
              f"median of the paired ratios against the first row; start-up and runs: what "
              f"the command reports (its process start and imports excluded); 1-minute load "
              f"average {r0['load_before']:.2f} before, {r0['load_after']:.2f} after")
        print(f"{'item':<44}{'wall s':>8}{'(min-max)':>14}{'start-up s':>12}{'runs s':>8}"
              f"{'x wall':>8}{'x runs':>8}  same table")
    for r in rows:
        if "wall_s" in r:
            span = "(%.2f-%.2f)" % (r["wall_min_s"], r["wall_max_s"])
            print(f"{r['item']:<44}{r['wall_s']:>8.2f}{span:>14}{r['setup_s']:>12.2f}"
                  f"{r['compute_s']:>8.2f}{r['speedup']:>8.2f}{r['compute_speedup']:>8.2f}"
                  f"  {'yes' if r['identical_table'] else 'NO'}"
                  + (f" ({r['errors']} errors)" if r["errors"] else ""))
    for r in rows:
        if "old_s_per_1e6" in r:
            print(f"{r['item']}: former writer {r['old_s_per_1e6']:.2f} s per 1e6 events, "
                  f"to_csv {r['new_s_per_1e6']:.2f} s ({r['speedup']:.1f}x; "
                  f"{'same bytes' if r['same_bytes'] else 'OUTPUT DIFFERS'})")


#: subcommand -> the figures it runs (key, function, printer), in order
SECTIONS = ("laws", "overhead", "routh3d", "rotation3d", "stepper", "pymunk", "compile", "pay",
            "sweep", "manybody", "memory")
WHAT = {
    "laws": ("laws", "overhead"),
    "routh3d": ("routh3d",),
    "rotation3d": ("rotation3d",),
    "stepper": ("stepper",),
    "crosscheck": ("pymunk",),
    "compile": ("compile",),
    "pay": ("pay",),
    "sweep": ("sweep",),
    "manybody": ("manybody",),
    "memory": ("memory",),
    "all": SECTIONS,
}


def _json_default(x):
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    raise TypeError(f"not serialisable: {x!r}")


def main(what="laws", repeat=7, json_path=None):
    """Run the figures of ``what`` (a key of ``WHAT``), print them and optionally write
    them all to ``json_path`` (one list of rows per figure). ``repeat``: an integer >= 1."""
    if what not in WHAT:
        raise ValueError(f"bench: what must be one of {', '.join(WHAT)}, got {what!r}")
    from ._validate import integer
    repeat = integer("bench: repeat", repeat)      # >= 1: a median of nothing is nan
    from . import bench_manybody as mb                # light: numpy and time only
    from . import bench_memory as bm
    runners = {
        "laws": (lambda: bench_laws(repeat=repeat), _print_laws),
        "overhead": (lambda: bench_overhead(repeat=repeat), _print_overhead),
        "routh3d": (lambda: bench_routh3d(repeat=repeat), _print_routh3d),
        "rotation3d": (lambda: bench_rotation3d(repeat=max(1, repeat // 2)), _print_rotation3d),
        "stepper": (lambda: bench_stepper(repeat=max(1, repeat // 2)), _print_stepper),
        "pymunk": (lambda: bench_pymunk(repeat=max(3, repeat // 2)), _print_pymunk),
        "compile": (bench_compile, _print_compile),
        "pay": (lambda: bench_pay(repeat=max(1, repeat // 2)), _print_pay),
        "sweep": (lambda: bench_sweep(repeat=max(1, repeat // 4)), _print_sweep),
        "manybody": (lambda: mb.bench_manybody(repeat=max(1, repeat // 4)), mb.print_manybody),
        "memory": (bm.bench_memory, bm.print_memory),
    }
    out = {}
    for key in WHAT[what]:
        run, show = runners[key]
        if out:
            print()
        out[key] = run()
        show(out[key])
    if json_path:
        with open(json_path, "w") as fh:
            json.dump(out, fh, indent=2, default=_json_default)
    return 0
