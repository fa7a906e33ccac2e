"""The collision laws' Python front end: a registry, parameter validation, results.

The Python layer validates; the kernels in ``rbimpact.kernels`` compute. Conventions
(DESIGN §3): contact-space vectors are normal first, ``v`` is the velocity of A's contact
point minus B's (``v_N < 0`` approaches), ``P`` is the impulse on A, ``W`` the symmetric
positive definite Delassus matrix (1/kg), ``v_f = v + W P``, and
``dE = P . (v + v_f) / 2`` is the exact kinetic energy change (J).

Laws are registered by name in ``LAWS`` (swappable, pooltool-style); kernels are imported
on first use, so constructing a ``Law`` compiles nothing.
"""
import math
from dataclasses import dataclass
from importlib import import_module
from types import MappingProxyType

import numpy as np

from ._validate import _scalar_reason, _show, _to_float, energy_check, real_array
from .errors import NoSolutionError

# Relative tolerance on ``dE`` for flagging energy creation: a gain is reported when
# dE > ENERGY_GAIN_RTOL * sum_k |P_k| (|v_k| + |v_f,k|) / 2, i.e. beyond the round-off
# of the dot product that defines dE (about 1e-16 of that scale).
ENERGY_GAIN_RTOL = 1e-12
# Relative asymmetry of W accepted as round-off: |W - W^T| <= SYMMETRY_RTOL * max|W|.
SYMMETRY_RTOL = 1e-12

# Mode codes: see rbimpact/kernels/common.py (kept in sync there).
MODE_SEPARATING = 0
MODE_STICK = 1
MODE_SLIP = 2
MODE_SLIP_STICK = 3
MODE_SLIP_REVERSE = 4
MODE_NO_SOLUTION = -1
MODE_NOT_CONVERGED = -2

#: int mode code -> (final mode name, phase sequence)
MODE_NAMES = MappingProxyType({
    MODE_SEPARATING: ("separating", ()),
    MODE_STICK: ("stick", ("stick",)),
    MODE_SLIP: ("slip", ("slip",)),
    MODE_SLIP_STICK: ("stick", ("slip", "stick")),
    MODE_SLIP_REVERSE: ("slip", ("slip", "reverse")),
    MODE_NO_SOLUTION: ("no_solution", ()),
    MODE_NOT_CONVERGED: ("not_converged", ()),
})

RESTITUTION_KINDS = ("energetic", "poisson", "newton")

# Parameter slots of Law.params (rbimpact/kernels/common.py: P_E, P_MU, P_ET, P_REST, P_TOL).
_SLOT = {"e": 0, "mu": 1, "e_t": 2, "restitution": 3, "tol": 4}
N_PARAMS = 5


@dataclass(frozen=True)
class _Param:
    lo: float
    hi: float
    default: object  # None: required
    unit: str = "dimensionless"


_E01 = _Param(0.0, 1.0, None)
_E11 = _Param(-1.0, 1.0, None)
_MU = _Param(0.0, np.inf, 0.0)
_ET = _Param(-1.0, 1.0, 0.0)
_TOL = _Param(1e-14, 1e-1, 1e-10)


@dataclass(frozen=True)
class LawSpec:
    """A registered law: its kernel module, integer id and parameter ranges."""

    name: str
    law_id: int
    module: str
    params: dict
    doc: str

    def may_create_energy(self, values):
        """True when the law, with these parameters, may create kinetic energy (DESIGN §4)."""
        if self.name in ("kane_levinson", "brach"):
            return True
        if self.name == "routh":
            return values["restitution"] == "newton"
        return False


LAWS = {
    "kane_levinson": LawSpec(
        "kane_levinson", 0, "kane_levinson", {"e": _E01, "mu": _MU},
        "Newton restitution + Coulomb friction along the final slip (Kane & Levinson 1985)"),
    "brach": LawSpec(
        "brach", 1, "brach", {"e": _E11, "mu": _MU, "e_t": _ET},
        "impulse ratio law (Brach 1991); e < 0 is perforation"),
    "smith": LawSpec(
        "smith", 2, "smith", {"e": _E01, "mu": _MU},
        "friction weighted over initial and final slip (Smith 1991)"),
    "routh": LawSpec(
        "routh", 3, "routh",
        {"e": _E01, "mu": _MU, "restitution": _Param(np.nan, np.nan, "energetic"), "tol": _TOL},
        "integration in normal-impulse space (Routh 1897; Stronge 1991)"),
    "chatterjee_ruina": LawSpec(
        "chatterjee_ruina", 4, "chatterjee_ruina", {"e": _E01, "mu": _MU, "e_t": _ET},
        "two-parameter law with a friction cone (Chatterjee & Ruina 1998)"),
}


