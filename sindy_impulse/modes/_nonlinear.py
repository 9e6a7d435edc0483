"""Whether a mode's fitted equation is nonlinear: a term other than the states themselves."""

from __future__ import annotations

import numpy as np

from ..feature_library.terms import term_table

__all__ = ["has_nonlinear_terms", "nonlinear_columns"]


def nonlinear_columns(model, n_states: int) -> np.ndarray | None:
    """Per column of the model's feature library, whether it is a term other than the states themselves
    (None if the library is unknown)."""
    try:
        library = getattr(model, "feature_library_", None) or model.feature_library
        return ~np.asarray(term_table(library, n_states).linear, bool)
    except (AttributeError, TypeError, ValueError):
        return None


def has_nonlinear_terms(model) -> bool:
    """Whether the fitted model uses a term other than the states themselves (False if unknown)."""
    try:
        coef = np.asarray(model.coefficients())
    except (AttributeError, TypeError, ValueError):
        return False
    columns = nonlinear_columns(model, coef.shape[0])
    return columns is not None and bool(np.any(coef[:, columns]))
