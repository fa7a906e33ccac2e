"""The contacts of one instant, shared by the 2D and 3D steppers (issue 14: one instant
resolver): the contact table's columns and the grouping of the gathered contacts into
clusters that share a body (each cluster is then resolved by the chosen policy).

``c_i`` int64[MAXC, N_CI] holds one row per contact of the instant (columns ``CI_*``).
"""
from numba import njit

# c_i columns (the same in 2D and 3D)
CI_TYPE = 0          # 0: body-plane, 1: body-body (a round pair)
CI_A = 1             # body A
CI_B = 2             # plane index (CI_TYPE 0) or body B (CI_TYPE 1)
CI_FEAT = 3          # contact feature row of A (vertex or feature table)
CI_LAW = 4           # law row
CI_OFF = 5           # perforated during a sequential resolution
N_CI = 6             # columns of c_i


@njit(cache=True, _nrt=False, inline="always")
def cluster_contacts(nc, c_i, comp):
    """Label the first ``nc`` contacts by cluster: ``comp[c]`` becomes the smallest contact
    index of the cluster of contact c, a cluster being the contacts connected through
    shared bodies (planes are not shared: they do not move)."""
    for c in range(nc):
        comp[c] = c
    changed = True
    while changed:
        changed = False
        for c in range(nc):
            for d in range(c + 1, nc):
                if comp[c] == comp[d]:
                    continue
                share = c_i[c, CI_A] == c_i[d, CI_A]
                if c_i[d, CI_TYPE] == 1 and c_i[c, CI_A] == c_i[d, CI_B]:
                    share = True
                if c_i[c, CI_TYPE] == 1 and (c_i[c, CI_B] == c_i[d, CI_A] or (
                        c_i[d, CI_TYPE] == 1 and c_i[c, CI_B] == c_i[d, CI_B])):
                    share = True
                if share:
                    lo = min(comp[c], comp[d])
                    comp[c] = lo
                    comp[d] = lo
                    changed = True


@njit(cache=True, _nrt=False, inline="always")
def cluster_members(nc, comp, root, tail):
    """Write the contacts of the cluster labelled ``root`` (in contact order) into
    ``comp[tail:]`` and return their number K (0: ``root`` labels no cluster)."""
    K = 0
    for c in range(nc):
        if comp[c] == root:
            comp[tail + K] = c
            K += 1
    return K
