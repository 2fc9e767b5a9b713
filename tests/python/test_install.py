"""The module tools/test-python.sh tests is the installed one."""

import os
from pathlib import Path

import pytest

import lhr


def test_module_is_the_installed_one():
    """Under tools/test-python.sh, the module comes from the install prefix."""
    prefix = os.environ.get("LHR_INSTALL_PREFIX")
    if prefix is None:
        pytest.skip("not run by tools/test-python.sh")
    assert Path(lhr.__file__).resolve().is_relative_to(Path(prefix).resolve())