def _check_param(law, key, value, spec):
    if key == "restitution":
        if not (isinstance(value, str) and value in RESTITUTION_KINDS):
            raise ValueError(f"law {law!r}: restitution must be one of {RESTITUTION_KINDS}, "
                             f"got {_show(value)}")
        return RESTITUTION_KINDS.index(value)
    hi = "inf)" if spec.hi == np.inf else f"{spec.hi:g}]"
    reason = _scalar_reason(value)
    if reason is not None:
        raise ValueError(f"law {law!r}: parameter {key!r} must be a real number in "
                         f"[{spec.lo:g}, {hi}, got {_show(value)}: {reason}")
    x = _to_float(value)
    if not (spec.lo <= x <= spec.hi) or np.isnan(x) or (x == np.inf):
        raise ValueError(f"law {law!r}: parameter {key!r} must be finite and in "
                         f"[{spec.lo:g}, {hi}, got {value!r}")
    return x


def _law_spec(name):
    if not isinstance(name, str):
        raise ValueError(f"the law name must be a string, one of {', '.join(LAWS)}; got "
                         f"{_show(name)} ({type(name).__name__})")
    try:
        return LAWS[name]
    except KeyError:
        raise ValueError(f"unknown law {name!r}; known laws: {', '.join(LAWS)}") from None


@dataclass(frozen=True)
class Impact:
    """The outcome of one impact (all vectors normal first, contact space).

    ``P`` impulse on A (N s); ``v_f`` final relative velocity (m/s); ``mode`` the final
    mode name ("separating", "stick" or "slip"); ``phases`` the phase sequence (Routh:
    e.g. ``("slip", "stick")``); ``dE`` kinetic energy change (J, negative = dissipated);
    ``energy_gain`` True when the law created kinetic energy beyond round-off;
    ``mode_code`` the kernel's integer code.
    """

    P: np.ndarray
    v_f: np.ndarray
    mode: str
    phases: tuple
    dE: float
    energy_gain: bool
    mode_code: int


@dataclass(frozen=True)
class BatchImpact:
    """Outcomes of n impacts: arrays ``P``, ``v_f`` (n, d), ``mode`` (n,) int codes
    (``MODE_NAMES`` maps them to names), ``dE`` (n,) J and ``energy_gain`` (n,) bool."""

    P: np.ndarray
    v_f: np.ndarray
    mode: np.ndarray
    dE: np.ndarray
    energy_gain: np.ndarray

    @property
    def mode_names(self):
        """Final mode name of every contact (list of str)."""
        return [MODE_NAMES[int(m)][0] for m in self.mode]


def _dot(a, b):
    """Dot product of two short lists, summed left to right."""
    acc = 0.0
    for x, y in zip(a, b):
        acc += x * y
    return acc


def _check_contact(v, W):
    """Validate one contact; return float64 copies with W exactly symmetrised.

    Scalar Python arithmetic on the 2 or 3 components (a per-call cost of a few
    microseconds, not the tens of NumPy's reductions on tiny arrays): finite, symmetric to
    SYMMETRY_RTOL, and positive definite by a Cholesky factorisation (every pivot > 0);
    the slow vectorised ``_check_W_values`` runs only to word an error. Booleans, strings,
    None, complex numbers and ragged rows are refused (``ValueError``), and so is a contact
    whose kinetic energy ``v . W^-1 v / 2`` (J) overflows float64."""
    v = real_array("v", v, "2 or 3 real numbers (m/s), normal first")
    W = real_array("W", W, "a 2x2 or 3x3 symmetric positive definite matrix (1/kg)")
    if v.ndim != 1 or v.shape[0] not in (2, 3):
        raise ValueError(f"v must have length 2 (2D) or 3 (3D), normal first; got shape {v.shape}")
    d = v.shape[0]
    if W.shape != (d, d):
        raise ValueError(f"W must have shape ({d}, {d}) to match v; got {W.shape}")
    rows = W.tolist()
    flat = v.tolist() + rows[0] + rows[1] + (rows[2] if d == 3 else [])
    if not all(map(math.isfinite, flat)):
        _check_W_values(v[None], W[None])  # raises, saying which
    asym = max(abs(rows[i][j] - rows[j][i]) for i in range(d) for j in range(i + 1, d))
    if asym > SYMMETRY_RTOL * max(map(abs, flat[d:])):
        _check_W_values(v[None], W[None])
    S = [[0.5 * (rows[i][j] + rows[j][i]) for j in range(d)] for i in range(d)]
    L = _cholesky(S)
    if L is None:
        _check_W_values(v[None], W[None])
        raise ValueError("W must be positive definite")
    # kinetic energy of the contact, |L^-1 v|^2 / 2 (J): must be representable
    vl, y, E = flat[:d], [0.0] * d, 0.0
    for i in range(d):
        y[i] = (vl[i] - sum(L[i][k] * y[k] for k in range(i))) / L[i][i]
        E += y[i] * y[i]
    if not math.isfinite(E):
        energy_check("resolve: contact (v, W)", {"kinetic energy v.W^-1 v / 2": 0.5 * E})
    return v, np.array(S)


