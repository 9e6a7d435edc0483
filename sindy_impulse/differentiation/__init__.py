"""Numerical differentiation methods for short, noisy ring-downs (PySINDy plug-ins), and the one function
that applies a method to trajectories."""

from .apply import differentiate
from .tvregdiff import TVRegDiff

__all__ = ["TVRegDiff", "differentiate"]
