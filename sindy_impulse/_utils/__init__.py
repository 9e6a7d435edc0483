"""Infrastructure under every layer of the package (as scikit-learn's ``utils``): argument validation
(:mod:`.validation`), single, multiple and ragged trajectories with their times and inputs
(:mod:`.trajectories`), parameter constraints (:mod:`.params`), the numba decorator (:mod:`.jit`), the kernel
cache it waits for (:mod:`.kernel_cache`) and the background build of that cache (:mod:`.warmup`).

Deliberately empty: importing one of these modules must not import the others (the kernels import
:mod:`.jit`, and :mod:`.warmup` imports the kernels to build them).
"""
