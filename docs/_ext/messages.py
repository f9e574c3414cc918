"""Every error and warning a user can meet, read from the code, for the troubleshooting page.

Read with ast from turkish_lipsync/ (the batch command's flags in core/batch/, an episode's in core/farm/)
and scripts/ (the entry points, which hold no message of their own today):

- errors: `raise SomeError(...)` of the add-on's error family (LipSyncError and every subclass, found by
  name; a list of messages too), `raise self.error(...)`/`raise error(...)` helpers that build one,
  argparse's `ArgumentTypeError` and `parser.error(...)` of the command lines, the problems an episode's
  manifest gathers (`.problem(key, message)`, `.problem_at(place, message)`) and what its checks return
  (a function returning `Problem`: what is wrong with a value, or None);
- warnings: strings appended to, or assigned as, a `warning`/`warnings` value, returned by a function whose
  name holds "warning", given as `warnings=`, and what `report({'WARNING'|'ERROR'}, ...)` shows.

A message is its template: the f-string's literal text with each `{value}` kept as the expression's name.
Each file belongs to one group of the troubleshooting page (GROUPS); a file with messages in no group, or a
group no `{messages}` directive shows, is a warning (an error under -W), so a new message cannot be missed.

    ```{messages} heads
    ```
"""

from __future__ import annotations

import ast
import functools
from dataclasses import dataclass
from pathlib import Path

from docutils import nodes
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

logger = logging.getLogger(__name__)
ROOT = Path(__file__).resolve().parents[2]
SOURCES = ("turkish_lipsync", "scripts")
# Errors raised for the developer (a bug), never shown to a user as a message of ours.
INTERNAL_ERRORS = {
    "ValueError",
    "TypeError",
    "KeyError",
    "RuntimeError",
    "NotImplementedError",
    "AssertionError",
}
USER_ERRORS = {"ArgumentTypeError"}  # argparse shows these as "error: argument --x: <message>"
MESSAGE_WORDS = 6  # a string of this many words returned beside a result is a message, not a name

# Group -> the files (path prefixes from the repository root) whose messages it shows.
GROUPS: dict[str, tuple[str, ...]] = {
    "text": ("turkish_lipsync/core/text/",),
    "landmarks": (
        "turkish_lipsync/core/faces/landmarks.py",
        "turkish_lipsync/core/faces/face_reader.py",
        "turkish_lipsync/core/faces/landmark_fallbacks.py",
        "turkish_lipsync/core/faces/registration.py",
        "turkish_lipsync/core/faces/depth.py",
        "turkish_lipsync/core/faces/topology.py",
    ),
    "heads": (
        "turkish_lipsync/core/faces/",
        "turkish_lipsync/blender/shapekeys.py",
        "turkish_lipsync/blender/heads.py",
        "turkish_lipsync/blender/landmarks.py",
        "turkish_lipsync/blender/mesh.py",
        "turkish_lipsync/blender/eye_keys.py",
        "turkish_lipsync/blender/head_materials.py",
        "turkish_lipsync/blender/owned_keys.py",
    ),
    "buttons": ("turkish_lipsync/blender/operators.py",),
    "rigs": (
        "turkish_lipsync/core/faces/rig_",
        "turkish_lipsync/blender/face_rig.py",
        "turkish_lipsync/blender/rig_",
        "turkish_lipsync/blender/pose_recording.py",
        "turkish_lipsync/blender/character.py",
        "turkish_lipsync/blender/linking.py",
        "turkish_lipsync/blender/marked_curves.py",
    ),
    "engine": (
        "turkish_lipsync/core/speech/espeak.py",
        "turkish_lipsync/core/speech/timeline.py",
        "turkish_lipsync/core/speech/timing.py",
        "turkish_lipsync/core/speech/align.py",
        "turkish_lipsync/core/speech/base.py",
        "turkish_lipsync/core/speech/sources/",
        "turkish_lipsync/blender/preferences.py",
    ),
    "recordings": (
        "turkish_lipsync/core/speech/recording.py",
        "turkish_lipsync/core/speech/audio.py",
        "turkish_lipsync/core/speech/wav.py",
        "turkish_lipsync/core/speech/judgement.py",
        "turkish_lipsync/core/speech/voice_activity.py",
        "turkish_lipsync/core/speech/speech_detector.py",
        "turkish_lipsync/core/speech/features.py",
        "turkish_lipsync/core/speech/recognition/",
        "turkish_lipsync/core/speech/acoustic/",
        "turkish_lipsync/core/speech/decoders/",
        "turkish_lipsync/blender/audio_decoding.py",
        "turkish_lipsync/blender/recording_browser.py",
    ),
    "cues": ("turkish_lipsync/core/speech/cues/", "turkish_lipsync/core/speech/cue_timing.py"),
    "living": ("turkish_lipsync/core/motion/", "turkish_lipsync/blender/living"),
    "scene": (
        "turkish_lipsync/core/pipeline.py",
        "turkish_lipsync/blender/pipeline.py",
        "turkish_lipsync/blender/generate.py",
        "turkish_lipsync/blender/sequencer.py",
        "turkish_lipsync/blender/keyframes.py",
        "turkish_lipsync/blender/compat.py",
    ),
    "conversation": (
        "turkish_lipsync/core/scene/",
        "turkish_lipsync/blender/conversation.py",
        "turkish_lipsync/blender/scene_record.py",
    ),
    "exports": (
        "turkish_lipsync/core/interchange/",
        "turkish_lipsync/blender/exports.py",
        "turkish_lipsync/blender/gltf_export.py",
    ),
    "render": (
        "turkish_lipsync/blender/render.py",
        "turkish_lipsync/blender/farm.py",
        "turkish_lipsync/core/interchange/video.py",
    ),
    "command-line": (
        "turkish_lipsync/core/cli.py",
        "turkish_lipsync/core/base/files.py",
        "turkish_lipsync/core/batch/",
        "turkish_lipsync/blender/batch.py",
        "scripts/",
    ),
    "data": ("turkish_lipsync/core/base/",),
    "episodes": ("turkish_lipsync/core/farm/", "scripts/episode.py"),
}


