"""The panel reference in the manual, generated from the add-on itself so that it cannot fall out of date.

    ```{panel-fields} Head
    ```
    ```{preferences-fields}
    ```
    ```{turkish-labels}
    ```

The facts come from docs/_ext/panel_fields.py (what panel.py draws, read with ast; what the registered RNA
says of each field). The build fails (a warning, an error under -W) when a drawn property or operator is
missing from the RNA or lacks a description, when an enum item lacks one, when a name has no Turkish
translation, when the panel draws a property of another data block than the add-on's settings, and when a
section of the panel is in no `panel-fields` directive of the manual.
"""

from __future__ import annotations

from docutils import nodes
from panel_fields import (
    Drawn,
    condition_text,
    dependencies,
    drawn_by_the_panels,
    operator_rna,
    path_of,
    preferences_rna,
    property_problems,
    reference_problems,
    settings_rna,
    struct_of,
    turkish,
)
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

logger = logging.getLogger(__name__)
LABEL_WORDS = 4  # a text of the translation table this short is a label; longer ones are tooltips


def _type_text(prop, browsed: bool = False) -> str:
    """browsed: a button beside the field browses for its file (an operator with a file filter)."""
    if prop.type == "ENUM" and not prop.default:  # items the add-on lists as the panel is drawn
        return "one of the items the panel lists"
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
        kinds = {"FILE_PATH": "a file", "DIR_PATH": "a folder"}
        kind = kinds.get(prop.subtype, "a file (its button shows only what it reads)" if browsed else "text")
        shown = f"`{default}`" if default else "empty"
        return f"{kind}; default {shown}" + (
            " (`//` is the folder of the saved .blend)" if "//" in default else ""
        )
    if prop.type == "POINTER":
        kind = {"Object": "an object", "Text": "a Text data block (Text Editor)", "Action": "an action"}.get(
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


def property_item(
    struct, identifier: str, drawn: Drawn | None = None, settings=None, browsed: bool = False
) -> nodes.definition_list_item:
    """One field: `struct` holds it, `settings` (the add-on's settings, when they are not the struct) say
    how a script reaches it and what its conditions name; browsed: a button beside it browses for it."""
    settings = settings or struct
    prop = struct.properties[identifier]
    path = path_of(drawn) if drawn is not None else identifier
    item = nodes.definition_list_item(ids=[f"field-{path.replace('_', '-').replace('[i].', '-')}"])
    item += _term(prop.name, path)
    definition = nodes.definition()
    definition += _paragraph(prop.description)
    details = [_type_text(prop, browsed)]
    if drawn is not None and drawn.shown_when:
        details.append("shown when " + " and ".join(condition_text(c, settings) for c in drawn.shown_when))
    if drawn is not None and drawn.active_when:
        details.append("active when " + " and ".join(condition_text(c, settings) for c in drawn.active_when))
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


def _browses(drawn: Drawn | None) -> bool:
    """Whether this drawn item is a button that opens a file browser with a filter."""
    if drawn is None or drawn.kind != "operator":
        return False
    rna = operator_rna(drawn.name)
    return rna is not None and "filter_glob" in rna.properties


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
        drawn = [item for item in drawn_by_the_panels() if item.section == section]
        for source in dependencies():
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
        for item, after in zip(drawn, [*drawn[1:], None], strict=True):
            if (item.kind, item.name) in seen:
                continue  # drawn twice (in both branches of a condition): described once
            seen.add((item.kind, item.name))
            fields += (
                property_item(struct_of(item.struct, struct), item.name, item, struct, _browses(after))
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

        self.env.note_dependency(str(dependencies()[-1]))
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
    sections = dict.fromkeys(item.section for item in drawn_by_the_panels())
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


def register_addon(_app) -> None:
    """The add-on registered in the build's process, as Blender registers it, for its RNA."""
    from turkish_lipsync import blender

    blender.register()


def unregister_addon(_app, _exception) -> None:
    from turkish_lipsync import blender

    blender.unregister()


def setup(app) -> dict:
    app.add_directive("panel-fields", PanelFields)
    app.add_directive("preferences-fields", PreferencesFields)
    app.add_directive("turkish-labels", TurkishLabels)
    app.connect("env-purge-doc", forget_document)
    app.connect("env-check-consistency", check_every_section_described)
    app.connect("builder-inited", register_addon)
    app.connect("build-finished", unregister_addon)
    return {"parallel_read_safe": False, "parallel_write_safe": True}
