"""From a fitted feature library to what the simulator evaluates.

:func:`term_table` describes the terms of the libraries the compiled simulator supports
(:class:`pysindy.PolynomialLibrary`, :class:`pysindy.FourierLibrary`, their ``ConcatLibrary``,
``TensoredLibrary`` and ``GeneralizedLibrary``, :class:`~sindy_impulse.MechanicalLibrary` and anything with a
``term_table_``) as a :class:`~sindy_impulse.simulation.TermTable`. :func:`library_terms` returns that table,
or for any other library a function that evaluates the library's terms, which the simulator's general
fallback uses: on plain arrays for ``CustomLibrary`` and compositions of known libraries (microseconds a
call), through the library's own ``transform`` otherwise. Each is checked against ``transform`` on random
points before it is used.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable

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


def _leaf_table(library) -> TermTable | None:
    """The table of a library that is not a composition (None if unknown or not fitted)."""
    table = getattr(library, "term_table_", None)
    if table is not None or not hasattr(library, "n_output_features_"):
        return table
    kind = type(library).__name__
    if kind == "PolynomialLibrary":  # IdentityLibrary() is one too
        return TermTable.polynomial(np.asarray(library.powers_))
    if kind == "FourierLibrary":
        return _fourier_table(library, int(library.n_features_in_))
    return None


# -- compositions: the same recursion builds tables (compiled) and array evaluators (fallback) ------------
class _Tables:
    """How term tables combine."""

    @staticmethod
    def leaf(library, n_inputs: int) -> TermTable:
        table = _leaf_table(library)
        if table is None:
            raise TypeError(f"{type(library).__name__} has no term table")
        return table

    @staticmethod
    def on_inputs(table: TermTable, inputs: list[int], n_inputs: int) -> TermTable:
        idx = np.asarray(inputs, dtype=np.int64)
        powers = np.zeros((table.n_features, n_inputs), np.int64)
        powers[:, idx] = table.powers
        return TermTable(powers, table.func.copy(), idx[table.func_state], table.func_param.copy())

    @staticmethod
    def product(a: TermTable, b: TermTable) -> TermTable:
        """Every term of ``a`` times every term of ``b``, row-major (TensoredLibrary's order)."""
        i = np.repeat(np.arange(a.n_features), b.n_features)
        j = np.tile(np.arange(b.n_features), a.n_features)
        fa, fb = a.func[i], b.func[j]
        if np.any((fa != PLAIN) & (fb != PLAIN)):
            raise TypeError("a product of two non-polynomial terms is not a compiled term")
        use_a = fa != PLAIN
        return TermTable(
            np.ascontiguousarray(a.powers[i] + b.powers[j]),
            np.where(use_a, fa, fb).astype(np.int64),
            np.where(use_a, a.func_state[i], b.func_state[j]).astype(np.int64),
            np.where(use_a, a.func_param[i], b.func_param[j]).astype(float),
        )

    concatenate = staticmethod(TermTable.concatenate)


class _Evaluators:
    """How functions ``Z (n_points, n_inputs) -> Theta`` on plain arrays combine."""

    @staticmethod
    def leaf(library, n_inputs: int) -> Callable:
        table = _leaf_table(library)
        if table is not None:
            return table.evaluate
        if type(library).__name__ == "CustomLibrary" and hasattr(library, "n_output_features_"):
            return _custom_evaluator(library, n_inputs)
        raise TypeError(f"{type(library).__name__} has no array evaluator")

    @staticmethod
    def on_inputs(evaluate: Callable, inputs: list[int], n_inputs: int) -> Callable:
        return lambda Z: evaluate(Z[:, inputs])

    @staticmethod
    def product(a: Callable, b: Callable) -> Callable:
        def evaluate(Z):
            A, B = a(Z), b(Z)
            return (A[:, :, None] * B[:, None, :]).reshape(Z.shape[0], -1)

        return evaluate

    @staticmethod
    def concatenate(parts) -> Callable:
        parts = list(parts)
        return lambda Z: np.hstack([p(Z) for p in parts])


def _custom_evaluator(library, n_inputs: int) -> Callable:
    """CustomLibrary's terms (bias, then each function on each combination of inputs) on plain arrays."""
    terms = [
        (f, list(c))
        for f in library.functions
        for c in library._combinations(n_inputs, f.__code__.co_argcount, library.interaction_only)
    ]

    def evaluate(Z):
        cols = [np.ones(Z.shape[0])] if library.include_bias else []
        cols += [np.broadcast_to(np.asarray(f(*Z[:, c].T), dtype=float), Z.shape[:1]) for f, c in terms]
        return np.column_stack(cols)

    return evaluate


def _unique(inputs) -> list[int]:
    return list(dict.fromkeys(int(k) for k in inputs))


def _compose(library, n_inputs: int, kind):
    """The library's terms in ``kind`` (:class:`_Tables` or :class:`_Evaluators`), recursing through
    ConcatLibrary, TensoredLibrary and GeneralizedLibrary (each sub-library on its inputs)."""
    names = {c.__name__ for c in type(library).__mro__}  # subclasses too (ParameterizedLibrary)
    if "ConcatLibrary" in names:
        return kind.concatenate(_compose(sub, n_inputs, kind) for sub in library.libraries)
    if "TensoredLibrary" in names:
        per = library.inputs_per_library or [range(n_inputs)] * len(library.libraries)
        parts = [_on(sub, _unique(ins), n_inputs, kind) for sub, ins in zip(library.libraries, per)]
        out = parts[0]
        for part in parts[1:]:
            out = kind.product(out, part)
        return out
    if "GeneralizedLibrary" in names and hasattr(library, "libraries_full_"):
        per, parts = library.inputs_per_library, []
        for i, sub in enumerate(library.libraries_full_):
            if i >= len(per):  # the tensor products, on all inputs
                parts.append(_compose(sub, n_inputs, kind))
            elif i not in (library.exclude_libraries or []):
                parts.append(_on(sub, _unique(per[i]), n_inputs, kind))
        return kind.concatenate(parts)
    return kind.leaf(library, n_inputs)


def _on(library, inputs: list[int], n_inputs: int, kind):
    return kind.on_inputs(_compose(library, len(inputs), kind), inputs, n_inputs)


def term_table(library, n_inputs: int) -> TermTable:
    """The :class:`TermTable` of a fitted feature library acting on ``n_inputs`` inputs.

    ``n_inputs`` counts the states and the control inputs the library was fitted on. Known: PySINDy's
    ``PolynomialLibrary`` (and ``IdentityLibrary``), ``FourierLibrary``, and ``ConcatLibrary``,
    ``TensoredLibrary``, ``GeneralizedLibrary`` of known libraries (a product of two non-polynomial factors
    excepted), and any library with a ``term_table_`` attribute.

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
    >>> tensor = (ps.IdentityLibrary() * ps.FourierLibrary()).fit(np.ones((5, 1)))
    >>> table = term_table(tensor, 1)
    >>> table.powers.ravel().tolist(), table.func.tolist()
    ([1, 1], [4, 5])
    """
    try:
        table = _compose(library, n_inputs, _Tables)
    except (TypeError, AttributeError):
        raise TypeError(
            f"{type(library).__name__} is not supported by the compiled simulator; use pysindy."
            "PolynomialLibrary, FourierLibrary, their Concat/Tensored/GeneralizedLibrary, or "
            "sindy_impulse.MechanicalLibrary (other libraries are simulated by the slower general fallback)"
        ) from None
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

    def transform(Z: np.ndarray) -> np.ndarray:
        return np.asarray(library.transform(AxesArray(np.atleast_2d(Z), {"ax_time": 0, "ax_coord": 1})))

    probe = np.random.default_rng(0).uniform(-2.0, 2.0, size=(8, n_inputs))
    for build in (term_table, lambda lib, n: _compose(lib, n, _Evaluators)):
        try:
            candidate = build(library, n_inputs)
        except (TypeError, AttributeError, ValueError):
            continue
        key = _verified_key(library, candidate)
        if key is not None and key in _VERIFIED:
            return candidate
        if _same_terms(candidate, transform, probe):
            if key is not None:
                _VERIFIED.add(key)
            return candidate
    return transform


#: Libraries whose table was checked against their own ``transform`` (:func:`_verified_key`): the same
#: class with the same plain parameters and the same table gives the same terms, checked once per process.
_VERIFIED: set = set()
_PLAIN = (bool, int, float, str, type(None))


def _verified_key(library, candidate):
    """A key naming a library's class, its parameters and its table, when all of them are plain values
    (None for anything else: such a library is checked every time)."""
    if not isinstance(candidate, TermTable):
        return None
    try:
        params = library.get_params(deep=False)
    except (AttributeError, TypeError):
        return None
    if not all(isinstance(v, _PLAIN) for v in params.values()):
        return None
    arrays = (candidate.powers, candidate.func, candidate.func_state, candidate.func_param)
    table = tuple(np.ascontiguousarray(a).tobytes() for a in arrays)
    return (type(library).__module__, type(library).__qualname__, tuple(sorted(params.items())), table)


def _same_terms(candidate, transform, probe) -> bool:
    """Whether a table or evaluator gives the library's own values (a library may order or scale its terms
    in a way the table does not know: any difference sends the model to the next, slower path)."""
    try:
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            expected = transform(probe)
            got = candidate.evaluate(probe) if isinstance(candidate, TermTable) else candidate(probe)
    except Exception:  # noqa: BLE001 - a library that cannot evaluate the probe: not verifiable
        return isinstance(candidate, TermTable)  # a declared table is trusted
    return got.shape == expected.shape and np.allclose(got, expected, rtol=1e-9, atol=1e-12, equal_nan=True)
