"""Rest on several points (2D): the static-equilibrium test of a body held by two contacts
(two planes, a groove, a corner, a face corner and a wall), DESIGN §6a "rest on a face /
several points".

A body of mass ``m`` under gravity ``g`` touches planes at contact points with arms ``r_k``
(from its centre of mass, m), unit normals ``n_k`` (into the body) and friction
coefficients ``mu_k``. It can rest there iff contact forces ``F_k = N_k n_k + T_k t_k``
(``t_k = (n_ky, -n_kx)``) exist with

    sum_k F_k + m g = 0,   sum_k r_k x F_k = 0,   N_k >= 0,   |T_k| <= mu_k N_k.

With two contacts the three equations leave a one-parameter family ``u = u0 + s z`` of the
four unknowns ``u = (N_1, T_1, N_2, T_2)`` (``z`` spans the null space of the 3x4 system,
its entries the signed 3x3 minors); each inequality bounds ``s`` on one side, so the test
is an exact interval intersection. Forces are compared with ``FEAS_RTOL m |g|``.
"""
import math

from numba import njit

FEAS_RTOL = 1e-12
"""Contact-force tolerance of the equilibrium test, relative to the weight m |g| (N/N)."""
RANK_RTOL = 1e-12
"""The two-contact system is degenerate (no unique one-parameter family) when its largest
3x3 minor is below this times the product of its column scales."""


@njit(cache=True, _nrt=False, inline="always")
def _det3(a00, a01, a02, a10, a11, a12, a20, a21, a22):
    return (a00 * (a11 * a22 - a12 * a21) - a01 * (a10 * a22 - a12 * a20)
            + a02 * (a10 * a21 - a11 * a20))


@njit(cache=True, _nrt=False)
def two_contact_rest(m, gx, gy, r1x, r1y, n1x, n1y, mu1, r2x, r2y, n2x, n2y, mu2):
    """True when the body can rest on the two contacts (see the module docstring).
    Units: m (kg), g (m/s^2), arms r (m), unit normals n, friction coefficients mu >= 0."""
    # columns of A (rows: force x, force y, moment)
    c0x, c0y = n1x, n1y
    c1x, c1y = n1y, -n1x
    c2x, c2y = n2x, n2y
    c3x, c3y = n2y, -n2x
    c0m = r1x * c0y - r1y * c0x
    c1m = r1x * c1y - r1y * c1x
    c2m = r2x * c2y - r2y * c2x
    c3m = r2x * c3y - r2y * c3x
    bx = -m * gx
    by = -m * gy
    # null space: z_j = (-1)^j det(A without column j)
    z0 = _det3(c1x, c2x, c3x, c1y, c2y, c3y, c1m, c2m, c3m)
    z1 = -_det3(c0x, c2x, c3x, c0y, c2y, c3y, c0m, c2m, c3m)
    z2 = _det3(c0x, c1x, c3x, c0y, c1y, c3y, c0m, c1m, c3m)
    z3 = -_det3(c0x, c1x, c2x, c0y, c1y, c2y, c0m, c1m, c2m)
    L = max(math.hypot(r1x, r1y), math.hypot(r2x, r2y), 1e-300)
    zmax = max(abs(z0), abs(z1), abs(z2), abs(z3))
    if not zmax > RANK_RTOL * L * L:
        return False
    # particular solution with the component of the largest |z_j| set to 0 (Cramer)
    u0 = 0.0
    u1 = 0.0
    u2 = 0.0
    u3 = 0.0
    if abs(z0) == zmax:
        D = z0
        u1 = _det3(bx, c2x, c3x, by, c2y, c3y, 0.0, c2m, c3m) / D
        u2 = _det3(c1x, bx, c3x, c1y, by, c3y, c1m, 0.0, c3m) / D
        u3 = _det3(c1x, c2x, bx, c1y, c2y, by, c1m, c2m, 0.0) / D
    elif abs(z1) == zmax:
        D = -z1
        u0 = _det3(bx, c2x, c3x, by, c2y, c3y, 0.0, c2m, c3m) / D
        u2 = _det3(c0x, bx, c3x, c0y, by, c3y, c0m, 0.0, c3m) / D
        u3 = _det3(c0x, c2x, bx, c0y, c2y, by, c0m, c2m, 0.0) / D
    elif abs(z2) == zmax:
        D = z2
        u0 = _det3(bx, c1x, c3x, by, c1y, c3y, 0.0, c1m, c3m) / D
        u1 = _det3(c0x, bx, c3x, c0y, by, c3y, c0m, 0.0, c3m) / D
        u3 = _det3(c0x, c1x, bx, c0y, c1y, by, c0m, c1m, 0.0) / D
    else:
        D = -z3
        u0 = _det3(bx, c1x, c2x, by, c1y, c2y, 0.0, c1m, c2m) / D
        u1 = _det3(c0x, bx, c2x, c0y, by, c2y, c0m, 0.0, c2m) / D
        u2 = _det3(c0x, c1x, bx, c0y, c1y, by, c0m, c1m, 0.0) / D
    # normalise the direction so that s is a force (N)
    z0 /= zmax
    z1 /= zmax
    z2 /= zmax
    z3 /= zmax
    tol = FEAS_RTOL * m * math.hypot(gx, gy)
    lo = -math.inf
    hi = math.inf
    # constraints a + s b >= -tol
    for k in range(6):
        if k == 0:
            a, b = u0, z0
        elif k == 1:
            a, b = u2, z2
        elif k == 2:
            a, b = mu1 * u0 - u1, mu1 * z0 - z1
        elif k == 3:
            a, b = mu1 * u0 + u1, mu1 * z0 + z1
        elif k == 4:
            a, b = mu2 * u2 - u3, mu2 * z2 - z3
        else:
            a, b = mu2 * u2 + u3, mu2 * z2 + z3
        if b > 0.0:
            lo = max(lo, (-tol - a) / b)
        elif b < 0.0:
            hi = min(hi, (-tol - a) / b)
        elif a < -tol:
            return False
    return lo <= hi


