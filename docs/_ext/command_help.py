"""The `command-help` directive: a command's own --help output, run at build time, so the manual's list of
flags is the program's and cannot fall out of date.

    ```{command-help} scripts/render.py --help
    ```

The argument is what follows `python` (the interpreter running the build), run from the repository root. A
command that fails is a warning (an error under -W), with what it printed.
"""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
from pathlib import Path

from docutils import nodes
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

logger = logging.getLogger(__name__)
ROOT = Path(__file__).resolve().parents[2]


def command_output(arguments: list[str]) -> tuple[int, str]:
    """The exit status and what `python ARGUMENTS` prints (stdout, then stderr) from the repository root."""
    environment = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="100")
    run = subprocess.run(
        [sys.executable, *arguments], cwd=ROOT, env=environment, capture_output=True, text=True, timeout=120
    )
    return run.returncode, run.stdout + run.stderr


class CommandHelp(SphinxDirective):
    required_arguments = 1
    final_argument_whitespace = True

    def run(self) -> list[nodes.Node]:
        arguments = shlex.split(self.arguments[0])
        status, output = command_output(arguments)
        if status != 0:
            logger.warning(
                "`python %s` failed (exit %d): %s",
                self.arguments[0],
                status,
                output.strip(),
                location=self.get_location(),
            )
        block = nodes.literal_block(output, output)
        block["language"] = "text"
        return [block]


def setup(app) -> dict:
    app.add_directive("command-help", CommandHelp)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
