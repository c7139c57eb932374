"""The package's version, in a leaf module that the cache keys can read
without importing the package's face."""

__version__ = "0.1.0"