@dataclass(frozen=True)
class Message:
    # "error", "warning", "message" (returned beside a result: a warning or what was done), or "disabled"
    # (why a button is greyed out, shown in its tooltip)
    kind: str
    template: str
    path: str  # from the repository root
    line: int


def template(node: ast.expr) -> str | None:
    """The text of a message expression, `{expression}` where it is filled in; None if it holds no text."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if isinstance(node, ast.JoinedStr):
        return "".join(
            part.value if isinstance(part, ast.Constant) else _placeholder(part.value) for part in node.values
        )
    if isinstance(node, ast.Call) and _name(node.func) in ("strip", "rstrip") and not node.args:
        return template(node.func.value)
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        left, right = template(node.left), template(node.right)
        if left is not None or right is not None:
            return (left or "{…}") + (right or "{…}")
    return None


def _placeholder(node: ast.expr) -> str:
    """A filled-in value as the reader can guess it: its name (head.name, path), or … for a computation."""
    simple = node
    while isinstance(simple, (ast.Attribute, ast.Subscript)):
        simple = simple.value
    return "{" + (ast.unparse(node) if isinstance(simple, ast.Name) else "…") + "}"


def _name(node: ast.expr) -> str:
    if isinstance(node, ast.Subscript):
        return _name(node.value)
    if isinstance(node, ast.Attribute):
        return node.attr
    return node.id if isinstance(node, ast.Name) else ""


def _error_classes(trees: dict[str, ast.Module]) -> set[str]:
    """LipSyncError and every class that derives from it (by name, across the sources)."""
    found = {"LipSyncError"}
    bases = {
        node.name: {_name(base) for base in node.bases}
        for tree in trees.values()
        for node in ast.walk(tree)
        if isinstance(node, ast.ClassDef)
    }
    while True:
        more = {name for name, parents in bases.items() if parents & found} - found
        if not more:
            return found
        found |= more


def _is_warning_name(node: ast.expr) -> bool:
    return "warning" in _name(node).lower()


def _strings(node: ast.expr) -> list[ast.expr]:
    """The message expressions of a value: itself, the elements of a tuple or list, what a comprehension
    makes, either branch of a conditional, and the messages of a sum of tuples."""
    if isinstance(node, (ast.Tuple, ast.List)):
        return [string for element in node.elts for string in _strings(element)]
    if isinstance(node, (ast.ListComp, ast.GeneratorExp, ast.SetComp)):
        return _strings(node.elt)
    if isinstance(node, ast.IfExp):
        return _strings(node.body) + _strings(node.orelse)
    if isinstance(node, ast.BinOp) and template(node) is None:  # a sum of tuples, a list times a condition
        return _strings(node.left) + _strings(node.right)
    return [node] if template(node) is not None else []


class _Collector(ast.NodeVisitor):
    def __init__(self, path: str, errors: set[str]) -> None:
        self.path, self.errors, self.found = path, errors, []
        self.function = ""

    def add(self, kind: str, node: ast.expr) -> None:
        text = template(node)
        if text is not None and text.strip():
            self.found.append(Message(kind, " ".join(text.split()), self.path, node.lineno))

    def visit_FunctionDef(self, node: ast.FunctionDef) -> None:
        outer, self.function = self.function, node.name
        returns = ast.unparse(node.returns) if node.returns is not None else ""
        # an operator's requirement: None where it is met, else why its button is greyed out; or a check
        # of a value: None where it is good, else what is wrong with it
        kind = {"str | None": "disabled", '"str | None"': "disabled", "Problem": "error"}.get(returns)
        if kind is not None:
            for returned in (child for child in ast.walk(node) if isinstance(child, ast.Return)):
                for value in _strings(returned.value) if returned.value is not None else ():
                    self.add(kind, value)
        self.generic_visit(node)
        self.function = outer

    def visit_Raise(self, node: ast.Raise) -> None:
        call = node.exc
        if isinstance(call, ast.Call) and call.args:
            name = _name(call.func)
            if name in self.errors or name in USER_ERRORS or name in ("error", "_error"):
                for value in _strings(call.args[0]):
                    self.add("error", value)
        self.generic_visit(node)

    def visit_Call(self, node: ast.Call) -> None:
        function = node.func
        name = _name(function)
        if name == "error" and _name(getattr(function, "value", function)) == "parser" and node.args:
            self.add("error", node.args[0])
        elif name in ("problem", "problem_at") and len(node.args) == 2:
            for value in _strings(node.args[1]):
                self.add("error", value)
        elif name in ("append", "extend") and _is_warning_name(function.value) and node.args:
            for value in _strings(node.args[0]):
                self.add("warning", value)
        elif name == "report" and len(node.args) == 2:
            level = ast.unparse(node.args[0])
            for value in _strings(node.args[1]):
                self.add("warning" if "WARNING" in level else "error", value)
        for keyword in node.keywords:
            if keyword.arg == "warnings":
                for value in _strings(keyword.value):
                    self.add("warning", value)
        self.generic_visit(node)

    def visit_Assign(self, node: ast.Assign) -> None:
        if any(_is_warning_name(target) for target in node.targets):
            for value in _strings(node.value):
                self.add("warning", value)
        self.generic_visit(node)

    def visit_AugAssign(self, node: ast.AugAssign) -> None:
        if _is_warning_name(node.target):
            for value in _strings(node.value):
                self.add("warning", value)
        self.generic_visit(node)

    def visit_Return(self, node: ast.Return) -> None:
        if node.value is not None and "warning" in self.function:
            for value in _strings(node.value):
                self.add("warning", value)
        elif isinstance(node.value, ast.Tuple):  # (what was done, the problem to tell the user)
            for value in _strings(node.value):
                if len(template(value).split()) >= MESSAGE_WORDS:
                    self.add("message", value)
        self.generic_visit(node)


def source_files(root: Path = ROOT) -> list[Path]:
    files: list[Path] = []
    for source in SOURCES:
        path = root / source
        files += sorted(path.rglob("*.py")) if path.is_dir() else [path]
    return files


@functools.cache
def collect_messages(root: Path = ROOT) -> tuple[Message, ...]:
    """Every message of the sources under root, in file and line order."""
    trees = {
        path.relative_to(root).as_posix(): _with_constants_inlined(
            ast.parse(path.read_text(encoding="utf-8"))
        )
        for path in source_files(root)
    }
    errors = _error_classes(trees) - INTERNAL_ERRORS
    messages: list[Message] = []
    for path, tree in trees.items():
        collector = _Collector(path, errors)
        collector.visit(tree)
        messages += sorted(set(collector.found), key=lambda message: message.line)
    return tuple(messages)


class _ConstantInliner(ast.NodeTransformer):
    """A module's string constants (NAME = "..." at its top level) read where they are used by name: a
    message written once and raised or shown in several places is found at each."""

    def __init__(self, constants: dict[str, ast.expr]) -> None:
        self.constants = constants

    def visit_Name(self, node: ast.Name) -> ast.expr:
        if isinstance(node.ctx, ast.Load) and node.id in self.constants:
            return ast.copy_location(ast.Constant(self.constants[node.id].value), node)
        return node


def _with_constants_inlined(tree: ast.Module) -> ast.Module:
    constants = {
        target.id: node.value
        for node in tree.body
        if isinstance(node, ast.Assign)
        and isinstance(node.value, ast.Constant)
        and isinstance(node.value.value, str)
        for target in node.targets
        if isinstance(target, ast.Name) and target.id.isupper()
    }
    return _ConstantInliner(constants).visit(tree) if constants else tree


def group_of(path: str) -> str | None:
    """The group whose prefix matches the path longest (a file may sit in a folder of another group)."""
    matches = [
        (len(prefix), group)
        for group, prefixes in GROUPS.items()
        for prefix in prefixes
        if path.startswith(prefix)
    ]
    return max(matches)[1] if matches else None


def _message_table(messages: list[Message]) -> nodes.table:
    table = nodes.table()
    group = nodes.tgroup(cols=2)
    table += group
    group += nodes.colspec(colwidth=10)
    group += nodes.colspec(colwidth=90)
    body = nodes.tbody()
    for message in messages:
        row = nodes.row()
        kind = nodes.entry()
        kind += nodes.paragraph(text=message.kind)
        text = nodes.entry()
        paragraph = nodes.paragraph()
        paragraph += nodes.Text(message.template + " ")
        location = f"{message.path}:{message.line}"
        paragraph += nodes.literal(location, location, classes=["message-source"])
        text += paragraph
        row += kind
        row += text
        body += row
    group += body
    return table


class Messages(SphinxDirective):
    """The messages of one group, as the code writes them ({...} is filled in at run time)."""

    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        group = self.arguments[0]
        if group not in GROUPS:
            logger.warning(
                "messages: no group %r; the groups are %s",
                group,
                ", ".join(GROUPS),
                location=self.get_location(),
            )
            return []
        for path in source_files():
            self.env.note_dependency(str(path))
        self.env.domaindata.setdefault("messages", {}).setdefault("groups", {})[group] = self.env.docname
        shown = [message for message in collect_messages() if group_of(message.path) == group]
        return [_message_table(shown)] if shown else [nodes.paragraph(text="No message.")]


def check_every_message_shown(app, env) -> None:
    shown_groups = env.domaindata.get("messages", {}).get("groups", {})
    for message in collect_messages():
        group = group_of(message.path)
        if group is None:
            logger.warning(
                "messages: %s:%d is in no group of docs/_ext/messages.py GROUPS: %s",
                message.path,
                message.line,
                message.template,
            )
        elif group not in shown_groups:
            logger.warning("messages: the group %r is in no {messages} directive of the manual", group)
            shown_groups[group] = ""  # said once


def forget_document(_app, env, docname: str) -> None:
    groups = env.domaindata.get("messages", {}).get("groups", {})
    for group in [group for group, document in groups.items() if document == docname]:
        del groups[group]


def setup(app) -> dict:
    app.add_directive("messages", Messages)
    app.connect("env-purge-doc", forget_document)
    app.connect("env-check-consistency", check_every_message_shown)
    return {"parallel_read_safe": False, "parallel_write_safe": True}
