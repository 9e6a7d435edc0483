"""scikit-learn transformers over the preprocessing functions, for pipelines of one signal.

``X`` is one record: shape (n,) or (n, 1) (samples along axis 0); :class:`ImpactTrimmer` also takes
(n, 2), the second column being the force channel. ``transform`` returns the same number of dimensions
it is given (one column for 2-D input). ``fs`` (Hz) is a parameter of each; parameters are stored
untouched and checked at ``fit``.

>>> from sklearn.pipeline import make_pipeline
>>> t = np.arange(15000) / 5000
>>> y = 0.3 + np.where(t >= 0.2, np.exp(-3 * (t - 0.2)) * np.sin(2 * np.pi * 120 * (t - 0.2) + 1), 0)
>>> pipe = make_pipeline(OffsetRemover(fs=5000.0), ImpactTrimmer(fs=5000.0), BandExtractor(fs=5000.0))
>>> out = pipe.fit_transform(y)
>>> [round(edge, 1) for edge in pipe[-1].band_hz_], pipe[-1].decimation_, pipe[-1].fs_out_
([109.1, 132.0], 2, 2500.0)
>>> out.ndim, bool(out.size / pipe[-1].band_.samples_per_period > 100)  # over 100 periods
(1, True)
"""

from __future__ import annotations

from numbers import Integral, Real

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from .._utils.params import Interval, Options, validate_params
from ._record import check_signal_1d
from .band import extract_band
from .filters import check_band
from .offset import estimate_offset
from .onset import Impact, find_impact, response_onset
from .peaks import spectral_peaks

__all__ = ["OffsetRemover", "ImpactTrimmer", "BandExtractor"]

_FS = [Interval(Real, 0, None, "neither")]
_ONSET = [Options({"auto"}), Interval(Integral, 0, None)]


class _OneSignal(TransformerMixin, BaseEstimator):
    """Shared input handling: one signal as (n,) or (n, 1); output with the input's dimensions."""

    def _signal(self, X, name: str = "X") -> tuple[np.ndarray, bool]:
        return check_signal_1d(X, name), np.ndim(X) == 2

    @staticmethod
    def _shaped(out: np.ndarray, two_d: bool) -> np.ndarray:
        return out[:, None] if two_d else out

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.one_d_array = True
        return tags


class OffsetRemover(_OneSignal):
    """Remove a record's offset (and drift): :func:`~sindy_impulse.preprocessing.offset.estimate_offset`.

    Parameters
    ----------
    fs : float
        Sampling rate (Hz).
    method : {"auto", "pre_trigger", "tail", "linear"} or float
        How the offset is estimated, or the offset itself.
    onset : "auto" or int
        First sample of the hit (``"auto"``: :func:`~sindy_impulse.preprocessing.onset.response_onset`).

    Attributes
    ----------
    onset_index_ : int
    offset_ : OffsetEstimate
    """

    _parameter_constraints = {"fs": _FS, "method": [Options({"auto", "pre_trigger", "tail", "linear"}), Real],
                              "onset": _ONSET}

    def __init__(self, fs=None, method="auto", onset="auto"):
        self.fs = fs
        self.method = method
        self.onset = onset

    def fit(self, X, y=None):
        """Estimate the offset of ``X``; returns ``self``."""
        validate_params(self)
        x, _ = self._signal(X)
        self.onset_index_ = response_onset(x) if self.onset == "auto" else int(self.onset)
        self.offset_ = estimate_offset(x, self.fs, onset_index=self.onset_index_, method=self.method)
        self.n_features_in_ = 1
        return self

    def transform(self, X):
        """``X`` minus the fitted offset (and drift, anchored at the fitted onset)."""
        check_is_fitted(self, "offset_")
        x, two_d = self._signal(X)
        return self._shaped(x - self.offset_.trend(x.size, self.fs), two_d)


