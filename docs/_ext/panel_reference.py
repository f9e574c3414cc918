"""The panel reference, generated from the add-on itself, so that it cannot fall out of date.

What the panel draws is read from turkish_lipsync/blender/panel.py (its draw methods, read with ast: the
sections by their headings, every `.prop(settings, ...)` and `.operator(...)` in order, with the conditions
under which it is shown or active); what each field is comes from the registered RNA of the add-on (bpy,
the add-on registered as Blender registers it): its UI name, description, type, default, range and enum
items, and its Turkish name from turkish_lipsync/blender/translations.py.

    ```{panel-fields} Head
    ```
    ```{preferences-fields}
    ```

The build fails (a warning, an error under -W) when a drawn property or operator is missing from the RNA
or lacks a description, when an enum item lacks one, when a name has no Turkish translation, when the panel
draws a property of another data block than the add-on's settings, and when a section of the panel is in no
`panel-fields` directive of the manual.
"""

from __future__ import annotations

import ast
import functools
from dataclasses import dataclass, field
from pathlib import Path

from docutils import nodes
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

logger = logging.getLogger(__name__)
ROOT = Path(__file__).resolve().parents[2]
PANEL_SOURCE = ROOT / "turkish_lipsync" / "blender" / "panel.py"
# Re-read the pages of the reference when what it is made from changes.
DEPENDENCIES = tuple(
    ROOT / "turkish_lipsync" / "blender" / name for name in ("panel.py", "properties.py", "translations.py")
)
SETTINGS = "settings"  # the name panel.py gives the add-on's settings (context.scene.turkish_lipsync)
LABEL_WORDS = 4  # a text of the translation table this short is a label; longer ones are tooltips


@dataclass(frozen=True)
class Drawn:
    """One thing the panel draws: a property of the settings or an operator's button."""

    kind: str  # "property" or "operator"
    name: str  # the property's identifier or the operator's bl_idname
    section: str
    shown_when: tuple[ast.expr, ...] = ()  # all must hold for it to be drawn
    active_when: tuple[ast.expr, ...] = ()  # drawn greyed out unless these hold
    struct: str = SETTINGS  # the variable whose property is drawn
    line: int = 0


@dataclass
class _Walk:
    methods: dict[str, ast.FunctionDef]
    drawn: list[Drawn] = field(default_factory=list)
    section: str = ""


def drawn_by_panel(source: str) -> list[Drawn]:
    """Every property and operator the panel classes of this source draw, in the order a user sees them."""
    drawn: list[Drawn] = []
    for cls in (node for node in ast.parse(source).body if isinstance(node, ast.ClassDef)):
        methods = {node.name: node for node in cls.body if isinstance(node, ast.FunctionDef)}
        if "draw" not in methods:
            continue
        walk = _Walk(methods, section=_class_label(cls))
        _walk_body(walk, methods["draw"].body, (), {}, {})
        drawn += walk.drawn
    return drawn


def _class_label(cls: ast.ClassDef) -> str:
    for node in cls.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "bl_label" for t in node.targets):
            return ast.literal_eval(node.value)
    return cls.name


def _walk_body(walk, body, shown, bound, active) -> None:
    """Statements in order: `if` adds its test (or its negation) to the conditions, a `for` over literal
    tuples is unrolled, `x.active = ...` marks what x draws, calls of the class's own draw_* methods are
    followed."""
    for statement in body:
        if isinstance(statement, ast.If):
            _walk_body(walk, statement.body, (*shown, statement.test), bound, active)
            negation = ast.UnaryOp(op=ast.Not(), operand=statement.test)
            _walk_body(walk, statement.orelse, (*shown, negation), bound, active)
        elif isinstance(statement, ast.For) and isinstance(statement.iter, ast.Tuple):
            for element in statement.iter.elts:
                names = (
                    statement.target.elts if isinstance(statement.target, ast.Tuple) else [statement.target]
                )
                values = element.elts if isinstance(element, ast.Tuple) else [element]
                binding = {n.id: v for n, v in zip(names, values, strict=True)}
                _walk_body(walk, statement.body, shown, {**bound, **binding}, active)
        elif isinstance(statement, ast.Assign) and _is_active_assignment(statement):
            active = {**active, statement.targets[0].value.id: _bind(statement.value, bound)}
        else:
            for call in _calls_in_order(statement):
                _visit_call(walk, call, shown, bound, active)


