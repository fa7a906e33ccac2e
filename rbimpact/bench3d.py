"""3D benchmarks (the lead wires them into ``rbimpact bench rotation3d`` and
``rbimpact bench stepper``). Every figure is a median of repeats; rows are dicts.

``bench_rotation3d``  torque-free rotation of a general (three different moments) body:
                      the error of the controlled integrator against a tight reference,
                      for a ladder of ``rot_tol``, with its run time and its drift of
                      energy and angular momentum; and the closed-form precession
                      (axisymmetric) against the integrator.
``bench_stepper3d``   die_toss: impacts per second of the event-driven 3D stepper (warm,
                      after compilation; compile time of the first run), and tosses per
                      second of the batch mode.
"""
import time

import numpy as np

#: body of the rotation benchmark: principal moments (kg m^2), initial angular velocity
#: (rad/s, world frame, near the unstable middle axis: a tumbling flip), duration (s)
ROT_INERTIA = (1.0, 2.0, 3.0)
ROT_OMEGA = (0.2, 5.0, 0.3)
ROT_T = 10.0
ROT_TOLS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
ROT_REF_TOL = 1e-14


def _state(q, w):
    st = np.zeros(19)
    st[3:7] = np.asarray(q, float) / np.linalg.norm(q)
    st[10:13] = w
    return st


def _rotate_angle(q1, q2):
    """Angle (rad) of the rotation between two unit quaternions."""
    w1, v1 = q1[0], np.asarray(q1[1:])
    w2, v2 = q2[0], np.asarray(q2[1:])
    # conj(q1) q2
    w = w1 * w2 + float(v1 @ v2)
    v = w1 * v2 - w2 * v1 - np.cross(v1, v2)
    return 2.0 * float(np.arctan2(np.linalg.norm(v), abs(w)))


def _L_E(pose, I):
    from .kernels.flight3d import rotmat
    R = np.zeros((3, 3))
    rotmat(pose[3:7], R)
    wb = R.T @ pose[10:13]
    return R @ (np.asarray(I) * wb), 0.5 * float(wb @ (np.asarray(I) * wb))


def bench_rotation3d(repeat=5):
    """Rows: ``{"case", "rot_tol", "orientation_error_rad", "omega_error_rel",
    "energy_drift_rel", "momentum_drift_rel", "steps", "time_s"}`` for the integrator
    ladder (error against ``rot_tol = 1e-14``), then the axisymmetric closed form against
    the integrator at 1e-12 (both directions exact to round-off / tolerance)."""
    from .kernels.flight3d import N_WS, ROT_AXISYM, ROT_GENERAL, WS_NSTEP, pose_at
    I = ROT_INERTIA
    st = _state((1.0, 0.1, -0.2, 0.05), ROT_OMEGA)
    ws = np.zeros(N_WS)
    out = np.zeros(19)

    def run(tol):
        ws[0] = -1.0
        pose_at(st, ROT_GENERAL, 2, *I, ws, ROT_T, tol, 100_000_000, out)
        return out.copy(), int(ws[WS_NSTEP])

    run(1e-6)  # compile
    ref, _ = run(ROT_REF_TOL)
    L0, E0 = _L_E(st, I)
    rows = []
    for tol in ROT_TOLS:
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            res, steps = run(tol)
            times.append(time.perf_counter() - t0)
        L, E = _L_E(res, I)
        rows.append({"case": "general inertia (1, 2, 3), integrated", "rot_tol": tol,
                     "orientation_error_rad": _rotate_angle(res[3:7], ref[3:7]),
                     "omega_error_rel": float(np.linalg.norm(res[10:13] - ref[10:13])
                                              / np.linalg.norm(ref[10:13])),
                     "energy_drift_rel": abs(E - E0) / E0,
                     "momentum_drift_rel": float(np.linalg.norm(L - L0) / np.linalg.norm(L0)),
                     "steps": steps, "time_s": float(np.median(times))})
    # axisymmetric: closed form (exact) against the integrator
    Ia = (1.0, 1.0, 2.5)
    sa = _state((0.9, 0.1, 0.3, -0.2), (1.0, -2.0, 3.0))
    wa = np.zeros(N_WS)
    oa = np.zeros(19)
    pose_at(sa, ROT_AXISYM, 2, *Ia, wa, ROT_T, 1e-12, 100_000_000, oa)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        pose_at(sa, ROT_AXISYM, 2, *Ia, wa, ROT_T, 1e-12, 100_000_000, oa)
        times.append(time.perf_counter() - t0)
    wa[0] = -1.0
    og = np.zeros(19)
    pose_at(sa, ROT_GENERAL, 2, *Ia, wa, ROT_T, 1e-12, 100_000_000, og)
    L0, E0 = _L_E(sa, Ia)
    L, E = _L_E(oa, Ia)
    rows.append({"case": "axisymmetric (1, 1, 2.5), closed form vs integrator at 1e-12",
                 "rot_tol": 0.0, "orientation_error_rad": _rotate_angle(oa[3:7], og[3:7]),
                 "omega_error_rel": float(np.linalg.norm(oa[10:13] - og[10:13])
                                          / np.linalg.norm(og[10:13])),
                 "energy_drift_rel": abs(E - E0) / E0,
                 "momentum_drift_rel": float(np.linalg.norm(L - L0) / np.linalg.norm(L0)),
                 "steps": 0, "time_s": float(np.median(times))})
    return rows


def bench_stepper3d(repeat=3, tosses=200):
    """Rows: die_toss (default law, seed 0) impacts per second, warm, with the first
    (cold) run's time; the same for a Kane & Levinson die; and the batch mode's tosses per
    second over ``tosses`` random tosses (with its count of unresolved tosses)."""
    from . import scenarios
    from .scenarios.die_toss import die_toss_batch  # registers the scenario
    rows = []
    for law in ("chatterjee_ruina", "kane_levinson"):
        sc = scenarios.get("die_toss", law=law)
        t0 = time.perf_counter()
        r = sc.simulate()
        cold = time.perf_counter() - t0
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            r = sc.simulate()
            times.append(time.perf_counter() - t0)
        t = float(np.median(times))
        n = r.n_impacts
        rows.append({"item": f"die_toss {law} (seed 0)", "impacts": n,
                     "events": len(r.events), "time_s": t, "impacts_per_s": n / t,
                     "first_run_s": cold})
    counts = die_toss_batch(tosses, seed=1000, progress=False)
    rows.append({"item": f"die_toss batch, {tosses} random tosses (chatterjee_ruina)",
                 "tosses_per_s": tosses / counts["seconds"],
                 "impacts_per_s": counts["impacts"] / counts["seconds"],
                 "unresolved": counts["unresolved"],
                 "faces": [counts[f] for f in range(1, 7)]})
    return rows


def format_rows(rows):
    """Plain-text table of benchmark rows (for the command line)."""
    keys = []
    for r in rows:
        for k in r:
            if k not in keys:
                keys.append(k)

    def fmt(v):
        if isinstance(v, float):
            return f"{v:.3g}"
        return str(v)

    table = [[fmt(r.get(k, "")) for k in keys] for r in rows]
    widths = [max(len(k), *(len(row[j]) for row in table)) for j, k in enumerate(keys)]
    lines = ["  ".join(k.ljust(w) for k, w in zip(keys, widths)),
             "  ".join("-" * w for w in widths)]
    lines += ["  ".join(c.ljust(w) for c, w in zip(row, widths)) for row in table]
    return "\n".join(lines)
