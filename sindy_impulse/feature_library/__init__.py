"""Feature libraries (PySINDy ``BaseFeatureLibrary`` plugins) and their compiled term tables."""

from .mechanical import MechanicalLibrary
from .terms import TermTable, term_table

__all__ = ["MechanicalLibrary", "TermTable", "term_table"]
