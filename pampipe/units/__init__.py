"""Units: quantities in, SI floats out (:mod:`.quantities`), and the user's display units
(:mod:`.display`)."""
