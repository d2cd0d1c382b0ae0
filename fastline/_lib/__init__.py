"""Plumbing shared by every layer of fastline: Numba's settings (:mod:`~fastline._lib.jit`),
input validation (:mod:`~fastline._lib.validate`), FFTW plans and aligned buffers
(:mod:`~fastline._lib.fftw`), executors for tables of tasks (:mod:`~fastline._lib.executors`),
where warnings point (:mod:`~fastline._lib.stack`) and the package's version
(:mod:`~fastline._lib.version`). Imports nothing of fastline."""
