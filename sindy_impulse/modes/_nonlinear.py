"""Whether a mode's fitted equation is nonlinear: a term other than the states themselves."""

from __future__ import annotations

import numpy as np

from ..feature_library.terms import term_table

__all__ = ["has_nonlinear_terms"]


def has_nonlinear_terms(model) -> bool:
    """Whether the fitted model uses a term other than the states themselves (False if unknown)."""
    try:
        coef = np.asarray(model.coefficients())
        library = getattr(model, "feature_library_", None) or model.feature_library
        terms = term_table(library, coef.shape[0])
    except (AttributeError, TypeError, ValueError):
        return False
    return bool(np.any(coef[:, ~terms.linear]))
