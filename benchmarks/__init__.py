"""The benchmarks of sindy-impulse: every figure the documentation quotes, rerunnable by anyone.

Run from the repository root (the folder holding this package)::

    python -m benchmarks --list                  # every benchmark, one line each
    python -m benchmarks NAME [--quick] [ARGS]   # run one; ARGS go to the benchmark (NAME --help lists them)

The runner prints the benchmark's tables and writes ``benchmarks/results/NAME.json`` (``NAME.quick.json``
for a ``--quick`` run; ``--out FILE`` elsewhere, ``--no-save`` nowhere): the command, the date, the git
commit, the machine's load average and core count, the printed output and the benchmark's result.

Groups (one sub-package each):

================== ==========================================================================================
``accuracy``       synthetic records of known truth: the paper's studies, the modal-table families,
                   nonlinearity, backbones, uncertainty, differentiation, preprocessing
``real_records``   measured records (shipped and public ones) and the files built from them
``robustness``     bad inputs, soak runs, work bounds, clipped records, file round trips
``speed``          speed figures, each beside a baseline measured in the same run
``pysindy_suite``  PySINDy's own test suite run against ImpulseSINDy as a drop-in
``tracking``       studies of tracking modes across records
================== ==========================================================================================

A benchmark is a module with ``main(argv=None) -> dict`` (it parses ``argv``, prints its tables and returns a
JSON-able result; a result with ``"ok": False`` makes the runner exit with status 1); every other module is
a helper shared by several benchmarks (e.g. :mod:`benchmarks.accuracy.families`, the modal-table
families). Benchmarks import only ``sindy_impulse`` and ``benchmarks.*``.
"""