def _is_active_assignment(statement: ast.Assign) -> bool:
    target = statement.targets[0]
    return (
        isinstance(target, ast.Attribute) and target.attr == "active" and isinstance(target.value, ast.Name)
    )


def _calls_in_order(statement: ast.stmt) -> list[ast.Call]:
    return sorted(
        (node for node in ast.walk(statement) if isinstance(node, ast.Call)),
        key=lambda node: (node.lineno, node.col_offset),
    )


def _bind(expression: ast.expr, bound: dict[str, ast.expr]) -> ast.expr:
    """The expression with the loop's names replaced by their values; getattr(settings, "x") is settings.x."""

    class Substitute(ast.NodeTransformer):
        def visit_Name(self, node):
            return bound.get(node.id, node)

        def visit_Call(self, node):
            self.generic_visit(node)
            if getattr(node.func, "id", "") == "getattr" and isinstance(node.args[1], ast.Constant):
                return ast.Attribute(value=node.args[0], attr=node.args[1].value, ctx=ast.Load())
            return node

    return Substitute().visit(ast.parse(ast.unparse(expression), mode="eval").body)


def _visit_call(walk, call: ast.Call, shown, bound, active) -> None:
    function = call.func
    if not isinstance(function, ast.Attribute):
        return
    receiver = function.value.id if isinstance(function.value, ast.Name) else ""
    if receiver == "self" and function.attr in walk.methods:
        _walk_body(walk, walk.methods[function.attr].body, shown, bound, active)
        return
    keywords = {keyword.arg: keyword.value for keyword in call.keywords}
    heading = keywords.get("heading")
    if function.attr == "column" and isinstance(heading, ast.Constant):
        walk.section = heading.value
    elif function.attr == "label" and receiver == "header" and isinstance(keywords.get("text"), ast.Constant):
        walk.section = keywords["text"].value
    elif function.attr in ("prop", "operator"):
        arguments = [_bind(argument, bound) for argument in call.args]
        conditions = (active[receiver],) if receiver in active else ()
        if function.attr == "operator" and isinstance(arguments[0], ast.Constant):
            walk.drawn.append(
                Drawn("operator", arguments[0].value, walk.section, shown, conditions, line=call.lineno)
            )
        elif function.attr == "prop" and len(arguments) > 1 and isinstance(arguments[1], ast.Constant):
            struct = arguments[0].id if isinstance(arguments[0], ast.Name) else ast.unparse(arguments[0])
            walk.drawn.append(
                Drawn(
                    "property", arguments[1].value, walk.section, shown, conditions, struct, line=call.lineno
                )
            )


# -- the RNA ------------------------------------------------------------------------------------------------


@functools.cache
def registered() -> None:
    """The add-on registered in this process, as Blender registers it (once per build)."""
    from turkish_lipsync import blender

    blender.register()


def settings_rna():
    import bpy

    registered()
    return bpy.types.Scene.bl_rna.properties["turkish_lipsync"].fixed_type


def preferences_rna():
    from turkish_lipsync.blender import preferences

    registered()
    return preferences.TurkishLipSyncPreferences.bl_rna


def operator_rna(idname: str):
    import bpy

    registered()
    group, _, name = idname.partition(".")
    operator = getattr(getattr(bpy.ops, group, None), name, None)
    try:
        return operator.get_rna_type() if operator is not None else None
    except KeyError:  # bpy.ops resolves any name; an unregistered one has no RNA
        return None


