"""The core's import graph, read from the source with ast: every import at any depth in a file counted, and
the packages Python imports on the way (importing a.b.c runs a/__init__.py and a/b/__init__.py first)."""

import ast
from pathlib import Path

CORE = Path(__file__).resolve().parents[2] / "turkish_lipsync" / "core"
PACKAGE = "turkish_lipsync.core"
# The stages in the order they may look: each imports only its own stage and the ones before it.
STAGES = [
    ["base"],
    ["text"],
    ["speech"],
    ["motion", "faces"],
    ["pipeline"],
    ["scene"],
    ["interchange"],
    ["cli"],
    ["batch"],
    ["farm"],
]


def _module_name(path: Path, core: Path) -> str:
    parts = path.relative_to(core.parent.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _with_parents(target: str, modules: set[str]) -> set[str]:
    """The module and every package above it that Python runs first (within the core)."""
    found = set()
    parts = target.split(".")
    for depth in range(len(parts), 0, -1):
        name = ".".join(parts[:depth])
        if name in modules:
            found.add(name)
    return found


def _imports(path: Path, name: str, modules: set[str]) -> set[str]:
    """The core modules that importing this module runs (relative and absolute imports at any depth)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.rsplit(".", node.level - 1)[0] if node.level > 1 else package
                target = f"{base}.{node.module}" if node.module else base
            else:
                target = node.module or ""
            found |= _with_parents(target, modules)
            for alias in node.names:  # "from . import x" may name a submodule
                found |= _with_parents(f"{target}.{alias.name}", modules)
        elif isinstance(node, ast.Import):
            for alias in node.names:
                found |= _with_parents(alias.name, modules)
    # A module's own packages are not imports of it (they are running it).
    found -= _with_parents(name, modules)
    return found


def core_import_graph(core: Path = CORE) -> dict[str, set[str]]:
    paths = {_module_name(path, core): path for path in core.rglob("*.py")}
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


def stage_of(module: str) -> int | None:
    top = module.removeprefix(PACKAGE + ".").split(".")[0]
    return next((rank for rank, names in enumerate(STAGES) if top in names), None)


def later_stage_imports(graph: dict[str, set[str]]) -> list[str]:
    """Every import of a later stage, as "module -> target"."""
    found = []
    for name, targets in sorted(graph.items()):
        rank = stage_of(name)
        for target in sorted(targets):
            other = stage_of(target)
            if rank is not None and other is not None and other > rank:
                found.append(f"{name} -> {target}")
    return found


def peer_stage_imports(graph: dict[str, set[str]]) -> list[str]:
    """Every import between two packages of one stage (faces and motion are peers: neither looks at the other;
    what both need lies below them), as "module -> target"."""
    found = []
    for name, targets in sorted(graph.items()):
        rank, top = stage_of(name), _top_package(name)
        for target in sorted(targets):
            if rank is not None and stage_of(target) == rank and _top_package(target) != top:
                found.append(f"{name} -> {target}")
    return found


def _top_package(module: str) -> str:
    return module.removeprefix(PACKAGE + ".").split(".")[0]


def test_the_graph_sees_the_imports_it_must():
    graph = core_import_graph()
    assert f"{PACKAGE}.motion.frames" in graph[f"{PACKAGE}.motion.natural"]
    # importing speech.sources runs speech/__init__.py first; base.choices runs base/__init__.py
    expected = {
        f"{PACKAGE}.speech",
        f"{PACKAGE}.speech.sources",
        f"{PACKAGE}.base",
        f"{PACKAGE}.base.choices",
    }
    assert expected <= graph[f"{PACKAGE}.pipeline"]
    # a module's own packages are not its imports: they are what runs it
    assert f"{PACKAGE}.speech" not in graph[f"{PACKAGE}.speech.cue_timing"]


def test_the_checks_fail_on_a_tree_with_a_hidden_cycle(tmp_path):
    """The tree before the stages were put in order: pipeline imported interchange.cue_timing inside a
    function, which runs interchange/__init__.py, which imported Choice from pipeline."""
    core = tmp_path / "turkish_lipsync" / "core"
    (core / "interchange").mkdir(parents=True)
    (core / "__init__.py").write_text("")
    (core / "pipeline.py").write_text(
        "class Choice: ...\n\ndef lip_sync():\n    from .interchange.cue_timing import speech_from_cues\n"
    )
    (core / "interchange" / "__init__.py").write_text("from ..pipeline import Choice\n")
    (core / "interchange" / "cue_timing.py").write_text("def speech_from_cues(): ...\n")
    graph = core_import_graph(core)
    assert find_cycle(graph) == [
        f"{PACKAGE}.interchange",
        f"{PACKAGE}.pipeline",
        f"{PACKAGE}.interchange",
    ]
    assert later_stage_imports(graph) == [
        f"{PACKAGE}.pipeline -> {PACKAGE}.interchange",
        f"{PACKAGE}.pipeline -> {PACKAGE}.interchange.cue_timing",
    ]


def test_every_module_of_the_core_has_a_stage():
    unplaced = [name for name in core_import_graph() if name != PACKAGE and stage_of(name) is None]
    assert not unplaced, f"modules outside the stages {STAGES}: {unplaced}"


def test_the_core_has_no_import_cycle():
    cycle = find_cycle(core_import_graph())
    assert cycle is None, " -> ".join(cycle)


def test_stages_import_only_the_stages_before_them():
    found = later_stage_imports(core_import_graph())
    assert not found, "\n".join(found)


def test_the_peer_check_fails_on_faces_importing_motion(tmp_path):
    """The tree as it was: the eyes of a head (faces) took their rotation helper from the living layers
    (motion), peers of the same stage."""
    core = tmp_path / "turkish_lipsync" / "core"
    for package in ("faces", "motion", "motion/living", "base"):
        (core / package).mkdir(parents=True, exist_ok=True)
        (core / package / "__init__.py").write_text("")
    (core / "__init__.py").write_text("")
    (core / "motion" / "living" / "rotations.py").write_text("def direction(): ...\n")
    (core / "faces" / "eyes.py").write_text("from ..motion.living.rotations import direction\n")
    graph = core_import_graph(core)
    assert later_stage_imports(graph) == []  # the same rank: the stage order alone does not see it
    assert peer_stage_imports(graph) == [
        f"{PACKAGE}.faces.eyes -> {PACKAGE}.motion",
        f"{PACKAGE}.faces.eyes -> {PACKAGE}.motion.living",
        f"{PACKAGE}.faces.eyes -> {PACKAGE}.motion.living.rotations",
    ]


def test_faces_and_motion_do_not_import_each_other():
    found = peer_stage_imports(core_import_graph())
    assert not found, "\n".join(found)
