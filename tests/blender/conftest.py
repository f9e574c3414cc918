"""The Blender tests' process on the PyPI bpy 4.2 and 4.5 modules ends without the interpreter's teardown.

The 4.2 module crashes (a segmentation fault) while Python tears it down after a long run that used the glTF
importer and exporter on several files, and the 4.5 module never ends once Rigify has generated a rig (a
lock taken in its C++ teardown, after Python's own), both after every test has passed and the summary is
printed; 5.0 tears down cleanly. The run's own exit status is kept.
"""

import os
import sys

import pytest

try:
    import bpy
except ImportError:  # the tests skip themselves without bpy
    bpy = None

_STATUS: dict[str, int] = {}


@pytest.fixture(scope="module")
def registered_extension():
    """The extension registered for a test module's tests (`pytestmark = usefixtures(...)`), as a user's
    Blender has it once the extension is enabled."""
    from turkish_lipsync import blender

    blender.register()
    yield
    blender.unregister()


def pytest_sessionfinish(session, exitstatus):
    _STATUS["exit"] = int(exitstatus)


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config):
    if bpy is not None and bpy.app.version < (5, 0, 0) and "exit" in _STATUS:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(_STATUS["exit"])