def turkish(text: str) -> str | None:
    from turkish_lipsync.blender.translations import TURKISH

    return TURKISH.get(text)


def property_problems(struct, identifier: str) -> list[str]:
    """Why the reference cannot describe this property of an RNA struct (empty: it can)."""
    prop = struct.properties.get(identifier)
    if prop is None:
        return [f"{struct.identifier} has no property {identifier!r}"]
    problems = []
    if not prop.description.strip():
        problems.append(f"{struct.identifier}.{identifier} has no description")
    if turkish(prop.name) is None:
        problems.append(
            f"{struct.identifier}.{identifier}: its name {prop.name!r} has no Turkish translation"
        )
    if prop.type == "ENUM":
        for item in prop.enum_items:
            if not item.description.strip():
                problems.append(
                    f"{struct.identifier}.{identifier}: the item {item.identifier!r} has no description"
                )
            if turkish(item.name) is None:
                problems.append(
                    f"{struct.identifier}.{identifier}: the item name {item.name!r} has no Turkish"
                )
    return problems


def operator_problems(idname: str) -> list[str]:
    rna = operator_rna(idname)
    if rna is None:
        return [f"no operator {idname} is registered"]
    problems = []
    if not rna.description.strip():
        problems.append(f"the operator {idname} has no description")
    if turkish(rna.name) is None:
        problems.append(f"the operator {idname}: its name {rna.name!r} has no Turkish translation")
    return problems


def reference_problems(drawn: list[Drawn], struct) -> list[str]:
    """Every drawn thing the reference cannot describe, and why."""
    problems = []
    for item in drawn:
        where = f"{PANEL_SOURCE.name}:{item.line}"
        if item.kind == "operator":
            problems += [f"{where}: {problem}" for problem in operator_problems(item.name)]
        elif item.struct != SETTINGS:
            problems.append(
                f"{where}: draws {item.struct}.{item.name}, a property of another data block than the "
                "add-on's settings, which the reference cannot describe"
            )
        else:
            problems += [f"{where}: {problem}" for problem in property_problems(struct, item.name)]
    return problems


# -- rendering ----------------------------------------------------------------------------------------------


def _value_name(struct, identifier: str, value: str) -> str:
    prop = struct.properties[identifier]
    if prop.type == "ENUM":
        names = {item.identifier: item.name for item in prop.enum_items}
        return names.get(value, value)
    return value


def condition_text(expression: ast.expr, struct) -> str:
    """A condition on the settings in words: "Shape-Key Source is Auto or Own Visemes"."""
    negated = isinstance(expression, ast.UnaryOp) and isinstance(expression.op, ast.Not)
    test = expression.operand if negated else expression
    if isinstance(test, ast.Attribute) and getattr(test.value, "id", "") == SETTINGS:
        name = struct.properties[test.attr].name
        return f"{name} is {'off' if negated else 'on'}"
    if (
        isinstance(test, ast.Compare)
        and isinstance(test.left, ast.Attribute)
        and getattr(test.left.value, "id", "") == SETTINGS
        and len(test.ops) == 1
    ):
        identifier = test.left.attr
        name = struct.properties[identifier].name
        values = ast.literal_eval(test.comparators[0])
        values = values if isinstance(values, tuple) else (values,)
        words = " or ".join(_value_name(struct, identifier, value) for value in values)
        positive = isinstance(test.ops[0], (ast.Eq, ast.In))
        return f"{name} is {'' if positive != negated else 'not '}{words}"
    return f"`{ast.unparse(expression)}`"


