"""`pampipe diagnose` (docs/physics.md §9): where model and data disagree, which effects are missing.

Modules: :mod:`.cells` (rows reduced per test), :mod:`.refit` (the baseline + effects NLP),
:mod:`.noise` (noise floors), :mod:`.structure` (checks of a fit, probes), :mod:`.search` (forward
and backward selection), :mod:`.selection` (BIC, cross-validation, intervals), :mod:`.verdict`,
:mod:`.separate` (experiments that separate confounded models), :mod:`.hidden` (synthetic experiments
with hidden effects), :mod:`.result` (frozen results), :mod:`.workflow` (orchestration).
"""
