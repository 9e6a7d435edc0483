"""From a fitted feature library to what the simulator evaluates.

:func:`term_table` describes the terms of the libraries the compiled simulator supports
(:class:`pysindy.PolynomialLibrary`, :class:`pysindy.FourierLibrary`, :class:`pysindy.ConcatLibrary` of
supported ones, :class:`~sindy_impulse.MechanicalLibrary` and anything with a ``term_table_``) as a
:class:`~sindy_impulse.simulation.TermTable`. :func:`library_terms` returns that table, or for any other
library a function that evaluates the library's terms, which the simulator's general fallback uses.
"""

from __future__ import annotations

import numpy as np
from pysindy.utils import AxesArray

from ..simulation.terms import ABS, COS, PLAIN, SIGNED_SQUARE, SIN, SMOOTH_SIGN, TermTable

__all__ = ["TermTable", "term_table", "library_terms", "PLAIN", "SIGNED_SQUARE", "SMOOTH_SIGN", "ABS"]


def _fourier_table(library, n_inputs: int) -> TermTable:
    """sin/cos of each input at frequencies 1..n_frequencies, in FourierLibrary's column order."""
    func, state, param = [], [], []
    for i in range(library.n_frequencies):
        for j in range(n_inputs):
            for enabled, code in ((library.include_sin, SIN), (library.include_cos, COS)):
                if enabled:
                    func.append(code)
                    state.append(j)
                    param.append(float(i + 1))
    n = len(func)
    return TermTable(
        np.zeros((n, n_inputs), np.int64),
        np.asarray(func, np.int64),
        np.asarray(state, np.int64),
        np.asarray(param, float),
    )


def term_table(library, n_inputs: int) -> TermTable:
    """The :class:`TermTable` of a fitted feature library acting on ``n_inputs`` inputs.

    ``n_inputs`` counts the states and the control inputs the library was fitted on.

    Raises
    ------
    TypeError
        For a library whose terms the compiled simulator cannot evaluate (use :func:`library_terms`).

    Examples
    --------
    >>> import numpy as np, pysindy as ps
    >>> lib = ps.PolynomialLibrary(degree=2).fit(np.ones((5, 2)))
    >>> term_table(lib, 2).powers.tolist()
    [[0, 0], [1, 0], [0, 1], [2, 0], [1, 1], [0, 2]]
    """
    table = getattr(library, "term_table_", None)
    kind = type(library).__name__
    if table is None and kind == "PolynomialLibrary" and hasattr(library, "n_output_features_"):
        table = TermTable.polynomial(np.asarray(library.powers_))
    elif table is None and kind == "FourierLibrary" and hasattr(library, "n_output_features_"):
        table = _fourier_table(library, int(library.n_features_in_))
    elif table is None and kind == "ConcatLibrary" and hasattr(library, "n_output_features_"):
        table = TermTable.concatenate(term_table(lib, n_inputs) for lib in library.libraries)
    if table is None:
        raise TypeError(
            f"{kind} is not supported by the compiled simulator; use pysindy.PolynomialLibrary, "
            "FourierLibrary, ConcatLibrary of those, or sindy_impulse.MechanicalLibrary (other libraries "
            "are simulated by the slower general fallback)"
        )
    if table.n_inputs != n_inputs:
        raise ValueError(f"library was fitted on {table.n_inputs} inputs, data have {n_inputs}")
    return table


def library_terms(library, n_inputs: int):
    """The library's :class:`TermTable`, or a function ``Z -> Theta(Z)`` for the general fallback.

    Examples
    --------
    >>> import numpy as np, pysindy as ps
    >>> lib = ps.CustomLibrary(library_functions=[lambda x: np.exp(x)]).fit(np.zeros((4, 1)))
    >>> evaluate = library_terms(lib, 1)
    >>> callable(evaluate), evaluate(np.zeros((1, 1))).tolist()
    (True, [[1.0]])
    """
    try:
        return term_table(library, n_inputs)
    except TypeError:
        pass

    def evaluate(Z: np.ndarray) -> np.ndarray:
        return np.asarray(library.transform(AxesArray(np.atleast_2d(Z), {"ax_time": 0, "ax_coord": 1})))

    return evaluate
