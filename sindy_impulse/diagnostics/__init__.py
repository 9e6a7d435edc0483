"""Answers a user can trust: every fitted :class:`~sindy_impulse.ImpulseSINDy` carries ``diagnostics_``.

A wrong model that looks right is the worst answer this library can give. At the end of ``fit`` the model
is checked against its data -- how well its simulation reproduces the filtered states, against the noise the
filter removed; which terms the data support; whether its frequencies are the data's spectral peaks; how
well conditioned its terms are; offset, clipping, quantisation and collinear channels in the measured
states; the work budget -- and given a verdict with reasons in plain words:

- ``"ok"``: nothing found;
- ``"doubtful"``: a problem that may make the model wrong (a term the data do not support, a fit worse than
  the noise explains, clipping...);
- ``"unreliable"``: the model does not describe the data (divergence, a large fit error, frequencies the data
  do not show, collinear terms or channels);
- ``"no dynamics"``: the data look like noise, or the model is ``x' = 0``.

Each verdict but "ok" warns once, with what to do (:class:`~sindy_impulse.exceptions.FitWarning`,
:class:`~sindy_impulse.exceptions.DataWarning` when only the data are at fault,
:class:`~sindy_impulse.exceptions.NoDynamicsWarning`); none raises. The rules are in :mod:`.verdict`.

The diagnostics only judge: what changes the data before the regression (the rest level removed, the
clipped samples left out) is :mod:`sindy_impulse.preprocessing.states`, which the estimator calls.

Modules: :mod:`.data` (the measured states, before the regression), :mod:`.model` (the fitted model
against its data), :mod:`.terms` (whether the data support each term), :mod:`.verdict` (the rules),
:mod:`.report` (:class:`FitDiagnostics`), :mod:`.diagnose` (:func:`diagnose_fit`, every check in order).
"""

from .data import MAGNITUDE_RANGE, DataChecks, check_magnitude, clipped_samples, screen_states
from .diagnose import diagnose_fit
from .report import VERDICTS, FitDiagnostics

__all__ = [
    "MAGNITUDE_RANGE",
    "VERDICTS",
    "DataChecks",
    "FitDiagnostics",
    "check_magnitude",
    "diagnose_fit",
    "screen_states",
    "clipped_samples",
]
