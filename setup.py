"""Packaging beyond pyproject.toml: the repository's ``problems/`` ship as ``pampipe/examples``.

pyproject.toml cannot map one folder to a package while also discovering the others, so the
package list and that mapping live here (everything else is in pyproject.toml).
"""

from setuptools import find_packages, setup

setup(
    packages=[*find_packages(include=["pampipe", "pampipe.*"]), "pampipe.examples"],
    package_dir={"pampipe.examples": "problems"},
    package_data={"pampipe.examples": ["*/*.yaml", "*/*/*/*.csv", "*/*/*.csv"]},
)
