"""The test suite runs every simulation on the general event loop (``$RBIMPACT_LOOP``,
``rbimpact._setup.LOOP_KINDS``): one compile per dimension serves every scene, where the
scene loops the suite's scenes reach would be 45 (2D) and 21 (3D) compiles (issue 14: the
CI run's time). The scene loops give the same results bit for bit: tests/test_loop_kinds.py
runs scenes of every feature pattern on both; the tests of the loop's switches
(test_shapes_switch2d, test_bench's pay-for-what-you-use rows) choose their loops
themselves. An explicit ``RBIMPACT_LOOP`` in the environment is kept.

A run of at least ``PREWARM_MIN_TESTS`` tests (the whole suite) first warms Numba's
on-disk cache with the slowest independent compiles (the two general loops, the gas
entries the suite runs: ``tests/_prewarm.py``) in ``PREWARM_WORKERS`` processes at once:
one pytest process compiles on one core, and the CI machine has two. With a warm cache
the warm-up only loads (a few seconds). ``RBIMPACT_PREWARM=0`` turns it off; a warm-up
that fails or overruns ``PREWARM_TIMEOUT`` is reported and the tests compile what they
need themselves, as without it."""
import os
import subprocess
import sys
import time

os.environ.setdefault("RBIMPACT_LOOP", "general")

PREWARM_MIN_TESTS = 1000    # tests collected; a file or a selection does not pay the warm-up
PREWARM_WORKERS = 2         # processes compiling at once (the CI machine's cores)
PREWARM_TIMEOUT = 1800.0    # s, for all of them


def pytest_collection_finish(session):
    if (len(session.items) < PREWARM_MIN_TESTS or session.config.option.collectonly
            or os.environ.get("RBIMPACT_PREWARM") == "0"
            or os.environ.get("NUMBA_DISABLE_JIT") == "1"):
        return
    script = os.path.join(os.path.dirname(__file__), "_prewarm.py")
    t0 = time.perf_counter()
    procs = [subprocess.Popen([sys.executable, script, str(k), str(PREWARM_WORKERS)],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
             for k in range(PREWARM_WORKERS)]
    lines = []
    for p in procs:
        try:
            out, _ = p.communicate(timeout=max(1.0, PREWARM_TIMEOUT - (time.perf_counter()
                                                                         - t0)))
        except subprocess.TimeoutExpired:
            p.kill()
            out, _ = p.communicate()
            lines.append("prewarm: timed out (the tests compile what is missing)")
        lines += out.strip().splitlines()[-8:] if p.returncode else out.strip().splitlines()
        if p.returncode:
            lines.append(f"prewarm: a worker failed (exit {p.returncode}); the tests "
                         "compile what is missing")
    writer = session.config.get_terminal_writer()
    for line in lines:
        writer.line(line)
    writer.line(f"prewarm: {PREWARM_WORKERS} processes, {time.perf_counter() - t0:.1f} s")