def _cholesky(S):
    """The lower Cholesky factor (nested lists) of the symmetric 2x2 or 3x3 ``S``, or None
    when a pivot is not > 0 (the positive-definiteness test of LAPACK potrf)."""
    d = len(S)
    L = [[0.0] * d for _ in range(d)]
    for j in range(d):
        s = S[j][j] - sum(L[j][k] * L[j][k] for k in range(j))
        if not s > 0.0:
            return None
        L[j][j] = math.sqrt(s)
        for i in range(j + 1, d):
            L[i][j] = (S[i][j] - sum(L[i][k] * L[j][k] for k in range(j))) / L[j][j]
    return L


def _check_W_values(v, W):
    bad = ~np.isfinite(v).all(axis=-1)
    if bad.any():
        raise ValueError(f"v must be finite; contact {int(np.argmax(bad))} has {v[bad][0]}")
    bad = ~np.isfinite(W).all(axis=(-1, -2))
    if bad.any():
        raise ValueError(f"W must be finite; contact {int(np.argmax(bad))} is not")
    WT = np.swapaxes(W, -1, -2)
    asym = np.abs(W - WT).max(axis=(-1, -2))
    bad = asym > SYMMETRY_RTOL * np.abs(W).max(axis=(-1, -2))
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"W must be symmetric (|W - W^T| <= {SYMMETRY_RTOL:g} max|W|); "
                         f"contact {i} has asymmetry {asym[i]:.3g}")
    lam = np.linalg.eigvalsh(0.5 * (W + WT))
    bad = ~(lam[..., 0] > 0.0)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"W must be positive definite; contact {i} has smallest "
                         f"eigenvalue {lam[i, 0]:.3g}")


