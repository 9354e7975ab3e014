"""Packaging beyond pyproject.toml: the repository's ``problems/`` ship as ``pampipe/examples``.

pyproject.toml cannot map one folder to a package while also discovering the others, so the
package list and that mapping live here (everything else is in pyproject.toml). Every folder of
``problems/`` is listed as a (data-only) package, so setuptools installs it without warning.
"""

from setuptools import find_namespace_packages, find_packages, setup

EXAMPLES = ["pampipe.examples", *(f"pampipe.examples.{name}" for name in find_namespace_packages("problems"))]

setup(
    packages=[*find_packages(include=["pampipe", "pampipe.*"]), *EXAMPLES],
    package_dir={"pampipe.examples": "problems"},
    package_data={"pampipe": ["py.typed"],  # PEP 561: the package's annotations are for type checkers too
                  # CREDIT.md: a measured data set ships with its credit
                  **{name: ["*.yaml", "*.csv", "*.md"] for name in EXAMPLES}},
)
