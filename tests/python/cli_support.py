"""What the tests that run the `exoid` command line share: the binary ctest names in EXOID_BINARY."""
import os
import subprocess

import pytest


def exoid_binary():
    """The `exoid` binary; skips the calling test where EXOID_BINARY is not set."""
    binary = os.environ.get("EXOID_BINARY")
    if not binary:
        pytest.skip("EXOID_BINARY not set (ctest sets it)")
    return binary


def identify(binary, *args):
    """`exoid identify ARGS`, its output captured as text."""
    return subprocess.run([binary, "identify", *map(str, args)], capture_output=True, text=True)