class ImpactTrimmer(_OneSignal):
    """Keep the free ring-down: drop the samples before the end of the hammer contact (or the onset).

    Parameters
    ----------
    fs : float
        Sampling rate (Hz).
    onset : "auto" or int
        First sample to keep (``"auto"``: :func:`~sindy_impulse.preprocessing.onset.find_impact`, from
        the force channel when ``X`` has a second column).
    n_sigma, level : float
        See :func:`~sindy_impulse.preprocessing.onset.find_impact`.

    Attributes
    ----------
    impact_ : Impact
    """

    _parameter_constraints = {"fs": _FS, "onset": _ONSET, "n_sigma": [Interval(Real, 1, None)],
                              "level": [Interval(Real, 0, 1, "neither")]}

    def __init__(self, fs=None, onset="auto", n_sigma=6.0, level=0.05):
        self.fs = fs
        self.onset = onset
        self.n_sigma = n_sigma
        self.level = level

    def _split(self, X):
        if np.ndim(X) == 2 and np.shape(X)[1] == 2:
            arr = np.asarray(X)
            return check_signal_1d(arr[:, 0], "X[:, 0]"), arr[:, 1], True
        x, two_d = self._signal(X)
        return x, None, two_d

    def fit(self, X, y=None):
        """Find the impact in ``X``; returns ``self``."""
        validate_params(self)
        x, force, _ = self._split(X)
        if self.onset == "auto":
            self.impact_ = find_impact(x, self.fs, force=force, n_sigma=self.n_sigma, level=self.level)
        else:
            start = int(self.onset)
            self.impact_ = Impact(start, start / self.fs, start, start / self.fs, "given", (), self.fs)
        self.n_features_in_ = 1 if force is None else 2
        return self

    def transform(self, X):
        """The response from the fitted start of the ring-down on."""
        check_is_fitted(self, "impact_")
        x, _, two_d = self._split(X)
        return self._shaped(x[self.impact_.ringdown_index :].copy(), two_d)


class BandExtractor(_OneSignal):
    """One band of a ring-down, band-passed, trimmed and decimated:
    :func:`~sindy_impulse.preprocessing.band.extract_band`.

    Parameters
    ----------
    fs : float
        Sampling rate (Hz).
    band_hz : (float, float) or None
        The band; None takes the band of the highest spectral peak at ``fit``.
    samples_per_period, min_samples_per_period, method, end_snr_db
        See :func:`~sindy_impulse.preprocessing.band.extract_band`.

    Attributes
    ----------
    band_hz_ : (float, float)
    band_ : BandSignal
        The extraction of the fitted signal.
    decimation_, fs_out_ : int, float
        Decimation factor and output sampling rate.
    """

    _parameter_constraints = {
        "fs": _FS,
        "band_hz": [None, "array-like"],
        "samples_per_period": [Interval(Real, 2, None, "neither")],
        "min_samples_per_period": [Interval(Real, 2, None, "neither")],
        "method": [Options({"fft", "butter"})],
        "end_snr_db": [None, Real],
    }

    def __init__(self, fs=None, band_hz=None, samples_per_period=16.0, min_samples_per_period=8.0,
                 method="fft", end_snr_db=10.0):
        self.fs = fs
        self.band_hz = band_hz
        self.samples_per_period = samples_per_period
        self.min_samples_per_period = min_samples_per_period
        self.method = method
        self.end_snr_db = end_snr_db

    def _extract(self, x, band):
        return extract_band(x, self.fs, band, samples_per_period=self.samples_per_period,
                            min_samples_per_period=self.min_samples_per_period, method=self.method,
                            end_snr_db=self.end_snr_db)

    def fit(self, X, y=None):
        """Choose the band (if not given) and extract it from ``X``; returns ``self``."""
        validate_params(self)
        x, _ = self._signal(X)
        if self.band_hz is None:
            peaks = spectral_peaks(x, self.fs)
            if len(peaks) == 0:
                raise ValueError("X has no significant spectral peak; pass band_hz")
            band = peaks.band_hz[int(np.argmax(peaks.height_db))]
        else:
            band = check_band(self.band_hz, self.fs)
        self.band_ = self._extract(x, band)
        self.band_hz_, self.decimation_ = self.band_.band_hz, self.band_.decimation
        self.fs_out_ = self.band_.fs
        self.n_features_in_ = 1
        return self

    def transform(self, X):
        """The band signal of ``X`` (decimated)."""
        check_is_fitted(self, "band_")
        x, two_d = self._signal(X)
        return self._shaped(self._extract(x, self.band_hz_).y, two_d)
