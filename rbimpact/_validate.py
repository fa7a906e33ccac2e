"""Argument checks shared by the 2D and 3D scenes and shapes: each returns the value as
float(s) or raises ``ValueError`` saying what is wrong and what is allowed."""
import math

import numpy as np


def vector(what, value, n, names):
    """``value`` as a finite float64[n]; ``names`` spells the components, e.g. "(x, y)"."""
    try:
        v = np.array(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be {n} numbers {names}, got {value!r}") from None
    if v.shape != (n,):
        raise ValueError(f"{what} must be {n} numbers {names}, got {value!r}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{what} must be finite, got {value!r}")
    return v


def real(what, value, unit):
    """``value`` as a finite float (``unit`` goes into the message)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be a number ({unit}), got {value!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{what} must be finite ({unit}), got {value!r}")
    return v


def size(cls, name, value, allow_zero=False):
    """A shape dimension (m): finite and > 0 (>= 0 with ``allow_zero``)."""
    v = real(f"{cls}: {name}", value, "m")
    if v < 0.0 or (v == 0.0 and not allow_zero):
        need = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{cls}: {name} must be {need} (m), got {value!r}")
    return v


class ValueShape:
    """Shapes compare and hash by value: subclasses define ``_key()`` (a tuple)."""

    def __eq__(self, other):
        return type(self) is type(other) and self._key() == other._key()

    def __hash__(self):
        return hash((type(self).__name__, self._key()))