def _type_text(prop) -> str:
    default = getattr(prop, "default", None)
    if prop.type == "BOOLEAN":
        return f"on or off; default {'on' if default else 'off'}"
    if prop.type in ("INT", "FLOAT"):
        kind = {"INT": "whole number", "FLOAT": "number"}[prop.type]
        if prop.subtype == "FACTOR":
            kind = "factor"
        text = f"{kind}, default {default:g}, {prop.hard_min:g} to {prop.hard_max:g}"
        if (prop.soft_min, prop.soft_max) != (prop.hard_min, prop.hard_max):
            text += f" (the slider {prop.soft_min:g} to {prop.soft_max:g})"
        return text
    if prop.type == "STRING":
        kind = {"FILE_PATH": "a file", "DIR_PATH": "a folder"}.get(prop.subtype, "text")
        shown = f"`{default}`" if default else "empty"
        return f"{kind}; default {shown}" + (
            " (`//` is the folder of the saved .blend)" if "//" in default else ""
        )
    if prop.type == "POINTER":
        kind = {"Object": "an object", "Text": "a Text data block (Text Editor)"}.get(
            prop.fixed_type.identifier, prop.fixed_type.identifier
        )
        return f"{kind}; default none"
    if prop.type == "ENUM":
        names = {item.identifier: item.name for item in prop.enum_items}
        return f"one of the items below; default {names.get(prop.default, prop.default)}"
    return prop.type.lower()


def _sentence(parts: list[str]) -> str:
    text = "; ".join(parts)
    return text[:1].upper() + text[1:] + "."


def _paragraph(*parts: nodes.Node | str) -> nodes.paragraph:
    paragraph = nodes.paragraph()
    for part in parts:
        paragraph += nodes.Text(part) if isinstance(part, str) else part
    return paragraph


def _term(name: str, identifier: str) -> nodes.term:
    term = nodes.term()
    term += nodes.strong(name, name)
    term += nodes.Text(" · ")
    term += nodes.emphasis(turkish(name) or "", turkish(name) or "")
    term += nodes.Text(" · ")
    term += nodes.literal(identifier, identifier)
    return term


def property_item(struct, identifier: str, drawn: Drawn | None = None) -> nodes.definition_list_item:
    prop = struct.properties[identifier]
    item = nodes.definition_list_item(ids=[f"field-{identifier.replace('_', '-')}"])
    item += _term(prop.name, identifier)
    definition = nodes.definition()
    definition += _paragraph(prop.description)
    details = [_type_text(prop)]
    if drawn is not None and drawn.shown_when:
        details.append("shown when " + " and ".join(condition_text(c, struct) for c in drawn.shown_when))
    if drawn is not None and drawn.active_when:
        details.append("active when " + " and ".join(condition_text(c, struct) for c in drawn.active_when))
    definition += _paragraph(nodes.emphasis("", _sentence(details)))
    if prop.type == "ENUM":
        items = nodes.bullet_list()
        for enum_item in prop.enum_items:
            entry = nodes.list_item()
            entry += _paragraph(
                nodes.strong(enum_item.name, enum_item.name),
                f" ({turkish(enum_item.name)}, ",
                nodes.literal(enum_item.identifier, enum_item.identifier),
                f"): {enum_item.description}",
            )
            items += entry
        definition += items
    item += definition
    return item


def operator_item(drawn: Drawn, struct) -> nodes.definition_list_item:
    rna = operator_rna(drawn.name)
    item = nodes.definition_list_item(ids=[f"button-{drawn.name.partition('.')[2].replace('_', '-')}"])
    item += _term(rna.name, f"bpy.ops.{drawn.name}")
    definition = nodes.definition()
    definition += _paragraph(rna.description)
    details = ["a button"]
    if drawn.shown_when:
        details.append("shown when " + " and ".join(condition_text(c, struct) for c in drawn.shown_when))
    definition += _paragraph(nodes.emphasis("", _sentence(details)))
    item += definition
    return item


def _report(problems: list[str], location) -> None:
    for problem in problems:
        logger.warning("panel reference: %s", problem, location=location)


