"""One function per kind of figure in the paper. Each takes fitted objects (or their attributes) and an
optional matplotlib ``Axes``, returns the ``Axes`` (or an array of them), and never calls ``plt.show()``.

=================================  ==============================================================
function                           figure of Stender, Oberst & Hoffmann (2019)
=================================  ==============================================================
:func:`plot_alpha_curve`           7a: the alpha-selection criterion over alpha, chosen alpha marked
:func:`plot_filtering`             7b, A1: input against filtered (time-integrated derivative) signal
:func:`plot_sweep`                 6a: Gamma over the threshold sweep, selected candidate marked
:func:`plot_reconstruction`        6b, 8a, 8d: input against the simulated model
:func:`plot_refinement`            8b, 8e: Gamma and coefficients per SLSQP iteration
:func:`plot_embedding`             9: ACF with tau, FNN fraction with m, reconstructed phase space
:func:`plot_complexity_error`      10b: Gamma against number of terms, Pareto front marked
:func:`plot_parameter_dependency`  11: coefficient ratio over the control parameter
:func:`plot_consensus`             12: histograms of the non-zero coefficients, consensus marked
:func:`plot_linear_vs_nonlinear`   13: linear against nonlinear ring-down (and their coefficients)
:func:`plot_feature_space`         14b: 2-D feature space (e.g. PCA of SINDyFeatures) by label
:func:`plot_backbone`              beyond the paper: backbone curves of data and models overlaid
:func:`plot_modes`                 beyond the paper: a hammer-test record's spectrum and its modes
:func:`plot_mode_decay`            beyond the paper: one mode against its model, whole decay and zoom
:func:`plot_mac`                   beyond the paper: the Modal Assurance Criterion of mode shapes
:func:`plot_tracking`              beyond the paper: control charts of many tests of one structure
=================================  ==============================================================

The functions live in one module per family of figures (``filtering``, ``sweep``, ``embedding``,
``complexity``, ``identification``, ``features``, ``backbone``, ``modes``, ``mac``, ``tracking``; shared
helpers in ``_common``); import them from here.
matplotlib is imported only when a function is called. Bad input raises ``ValueError`` or ``TypeError``
naming the argument (the array checks are the shared ones of :mod:`sindy_impulse._utils.validation`).
"""

from .backbone import plot_backbone
from .complexity import plot_complexity_error
from .embedding import plot_embedding
from .features import plot_feature_space
from .filtering import plot_alpha_curve, plot_filtering
from .identification import plot_consensus, plot_linear_vs_nonlinear, plot_parameter_dependency
from .mac import plot_mac
from .modes import plot_mode_decay, plot_modes
from .stabilisation import plot_stabilisation
from .sweep import plot_reconstruction, plot_refinement, plot_sweep
from .tracking import plot_tracking

__all__ = [
    "plot_alpha_curve",
    "plot_backbone",
    "plot_complexity_error",
    "plot_consensus",
    "plot_embedding",
    "plot_feature_space",
    "plot_filtering",
    "plot_linear_vs_nonlinear",
    "plot_mac",
    "plot_mode_decay",
    "plot_modes",
    "plot_parameter_dependency",
    "plot_reconstruction",
    "plot_refinement",
    "plot_stabilisation",
    "plot_sweep",
    "plot_tracking",
]
