"""Numerical differentiation methods for short, noisy ring-downs (PySINDy plug-ins)."""

from .tvregdiff import TVRegDiff

__all__ = ["TVRegDiff"]
