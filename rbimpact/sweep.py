"""Parameter sweeps: one scenario over a grid of parameters, laws and seeds, on Dask.

    >>> import rbimpact
    >>> df = rbimpact.sweep("die_toss", law=["kane_levinson", "routh"],
    ...                     grid={"mu": [0.2, 0.5]}, seeds=100, workers=2,
    ...                     out="toss.parquet")

One row per run (a pandas DataFrame), sorted by law, the grid parameters and the seed:

============  ================================================================================
column        meaning
============  ================================================================================
scenario      the scenario's name
law           the collision law
<grid keys>   the scenario parameters swept (typed as the scenario declares them)
seed          the scenario's ``seed`` parameter (0 for a scenario without one)
status        "done" or "max_events" (``Result.status``), or "error" (the run raised)
error         "" or the exception, ``Type: message`` (first line)
impacts       number of impact events (of the partial run for an error, if it has one)
events        number of events
t_final       time reached (s)
E_start       total energy (J, kinetic + gravitational) at the start
E_final       total energy (J) at ``t_final``
energy_lost   ``E_start - E_final`` (J; negative: energy was created)
x_final ...   position of body 0 at ``t_final`` (m): x, y in 2D; x, y, z in 3D
angle_final   2D only: the angle of body 0 at ``t_final`` (rad, counter-clockwise, not
              wrapped: a block that toppled once to the left ends near +pi/2)
face          die_toss only: the face up at the end (1..6), <NA> when not at rest on one
run_s         wall time of the run on its worker (s; the worker's code was loaded before)
============  ================================================================================

Reproducible: run ``k`` of a grid point uses ``seed = seeds[k]`` (``seeds=N`` means
0..N-1), whatever the number of workers, and the table is sorted, so any ``workers`` gives
the same table (``run_s`` aside). Resumable: with ``out``, every finished run is appended
at once to ``<out>.partial.jsonl`` and the table is consolidated into ``out`` (Parquet) at
the end; a new sweep with the same ``out`` skips the runs already there (same scenario,
law, grid values and seed). A run that raises is a row with status "error", never a lost
sweep. Everything is checked (scenario, law, grid keys and every grid value, by building
each grid point) before anything runs: ``ValueError`` saying what is allowed.

``workers=1`` runs in this process, without Dask; ``workers > 1`` starts a Dask
``LocalCluster`` (``workers`` processes of one thread; on Linux forked from this process
once it has loaded the scenario's compiled code, so they start without importing anything
or loading the Numba cache: ``START_METHOD``), ``scheduler="tcp://host:port"`` uses an
existing cluster instead (its workers load the code first, in parallel). The runs go out
in about ``TASKS_PER_WORKER`` chunks per worker. Needs pandas, pyarrow, dask[distributed]
(and tqdm for the progress bar): ``pip install 'rbimpact[sweep]'``. Importing this module
imports none of them.
"""
import itertools
import json
import math
import os
import sys
import time
import types

import numpy as np

from .result_base import require

__all__ = ["sweep", "plan", "Run"]

#: runs per Dask task: about ``TASKS_PER_WORKER`` tasks per worker, at most ``MAX_CHUNK``
#: runs each (a die toss takes ~2 ms; one task per run would be mostly scheduling)
TASKS_PER_WORKER = 8
MAX_CHUNK = 64
#: how a LocalCluster's workers start: "fork" (Linux; they inherit this process's loaded
#: code) or "spawn" (new interpreters, Dask's default; also used where fork is unavailable)
START_METHOD = "fork"
#: columns every row has, after the grid keys (``face`` and the final position depend on
#: the scenario)
RESULT_COLUMNS = ("status", "error", "impacts", "events", "t_final", "E_start", "E_final",
                  "energy_lost")
_INT_COLUMNS = ("impacts", "events", "face")


