"""Optimizers (PySINDy ``BaseOptimizer`` plugins) and the candidate path of any optimizer."""

from .path import candidate_path, fresh_copy, least_squares
from .sweep import ThresholdSweep, threshold_path

__all__ = ["ThresholdSweep", "candidate_path", "fresh_copy", "least_squares", "threshold_path"]
