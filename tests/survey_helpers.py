"""Checks shared by the survey's tests: a survey's modes against a synthetic record's true ones."""

import pytest


def nearest_mode(survey, frequency_hz: float):
    """The survey's mode nearest ``frequency_hz``."""
    return min(survey.modes, key=lambda m: abs(m.frequency_hz - frequency_hz))


def assert_true_modes_found(survey, rec, f_rel: float = 3e-3, z_rel: float = 0.1) -> None:
    """Every true mode of ``rec`` (an ``impact_record``) has a survey mode within ``f_rel`` in frequency
    and ``z_rel`` in damping ratio (the modes benchmark's marks)."""
    for f, z in zip(rec.modes.frequency_hz, rec.modes.damping_ratio):
        mode = nearest_mode(survey, f)
        assert mode.frequency_hz == pytest.approx(f, rel=f_rel)
        assert mode.damping_ratio == pytest.approx(z, rel=z_rel)
