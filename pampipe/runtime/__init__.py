"""Plumbing every command shares: the IPOPT toolkit, the on-disk cache, executors, progress, interrupts."""
