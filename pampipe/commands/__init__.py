"""The CLI layer of each command: its arguments and ``run``, which calls the library and emits the JSON, the
text (rendered by :mod:`pampipe.views`) and the plots.

Each module defines ``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int``.
Only :mod:`pampipe.cli` imports these modules.
"""
