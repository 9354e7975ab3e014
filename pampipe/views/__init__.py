"""Renderers of results into text, tables, HTML and plots (results never import views)."""
