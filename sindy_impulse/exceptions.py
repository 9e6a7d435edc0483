"""Errors and warnings of sindy-impulse: one hierarchy, so users can filter them or turn them into errors.

Every warning the library emits derives from :class:`SindyImpulseWarning`; the subclasses say what kind
of doubt it is. ``warnings.simplefilter("error", SindyImpulseWarning)`` makes every doubtful answer an
exception; ``warnings.simplefilter("ignore", DataWarning)`` silences the remarks about the input only.

=============================  ==========================================================================
class                          raised or warned when
=============================  ==========================================================================
InvalidParameterError          a constructor parameter has the wrong type or value (checked at ``fit``)
UnsupportedProblemError        PDE, weak-form or implicit problems (PySINDy's, not this library's)
SindyImpulseWarning            base class of every warning below
DataWarning                    the input is doubtful: offset, clipping, quantisation, collinear
                               channels, too few periods or samples per period, pure noise
FitWarning                     the fitted model is doubtful: poor fit, frequencies not in the data
NoDynamicsWarning              no deterministic dynamics found (a ``FitWarning``)
WorkBudgetWarning              not emitted any more (kept so that existing filters still import): a
                               budget that ran out is a note in ``diagnostics_.notes``, and a reason
                               in the FitWarning of a verdict that is not "ok"
DivergenceWarning              a simulation left the admissible range (rows after it are NaN)
ModalWarning                   modal parameters asked of a model its linear part does not describe
=============================  ==========================================================================

Examples
--------
>>> import warnings
>>> from sindy_impulse.exceptions import DataWarning, SindyImpulseWarning
>>> issubclass(DataWarning, SindyImpulseWarning)
True
>>> with warnings.catch_warnings():
...     warnings.simplefilter("error", SindyImpulseWarning)
...     try:
...         warnings.warn("offset of 5x the amplitude", DataWarning)
...     except DataWarning as err:
...         print("caught:", err)
caught: offset of 5x the amplitude
"""

from __future__ import annotations

__all__ = [
    "InvalidParameterError",
    "UnsupportedProblemError",
    "SindyImpulseWarning",
    "DataWarning",
    "FitWarning",
    "NoDynamicsWarning",
    "WorkBudgetWarning",
    "DivergenceWarning",
    "ModalWarning",
]


class InvalidParameterError(ValueError, TypeError):
    """A parameter of an estimator or function has the wrong type or value.

    Derives from both ``ValueError`` and ``TypeError`` (as scikit-learn's equivalent does), so code that
    catches either keeps working.
    """


class UnsupportedProblemError(NotImplementedError, ValueError):
    """A problem PySINDy handles but this library does not (PDE, weak-form and implicit SINDy).

    A ``NotImplementedError`` (the feature is missing here: use :class:`pysindy.SINDy`) and a ``ValueError``
    (the input is not a set of ordinary state trajectories).
    """


class SindyImpulseWarning(UserWarning):
    """Base class of every warning of sindy-impulse."""


class DataWarning(SindyImpulseWarning):
    """The input data are doubtful (offset, clipping, quantisation, collinear channels, pure noise...)."""


class FitWarning(SindyImpulseWarning, RuntimeWarning):
    """The fitted model is doubtful: a poor fit, frequencies the data do not show, an unstable model."""


class NoDynamicsWarning(FitWarning):
    """No deterministic dynamics were found: the answer is the empty model or no mode."""


class WorkBudgetWarning(FitWarning):
    """The deterministic simulation work budget of a fit ran out (no longer emitted: ``fit`` records it in
    ``diagnostics_.notes["budget"]`` and names it in the FitWarning of a doubtful verdict)."""


class DivergenceWarning(SindyImpulseWarning, RuntimeWarning):
    """A simulation left the admissible range; the rows after the divergence are NaN."""


class ModalWarning(SindyImpulseWarning):
    """Modal parameters of a model whose linearisation does not describe its dynamics."""
