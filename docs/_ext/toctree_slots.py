"""Open slots in the toctrees: a glob after the explicit entries picks up pages added later without editing
the index (docs/user/*, docs/developer/*). Until such a page exists the glob matches nothing, which Sphinx
reports as a warning that -W would make an error and that suppress_warnings cannot name (it has no type);
only the globs listed in `toctree_slots` may be empty. Every other warning stands.
"""

from __future__ import annotations

import logging

from sphinx.application import Sphinx

_EMPTY_GLOB = "toctree glob pattern %r didn't match any documents"


class _EmptySlots(logging.Filter):
    def __init__(self, app: Sphinx) -> None:
        super().__init__()
        self.app = app

    def filter(self, record: logging.LogRecord) -> bool:
        empty_slot = (
            record.msg == _EMPTY_GLOB and record.args and record.args[0] in self.app.config.toctree_slots
        )
        return not empty_slot


def setup(app: Sphinx) -> dict:
    app.add_config_value("toctree_slots", [], "env")
    logging.getLogger("sphinx.sphinx.directives.other").addFilter(_EmptySlots(app))
    return {"parallel_read_safe": True, "parallel_write_safe": True}
