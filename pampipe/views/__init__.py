"""Renderers of results into text, tables, HTML and plots: ``<command>_text`` per command, ``plots/``,
``html`` and ``tables``. A result names its views through loaders (:data:`pampipe.results.Loader`: a plain
import made when the view is first asked for); no view imports a result module, so there is no circle."""
