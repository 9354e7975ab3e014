"""Frozen SI descriptions of what the user states: experiments, missions, inventories, pipes, networks,
protocols."""
