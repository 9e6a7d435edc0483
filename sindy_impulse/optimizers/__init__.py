"""Optimizers (PySINDy ``BaseOptimizer`` plugins)."""

from .sweep import ThresholdSweep, threshold_path

__all__ = ["ThresholdSweep", "threshold_path"]
