"""`pampipe diagnose` (docs/physics.md §9): where model and data disagree, which effect is missing.

Modules: :mod:`.refit` (the baseline + effect NLP), :mod:`.signatures` (residual structure and the
noise floor), :mod:`.selection` (BIC, cross-validation, intervals), :mod:`.hidden` (synthetic
experiments with a hidden effect), :mod:`.result` (frozen results), :mod:`.run` (orchestration).
"""
