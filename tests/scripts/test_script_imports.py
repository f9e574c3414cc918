"""The scripts' import graph, read with ast: imports at any depth (a function's own import counts), as
`from scripts.x import ...`, `from scripts import x` or, for a script run from its folder, `import x`."""

import ast
import graphlib
from pathlib import Path

import pytest

SCRIPTS = Path(__file__).resolve().parents[2] / "scripts"


def script_import_graph(folder: Path = SCRIPTS) -> dict[str, set[str]]:
    """script name -> the scripts of the same folder it imports."""
    names = {path.stem for path in folder.glob("*.py")}
    graph = {}
    for path in sorted(folder.glob("*.py")):
        found = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                parts = node.module.split(".")
                if parts[0] == "scripts":
                    found |= {parts[1]} if len(parts) > 1 else {alias.name for alias in node.names}
                else:
                    found.add(parts[0])
            elif isinstance(node, ast.Import):
                for alias in node.names:  # import scripts.x, or import x run from the folder
                    found.add(alias.name.removeprefix("scripts.").split(".")[0])
        graph[path.stem] = (found & names) - {path.stem}
    return graph


def import_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    try:
        tuple(graphlib.TopologicalSorter(graph).static_order())
    except graphlib.CycleError as error:
        return error.args[1]
    return None


def test_the_graph_sees_every_kind_of_import(tmp_path):
    (tmp_path / "a.py").write_text("from scripts.b import x\nfrom scripts import c\n")
    (tmp_path / "b.py").write_text("def f():\n    import d\n")
    (tmp_path / "c.py").write_text("import scripts.d\n")
    (tmp_path / "d.py").write_text("import numpy\n")
    assert script_import_graph(tmp_path) == {"a": {"b", "c"}, "b": {"d"}, "c": {"d"}, "d": set()}


def test_a_cycle_through_an_import_inside_a_function_is_found(tmp_path):
    """The scripts as they were: face_report imported measure_parts' test heads inside a function, and
    measure_parts imported face_report's key reader inside another."""
    (tmp_path / "face_report.py").write_text(
        "def kit_object():\n    from scripts.measure_parts import kit_heads\n"
    )
    (tmp_path / "measure_parts.py").write_text(
        "def glb_parts():\n    from scripts.face_report import world_key_deltas\n"
    )
    cycle = import_cycle(script_import_graph(tmp_path))
    assert cycle is not None and set(cycle) == {"face_report", "measure_parts"}


@pytest.mark.parametrize("script", ["face_report", "measure_parts"])
def test_the_graph_of_the_real_scripts_holds_their_imports(script):
    assert "kit_heads" in script_import_graph()[script]


def test_scripts_do_not_import_each_other_in_a_cycle():
    cycle = import_cycle(script_import_graph())
    assert cycle is None, " -> ".join(cycle)
