"""Benchmarks: every figure is a median of repeats, judged by a ratio measured in the same run.

``rbimpact bench laws``     batched law throughput (contacts/s), 2D and 3D, one thread and
                            all threads, against NumPy Kane & Levinson 2D and a plain copy.
``rbimpact bench routh3d``  error of Routh 3D against run time on the DESIGN §5 swerve case.
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
    """Rows of batched throughput per law and dimension; one thread and all threads."""
    import numba
    from .kernels.batch import batch_2d, batch_3d
    from .laws import Law
    from .numpy_laws import kane_levinson_2d_numpy

    rows = []
    threads_all = numba.config.NUMBA_NUM_THREADS
    for d, batch in ((2, batch_2d), (3, batch_3d)):
        nd = n if d == 2 else n // 4
        v, W = random_contacts(nd, d)
        P, vf, dE = np.empty((nd, d)), np.empty((nd, d)), np.empty(nd)
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
                         "contacts_per_s": nd / t_np})
        for name, params in LAW_SETTINGS.items():
            law = Law(name, **params)
            table = law.params[None, :]
            for threads in sorted({1, threads_all}):
                numba.set_num_threads(threads)
                t = _median_time(lambda: batch(law.law_id, v, W, table, P, vf, dE, mode),
                                 repeat)
                row = {"item": f"{name} {d}D", "dim": d, "threads": threads,
                       "contacts_per_s": nd / t, "vs_copy": t_copy / t}
                if d == 2:
                    row["vs_numpy_kl2d"] = t_np / t
                rows.append(row)
            numba.set_num_threads(threads_all)
    return rows


def bench_routh3d(repeat=7, n=2000):
    """Rows of (tol, error of v_f against tol = 1e-14, run time per impact) on the swerve case."""
    from .kernels.batch import batch_3d
    from .laws import Law
    import numba

    v = np.repeat(np.array([SWERVE["v"]]), n, axis=0)
    W = np.repeat(np.array([SWERVE["W"]]), n, axis=0)
    P, vf, dE = np.empty((n, 3)), np.empty((n, 3)), np.empty(n)
    mode = np.empty(n, dtype=np.int64)
    ref = Law("routh", e=SWERVE["e"], mu=SWERVE["mu"], tol=1e-14).resolve(v[0], W[0]).v_f
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    rows = []
    try:
        for k in range(3, 13):
            law = Law("routh", e=SWERVE["e"], mu=SWERVE["mu"], tol=10.0 ** -k)
            table = law.params[None, :]
            t = _median_time(lambda: batch_3d(law.law_id, v, W, table, P, vf, dE, mode), repeat)
            rows.append({"tol": 10.0 ** -k, "error": float(np.abs(vf[0] - ref).max()),
                         "time_per_impact_s": t / n, "impacts_per_s": n / t})
    finally:
        numba.set_num_threads(threads)
    return rows


def bench_overhead(repeat=7, n=20000):
    """Per-call cost of one 2D impact: ``Law.resolve`` from Python, and ``Law.kernel`` called
    from a user's njit loop (the way a user's own stepper would call it)."""
    from numba import njit
    from .laws import Law

    v, W = random_contacts(n, 2, seed=1)
    rows = []
    for name, params in LAW_SETTINGS.items():
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
        m = 2000

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
    return rows


def bench_stepper(repeat=5):
    """Warm event rates of the 2D stepper: elastic bouncing_ball (1e5 impacts), falling_rod,
    and the figures that show a scene pays only for what it uses."""
    import warnings
    from . import scenarios

    rows = []
    cases = [
        ("bouncing_ball elastic, 1e5 impacts", dict(elastic=True), 1e9, 100_000),
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
    return rows


def bench_pymunk(repeat=3, dt=1e-4):
    """rbimpact against pymunk on bouncing_ball (first 5 impacts): pymunk at ``dt`` and at
    its best step on the ladder, rbimpact exact; time and error ratios from one run."""
    from .crosscheck import crosscheck_report
    _, rows = crosscheck_report("bouncing_ball", dts=(1e-3, dt, 1e-5), repeat=repeat)
    return rows


def _print_stepper(rows):
    print("2D stepper, warm (median of repeats; first call includes loading compiled code)")
    print(f"{'scene':<36}{'impacts':>9}{'events':>8}{'run ms':>10}{'M impacts/s':>13}"
          f"{'first call s':>14}")
    for r in rows:
        print(f"{r['item']:<36}{r['impacts']:>9}{r['events']:>8}{1e3 * r['run_s']:>10.2f}"
              f"{r['impacts_per_s'] / 1e6:>13.3f}{r['first_call_s']:>14.2f}")


def _print_pymunk(rows):
    print("rbimpact against pymunk, bouncing_ball (first 5 impacts; error: max distance of the")
    print("centre of mass from the exact trajectory, m; run time median of repeats)")
    exact = next(r for r in rows if r["engine"] == "rbimpact")
    print(f"{'engine':<10}{'setting':<14}{'run time s':>12}{'error m':>11}{'time ratio':>12}"
          f"{'error ratio':>13}")
    for r in rows:
        ratio_t = r["run_time_s"] / exact["run_time_s"]
        ratio_e = r["error_m"] / max(exact["error_m"], 1e-300)
        print(f"{r['engine']:<10}{r['setting']:<14}{r['run_time_s']:>12.3g}{r['error_m']:>11.2e}"
              f"{ratio_t:>12.0f}{ratio_e:>13.1e}")
    print("(ratios: pymunk / rbimpact; rbimpact's error is round-off against the exact solution)")


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
        print(f"{r['item']:<44}{r['import_s']:>9.3f}{r['first_calls_s']:>13.3f}"
              f"{r['process_wall_s']:>10.2f}")


def _print_laws(rows):
    print("Batched law throughput (median of repeats; ratios measured in this run)")
    print(f"{'item':<34}{'threads':>8}{'M contacts/s':>14}{'x NumPy KL2D':>14}{'of copy':>10}")
    for r in rows:
        ratio = f"{r['vs_numpy_kl2d']:.1f}" if "vs_numpy_kl2d" in r else ""
        copy = f"{100 * r['vs_copy']:.0f}%" if "vs_copy" in r else ""
        print(f"{r['item']:<34}{r['threads']:>8}{r['contacts_per_s'] / 1e6:>14.1f}"
              f"{ratio:>14}{copy:>10}")


def _print_routh3d(rows):
    print("Routh 3D, DESIGN §5 swerve case: error of v_f (max abs, m/s) against tol = 1e-14,")
    print("run time per impact (median, one thread)")
    print(f"{'tol':>8}{'error':>12}{'us/impact':>12}{'impacts/s':>12}")
    for r in rows:
        print(f"{r['tol']:>8.0e}{r['error']:>12.2e}{1e6 * r['time_per_impact_s']:>12.3f}"
              f"{r['impacts_per_s']:>12.3g}")


def main(what="laws", repeat=7, json_path=None):
    out = {}
    if what in ("laws", "all"):
        out["laws"] = bench_laws(repeat=repeat)
        _print_laws(out["laws"])
    for key, run, show in (("overhead", bench_overhead, _print_overhead),
                           ("routh3d", bench_routh3d, _print_routh3d),
                           ("stepper", bench_stepper, _print_stepper),
                           ("pymunk", bench_pymunk, _print_pymunk),
                           ("compile", bench_compile, _print_compile)):
        if what in (key, "all") or (what == "laws" and key == "overhead") or (
                what == "crosscheck" and key == "pymunk"):
            if out:
                print()
            out[key] = run() if key == "compile" else run(repeat=repeat)
            show(out[key])
    if json_path:
        with open(json_path, "w") as fh:
            json.dump(out, fh, indent=2)
    return 0
