"""Numba kernels of rbimpact: collision laws (2D, 3D, batched), flight and time of impact.

Arrays and scalars in, arrays and scalars out: every function here can be called from a
user's own ``@numba.njit`` code. See ``common.py`` for the kernel contract.
"""