class Run(tuple):
    """One run: ``(law, values, seed)``; ``values`` is a tuple in the grid's key order."""

    __slots__ = ()

    def __new__(cls, law, values, seed):
        return tuple.__new__(cls, (law, tuple(values), int(seed)))

    law = property(lambda self: self[0])
    values = property(lambda self: self[1])
    seed = property(lambda self: self[2])


def _one_line(text):
    return " ".join(str(text).split())


def plan(scenario, law=None, grid=None, seeds=1):
    """Check a sweep and list its runs, without running anything.

    Returns ``(spec, laws, keys, runs)``: the scenario's ``ScenarioSpec``, the laws (tuple),
    the grid keys (tuple) and the runs (list of ``Run``, in law, grid, seed order). Raises
    a one-line ``ValueError`` for an unknown scenario or law, a grid key that is not a
    parameter of the scenario, a value of the wrong type or out of range (every grid
    point is built), or ``seeds > 1`` for a scenario without a ``seed`` parameter."""
    from . import scenarios
    if not isinstance(scenario, str):
        raise ValueError(f"sweep: scenario must be a scenario name (str), got {scenario!r}")
    spec = scenarios.spec(scenario)
    if law is None:
        laws = (spec.default_law,)
    elif isinstance(law, str):
        laws = (law,)
    else:
        laws = tuple(law)
    if not laws:
        raise ValueError("sweep: law must be a law name or a non-empty list of law names")
    for x in laws:
        if x not in spec.laws:
            raise ValueError(f"sweep: scenario {scenario!r} supports the laws "
                             f"{', '.join(spec.laws)}; got law={x!r}")
    if len(set(laws)) != len(laws):
        raise ValueError(f"sweep: a law is listed twice: {', '.join(laws)}")
    grid = dict(grid or {})
    has_seed = "seed" in spec.params
    allowed = [k for k in spec.params if k not in ("law", "seed")]
    keys = tuple(grid)
    values = []
    for k in keys:
        if k in ("law", "seed") and k in spec.params:
            raise ValueError(f"sweep: {k!r} is not a grid key: use the "
                             f"{'law' if k == 'law' else 'seeds'} argument")
        if k not in spec.params:
            raise ValueError(f"sweep: scenario {scenario!r} has no parameter {k!r}; its "
                             f"parameters are {', '.join(allowed)}")
        vs = grid[k]
        if isinstance(vs, (str, bytes)) or not hasattr(vs, "__iter__"):
            vs = [vs]
        vs = [spec.params[k].coerce(v.item() if isinstance(v, np.generic) else v, scenario)
              for v in vs]
        if not vs:
            raise ValueError(f"sweep: grid key {k!r} has no values")
        if len(set(vs)) != len(vs):
            raise ValueError(f"sweep: grid key {k!r} lists a value twice: {vs}")
        values.append(vs)
    if isinstance(seeds, (bool, np.bool_)):
        raise ValueError(f"sweep: seeds must be a positive int or a list of ints, "
                         f"got {seeds!r}")
    if isinstance(seeds, (int, np.integer)):
        if seeds < 1:
            raise ValueError(f"sweep: seeds must be >= 1, got {seeds}")
        seed_list = list(range(int(seeds)))
    else:
        seed_list = list(seeds)
        if not seed_list or not all(isinstance(s, (int, np.integer))
                                    and not isinstance(s, (bool, np.bool_)) for s in seed_list):
            raise ValueError(f"sweep: seeds must be a positive int or a non-empty list of "
                             f"ints, got {seeds!r}")
        if len(set(seed_list)) != len(seed_list):
            raise ValueError("sweep: a seed is listed twice")
        if min(seed_list) < 0:
            raise ValueError(f"sweep: seeds must be >= 0, got {min(seed_list)}")
        seed_list = [int(x) for x in seed_list]
    if not has_seed and seed_list != [0]:
        raise ValueError(f"sweep: scenario {scenario!r} has no seed parameter (it is "
                         f"deterministic): use seeds=1")
    points = list(itertools.product(*values))
    for lw in laws:                       # build every grid point: values the builder rejects
        for p in points:
            params = dict(zip(keys, p), law=lw)
            if has_seed:
                params["seed"] = seed_list[0]
            try:
                scenarios.get(scenario, **params)
            except ValueError as exc:
                where = ", ".join(f"{k}={v!r}" for k, v in params.items())
                raise ValueError(f"sweep: {where}: {_one_line(exc)}") from None
    runs = [Run(lw, p, s) for lw in laws for p in points for s in seed_list]
    return spec, laws, keys, runs


