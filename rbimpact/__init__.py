"""rbimpact: algebraic collision laws with friction and an exact event-driven stepper.

``import rbimpact`` is cheap: submodules (and Numba) load on first use of a name, and
kernels compile lazily (with an on-disk cache). Optional pieces (pymunk, matplotlib)
are imported only by the functions that need them.
"""
from importlib import import_module

from .errors import NoSolutionError, SimulationError

__version__ = "0.1.0"

# public name -> defining submodule (loaded on first access)
_LAZY = {
    "Law": "laws", "resolve": "laws", "Impact": "laws", "BatchImpact": "laws",
    "LAWS": "laws", "MODE_NAMES": "laws",
    "Disk": "shapes", "Box": "shapes", "Polygon": "shapes", "Rod": "shapes",
    "Ellipse": "shapes",
    "Scene2D": "scene", "Simulation": "simulation", "Result": "result",
    "impulse_space": "impulse_region", "ImpulseSpace": "impulse_region",
    "Sphere": "shapes3d", "Box3D": "shapes3d", "Capsule": "shapes3d",
    "Scene3D": "scene3d", "Simulation3D": "simulation3d", "Result3D": "result3d",
    "sweep": "sweep",   # needs the sweep extra (pandas, pyarrow, dask) only when called
    "random_gas": "manybody", "run_gas": "manybody", "GasState": "manybody",
    "GasResult": "manybody",
}

__all__ = ["NoSolutionError", "SimulationError", *_LAZY]


def __getattr__(name):
    if name in _LAZY:
        value = getattr(import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    if name in ("scenarios", "kernels"):
        return import_module(f".{name}", __name__)
    raise AttributeError(f"module 'rbimpact' has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
