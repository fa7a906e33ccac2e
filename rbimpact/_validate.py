"""Argument checks shared by the public entry points (shapes, scenes, laws, the simulation
front ends, the command line): each returns the value as float(s) or int, or raises
``ValueError`` saying what is wrong and what is allowed -- never a raw NumPy message, and
never a NaN or an infinity passed on.

What counts as a number: ``int``, ``float``, NumPy integer and floating scalars (and 0-d
arrays of them), ``fractions.Fraction``, ``decimal.Decimal``. Not numbers here: booleans,
strings, ``None``, complex numbers; sequences must not be ragged.
"""
import math
import numbers
import os
from decimal import Decimal

import numpy as np

#: the largest count the compiled code can hold (int64)
INT64_MAX = 2 ** 63 - 1

_KIND_REASON = {"b": "booleans are not numbers here", "c": "complex numbers are not allowed",
                "U": "strings are not numbers", "S": "strings are not numbers",
                "M": "dates are not numbers", "m": "time deltas are not numbers",
                "V": "structured values are not numbers"}


def _show(value, limit=80):
    """``repr(value)`` shortened to ``limit`` characters."""
    try:
        text = repr(value)
    except Exception:  # pragma: no cover - a broken __repr__
        text = f"<{type(value).__name__}>"
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _scalar_reason(x):
    """Why ``x`` is not a real number (str), or None when it is one."""
    t = type(x)
    if t is float or t is int:          # the common case, fast
        return None
    if isinstance(x, (bool, np.bool_)):
        return f"{x!r} is a boolean, not a number"
    if isinstance(x, (str, bytes)):
        return f"{_show(x)} is a string, not a number"
    if x is None:
        return "None is not a number"
    if isinstance(x, (complex, np.complexfloating)):
        return f"{_show(x)} is a complex number"
    if isinstance(x, np.ndarray):
        if x.ndim != 0:
            return f"an array of shape {x.shape} is not a single number"
        if x.dtype.kind not in "iuf":
            return _KIND_REASON.get(x.dtype.kind, f"an array of dtype {x.dtype}")
        return None
    if isinstance(x, (numbers.Real, Decimal)):
        return None
    if isinstance(x, (list, tuple)):
        return f"a sequence of {len(x)} items is not a single number"
    return f"a {type(x).__name__} is not a number"


def _to_float(x):
    """float(x) for a value ``_scalar_reason`` accepted; +-inf when it overflows float64."""
    try:
        return float(x)
    except OverflowError:
        return math.inf if x > 0 else -math.inf
    except ValueError:                  # Decimal("sNaN")
        return math.nan


def real(what, value, unit):
    """``value`` as a finite float (``unit`` goes into the message)."""
    reason = _scalar_reason(value)
    if reason is not None:
        raise ValueError(f"{what} must be a real number ({unit}), got {_show(value)}: {reason}")
    v = _to_float(value)
    if not math.isfinite(v):
        raise ValueError(f"{what} must be finite ({unit}), got {_show(value)}")
    return v


def _leaf_reason(value, depth=0):
    """Why the nested lists/tuples/arrays ``value`` hold something other than real numbers
    (str), or None."""
    t = type(value)
    if t is list or t is tuple:
        for item in value:
            ti = type(item)
            if ti is float or ti is int:      # the common case, fast
                continue
            r = _leaf_reason(item, depth + 1)
            if r is not None:
                return r
        return None
    if t is np.ndarray and value.ndim > 0:
        kind = value.dtype.kind
        if kind in "iuf":
            return None
        if kind == "O":
            return _leaf_reason(value.tolist(), depth + 1)
        return _KIND_REASON.get(kind, f"an array of dtype {value.dtype}")
    if isinstance(value, (list, tuple)):          # subclasses (named tuples)
        return _leaf_reason(list(value), depth)
    if depth == 0 and not isinstance(value, (str, bytes, np.ndarray)) \
            and hasattr(value, "__len__") and hasattr(value, "__getitem__"):
        return _leaf_reason(list(value), depth + 1)   # another sequence type
    r = _scalar_reason(value)
    if r is not None and depth > 0:
        r = "an element: " + r
    return r


def real_array(what, value, expect):
    """``value`` (nested sequences or an array of real numbers) as a float64 array of its
    own shape; ``expect`` says what is allowed, e.g. "2 numbers (x, y) in m". Booleans,
    strings, None, complex numbers and ragged rows raise ``ValueError``. Finiteness and
    shape are the caller's to check (``vector`` does both)."""
    reason = _leaf_reason(value)
    if reason is None:
        try:
            return np.array(value, dtype=np.float64)
        except OverflowError:
            reason = "a number too large for float64"
        except (TypeError, ValueError):
            reason = "the rows have different lengths (ragged)"
    raise ValueError(f"{what} must be {expect}, got {_show(value)}: {reason}")


