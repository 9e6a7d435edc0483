"""scikit-learn's check_estimator on every estimator of the package.

The building blocks (TVRegDiff, DelayEmbedding, MechanicalLibrary, ThresholdSweep, SINDyFeatures) run
through ``parametrize_with_checks`` (one test per check) with ``xfail_strict=True``: a listed failure that
starts to pass fails the run, so every exclusion below stays true, and each is written next to its reason.
A class whose defaults cannot work on the checks' 10-50 random samples runs twice: as constructed by default
(the short-data checks listed) and configured for short data (only the checks that cannot apply listed).

ImpulseSINDy
------------

ImpulseSINDy keeps PySINDy's signature ``fit(x, t=None, ...)`` so that it is a drop-in PySINDy model:
the second positional argument is the time, not a target, and PySINDy's own tests demand that a ``t`` out
of order is refused with a ValueError. scikit-learn's checks call ``fit(X, y)`` with a target ``y`` there
(class labels such as ``[1, 0, 2, 1, ...]`` or a column of ``X``), which is not a strictly increasing time
vector: the estimator refuses it, as it must. Two runs therefore show the contract:

1. the class itself: every check passes except those that call ``fit(X, y)`` with such a ``y``; each
   listed exclusion is asserted to fail *because* ``t`` was refused (the exception, or its cause, is the
   "t must be strictly increasing" error), so no exclusion hides another failure;
2. the same class behind a two-line adapter that routes ``y`` away (``fit(X, y=None)``), which must pass
   every check but ``check_fit1d`` (a 1-D signal is one measured state, as in PySINDy, where scikit-learn
   expects a refusal): the listed checks themselves (pickling, dtypes, idempotence, n_features_in_, ...)
   hold.

Both use a degree-1 library and finite differences: the checks fit on 10-50 random samples, fewer than a
degree-3 library has terms or the TVRegDiff end trim can use, which the estimator refuses by design. Both
run in the default mode (sweep and refinement) and in plain mode (``sweep=False, refine=False``).
"""

import warnings

import pysindy as ps
import pytest
from sklearn.utils.estimator_checks import check_estimator, parametrize_with_checks

from sindy_impulse import (
    DelayEmbedding,
    ImpulseSINDy,
    MechanicalLibrary,
    SINDyFeatures,
    ThresholdSweep,
    TVRegDiff,
)

Y_AS_T = (
    "calls fit(X, y) with a target y, which lands in PySINDy's positional t and is not a strictly increasing "
    "time vector (refused by design, as pysindy.SINDy refuses it); passes with y routed away"
)
T_REFUSED = "t must be strictly increasing"
#: Checks that call fit(X, y) with a target: each is asserted to fail only through the refusal of t.
Y_AS_T_CHECKS = [
    "check_fit_score_takes_y",
    "check_estimators_overwrite_params",
    "check_dont_overwrite_parameters",
    "check_estimators_fit_returns_self",
    "check_readonly_memmap_input",
    "check_n_features_in_after_fitting",
    "check_positive_only_tag_during_fit",
    "check_estimators_dtypes",
    "check_dtype_object",
    "check_pipeline_consistency",
    "check_estimators_nan_inf",
    "check_estimators_pickle",
    "check_f_contiguous_array_estimator",
    "check_methods_sample_order_invariance",
    "check_methods_subset_invariance",
    "check_fit2d_1feature",
    "check_dict_unchanged",
    "check_fit_idempotent",
    "check_fit_check_is_fitted",
    "check_n_features_in",
    "check_fit2d_predict1d",
]
EXPECTED_FAILURES_BARE = dict.fromkeys(Y_AS_T_CHECKS, Y_AS_T)
FIT1D = "a 1-D signal is one measured state, as in pysindy.SINDy (scikit-learn expects a refusal)"
EXPECTED_FAILURES_BARE["check_fit1d"] = FIT1D
MODES = {"default": {}, "plain": {"sweep": False, "refine": False}}
IN_PLACE = (
    "plain mode fits the given optimizer, library and differentiation objects in place, as pysindy.SINDy "
    "does (PySINDy's tests read the optimizer's coef_ and the library's n_output_features_ after fit)"
)
#: Checks that the plain mode fails by design, in either run.
PLAIN_ONLY = {"check_estimators_overwrite_params": IN_PLACE}


class _RoutedY(ImpulseSINDy):
    """ImpulseSINDy with scikit-learn's fit(X, y=None) signature (y ignored)."""

    def fit(self, x, y=None):
        return super().fit(x)

    def score(self, x, y=None):
        return super().score(x)


def _small(**kwargs):
    return dict(
        feature_library=ps.PolynomialLibrary(degree=1), differentiation_method=ps.FiniteDifference(), **kwargs
    )


def _results(estimator, expected):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return check_estimator(estimator, expected_failed_checks=expected, on_fail=None)


