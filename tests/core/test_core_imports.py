"""The core's import graph: read from the source with ast, every module-level and local import counted."""

import ast
from pathlib import Path

CORE = Path(__file__).resolve().parents[2] / "turkish_lipsync" / "core"
PACKAGE = "turkish_lipsync.core"


def _module_name(path: Path) -> str:
    parts = path.relative_to(CORE.parent.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path, name: str, modules: set[str]) -> set[str]:
    """The core modules that the module imports (relative and absolute, at any depth in the file)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.rsplit(".", node.level - 1)[0] if node.level > 1 else package
                target = f"{base}.{node.module}" if node.module else base
            else:
                target = node.module or ""
            # "from . import x" may name a submodule.
            for alias in node.names:
                if f"{target}.{alias.name}" in modules:
                    found.add(f"{target}.{alias.name}")
            if target in modules:
                found.add(target)
        elif isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names if alias.name in modules}
    found.discard(name)
    return found


def core_import_graph() -> dict[str, set[str]]:
    paths = {_module_name(path): path for path in CORE.rglob("*.py")}
    modules = set(paths)
    return {name: _imports(path, name, modules) for name, path in paths.items()}


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    state: dict[str, str] = {}
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = "open"
        path.append(node)
        for target in sorted(graph.get(node, ())):
            if state.get(target) == "open":
                return path[path.index(target) :] + [target]
            if target not in state:
                cycle = visit(target)
                if cycle:
                    return cycle
        state[node] = "done"
        path.pop()
        return None

    for node in sorted(graph):
        if node not in state:
            cycle = visit(node)
            if cycle:
                return cycle
    return None


def test_the_graph_sees_the_imports_it_must():
    graph = core_import_graph()
    assert f"{PACKAGE}.motion.frames" in graph[f"{PACKAGE}.motion.natural"]
    assert f"{PACKAGE}.text.utterance" in graph[f"{PACKAGE}.pipeline"]  # a local import inside lip_sync
    assert f"{PACKAGE}.motion" in graph[f"{PACKAGE}.motion.quality"]  # "from . import weight_tracks"


def test_a_cycle_is_found_where_there_is_one():
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b"}, "b": set()}) is None


def test_the_core_has_no_import_cycle():
    cycle = find_cycle(core_import_graph())
    assert cycle is None, " -> ".join(cycle)


def test_stages_import_only_downstream_of_them():
    """text -> speech -> motion -> faces: a stage never imports a later one."""
    order = ["text", "speech", "motion", "faces"]
    graph = core_import_graph()
    for name, targets in graph.items():
        stage = name.removeprefix(PACKAGE + ".").split(".")[0]
        if stage not in order:
            continue
        for target in targets:
            other = target.removeprefix(PACKAGE + ".").split(".")[0]
            if other in order:
                assert order.index(other) <= order.index(stage), f"{name} imports {target}"