def vector(what, value, n, names, unit=None):
    """``value`` as a finite float64[n]; ``names`` spells the components, e.g. "(x, y)"."""
    expect = f"{n} real numbers {names}" + (f" ({unit})" if unit else "")
    v = real_array(what, value, expect).reshape(-1)
    if v.shape != (n,):
        raise ValueError(f"{what} must be {expect}, got {_show(value)}")
    if not all(map(math.isfinite, v.tolist())):
        raise ValueError(f"{what} must be finite, got {_show(value)}")
    return v


def unit_vector(what, v, value):
    """The float64 vector ``v`` (already checked finite) divided by its length; ``value``
    (the caller's argument) goes into the message when ``v`` is zero. The length is taken
    by ``math.hypot``, which neither overflows nor underflows (|v| ~ 1e200 or 1e-200)."""
    n = math.hypot(*(float(x) for x in v))
    if not n > 0.0:
        raise ValueError(f"{what} must be non-zero, got {_show(value)}")
    return v / n


#: shape dimensions (m) lie in [SIZE_MIN, SIZE_MAX], so that areas, volumes and unit
#: moments of inertia (size^2, size^3) are normal float64 numbers
SIZE_MIN, SIZE_MAX = 1e-100, 1e100


def size(cls, name, value, allow_zero=False):
    """A shape dimension (m): finite and > 0 (or 0 with ``allow_zero``), within
    [SIZE_MIN, SIZE_MAX] = [1e-100, 1e100] m so that area, volume and moment of inertia
    are representable."""
    v = real(f"{cls}: {name}", value, "m")
    if v < 0.0 or (v == 0.0 and not allow_zero):
        need = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{cls}: {name} must be {need} (m), got {value!r}")
    if v != 0.0 and not SIZE_MIN <= v <= SIZE_MAX:
        raise ValueError(f"{cls}: {name} must be {'0 or ' if allow_zero else ''}between "
                         f"{SIZE_MIN:g} and {SIZE_MAX:g} m (so that its area, volume and "
                         f"moment of inertia are representable in float64), got {value!r}")
    return v


def integer(what, value, lo=1, hi=INT64_MAX, integral_float=False):
    """``value`` as an int in [lo, hi] (hi defaults to the int64 limit of the compiled
    code). ``integral_float``: also accept a float with an integral value (1e6)."""
    allowed = f"an integer in [{lo}, {hi}]"
    if isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{what} must be {allowed}, got {value!r}: a boolean, not a number")
    if isinstance(value, (numbers.Integral, np.integer)):
        v = int(value)
    elif (integral_float and isinstance(value, (float, np.floating))
          and math.isfinite(value) and float(value).is_integer()):
        v = int(value)
    else:
        reason = _scalar_reason(value) or "not an integer"
        raise ValueError(f"{what} must be {allowed}, got {_show(value)}: {reason}")
    if not lo <= v <= hi:
        raise ValueError(f"{what} must be {allowed}, got {_show(value)}")
    return v


def choice(what, value, choices):
    """``value`` if it is one of the strings ``choices``, else ``ValueError`` listing them."""
    if isinstance(value, str) and value in choices:
        return value
    raise ValueError(f"{what} must be one of {', '.join(map(repr, choices))}, got "
                     f"{_show(value)}")


# ---------------------------------------------------------------- simulation front ends

def validate_run_args(t_end, max_events, who="run"):
    """``run(t_end, max_events)``: ``t_end`` a finite time > 0 (s), ``max_events`` an
    integer in [1, 2^63 - 1]; returns ``(float(t_end), int(max_events))``."""
    t = real(f"{who}: t_end", t_end, "s")
    if not t > 0.0:
        raise ValueError(f"{who}: t_end must be a positive finite time (s), got {t_end!r}")
    return t, integer(f"{who}: max_events", max_events)


def validate_tolerance(who, name, value, unit):
    """One stepper keyword: a finite number >= 0 (``unit`` goes into the message); names
    ending in max_iter, max_steps, events or impacts are iteration limits, integers in
    [1, 2^63 - 1] (an integral float such as 1e5 is accepted)."""
    if name.endswith(("max_iter", "max_steps", "events", "impacts")):
        return integer(f"{who}: {name}", value, integral_float=True)
    v = real(f"{who}: {name}", value, unit)
    if v < 0.0:
        raise ValueError(f"{who}: {name} must be finite and >= 0 ({unit}), got {value!r}")
    return v


def validate_tolerances(who, table, tolerances):
    """The tolerance dict of ``Simulation``/``Simulation3D``: ``table`` (keyword ->
    (default, unit, meaning)) defaults updated with ``tolerances``, each checked by
    ``validate_tolerance`` (``zeno_speed`` may be None). Unknown keywords raise
    ``TypeError`` listing the tolerances."""
    unknown = [k for k in tolerances if k not in table]
    if unknown:
        raise TypeError(f"{who}: unknown keyword {unknown[0]!r}; tolerances are "
                        + ", ".join(f"{k} ({u})" for k, (_, u, _) in table.items()))
    tol = {k: v[0] for k, v in table.items()}
    for k, v in tolerances.items():
        if k == "zeno_speed" and v is None:
            tol[k] = None
            continue
        tol[k] = validate_tolerance(who, k, v, table[k][1])
    return tol


