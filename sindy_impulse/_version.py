"""The package's version (read by ``pyproject.toml`` and ``sindy_impulse.__version__``)."""

__version__ = "0.1.0"
