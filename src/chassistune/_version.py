"""The package's version (as in pyproject.toml): a leaf, so that modules inside the package read
it without importing the package's `__init__` and the public API it pulls in."""

__version__ = "0.1.0"
