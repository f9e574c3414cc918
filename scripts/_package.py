"""The turkish_lipsync package beside these scripts, imported by its path: the scripts run from a checkout
(the zip carries neither them nor the batch code), inside Blender (-P) or with the bpy module, where the
package is not installed; the import path is left as it is. Each script loads this file by path too
(runpy.run_path)."""

import importlib.util
import sys
from pathlib import Path

PACKAGE = "turkish_lipsync"


def import_package():
    """The package (once a process), registered under its name so that its modules import as usual."""
    if PACKAGE not in sys.modules:
        init = Path(__file__).resolve().parent.parent / PACKAGE / "__init__.py"
        spec = importlib.util.spec_from_file_location(
            PACKAGE, init, submodule_search_locations=[str(init.parent)]
        )
        module = importlib.util.module_from_spec(spec)
        sys.modules[PACKAGE] = module
        spec.loader.exec_module(module)
    return sys.modules[PACKAGE]