# ---------------------------------------------------------------- one run (on a worker)

def _summary(scenario, result):
    """Final-state columns of a finished (or partial) result."""
    row = {"impacts": int(result.n_impacts), "events": int(len(result.events)),
           "t_final": float(result.t_end)}
    e = np.asarray(result.energy(np.array([result.t_start, result.t_end])), dtype=float)
    row.update(E_start=float(e[0]), E_final=float(e[1]), energy_lost=float(e[0] - e[1]))
    s = result.sample([result.t_end])
    if "position" in s:
        pos = s["position"][0, 0]
        row.update(x_final=float(pos[0]), y_final=float(pos[1]), z_final=float(pos[2]))
    else:
        row.update(x_final=float(s["x"][0, 0]), y_final=float(s["y"][0, 0]),
                   angle_final=float(s["angle"][0, 0]))
    extra = SUMMARIES.get(scenario)
    if extra is not None:
        row.update(extra(result))
    return row


def _die_face(result):
    from .scenarios.die_toss import face_up
    return {"face": face_up(result)}


#: scenario -> function(result) -> dict of extra final-state columns (ints or floats;
#: None for missing); ints listed in ``_INT_COLUMNS`` become nullable Int64 columns
SUMMARIES = {"die_toss": _die_face}


def run_one(scenario, keys, run):
    """Run one ``Run`` of ``scenario`` and return its row (a dict); exceptions become a
    row with status "error"."""
    import warnings
    from . import scenarios
    spec = scenarios.spec(scenario)
    params = dict(zip(keys, run.values), law=run.law)
    if "seed" in spec.params:
        params["seed"] = run.seed
    row = {"scenario": scenario, "law": run.law, **dict(zip(keys, run.values)),
           "seed": run.seed, "status": "error", "error": ""}
    t0 = time.perf_counter()
    try:
        sc = scenarios.get(scenario, **params)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = sc.simulate()
        row["run_s"] = time.perf_counter() - t0
        summary = _summary(scenario, result)
        row.update(summary, status=str(result.status))
    except Exception as exc:  # noqa: BLE001 - a failed run is a row, never a lost sweep
        row["run_s"] = time.perf_counter() - t0
        text = str(exc).splitlines()[0] if str(exc) else ""
        row["error"] = f"{type(exc).__name__}: {text}"[:500]
        partial = getattr(exc, "result", None)
        if partial is not None:
            try:
                row.update(_summary(scenario, partial))
            except Exception:  # noqa: BLE001
                pass
    return row


def run_chunk(scenario, keys, runs):
    """``run_one`` over a list of runs (one Dask task)."""
    return [run_one(scenario, keys, Run(*r)) for r in runs]


def _warm(scenario, keys, runs):
    """Load the compiled code a worker needs (one run per law), untimed."""
    seen = set()
    for r in runs:
        if r[0] not in seen:
            seen.add(r[0])
            run_one(scenario, keys, Run(*r))
    return len(seen)


# ---------------------------------------------------------------- the table

