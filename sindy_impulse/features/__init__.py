"""SINDy coefficients as features of time series (paper section 3.4): :class:`SINDyFeatures`, a scikit-learn
transformer that fits one model per series (in parallel with joblib, on a dask cluster through joblib's
backend) and returns the flattened coefficients."""

from .extractor import SINDyFeatures

__all__ = ["SINDyFeatures"]