class PanelFields(SphinxDirective):
    """Every field and button of one section of the panel, as the panel draws them."""

    required_arguments = 1
    final_argument_whitespace = True

    def run(self) -> list[nodes.Node]:
        section = self.arguments[0]
        struct = settings_rna()
        drawn = [
            item
            for item in drawn_by_panel(PANEL_SOURCE.read_text(encoding="utf-8"))
            if item.section == section
        ]
        for source in DEPENDENCIES:
            self.env.note_dependency(str(source))
        if not drawn:
            _report([f"the panel has no section {section!r}"], self.get_location())
            return []
        self.env.domaindata.setdefault("panel_reference", {}).setdefault("sections", {})[section] = (
            self.env.docname
        )
        problems = reference_problems(drawn, struct)
        _report(problems, self.get_location())
        if problems:
            return []
        fields = nodes.definition_list()
        seen: set[str] = set()
        for item in drawn:
            if (item.kind, item.name) in seen:
                continue  # drawn twice (in both branches of a condition): described once
            seen.add((item.kind, item.name))
            fields += (
                property_item(struct, item.name, item)
                if item.kind == "property"
                else operator_item(item, struct)
            )
        return [fields]


class PreferencesFields(SphinxDirective):
    """Every field of the add-on's preferences."""

    def run(self) -> list[nodes.Node]:
        struct = preferences_rna()
        identifiers = [
            prop.identifier for prop in struct.properties if prop.identifier not in ("rna_type", "bl_idname")
        ]
        problems = [
            problem for identifier in identifiers for problem in property_problems(struct, identifier)
        ]
        _report(problems, self.get_location())
        fields = nodes.definition_list()
        for identifier in identifiers:
            fields += property_item(struct, identifier)
        return [] if problems else [fields]


class TurkishLabels(SphinxDirective):
    """Every short text of the translation table (labels, not tooltips), English beside Turkish."""

    def run(self) -> list[nodes.Node]:
        from turkish_lipsync.blender.translations import TURKISH

        self.env.note_dependency(str(DEPENDENCIES[-1]))
        labels = [
            (english, turkish) for english, turkish in TURKISH.items() if len(english.split()) <= LABEL_WORDS
        ]
        table = nodes.table()
        group = nodes.tgroup(cols=2)
        table += group
        group += nodes.colspec(colwidth=50)
        group += nodes.colspec(colwidth=50)
        head = nodes.thead()
        body = nodes.tbody()
        for cells, part in ((("English", "Türkçe"), head), *((label, body) for label in sorted(labels))):
            row = nodes.row()
            for text in cells:
                entry = nodes.entry()
                entry += nodes.paragraph(text=text)
                row += entry
            part += row
        group += head
        group += body
        return [table]


def check_every_section_described(app, env) -> None:
    described = env.domaindata.get("panel_reference", {}).get("sections", {})
    sections = dict.fromkeys(
        item.section for item in drawn_by_panel(PANEL_SOURCE.read_text(encoding="utf-8"))
    )
    for section in sections:
        if section not in described:
            logger.warning(
                "panel reference: the panel's section %r is in no {panel-fields} directive of the manual",
                section,
            )


def forget_document(_app, env, docname: str) -> None:
    sections = env.domaindata.get("panel_reference", {}).get("sections", {})
    for section in [section for section, document in sections.items() if document == docname]:
        del sections[section]


def unregister(_app, _exception) -> None:
    if registered.cache_info().currsize:
        from turkish_lipsync import blender

        blender.unregister()
        registered.cache_clear()


def setup(app) -> dict:
    app.add_directive("panel-fields", PanelFields)
    app.add_directive("preferences-fields", PreferencesFields)
    app.add_directive("turkish-labels", TurkishLabels)
    app.connect("env-purge-doc", forget_document)
    app.connect("env-check-consistency", check_every_section_described)
    app.connect("build-finished", unregister)
    return {"parallel_read_safe": False, "parallel_write_safe": True}
