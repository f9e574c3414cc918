"""The Blender tests' process on the PyPI bpy 4.2 module ends without the interpreter's teardown.

That module crashes (a segmentation fault) while Python tears it down after a long run that used the glTF
importer and exporter on several files, after every test has passed and the summary is printed; 4.5 and
5.0 tear down cleanly. The run's own exit status is kept.
"""

import os
import sys

import pytest

try:
    import bpy
except ImportError:  # the tests skip themselves without bpy
    bpy = None

_STATUS: dict[str, int] = {}


def pytest_sessionfinish(session, exitstatus):
    _STATUS["exit"] = int(exitstatus)


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config):
    if bpy is not None and bpy.app.version < (4, 5, 0) and "exit" in _STATUS:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(_STATUS["exit"])
