"""scikit-learn's check_estimator on ImpulseSINDy.

ImpulseSINDy keeps PySINDy's signature ``fit(x, t=None, ...)`` so that it is a drop-in PySINDy model:
the second positional argument is the time, not a target. scikit-learn's checks pass a target ``y``
there (e.g. ``[0, 1, 2, 0, 1, ...]``), which is not a strictly increasing time vector, and the estimator
refuses it by design. Two runs therefore show the contract:

1. the class itself, with the checks that fail only because ``y`` lands in ``t`` listed below;
2. the same class behind a two-line adapter that routes ``y`` away (``fit(X, y=None)``), which must pass
   every check but ``check_fit1d`` (a 1-D signal is one measured state, as in PySINDy).

Both use a degree-1 library and finite differences: the checks fit on 10-50 random samples, fewer than a
degree-3 library has terms or the TVRegDiff end trim can use, which the estimator refuses by design.
"""

import warnings

import pysindy as ps
import pytest
from sklearn.utils.estimator_checks import check_estimator

from sindy_impulse import ImpulseSINDy

Y_AS_T = "sklearn passes a target y as the second positional argument, which is PySINDy's time t"

EXPECTED_FAILURES_BARE = {
    name: Y_AS_T
    for name in [
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
}
FIT1D = "a 1-D signal is one measured state, as in pysindy.SINDy"
EXPECTED_FAILURES_BARE["check_fit1d"] = FIT1D


class _RoutedY(ImpulseSINDy):
    """ImpulseSINDy with scikit-learn's fit(X, y=None) signature (y ignored)."""

    def fit(self, x, y=None):
        return super().fit(x)

    def score(self, x, y=None):
        return super().score(x)


def _small():
    return dict(feature_library=ps.PolynomialLibrary(degree=1), differentiation_method=ps.FiniteDifference())


@pytest.mark.filterwarnings("ignore")
def test_check_estimator_with_y_routed_away():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        results = check_estimator(
            _RoutedY(**_small()), expected_failed_checks={"check_fit1d": FIT1D}, on_fail=None
        )
    failed = [r["check_name"] for r in results if r["status"] == "failed"]
    assert failed == []
    assert sum(r["status"] == "passed" for r in results) >= 38


@pytest.mark.filterwarnings("ignore")
def test_check_estimator_bare_class_fails_only_where_y_is_taken_as_t():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        results = check_estimator(
            ImpulseSINDy(**_small()), expected_failed_checks=EXPECTED_FAILURES_BARE, on_fail=None
        )
    failed = [r["check_name"] for r in results if r["status"] == "failed"]
    assert failed == []
    assert sum(r["status"] == "passed" for r in results) >= 15
