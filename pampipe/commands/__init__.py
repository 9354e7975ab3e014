"""The CLI layer of each command: its arguments, the library call, and the text/JSON/plots it emits.

Each module defines ``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> int``.
Only :mod:`pampipe.cli` imports these modules.
"""
