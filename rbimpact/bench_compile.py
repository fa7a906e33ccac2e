"""Cold start of a scene (issue 14): ``rbimpact run NAME`` in a new process with an empty
Numba cache, then with the warm cache; which functions compile (their count, the laws and
whether any 3D code compiles for a 2D scene). Used by ``rbimpact bench compile``."""
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

#: the scenes timed by ``rbimpact bench compile`` (a new user's first command first)
COMPILE_SCENES = ("bouncing_ball", "falling_rod", "spinning_ball_3d", "die_toss")

_LAW_MODULES = ("kane_levinson", "brach", "smith", "routh", "chatterjee_ruina")

_SCRIPT = """
import contextlib, io, json, sys, time
from numba.core import event
names = []
class _Listener(event.Listener):
    def on_start(self, ev):
        pass
    def on_end(self, ev):
        f = ev.data["dispatcher"].py_func
        names.append(f.__module__ + "." + f.__qualname__)
event.register("numba:compile", _Listener())
t0 = time.perf_counter()
from rbimpact.cli import main
with contextlib.redirect_stdout(io.StringIO()):
    status = main(["run", {name!r}])
print(json.dumps({{"seconds": time.perf_counter() - t0, "names": names, "status": status}}))
"""


def _laws(names):
    """The laws among the compiled functions' modules."""
    return sorted({m for n in names for m in _LAW_MODULES if f".{m}." in f".{n}"})


def scene_compile(name):
    """One row: the scene's cold (empty cache) and warm process times (s, whole command
    from the interpreter's start: wall ``*_s`` and CPU ``*_cpu_s``), the number of functions
    compiled cold, the laws among them, and the number of 3D functions compiled."""
    code = _SCRIPT.format(name=name)
    row = {"item": f"rbimpact run {name}"}
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "RBIMPACT_LOOP": "scene"}
        for label in ("cold", "warm"):
            t0 = time.perf_counter()
            c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            out = subprocess.run([sys.executable, "-c", code], env=env, check=True,
                                 capture_output=True, text=True).stdout
            wall = time.perf_counter() - t0
            c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            info = json.loads(out.strip().splitlines()[-1])
            row[f"{label}_s"] = wall
            # CPU seconds of the process (user + system): robust on a loaded machine
            row[f"{label}_cpu_s"] = (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime)
            if label == "cold":
                names = info["names"]
                row["functions"] = len(names)
                row["laws"] = ",".join(_laws(names)) or "-"
                row["functions_3d"] = sum(("3d" in n) for n in names)
    return row


def bench_compile_scenes(scenes=COMPILE_SCENES):
    """Rows of ``scene_compile`` for each scene."""
    return [scene_compile(name) for name in scenes]
