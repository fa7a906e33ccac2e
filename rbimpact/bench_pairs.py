"""Throughput of the 3D body-body pair kernels (``kernels/pair3d*.py``): contact frames and
times of impact per second for each pair of shapes, in compiled loops (warm, after
compilation), one core. Run ``python -m rbimpact.bench_pairs`` (not wired into the CLI).

``bench_pairs3d``  rows ``{"pair", "frames_per_s", "tois_per_s", "toi_hits", "toi_failed"}``:
                   ``pair_frame`` on ``n`` random poses (a third apart, a third touching
                   to 1e-3 of the size, a third overlapping), and ``pair_toi`` on ``n_toi``
                   throws aimed at each other (spins up to 10 rad/s x size / speed, gravity
                   on one body), ``toi_hits`` the fraction that hit, ``toi_failed`` the
                   number of searches that did not end ``TOI_OK`` or ``TOI_MISSED`` (an
                   aimed throw may start overlapping). Medians of ``repeat`` runs.
"""
import math
import time

import numpy as np
from numba import njit

SHAPES = ("sphere", "box", "capsule")
PAIRS = tuple((a, b) for i, a in enumerate(SHAPES) for b in SHAPES[i:])


def random_body(rng, name):
    """``(kind, rad, hx, hy, hz)`` of a random body of roughly unit size (also drawn by
    tests/test_pair3d.py)."""
    from .kernels.pair3d_shape import SH_BOX, SH_CAPSULE, SH_SPHERE
    if name == "sphere":
        return (SH_SPHERE, rng.uniform(0.2, 1.0), 0.0, 0.0, 0.0)
    if name == "box":
        h = rng.uniform(0.15, 1.0, 3)
        return (SH_BOX, 0.0, h[0], h[1], h[2])
    return (SH_CAPSULE, rng.uniform(0.1, 0.5), 0.0, 0.0, rng.uniform(0.2, 1.0))


def random_quat(rng):
    """A uniformly random unit quaternion."""
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def _rotation(body):
    from . import shapes3d
    from .pair3d_input import rotation
    k, r, hx, hy, hz = body
    if k == 0:
        return rotation(shapes3d.Sphere(r))
    if k == 2:
        return rotation(shapes3d.Capsule(2 * hz, r))
    return rotation(shapes3d.Box3D((2 * hx, 2 * hy, 2 * hz)))


def _tables(rng, pair, n):
    """Body tables ``geo`` float64[n, 2, 5] (kind, rad, hx, hy, hz), rotations float64[n,
    2, 5] (rk, axis, I1, I2, I3) and state rows float64[n, 2, 19]."""
    geo = np.zeros((n, 2, 5))
    rot = np.zeros((n, 2, 5))
    st = np.zeros((n, 2, 19))
    for i in range(n):
        a, b = pair if i % 2 == 0 else pair[::-1]
        for j, name in enumerate((a, b)):
            geo[i, j] = random_body(rng, name)
            rot[i, j] = _rotation(tuple(geo[i, j]))
            st[i, j, 3:7] = random_quat(rng)
    return geo, rot, st


def _compile_loops():
    from .kernels.flight3d import N_WS
    from .kernels.pair3d import pair_frame
    from .kernels.pair3d_toi import pair_toi

    @njit
    def frames(geo, st, fr, fe):
        acc = 0.0
        for i in range(geo.shape[0]):
            acc += pair_frame(int(geo[i, 0, 0]), geo[i, 0, 1], geo[i, 0, 2], geo[i, 0, 3],
                              geo[i, 0, 4], st[i, 0], int(geo[i, 1, 0]), geo[i, 1, 1],
                              geo[i, 1, 2], geo[i, 1, 3], geo[i, 1, 4], st[i, 1], fr, fe)
        return acc

    @njit
    def tois(geo, rot, st, S, out, pa, pb):
        wsA = np.zeros(N_WS)
        wsB = np.zeros(N_WS)
        for i in range(geo.shape[0]):
            out[i, 0], c = pair_toi(
                int(geo[i, 0, 0]), geo[i, 0, 1], geo[i, 0, 2], geo[i, 0, 3], geo[i, 0, 4],
                st[i, 0], int(rot[i, 0, 0]), int(rot[i, 0, 1]), rot[i, 0, 2], rot[i, 0, 3],
                rot[i, 0, 4], wsA,
                int(geo[i, 1, 0]), geo[i, 1, 1], geo[i, 1, 2], geo[i, 1, 3], geo[i, 1, 4],
                st[i, 1], int(rot[i, 1, 0]), int(rot[i, 1, 1]), rot[i, 1, 2], rot[i, 1, 3],
                rot[i, 1, 4], wsB,
                0.0, S[i], 1e-14, 1e-15, 1e-9, 200000, 1e-12, 100000, pa, pb)
            out[i, 1] = c
    return frames, tois


