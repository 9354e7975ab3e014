"""The package version, in one place: the CLI, the exported C, the fitted PAM files and the wheel agree."""

__version__ = "0.1.0"
