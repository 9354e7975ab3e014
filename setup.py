"""Packaging beyond pyproject.toml: the repository's ``problems/`` ship as ``pampipe/examples`` and its
``yaml/`` (the JSON Schemas of the files a user writes) as ``pampipe/schemas``.

pyproject.toml cannot map one folder to a package while also discovering the others, so the
package list and those mappings live here (everything else is in pyproject.toml). Every folder of
``problems/`` is listed as a (data-only) package, so setuptools installs it without warning.
"""

from setuptools import find_namespace_packages, find_packages, setup

EXAMPLES = ["pampipe.examples", *(f"pampipe.examples.{name}" for name in find_namespace_packages("problems"))]

setup(
    packages=[*find_packages(include=["pampipe", "pampipe.*"]), *EXAMPLES, "pampipe.schemas"],
    package_dir={"pampipe.examples": "problems", "pampipe.schemas": "yaml"},
    package_data={"pampipe": ["py.typed"],  # PEP 561: the package's annotations are for type checkers too
                  "pampipe.schemas": ["*.schema.json"],  # what `example` copies beside the files it copies
                  # CREDIT.md: a measured data set ships with its credit
                  **{name: ["*.yaml", "*.csv", "*.md"] for name in EXAMPLES}},
)
