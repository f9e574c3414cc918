"""Links to the web are checked for their form, never fetched: the build runs without a network.

A link with a scheme must be http(s) with a host that has a dot, or mailto with an address; anything else
(a typo such as "htps://", "http:/example.org", a space in the address) is a warning, which -W makes an
error. Internal links (pages, anchors, pictures) are Sphinx's and MyST's own checks.
"""

from __future__ import annotations

import re
from urllib.parse import urlsplit

from docutils import nodes
from sphinx.application import Sphinx
from sphinx.util import logging

logger = logging.getLogger(__name__)

_HOST = re.compile(r"^[A-Za-z0-9-]+(\.[A-Za-z0-9-]+)+(:\d+)?$")
_ADDRESS = re.compile(r"^[^@\s]+@[A-Za-z0-9-]+(\.[A-Za-z0-9-]+)+$")


def web_link_problem(uri: str) -> str | None:
    """Why a link to the web is malformed, or None where it is well formed (or not a web link)."""
    if ":" not in uri or uri.startswith(("#", "/", ".")):
        return None
    scheme = uri.split(":", 1)[0].lower()
    if not re.fullmatch(r"[a-z][a-z0-9+.-]*", scheme):
        return None  # a relative path with a colon further on, not a scheme
    if any(character.isspace() for character in uri):
        return "contains white space"
    if scheme == "mailto":
        return None if _ADDRESS.match(uri[len("mailto:") :]) else "is not a mail address"
    if scheme not in ("http", "https"):
        return f"has the scheme {scheme!r}; links to the web use https"
    parts = urlsplit(uri)
    if not uri.lower().startswith(f"{scheme}://") or not _HOST.match(parts.netloc):
        return "has no host name"
    return None


def check_web_links(app: Sphinx, doctree: nodes.document) -> None:
    for reference in doctree.findall(nodes.reference):
        uri = reference.get("refuri", "")
        problem = web_link_problem(uri) if uri else None
        if problem:
            logger.warning("malformed web link %r: it %s", uri, problem, location=reference)


def setup(app: Sphinx) -> dict:
    app.connect("doctree-read", check_web_links)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