def _refused_t(exc) -> bool:
    """The failure is the refusal of t (the check's own message, or the error it wraps)."""
    return any(T_REFUSED in str(e) for e in (exc, exc.__cause__, exc.__context__) if e is not None)


@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize("mode", MODES)
def test_check_estimator_with_y_routed_away(mode):
    expected = {"check_fit1d": FIT1D, **(PLAIN_ONLY if mode == "plain" else {})}
    results = _results(_RoutedY(**_small(**MODES[mode])), expected)
    failed = [r["check_name"] for r in results if r["status"] == "failed"]
    assert failed == []
    passed = {r["check_name"] for r in results if r["status"] == "passed"}
    assert set(Y_AS_T_CHECKS) - set(expected) <= passed  # what the bare class cannot show holds
    assert len(passed) >= 39 - len(expected)


@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize("mode", MODES)
def test_check_estimator_bare_class_fails_only_where_y_is_taken_as_t(mode):
    results = _results(ImpulseSINDy(**_small(**MODES[mode])), EXPECTED_FAILURES_BARE)
    assert [r["check_name"] for r in results if r["status"] == "failed"] == []
    for r in results:
        if r["status"] == "xfail" and r["check_name"] in Y_AS_T_CHECKS:
            assert _refused_t(r["exception"]), (r["check_name"], r["exception"])
    assert sum(r["status"] == "passed" for r in results) >= 15


# ------------------------------------------------------------------------------------------------------
# The building blocks
# ------------------------------------------------------------------------------------------------------
SHORT = "the check fits on 10 samples, fewer than the defaults need (refused: 'at least N are needed')"
IN_TIME = {
    "check_methods_sample_order_invariance": "a derivative or delay vector depends on the samples' order",
    "check_methods_subset_invariance": "a derivative or delay vector is not defined sample by sample",
}
EMBEDDING_SHORT = {"check_estimators_nan_inf": SHORT, "check_fit2d_1feature": SHORT}
TVREGDIFF_SHORT = {"check_estimators_nan_inf": SHORT, "check_fit2d_1feature": SHORT}
ROWS = (
    "the embedding has N - (dimension - 1) * tau rows: the first samples have no complete delay vector "
    "(transform_time gives the rows' times); scikit-learn's transformer checks expect N rows"
)
FIT1D = "a 1-D array is one signal, the natural input of DelayEmbedding (scikit-learn expects a refusal)"
EMBEDDING_INHERENT = {
    "check_transformer_general": ROWS,
    "check_transformer_data_not_an_array": ROWS,
    "check_fit1d": FIT1D,
}
SERIES = (
    "SINDyFeatures reads each row of X as one series (n_series, n_times): the checks' rows of 2-10 values "
    "are too short to embed and fit (refused clearly: 'at least N are needed')"
)
SINDY_FEATURES_SERIES_CHECKS = [
    "check_fit_score_takes_y",
    "check_estimators_overwrite_params",
    "check_dont_overwrite_parameters",
    "check_estimators_fit_returns_self",
    "check_readonly_memmap_input",
    "check_n_features_in_after_fitting",
    "check_positive_only_tag_during_fit",
    "check_estimators_dtypes",
    "check_dtype_object",
    "check_pipeline_consistency",
    "check_estimators_nan_inf",
    "check_estimators_pickle",
    "check_f_contiguous_array_estimator",
    "check_transformer_data_not_an_array",
    "check_transformer_general",
    "check_transformer_preserve_dtypes",
    "check_methods_sample_order_invariance",
    "check_methods_subset_invariance",
    "check_fit2d_1sample",
    "check_fit2d_1feature",
    "check_dict_unchanged",
    "check_fit_idempotent",
    "check_fit_check_is_fitted",
    "check_n_features_in",
    "check_fit2d_predict1d",
]

#: (estimator, {check name: reason it cannot pass}) -- the configured instances show that the short-data
#: exclusions of the default ones are about the data only.
BUILDING_BLOCKS = [
    (TVRegDiff(), {**IN_TIME, **TVREGDIFF_SHORT}),
    (TVRegDiff(trim=1), IN_TIME),  # trim=1: 7 samples suffice
    (DelayEmbedding(), {**EMBEDDING_INHERENT, **EMBEDDING_SHORT}),
    (DelayEmbedding(tau=1, dimension=2), {**EMBEDDING_INHERENT, **IN_TIME}),
    (MechanicalLibrary(), {}),
    (ThresholdSweep(), {}),
    (SINDyFeatures(), dict.fromkeys(SINDY_FEATURES_SERIES_CHECKS, SERIES)),
]
_EXPECTED = {id(est): expected for est, expected in BUILDING_BLOCKS}


@pytest.mark.filterwarnings("ignore")
@parametrize_with_checks(
    [est for est, _ in BUILDING_BLOCKS],
    expected_failed_checks=lambda est: _EXPECTED[id(est)],
    xfail_strict=True,
)
def test_building_blocks_pass_scikit_learn_checks(estimator, check):
    check(estimator)