@njit(cache=True, _nrt=False, inline="always")
def _generator(c, g, L):
    """Edge g of the friction cones of the contacts c (g // 2 the contact, g % 2 the
    side): the unit force ``(n +- mu t) / |n +- mu t|`` and its moment about the centre of
    mass divided by L (so the three components are forces, N per N)."""
    rx, ry, nx, ny, mu = c[g // 2]
    s = mu if g % 2 == 0 else -mu
    fx = nx + s * ny
    fy = ny - s * nx
    h = math.hypot(fx, fy)
    fx /= h
    fy /= h
    return fx, fy, (rx * fy - ry * fx) / L


@njit(cache=True, _nrt=False)
def three_contact_rest(m, gx, gy, c):
    """True when the body can rest on the three contacts ``c`` (a tuple of three ``(r_x,
    r_y, n_x, n_y, mu)``: arm from the centre of mass (m), unit normal into the body,
    friction coefficient; e.g. a face's two corners on one plane and a corner on another).
    Each contact force is a non-negative combination of its friction cone's two edges, so
    the body rests iff ``A x = -(m g, 0)`` has a solution ``x >= 0`` over the six edges; by
    Caratheodory's theorem some solution then uses at most three edges (a basic solution),
    so the test enumerates the 20 triples (and the pairs and single edges, for degenerate
    systems) and solves each exactly (Cramer), accepting coefficients and residuals within
    ``FEAS_RTOL m |g|``."""
    L = 1e-300
    for k in range(3):
        L = max(L, math.hypot(c[k][0], c[k][1]))
    bx = -m * gx
    by = -m * gy
    tol = FEAS_RTOL * m * math.hypot(gx, gy)
    for a in range(6):
        ax, ay, am = _generator(c, a, L)
        # one edge: b = x a
        x = ax * bx + ay * by
        if x >= -tol and math.hypot(bx - x * ax, by - x * ay) + abs(x * am) <= tol:
            return True
        for b in range(a + 1, 6):
            cx, cy, cm = _generator(c, b, L)
            # two edges: least squares on the 3 x 2 system, then its residual
            s11 = ax * ax + ay * ay + am * am
            s12 = ax * cx + ay * cy + am * cm
            s22 = cx * cx + cy * cy + cm * cm
            r1 = ax * bx + ay * by
            r2 = cx * bx + cy * by
            det2 = s11 * s22 - s12 * s12
            if det2 > RANK_RTOL:
                x1 = (s22 * r1 - s12 * r2) / det2
                x2 = (s11 * r2 - s12 * r1) / det2
                if (x1 >= -tol and x2 >= -tol
                        and abs(bx - x1 * ax - x2 * cx) + abs(by - x1 * ay - x2 * cy)
                        + abs(x1 * am + x2 * cm) <= tol):
                    return True
            for d in range(b + 1, 6):
                ex, ey, em = _generator(c, d, L)
                D = _det3(ax, cx, ex, ay, cy, ey, am, cm, em)
                if not abs(D) > RANK_RTOL:
                    continue
                x1 = _det3(bx, cx, ex, by, cy, ey, 0.0, cm, em) / D
                x2 = _det3(ax, bx, ex, ay, by, ey, am, 0.0, em) / D
                x3 = _det3(ax, cx, bx, ay, cy, by, am, cm, 0.0) / D
                if x1 >= -tol and x2 >= -tol and x3 >= -tol:
                    return True
    return False
