"""The lab beside the product: nothing edits sys.path, the tests use only the lab's kit, and the lab's
modules import each other without a cycle. Read from the sources with ast (an import inside a function
counts), so a script that runs only by hand is checked as well."""

import ast
import graphlib
from pathlib import Path

import pytest

REPOSITORY = Path(__file__).resolve().parents[2]
LAB_PACKAGES = ("lab", "tools")
FORBIDDEN_TO_TESTS = ("lab.measure", "lab.tune", "lab.train", "tools.figures")


def imported_modules(path: Path) -> set[str]:
    """Every absolute module a file imports, at any depth (`from a.b import c` gives a.b and a.b.c)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module)
            found |= {f"{node.module}.{alias.name}" for alias in node.names}
        elif isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
    return found


def edits_sys_path(path: Path) -> bool:
    """Whether a file changes sys.path (insert, append, extend, assignment or slice assignment)."""
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Attribute) and node.attr == "path":
            if isinstance(node.value, ast.Name) and node.value.id == "sys":
                return True
    return False


def module_name(path: Path, root: Path = REPOSITORY) -> str:
    parts = path.relative_to(root).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def lab_import_graph(root: Path = REPOSITORY) -> dict[str, set[str]]:
    """module -> the lab and tools modules it imports."""
    modules = {
        module_name(path, root): path for package in LAB_PACKAGES for path in (root / package).rglob("*.py")
    }
    return {name: (imported_modules(path) & modules.keys()) - {name} for name, path in modules.items()}


def import_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    try:
        tuple(graphlib.TopologicalSorter(graph).static_order())
    except graphlib.CycleError as error:
        return error.args[1]
    return None


def python_files(*folders: str) -> list[Path]:
    return sorted(path for folder in folders for path in (REPOSITORY / folder).rglob("*.py"))


def test_the_readers_see_what_they_look_for(tmp_path):
    """The checks below can fail: each reader finds what it must on a file written to show it."""
    source = tmp_path / "lab" / "measure" / "x.py"
    source.parent.mkdir(parents=True)
    source.write_text(
        "import sys\nfrom lab.kit import people\n\n"
        "def f():\n    from lab.train.recogniser import train\n    sys.path.insert(0, '.')\n"
    )
    (tmp_path / "lab" / "train").mkdir()
    (tmp_path / "lab" / "train" / "recogniser.py").write_text("from lab.measure.x import f\n")
    assert edits_sys_path(source)
    assert {"lab.kit.people", "lab.train.recogniser", "sys"} <= imported_modules(source)
    assert set(import_cycle(lab_import_graph(tmp_path))) == {"lab.measure.x", "lab.train.recogniser"}
    (tmp_path / "lab" / "train" / "recogniser.py").write_text("import numpy\n")
    assert import_cycle(lab_import_graph(tmp_path)) is None


@pytest.mark.parametrize("path", python_files("scripts", "lab", "tools"), ids=str)
def test_no_script_edits_the_import_path(path):
    assert not edits_sys_path(path), f"{path.relative_to(REPOSITORY)} edits sys.path: run it with python -m"


@pytest.mark.parametrize("path", python_files("tests"), ids=str)
def test_tests_import_only_the_kit_of_the_lab(path):
    wrong = sorted(
        name
        for name in imported_modules(path)
        if any(name == forbidden or name.startswith(forbidden + ".") for forbidden in FORBIDDEN_TO_TESTS)
    )
    assert not wrong, f"{path.relative_to(REPOSITORY)} imports {wrong}: of the lab, tests use only lab.kit"


def test_the_lab_imports_without_a_cycle():
    assert import_cycle(lab_import_graph()) is None