def _frame(rows, spec, keys):
    """Rows -> a DataFrame with the sweep's column order and dtypes, sorted."""
    pd = require("pandas", "rbimpact.sweep")
    df = pd.DataFrame(rows)
    head = ["scenario", "law", *keys, "seed", *RESULT_COLUMNS]
    tail = [c for c in ("x_final", "y_final", "z_final", "angle_final", "face", "run_s")
            if c in df.columns
            or c == "run_s"]
    for c in head + tail:
        if c not in df.columns:
            df[c] = np.nan if c not in ("status", "error", "scenario", "law") else ""
    extra = [c for c in df.columns if c not in head + tail]
    df = df[head + tail + extra]
    for k in keys:
        t = spec.params[k].type
        if t is float:
            df[k] = df[k].astype("float64")
        elif t is int:
            df[k] = df[k].astype("int64")
        elif t is bool:
            df[k] = df[k].astype("bool")
        else:
            df[k] = df[k].astype(object)
    df["seed"] = df["seed"].astype("int64")
    for c in _INT_COLUMNS:
        if c in df.columns:
            df[c] = pd.array([None if v is None or (isinstance(v, float) and math.isnan(v))
                              else int(v) for v in df[c]], dtype="Int64")
    for c in ("t_final", "E_start", "E_final", "energy_lost", "x_final", "y_final",
              "z_final", "angle_final", "run_s"):
        if c in df.columns:
            df[c] = df[c].astype("float64")
    for c in ("scenario", "law", "status", "error"):
        df[c] = df[c].fillna("").astype(object)
    df = df.sort_values(["law", *keys, "seed"], kind="mergesort").reset_index(drop=True)
    return df


def _key(row, keys):
    return (row["law"], tuple(row[k] for k in keys), int(row["seed"]))


def _coerce_row(row, spec, keys):
    """A row read back from a file, with its grid values in the scenario's types."""
    row = dict(row)
    for k in keys:
        v = row[k]
        if isinstance(v, np.generic):
            v = v.item()
        row[k] = spec.params[k].type(v)
    return row


class _Store:
    """The ``out`` file and its sidecar ``<out>.partial.jsonl`` (one JSON row per finished
    run, flushed at once): what a killed sweep leaves behind is read back on resume."""

    def __init__(self, out, spec, keys):
        from ._validate import writable_path
        self.out = os.fspath(out)
        if not self.out.endswith(".parquet"):
            raise ValueError(f"sweep: out must be a .parquet file, got {self.out!r}")
        writable_path("sweep: out", self.out)
        self.partial = self.out + ".partial.jsonl"
        self.spec, self.keys = spec, keys
        self._fh = None

    def load(self):
        """Rows already finished (from ``out`` and the sidecar), deduplicated."""
        pd = require("pandas", "rbimpact.sweep")
        require("pyarrow", "rbimpact.sweep (Parquet output)")
        rows = []
        if os.path.exists(self.out):
            old = pd.read_parquet(self.out)
            want = {"scenario", "law", "seed", *self.keys}
            params = (set(old.columns) & set(self.spec.params)) - {"law", "seed"}
            if not want <= set(old.columns) or params != set(self.keys) or (
                    len(old) and set(old["scenario"]) != {self.spec.name}):
                raise ValueError(
                    f"sweep: {self.out} holds another sweep (scenario "
                    f"{sorted(set(old['scenario'])) if 'scenario' in old else '?'}, grid keys "
                    f"{sorted(params)}); this one is {self.spec.name!r} with grid keys "
                    f"{sorted(self.keys)}: choose another out file")
            rows = [r for r in old.astype(object).where(old.notna(), None)
                    .to_dict("records")]
        if os.path.exists(self.partial):
            with open(self.partial) as f:
                for line in f:
                    try:
                        r = json.loads(line)
                    except ValueError:        # a line cut short by a kill
                        continue
                    params = (set(r) & set(self.spec.params)) - {"law", "seed"}
                    if r.get("scenario") != self.spec.name or params != set(self.keys):
                        raise ValueError(
                            f"sweep: {self.partial} (the finished runs of an interrupted "
                            f"sweep) holds another sweep ({r.get('scenario')!r}, grid keys "
                            f"{sorted(params)}); finish it, or delete the file")
                    rows.append(r)
        seen = {}
        for r in rows:
            r = _coerce_row(r, self.spec, self.keys)
            seen[_key(r, self.keys)] = r
        return seen

    def append(self, row):
        if self._fh is None:
            self._fh = open(self.partial, "a+")
            if self._fh.tell() > 0:              # a line cut by a kill: end it first
                self._fh.seek(self._fh.tell() - 1)
                last = self._fh.read(1)
                self._fh.seek(0, os.SEEK_END)
                if last != "\n":
                    self._fh.write("\n")
        self._fh.write(json.dumps(row, default=_json_default) + "\n")
        self._fh.flush()

    def close(self):
        if self._fh is not None:
            self._fh.close()
            self._fh = None

    def consolidate(self, df):
        """Write the whole table to ``out`` (atomically) and drop the sidecar."""
        self.close()
        tmp = self.out + ".tmp"
        df.to_parquet(tmp, index=False)
        os.replace(tmp, self.out)
        if os.path.exists(self.partial):
            os.remove(self.partial)