def bench_pairs3d(n=20000, n_toi=2000, repeat=5, seed=0):
    """Rows per pair of shapes (see the module docstring)."""
    from .kernels.pair3d import N_FE, N_FR, pair_frame
    frames, tois = _compile_loops()
    rng = np.random.default_rng(seed)
    rows = []
    fr = np.zeros(N_FR)
    fe = np.zeros(N_FE, np.int64)
    for pair in PAIRS:
        geo, rot, st = _tables(rng, pair, n)
        # poses: B along a random direction at a gap drawn per third (far, touching, overlap)
        for i in range(n):
            u = rng.normal(size=3)
            u /= np.linalg.norm(u)
            size = sum(geo[i, j, 1] + math.sqrt(float(geo[i, j, 2:] @ geo[i, j, 2:]))
                       for j in range(2))
            target = (rng.uniform(0.05, 1.0) * size, rng.uniform(-1e-3, 1e-3) * size,
                      -rng.uniform(0.01, 0.2) * size)[i % 3]
            lo, hi = 0.0, 3.0 * size
            for _ in range(40):
                mid = 0.5 * (lo + hi)
                st[i, 1, 0:3] = mid * u
                g = pair_frame(int(geo[i, 0, 0]), *geo[i, 0, 1:], st[i, 0],
                               int(geo[i, 1, 0]), *geo[i, 1, 1:], st[i, 1], fr, fe)
                lo, hi = (mid, hi) if g < target else (lo, mid)
        frames(geo[:10], st[:10], fr, fe)
        times = []
        for _ in range(repeat):
            t = time.perf_counter()
            frames(geo, st, fr, fe)
            times.append(time.perf_counter() - t)
        f_rate = n / float(np.median(times))
        # throws
        geo, rot, st = _tables(rng, pair, n_toi)
        S = np.zeros(n_toi)
        for i in range(n_toi):
            size = sum(geo[i, j, 1] + math.sqrt(float(geo[i, j, 2:] @ geo[i, j, 2:]))
                       for j in range(2))
            u = rng.normal(size=3)
            u /= np.linalg.norm(u)
            speed = rng.uniform(0.5, 2.0)
            S[i] = 4.0 * size / speed
            st[i, 0, 0:3] = 0.0
            st[i, 0, 7:10] = speed * u
            st[i, 0, 13:16] = (0.0, 0.0, -9.81)
            st[i, 1, 7:10] = -speed * u * rng.uniform(0, 1)
            for j in range(2):
                st[i, j, 10:13] = rng.normal(size=3) * rng.uniform(0, 10) * speed / size
            s = 0.5 * S[i]
            xa = st[i, 0, 7:10] * s + 0.5 * st[i, 0, 13:16] * s * s
            xb = st[i, 1, 7:10] * s
            st[i, 1, 0:3] = xa - xb + rng.normal(size=3) * 0.3 * size
        out = np.zeros((n_toi, 2))
        pa = np.zeros(19)
        pb = np.zeros(19)
        tois(geo[:5], rot[:5], st[:5], S[:5], out[:5], pa, pb)
        times = []
        for _ in range(repeat):
            t = time.perf_counter()
            tois(geo, rot, st, S, out, pa, pb)
            times.append(time.perf_counter() - t)
        rows.append({"pair": "-".join(pair), "frames_per_s": f_rate,
                     "tois_per_s": n_toi / float(np.median(times)),
                     "toi_hits": float(np.mean(np.isfinite(out[:, 0]) & (out[:, 1] == 0))),
                     "toi_failed": int(np.sum((out[:, 1] != 0) & (out[:, 1] != 1)))})
    return rows


def print_pairs3d(rows):
    print(f"{'pair':<18}{'frames/s':>12}{'tois/s':>12}{'hit':>7}{'failed':>8}")
    for r in rows:
        print(f"{r['pair']:<18}{r['frames_per_s']:>12.3g}{r['tois_per_s']:>12.3g}"
              f"{r['toi_hits']:>7.2f}{r['toi_failed']:>8d}")


if __name__ == "__main__":     # pragma: no cover
    print_pairs3d(bench_pairs3d())
