"""The test suite runs every simulation on the general event loop (``$RBIMPACT_LOOP``,
``rbimpact._setup.LOOP_KINDS``): one compile per dimension serves every scene, where the
scene loops the suite's scenes reach would be 45 (2D) and 21 (3D) compiles (issue 14: the
CI run's time). The scene loops give the same results bit for bit: tests/test_loop_kinds.py
runs scenes of every feature pattern on both; the tests of the loop's switches
(test_shapes_switch2d, test_bench's pay-for-what-you-use rows) choose their loops
themselves. An explicit ``RBIMPACT_LOOP`` in the environment is kept."""
import os

os.environ.setdefault("RBIMPACT_LOOP", "general")