def _available(module):
    """Raise the ImportError of ``require`` when ``module`` is not installed, without
    importing it."""
    import importlib.util
    if importlib.util.find_spec(module) is None:
        require(module, "rbimpact.sweep")


def _json_default(x):
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(f"not serialisable: {x!r}")


# ---------------------------------------------------------------- the sweep

def _chunks(runs, workers):
    size = max(1, min(MAX_CHUNK, math.ceil(len(runs) / (TASKS_PER_WORKER * workers))))
    return [runs[i:i + size] for i in range(0, len(runs), size)]


def sweep(scenario, law=None, grid=None, seeds=1, workers=1, scheduler=None, out=None,
          progress=True):
    """Run ``scenario`` over ``grid`` (parameter -> list of values), ``law`` (a law name or
    a list; default the scenario's) and ``seeds`` (N: seeds 0..N-1, or a list of ints) and
    return the table (pandas DataFrame, one row per run; the columns are listed in the
    module docstring).

    ``workers``: processes of a Dask ``LocalCluster`` (1: in this process, no Dask);
    ``scheduler``: the address of a running Dask scheduler to use instead; ``out``: a
    ``.parquet`` file, written as runs finish (resumable: runs already in it are
    skipped); ``progress``: a progress bar on stderr when it is a terminal.

    ``df.attrs``: runs, ran (computed now), skipped (found in ``out``), seconds (wall
    time), setup_s (loading the code, starting the cluster and its workers), compute_s
    (from then to the last run), workers."""
    _available("pandas")                  # imported later: while the workers run, if any
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise ValueError(f"sweep: workers must be a positive int, got {workers!r}")
    spec, laws, keys, runs = plan(scenario, law, grid, seeds)
    store = _Store(out, spec, keys) if out is not None else None
    done = store.load() if store is not None else {}
    todo = [r for r in runs if tuple(r) not in done]
    rows = list(done.values())
    from .progress import progress as bar
    t0 = time.perf_counter()
    clock = {"start": t0}
    gen = _execute(scenario, keys, todo, workers, scheduler, clock) if todo else iter(())
    try:
        it = bar(gen, total=len(todo), desc=f"sweep {scenario}", unit="run") \
            if progress and todo else gen
        for row in it:
            rows.append(row)
            if store is not None:
                store.append(row)
    finally:
        if hasattr(gen, "close"):
            gen.close()                          # stops the cluster now, even on Ctrl-C
        if store is not None:
            store.close()
            if rows:
                store.consolidate(_frame(rows, spec, keys))
    wanted = set(map(tuple, runs))
    df = _frame([r for r in rows if _key(r, keys) in wanted], spec, keys)
    df.attrs = {"scenario": scenario, "runs": len(runs), "ran": len(todo),
                "skipped": len(runs) - len(todo), "seconds": time.perf_counter() - t0,
                "setup_s": clock.get("setup", t0) - t0,
                "compute_s": clock.get("done", t0) - clock.get("setup", t0),
                "workers": int(workers) if scheduler is None else None}
    return df


