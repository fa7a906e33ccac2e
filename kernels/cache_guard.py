"""Stale-cache guard for compiled kernels that call kernels of other modules.

Numba's on-disk cache (``cache=True``) keys a compiled function on the stamp (mtime and
size) of the function's *own* source file only. A caller compiled with a callee of another
module inlined or linked into it (the steppers call the laws, flight and time-of-impact
kernels; ``dispatch`` calls the laws; the laws call ``common``) keeps running the old
callee after that callee's file changed. ``guard`` closes the gap.

Call it at the top of a kernel module, before its ``from .x import`` lines::

    from .cache_guard import guard
    guard(__name__, __file__)

It finds the module's kernel dependencies (the ``from .x import`` and ``from . import x``
lines of the module and, transitively, of those modules; or an explicit list), and keeps
in the cache directory a stamp file ``<module>.deps`` with the (mtime, size) of each of
them, the same freshness test Numba applies to a function's own file. When a dependency
changed (or no stamp exists yet), it deletes the cached index and data files
(``<module>.*.nbi``/``.nbc``) of the guarded module and of every module of its closure
that (transitively) imports a changed file; they are recompiled on first call.

Running it first in the module matters: functions compiled eagerly at import (explicit
signatures) load their cache when defined, so stale files must be gone by then.

Cost per import when nothing changed: one small file read and one ``os.stat`` per
dependency (no source is read or hashed). A read-only or disabled cache is left alone.
"""
import os

_HERE = os.path.dirname(os.path.abspath(__file__))
_PKG = os.path.basename(_HERE)
_STAMP_EXT = ".kdeps"
_DIR = []           # memo: [cache directory or None], shared by every guarded module


def _cache_dir():
    """Numba's cache directory for the files of this package (the same for every kernel
    module: it depends on the source directory only), or None when caching is off."""
    if not _DIR:
        _DIR.append(_locate())
    return _DIR[0]


def _locate():
    from numba import njit

    def _probe():       # never compiled: only its cache locator is used
        return 0
    _probe.__module__ = __name__
    _probe.__qualname__ = "_probe"
    try:
        disp = njit(cache=True)(_probe)
        return disp._cache.cache_path
    except Exception:   # noqa: BLE001 (no usable cache locator: nothing is cached)
        return None


def _imports(name):
    """Kernel modules imported by module ``name`` of this package (relative imports)."""
    out = []
    try:
        with open(os.path.join(_HERE, name + ".py"), encoding="utf-8") as f:
            lines = f.read().splitlines()
    except OSError:
        return out
    for line in lines:
        s = line.strip()
        if s.startswith("from ."):
            rest = s[len("from ."):]
            mod, _, names = rest.partition(" import ")
            mod = mod.strip()
            if mod:
                out.append(mod)
            else:   # from . import a, b (or a as b)
                out += [x.split(" as ")[0].strip(" ()\\") for x in names.split(",")
                        if x.strip(" ()\\")]
    return [m for m in out if m != "cache_guard"]


def _closure(name, deps=None):
    """{module: direct kernel imports} over the transitive closure of ``name``."""
    graph = {}
    todo = [name]
    while todo:
        m = todo.pop()
        if m in graph:
            continue
        graph[m] = list(deps) if (m == name and deps is not None) else _imports(m)
        todo += graph[m]
    return graph


def _stat(name):
    try:
        st = os.stat(os.path.join(_HERE, name + ".py"))
        return f"{st.st_mtime_ns}:{st.st_size}"
    except OSError:
        return "missing"


def _read_stamp(path):
    try:
        with open(path, encoding="utf-8") as f:
            rows = [ln.split() for ln in f.read().splitlines() if ln.strip()]
        return {r[0]: r[1] for r in rows if len(r) == 2}
    except OSError:
        return None


def _flush(cache_dir, module):
    """Delete the cached index and data files of kernel module ``module``."""
    prefix = module + "."
    for fn in os.listdir(cache_dir):
        if fn.startswith(prefix) and (fn.endswith(".nbi") or fn.endswith(".nbc")):
            try:
                os.remove(os.path.join(cache_dir, fn))
            except OSError:
                pass


def guard(module_name, module_file=None, deps=None):
    """Flush the Numba cache of kernel module ``module_name`` (``__name__``) and of the
    modules of its dependency closure whose dependencies changed since the last import.
    ``deps``: explicit list of the module's direct kernel dependencies (module names of
    this package) instead of those found in its source. Returns the list of flushed
    modules (empty when everything was fresh)."""
    name = module_name.rsplit(".", 1)[-1]
    cache_dir = _cache_dir()
    if not cache_dir:
        return []           # caching off: nothing can be stale
    path = os.path.join(cache_dir, name + _STAMP_EXT)
    old = _read_stamp(path)
    if old is not None and name in old and all(_stat(m) == s for m, s in old.items()):
        return []           # fast path: every recorded dependency unchanged
    try:
        os.makedirs(cache_dir, exist_ok=True)
    except OSError:
        return []
    graph = _closure(name, deps)
    now = {m: _stat(m) for m in graph}
    changed = set(graph) if old is None else {m for m in graph if old.get(m) != now[m]}

    def stale(m, seen):
        for d in graph.get(m, ()):
            if d in seen:
                continue
            seen.add(d)
            if d in changed or stale(d, seen):
                return True
        return False
    flushed = [m for m in graph if m == name or stale(m, set())]
    try:
        for m in flushed:
            _flush(cache_dir, m)
        tmp = f"{path}.{os.getpid()}.tmp"
        with open(tmp, "w", encoding="utf-8") as f:
            f.write("".join(f"{m} {s}\n" for m, s in sorted(now.items())))
        os.replace(tmp, path)
    except OSError:         # read-only cache: nothing we can write, nothing we can fix
        return []
    return flushed