# ---------------------------------------------------------------- energy

def energy_check(what, terms, base=0.0):
    """Raise ``ValueError`` when an energy is not representable in float64: a term of
    ``terms`` (name -> J, computed in float64 as the stepper does, e.g. ``m v.v / 2``) or
    ``base + sum |term|`` overflows. Returns that sum (J)."""
    total = float(base)
    for name, t in terms.items():
        total += abs(float(t))
        if not math.isfinite(t):
            break
    if not math.isfinite(total):
        bad = next((k for k, t in terms.items() if not math.isfinite(t)), None)
        why = f"its {bad} is {float(terms[bad])}" if bad else "the energies sum to inf"
        raise ValueError(f"{what}: the state's energy is not representable in float64 ({why}; "
                         f"energies must stay below ~1.8e308 J): use smaller speeds, masses "
                         f"or distances, or other units")
    return total


def body_energy_2d(mass, moment, position, velocity, angular_velocity, gravity):
    """The energies (J) of a 2D body, as the stepper computes them: kinetic ``m v.v / 2``,
    rotational ``I w^2 / 2`` and gravitational ``-m g.x`` (dict; inf on overflow)."""
    m = float(mass)
    vx, vy = (float(c) for c in velocity)
    x, y = (float(c) for c in position)
    w = float(angular_velocity)
    return {"kinetic energy m |v|^2 / 2": 0.5 * m * (vx * vx + vy * vy),
            "rotational energy I w^2 / 2": 0.5 * float(moment) * (w * w),
            "gravitational energy m g.x": -m * (float(gravity[0]) * x + float(gravity[1]) * y)}


def body_energy_3d(mass, inertia, position, orientation, velocity, angular_velocity,
                   gravity):
    """As ``body_energy_2d`` for 3D: ``inertia`` the principal moments (kg m^2) about the
    body axes, ``orientation`` a unit quaternion (w, x, y, z), ``angular_velocity`` in the
    world frame (rad/s)."""
    m = float(mass)
    qw, qx, qy, qz = (float(c) for c in orientation)
    R = ((1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)),
         (2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)),
         (2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)))
    w = [float(c) for c in angular_velocity]
    wb = [R[0][k] * w[0] + R[1][k] * w[1] + R[2][k] * w[2] for k in range(3)]  # R^T w
    v = [float(c) for c in velocity]
    return {"kinetic energy m |v|^2 / 2": 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]),
            "rotational energy w.I w / 2": 0.5 * sum(float(i) * (x * x)
                                                     for i, x in zip(inertia, wb)),
            "gravitational energy m g.x": -m * sum(float(g) * float(x)
                                                   for g, x in zip(gravity, position))}


def scene_energy_check(who, scene):
    """Raise ``ValueError`` when the energy of ``scene`` (a Scene2D or Scene3D) is not
    representable in float64; returns the sum of |energies| of its bodies (J)."""
    total = 0.0
    for b in scene.bodies:
        if hasattr(b, "moment"):
            terms = body_energy_2d(b.mass, b.moment, b.position, b.velocity,
                                   b.angular_velocity, scene.gravity)
        else:
            terms = body_energy_3d(b.mass, b.inertia, b.position, b.orientation, b.velocity,
                                   b.angular_velocity, scene.gravity)
        total = energy_check(f"{who}: body {b.index}", terms, total)
    return total


# ---------------------------------------------------------------- output files

def writable_path(what, path):
    """Check, before a long run, that a file can be written at ``path``: its directory
    exists, it is not a directory, and we may write there. Raises ``ValueError`` naming
    ``what`` (e.g. "--out") and the reason; returns ``path``."""
    p = os.fspath(path)
    if not p:
        raise ValueError(f"{what}: the file name is empty")
    full = os.path.abspath(p)
    parent = os.path.dirname(full)
    if os.path.isdir(full):
        raise ValueError(f"{what}: cannot write {p!r}: it is a directory; give a file name")
    if not os.path.exists(parent):
        raise ValueError(f"{what}: cannot write {p!r}: directory {parent!r} does not exist")
    if not os.path.isdir(parent):
        raise ValueError(f"{what}: cannot write {p!r}: {parent!r} is not a directory")
    if os.path.exists(full):
        if not os.access(full, os.W_OK):
            raise ValueError(f"{what}: cannot write {p!r}: no permission to write the file")
    elif not os.access(parent, os.W_OK | os.X_OK):
        raise ValueError(f"{what}: cannot write {p!r}: no permission to create files in "
                         f"{parent!r}")
    return path


class ValueShape:
    """Shapes compare and hash by value: subclasses define ``_key()`` (a tuple)."""

    def __eq__(self, other):
        return type(self) is type(other) and self._key() == other._key()

    def __hash__(self):
        return hash((type(self).__name__, self._key()))