def _can_fork():
    """True where LocalCluster workers are forked from this process (Linux): they start
    with this process's imported modules and loaded compiled code, in ~0.1 s instead of
    ~1.5 s each (a new interpreter importing NumPy, Numba, SciPy, Dask and loading the
    Numba cache)."""
    import multiprocessing
    return (START_METHOD == "fork" and sys.platform.startswith("linux")
            and "fork" in multiprocessing.get_all_start_methods())


def _local_cluster(workers):
    """A LocalCluster of ``workers`` processes of one thread, no dashboard; forked from
    this process when ``_can_fork()`` (the Dask option
    ``distributed.worker.multiprocessing-method``, for this cluster only). Returns
    ``(cluster, forked)``."""
    import logging
    import warnings
    import dask
    from distributed import LocalCluster
    forked = _can_fork()
    # no dashboard, so nobody reads the workers' statistical profiler: spare its sampling
    config = {"distributed.worker.profile.enabled": False}
    if forked:
        config["distributed.worker.multiprocessing-method"] = "fork"
    sys.stdout.flush()
    sys.stderr.flush()
    with dask.config.set(config), warnings.catch_warnings():
        # Python >= 3.12 warns that forking a process with threads (Dask's event loop)
        # may deadlock the child; the child runs a new Dask worker and nothing else
        warnings.filterwarnings("ignore", message=r".*use of fork\(\) may lead to deadlocks",
                                category=DeprecationWarning)
        cluster = LocalCluster(n_workers=int(workers), threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR)
    return cluster, forked


def _execute(scenario, keys, todo, workers, scheduler, clock):
    """Yield the rows of ``todo`` as they finish; ``clock["setup"]`` and ``clock["done"]``
    get the times (``time.perf_counter``) the runs started (cluster up, code loaded) and
    the last one finished.

    ``workers > 1``: the code is loaded here first (one run per law), then the
    LocalCluster's workers are forked from this process (they inherit it: no import, no
    Numba cache load), and the runs go out in a few large chunks (``_chunks``). pandas is
    imported here while the workers compute. On an existing cluster (``scheduler``) or
    where forking is not available, every worker loads the code at once
    (``Client.run``), in parallel."""
    if scheduler is None and workers == 1:
        _warm(scenario, keys, todo)
        clock["setup"] = time.perf_counter()
        for r in todo:
            yield run_one(scenario, keys, r)
        clock["done"] = time.perf_counter()
        return
    require("distributed", "rbimpact.sweep with workers > 1 or a scheduler")
    from distributed import Client, as_completed
    cluster, forked = None, False
    if scheduler is None:
        _warm(scenario, keys, todo)              # inherited by the forked workers
        cluster, forked = _local_cluster(workers)
        client = Client(cluster)
    else:
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise ValueError(f"sweep: no Dask scheduler at {scheduler!r}: "
                             f"{_one_line(exc)}") from None
    try:
        n_workers = max(1, len(client.scheduler_info().get("workers", {})) or int(workers))
        runs = [tuple(r) for r in todo]
        if not forked:
            client.run(_warm, scenario, keys, runs)
        clock["setup"] = time.perf_counter()
        chunks = _chunks(runs, n_workers)
        futures = [client.submit(run_chunk, scenario, keys, c, pure=False) for c in chunks]
        index = {f.key: i for i, f in enumerate(futures)}
        require("pandas", "rbimpact.sweep")     # the table's; meanwhile the workers run
        for fut in as_completed(futures):
            try:
                chunk_rows = fut.result()
            except Exception as exc:  # noqa: BLE001 - a lost worker: rows with the error
                chunk_rows = [{"scenario": scenario, "law": r[0],
                               **dict(zip(keys, r[1])), "seed": r[2],
                               "status": "error",
                               "error": f"{type(exc).__name__}: {_one_line(exc)}"[:500]}
                              for r in chunks[index[fut.key]]]
            yield from chunk_rows
        clock["done"] = time.perf_counter()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


# ---------------------------------------------------------------- command line

