"""The version of fastline, one place for the package, its files and its command line."""

__version__ = "0.2.0"
