"""Pneumatic timing of a muscle: the gait block's valve and gas options, chamber volume, ISO 6358 flow."""
