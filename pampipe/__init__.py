"""pampipe: pressures for pneumatic-muscle pipe crawlers, from a symbolic CasADi model of the muscle."""

__version__ = "0.1.0"
