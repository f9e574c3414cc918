"""Links to the web are checked for their form only (the build has no network)."""

import sys
from pathlib import Path

import pytest

pytest.importorskip("sphinx")
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "docs" / "_ext"))

from web_links import web_link_problem  # noqa: E402


@pytest.mark.parametrize(
    "uri",
    [
        "https://docs.blender.org/manual/en/latest/",
        "http://localhost.example:8080/path?q=1#part",
        "mailto:someone@example.org",
        "user/heads.md#show-landmarks",
        "#a-heading",
        "../images/demo_frame.jpg",
    ],
)
def test_well_formed_links_pass(uri):
    assert web_link_problem(uri) is None


@pytest.mark.parametrize(
    ("uri", "problem"),
    [
        ("http:/docs.blender.org", "has no host name"),
        ("https://localhost/", "has no host name"),
        ("https://docs.blender .org/", "contains white space"),
        ("ftp://example.org/file", "has the scheme 'ftp'; links to the web use https"),
        ("mailto:nobody", "is not a mail address"),
    ],
)
def test_malformed_links_are_named(uri, problem):
    assert web_link_problem(uri) == problem
