"""Random sequential insertion of non-overlapping equal disks/spheres (set-up of
``rbimpact.manybody.random_gas``): candidates are accepted in order when they overlap
no accepted body, checked on a grid of cells of side >= 2r."""
import numpy as np
from numba import njit


@njit(cache=True, error_model="numpy")
def rsa_place(cand, x, got, radius, L):
    """Accept candidates ``cand`` (m, dim) (centres in [r, L - r], m) into ``x`` (n, dim)
    after the ``got`` bodies already there, while they do not overlap (centre distance
    >= 2r); returns the new count (stops at n)."""
    n, dim = x.shape
    nc = max(1, int(L / (2.0 * radius)))
    cs = L / nc
    ncell = nc ** dim
    head = np.full(ncell, -1, np.int64)
    nxt = np.full(n, -1, np.int64)
    sig2 = 4.0 * radius * radius
    for i in range(got):
        c = 0
        for a in range(dim - 1, -1, -1):
            c = c * nc + min(nc - 1, int(x[i, a] / cs))
        nxt[i] = head[c]
        head[c] = i
    for k in range(cand.shape[0]):
        if got >= n:
            break
        ci = np.empty(3, np.int64)
        ci[:] = 0
        for a in range(dim):
            ci[a] = min(nc - 1, int(cand[k, a] / cs))
        ok = True
        lo2 = ci[2] - 1 if dim == 3 else 0
        hi2 = ci[2] + 1 if dim == 3 else 0
        for c2 in range(max(lo2, 0), min(hi2, nc - 1) + 1):
            for c1 in range(max(ci[1] - 1, 0), min(ci[1] + 1, nc - 1) + 1):
                for c0 in range(max(ci[0] - 1, 0), min(ci[0] + 1, nc - 1) + 1):
                    j = head[c0 + nc * (c1 + (nc * c2 if dim == 3 else 0))]
                    while j >= 0 and ok:
                        d = 0.0
                        for a in range(dim):
                            d += (cand[k, a] - x[j, a]) ** 2
                        if d < sig2:
                            ok = False
                        j = nxt[j]
        if ok:
            for a in range(dim):
                x[got, a] = cand[k, a]
            c = ci[0] + nc * (ci[1] + (nc * ci[2] if dim == 3 else 0))
            nxt[got] = head[c]
            head[c] = got
            got += 1
    return got
