"""What the tests share: paths of the bundled problems, subprocess runners, data generators and references.

Test modules import from here (or take a fixture of tests/conftest.py), never from one another.
"""
