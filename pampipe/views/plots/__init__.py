"""Plots of each command (matplotlib, imported lazily by the command modules)."""