def parse_grid(scenario, items):
    """``KEY=V1,V2,...`` strings (``--grid``) -> {key: [typed values]} for ``scenario``."""
    from . import scenarios
    spec = scenarios.spec(scenario)
    grid = {}
    for text in items or ():
        key, sep, values = str(text).partition("=")
        key = key.strip()
        if not sep or not key or not values.strip():
            raise ValueError(f"--grid {text!r} is not of the form KEY=V1,V2,...")
        if key in grid:
            raise ValueError(f"--grid {key} is given twice; list all its values in one --grid")
        if key not in spec.params or key in ("law", "seed"):
            plan(scenario, grid={key: []})          # raises the one-line error
        grid[key] = [spec.params[key].parse(v, scenario) for v in values.split(",")]
    return grid


def sweep_command(scenario, law=None, grid=(), seeds=1, workers=1, scheduler=None,
                  out=None):
    """``rbimpact sweep``: run the sweep and return the printed summary (one line per grid
    point and law: runs, failures, mean impacts and energy lost; die_toss: the faces)."""
    laws = None
    if law:
        laws = [x.strip() for item in law for x in str(item).split(",") if x.strip()]
    grid = parse_grid(scenario, grid)
    keys = list(grid)
    try:
        df = sweep(scenario, law=laws, grid=grid, seeds=seeds, workers=workers,
                   scheduler=scheduler, out=out)
    except ValueError as exc:            # the command line says "rbimpact sweep: error:"
        text = str(exc)
        raise ValueError(text[len("sweep: "):] if text.startswith("sweep: ") else text) \
            from None
    a = df.attrs
    where = (f"the cluster at {scheduler}" if scheduler else
             "this process" if workers == 1 else f"a LocalCluster of {workers} workers")
    lines = [f"sweep {scenario}: {a['runs']} runs, {a['ran']} computed in "
             f"{a['seconds']:.2f} s on {where}"
             + (f" (start-up {a['setup_s']:.2f} s, runs {a['compute_s']:.2f} s)"
                if a["ran"] else "")
             + (f", {a['skipped']} already in {out}" if out else "")]
    counts = df["status"].value_counts()
    lines.append("status: " + ", ".join(f"{k} {v}" for k, v in counts.items()))
    groups = ["law", *keys]
    rows = []
    for g, part in df.groupby(groups, sort=False):
        g = g if isinstance(g, tuple) else (g,)
        ok = part[part["status"] != "error"]
        r = [*map(str, g), str(len(part)), str(len(part) - len(ok)),
             f"{ok['impacts'].mean():.1f}" if len(ok) else "-",
             f"{ok['energy_lost'].mean():.4g}" if len(ok) else "-"]
        if "face" in part:
            f = part["face"].value_counts()
            r.append(" ".join(str(int(f.get(k, 0))) for k in range(1, 7)))
        rows.append(r)
    head = [*groups, "runs", "errors", "mean impacts", "mean energy lost (J)"]
    if "face" in df:
        head.append("faces 1..6")
    widths = [max(len(x) for x in col) for col in zip(head, *rows)]
    fmt = "  ".join("{:<%d}" % w for w in widths)
    lines += ["", fmt.format(*head).rstrip(), "  ".join("-" * w for w in widths)]
    lines += [fmt.format(*r).rstrip() for r in rows]
    errors = df[df["status"] == "error"]
    if len(errors):
        lines.append("")
        lines += ["error: " + ", ".join(f"{k} {r[k]}" for k in ("law", *keys, "seed"))
                  + f": {r['error']}" for _, r in errors.head(5).iterrows()]
        if len(errors) > 5:
            lines.append(f"... and {len(errors) - 5} more (column 'error' of the table)")
    if out:
        lines.append(f"table written to {out} ({len(df)} rows of this sweep)")
    return "\n".join(lines)


class _CallableModule(types.ModuleType):
    """``rbimpact.sweep`` is this module once ``import rbimpact.sweep`` has run (the
    import system sets the attribute); calling it calls ``sweep``."""

    def __call__(self, *args, **kwargs):
        return sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