class Law:
    """A collision law with its parameters, e.g. ``Law("routh", e=0.5, mu=0.3)``.

    Parameters (DESIGN §4; all dimensionless):

    - ``e``: normal restitution, required; [0, 1] (Brach: [-1, 1], negative = perforation).
    - ``mu``: Coulomb friction coefficient, [0, inf), default 0.
    - ``e_t``: tangential restitution (Brach, Chatterjee & Ruina), [-1, 1], default 0.
    - ``restitution`` (Routh): "energetic" (Stronge, default), "poisson" or "newton".
    - ``tol`` (Routh 3D): relative integration tolerance, [1e-14, 0.1], default 1e-10.

    Attributes for compiled callers: ``law_id`` (int), ``params`` (float64[5], layout in
    ``rbimpact.kernels.common``), ``kernel`` (njit ``mode = kernel(v, W, params, P_out)``,
    2D or 3D by ``len(v)``), ``kernel_2d`` and ``kernel_3d``.
    """

    def __init__(self, name, **params):
        spec = _law_spec(name)
        unknown = set(params) - set(spec.params)
        if unknown:
            raise ValueError(f"law {name!r} takes no parameter {sorted(unknown)[0]!r}; "
                             f"its parameters are {', '.join(spec.params)}")
        values, slots = {}, np.zeros(N_PARAMS)
        slots[_SLOT["tol"]] = _TOL.default
        for key, p in spec.params.items():
            if key not in params and p.default is None:
                raise ValueError(f"law {name!r}: parameter {key!r} is required "
                                 f"(range [{p.lo:g}, {p.hi:g}])")
            value = params.get(key, p.default)
            slots[_SLOT[key]] = _check_param(name, key, value, p)
            values[key] = value if key == "restitution" else float(value)
        self.name = name
        self.law_id = spec.law_id
        self.params = slots
        self.params.flags.writeable = False
        self.params_dict = MappingProxyType(values)
        self.may_create_energy = spec.may_create_energy(values)
        self._spec = spec
        self._kernels = {}  # dimension -> compiled kernel, looked up on first use
        self._batch = {}    # dimension -> batch entry (kernels/batch.py), on first use
        # per-slot ranges the batch loop checks every parameter row against (finite too);
        # restitution (checked by name in Python) and unused slots: no range
        self._lo = np.full(N_PARAMS, -np.inf)
        self._hi = np.full(N_PARAMS, np.inf)
        for key, p in spec.params.items():
            if key != "restitution":
                self._lo[_SLOT[key]] = p.lo
                self._hi[_SLOT[key]] = p.hi

    def __repr__(self):
        args = ", ".join(f"{k}={v!r}" for k, v in self.params_dict.items())
        return f"Law({self.name!r}, {args})"

    def __eq__(self, other):
        return (isinstance(other, Law) and self.name == other.name
                and dict(self.params_dict) == dict(other.params_dict))

    def __hash__(self):
        return hash((self.name, tuple(sorted(self.params_dict.items()))))

    def _kernel(self, suffix):
        module = import_module(f"rbimpact.kernels.{self._spec.module}")  # cached by Python
        return getattr(module, self._spec.module + suffix)

    @property
    def kernel(self):
        """The law's njit kernel, 2D or 3D chosen by ``v.shape[0]``."""
        return self._kernel("")

    @property
    def kernel_2d(self):
        return self._kernel("_2d")

    @property
    def kernel_3d(self):
        return self._kernel("_3d")

    def resolve(self, v, W):
        """Resolve one impact; returns an ``Impact``. Raises ``NoSolutionError`` when the
        law has no solution for this contact, ``ValueError`` for bad input."""
        v, W = _check_contact(v, W)
        P = np.zeros(v.shape[0])
        kernel = self._kernels.get(v.shape[0])
        if kernel is None:
            kernel = self._kernels[v.shape[0]] = self._kernel(f"_{v.shape[0]}d")
        code = int(kernel(v, W, self.params, P))
        if code < 0:
            raise NoSolutionError(self._failure(code, v, W), code)
        # v_f = v + W P and dE = P . (v + v_f) / 2, in scalars (same operation order as
        # NumPy's for these sizes: rows of W times P summed left to right)
        pl, vl, rows = P.tolist(), v.tolist(), W.tolist()
        fl = [vl[i] + _dot(rows[i], pl) for i in range(len(vl))]
        dE = 0.5 * _dot(pl, [a + b for a, b in zip(vl, fl)])
        scale = 0.5 * _dot([abs(x) for x in pl], [abs(a) + abs(b) for a, b in zip(vl, fl)])
        if not (math.isfinite(dE) and all(map(math.isfinite, fl))):
            energy_check(f"law {self.name!r}: impact", {"energy change dE": dE, **{
                f"final velocity v_f[{i}]": x for i, x in enumerate(fl)}})
        mode, phases = MODE_NAMES[code]
        return Impact(P, np.array(fl), mode, phases, dE, dE > ENERGY_GAIN_RTOL * scale, code)

    def _failure(self, code, v, W):
        what = ("has no solution" if code == MODE_NO_SOLUTION
                else "did not converge within its iteration limit")
        return (f"law {self.name!r} {what} for v = {v.tolist()}, W = {W.tolist()} "
                f"(params {dict(self.params_dict)})")

    def resolve_batch(self, v, W, *, on_failure="raise", validate=True, **params):
        """Resolve n contacts in one parallel compiled loop (``kernels/batch.py``).

        ``v`` (n, d), ``W`` (n, d, d); keyword ``params`` override the law's parameters
        with scalars or length-n arrays (same names and ranges). ``on_failure``:
        "raise" (``NoSolutionError`` naming the first failed contact) or "flag" (failed
        contacts keep ``P = 0``, ``v_f = v`` and a negative mode code).

        With ``validate`` (default) every contact is checked inside the compiled loop:
        ``v`` and ``W`` finite, ``W`` symmetric to ``SYMMETRY_RTOL`` (then used as
        ``(W + W^T) / 2``), positive definite (leading minors > 0, i.e. the pivots of
        ``L D L^T``; 2x2 minors with an exact sign), per-contact parameters in range; the first refused contact raises
        ``ValueError`` naming its index and what is wrong. ``validate=False`` skips these
        checks and reads the upper triangle of ``W`` as given. ``energy_gain`` flags
        ``dE > ENERGY_GAIN_RTOL * sum_k |P_k| (|v_k| + |v_f,k|) / 2``, computed in the loop.
        """
        if on_failure not in ("raise", "flag"):
            raise ValueError(f"on_failure must be 'raise' or 'flag', got {on_failure!r}")
        v = np.ascontiguousarray(v, dtype=np.float64)
        W = np.ascontiguousarray(W, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] not in (2, 3):
            raise ValueError(f"v must have shape (n, 2) or (n, 3); got {v.shape}")
        n, d = v.shape
        if W.shape != (n, d, d):
            raise ValueError(f"W must have shape ({n}, {d}, {d}) to match v; got {W.shape}")
        table = self._param_table(n, params)
        kernel = self._batch.get(d)
        if kernel is None:
            from .kernels.batch import kernel_for
            kernel = self._batch[d] = kernel_for(self.law_id, d)
        P = np.empty((n, d))
        v_f = np.empty((n, d))
        dE = np.empty(n)
        gain = np.empty(n, dtype=np.bool_)
        mode = np.empty(n, dtype=np.int64)
        nbad, ibad, nfail, ifail = kernel(v, W, table, self._lo, self._hi, bool(validate),
                                          SYMMETRY_RTOL, ENERGY_GAIN_RTOL, P, v_f, dE, gain,
                                          mode)
        if nbad:
            self._refused(int(ibad), int(mode[ibad]), v, W, table)
        if nfail and on_failure == "raise":
            i = int(ifail)
            Wi = 0.5 * (W[i] + W[i].T) if validate else W[i]
            raise NoSolutionError(f"{int(nfail)} of {n} contacts failed; first: contact "
                                  f"{i}: " + self._failure(int(mode[i]), v[i], Wi), int(mode[i]))
        return BatchImpact(P, v_f, mode, dE, gain)

    def _refused(self, i, code, v, W, table):
        """Raise the ValueError for contact ``i`` refused by the batch kernel's validation
        (``code``: one of ``kernels.batch.BAD_*``), worded as the single-contact checks."""
        from .kernels import batch as kb
        if code == kb.BAD_V:
            raise ValueError(f"v must be finite; contact {i} has {v[i]}")
        if code == kb.BAD_W:
            raise ValueError(f"W must be finite; contact {i} is not")
        if code == kb.BAD_SYM:
            asym = float(np.abs(W[i] - W[i].T).max())
            raise ValueError(f"W must be symmetric (|W - W^T| <= {SYMMETRY_RTOL:g} max|W|); "
                             f"contact {i} has asymmetry {asym:.3g}")
        if code == kb.BAD_SPD:
            lam = np.linalg.eigvalsh(0.5 * (W[i] + W[i].T))[0]
            raise ValueError(f"W must be positive definite; contact {i} has smallest "
                             f"eigenvalue {lam:.3g}")
        for key, p in self._spec.params.items():
            if key == "restitution":
                continue
            try:
                _check_param(self.name, key, float(table[min(i, len(table) - 1), _SLOT[key]]), p)
            except ValueError as exc:
                raise ValueError(f"contact {i}: {exc}") from None
        raise ValueError(f"contact {i}: refused by validation (code {code})")  # not reached

    def _param_table(self, n, overrides):
        """The (1 or n, N_PARAMS) parameter table of a batch. Scalars are checked here;
        the ranges of per-contact arrays are checked in the compiled loop (``_lo``,
        ``_hi``), except restitution names, converted here."""
        spec = self._spec
        unknown = set(overrides) - set(spec.params)
        if unknown:
            raise ValueError(f"law {self.name!r} takes no parameter {sorted(unknown)[0]!r}")
        arrays = {k: np.asarray(x) for k, x in overrides.items() if np.ndim(x) > 0}
        base = self.params.copy()
        for key, x in overrides.items():
            if key not in arrays:
                base[_SLOT[key]] = _check_param(self.name, key, x, spec.params[key])
        if not arrays:
            return base[None, :]
        for key, x in arrays.items():
            if x.shape != (n,):
                raise ValueError(f"parameter {key!r} must be a scalar or have shape ({n},); "
                                 f"got {x.shape}")
        table = np.empty((n, N_PARAMS))
        table[:] = base
        for key, x in arrays.items():
            if key == "restitution":
                table[:, _SLOT[key]] = [_check_param(self.name, key, r, spec.params[key])
                                        for r in x]
            else:
                table[:, _SLOT[key]] = x.astype(np.float64)
        return table


def resolve(name, v, W, **params):
    """Resolve one impact with law ``name``: ``Law(name, **params).resolve(v, W)``."""
    return Law(name, **params).resolve(v, W)
