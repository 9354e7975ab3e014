"""Plots of each command (matplotlib imported lazily): each draws what its result carries."""
