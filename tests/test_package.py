import importlib

import pytest

import sindy_impulse


@pytest.mark.parametrize("name", sindy_impulse.__all__)
def test_public_names_resolve(name):
    assert getattr(sindy_impulse, name) is not None


def test_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        sindy_impulse.nope  # noqa: B018


def test_analysis_binds_functions_not_modules():
    analysis = importlib.import_module("sindy_impulse.analysis")
    importlib.import_module("sindy_impulse.analysis.consensus")
    assert callable(analysis.consensus) and not hasattr(analysis.consensus, "__path__")
    assert type(analysis.consensus).__name__ == "function"
