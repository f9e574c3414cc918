"""What the panel draws and what the add-on's RNA says of it: the facts the panel reference is made of.

What the panel draws is read from the panels of turkish_lipsync/blender (panel.py, and any other module with
a bpy.types.Panel: their draw methods, read with ast: the
sections by their headings, every `.prop(settings, ...)` and `.operator(...)` in order, with the conditions
under which it is shown or active); what each field is comes from the registered RNA of the add-on (bpy,
the add-on registered as Blender registers it, no stand-ins), its Turkish name from
turkish_lipsync/blender/translations.py. `reference_problems` says what the reference cannot describe:
docs/_ext/panel_reference.py turns that into the build's warnings, tests/blender/test_panel_fields.py
checks that it finds them. No Sphinx here, so the tests run on every Blender.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BLENDER_LAYER = ROOT / "turkish_lipsync" / "blender"
SETTINGS = "settings"  # the name panel.py gives the add-on's settings (context.scene.turkish_lipsync)
# Names panel.py gives an item of a collection of the settings, the one chosen in its list
# (member = settings.cast[settings.cast_index]): the collection each names.
COLLECTION_ITEMS = {"member": "cast"}


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
    file_name: str = "panel.py"


@dataclass
class _Walk:
    methods: dict[str, ast.FunctionDef]
    file_name: str
    drawn: list[Drawn] = field(default_factory=list)
    section: str = ""


def panel_sources(folder: Path = BLENDER_LAYER) -> list[Path]:
    """The modules of the Blender layer that define a panel (a class deriving from bpy.types.Panel)."""
    return [path for path in sorted(folder.glob("*.py")) if _panel_classes(path.read_text(encoding="utf-8"))]


def _panel_classes(source: str) -> list[ast.ClassDef]:
    return [
        node
        for node in ast.parse(source).body
        if isinstance(node, ast.ClassDef) and any(ast.unparse(base).endswith("Panel") for base in node.bases)
    ]


def drawn_by_panel(source: str, file_name: str = "panel.py") -> list[Drawn]:
    """Every property and operator the panel classes of this source draw, in the order a user sees them."""
    drawn: list[Drawn] = []
    for cls in _panel_classes(source):
        methods = {node.name: node for node in cls.body if isinstance(node, ast.FunctionDef)}
        if "draw" not in methods:
            continue
        walk = _Walk(methods, file_name, section=_class_label(cls))
        _walk_body(walk, methods["draw"].body, (), {}, {})
        drawn += walk.drawn
    return drawn


def drawn_by_the_panels(folder: Path = BLENDER_LAYER) -> list[Drawn]:
    """What every panel of the Blender layer draws, module by module."""
    return [
        item
        for path in panel_sources(folder)
        for item in drawn_by_panel(path.read_text(encoding="utf-8"), path.name)
    ]


def dependencies(folder: Path = BLENDER_LAYER) -> list[Path]:
    """What the reference is made of: the panels, the settings and the translations."""
    return [*panel_sources(folder), folder / "properties.py", folder / "translations.py"]


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
                Drawn(
                    "operator",
                    arguments[0].value,
                    walk.section,
                    shown,
                    conditions,
                    line=call.lineno,
                    file_name=walk.file_name,
                )
            )
        elif function.attr == "prop" and len(arguments) > 1 and isinstance(arguments[1], ast.Constant):
            struct = arguments[0].id if isinstance(arguments[0], ast.Name) else ast.unparse(arguments[0])
            walk.drawn.append(
                Drawn(
                    "property",
                    arguments[1].value,
                    walk.section,
                    shown,
                    conditions,
                    struct,
                    line=call.lineno,
                    file_name=walk.file_name,
                )
            )


def settings_rna():
    """The RNA of the add-on's settings (the add-on must be registered: blender.register())."""
    import bpy

    return bpy.types.Scene.bl_rna.properties["turkish_lipsync"].fixed_type


def preferences_rna():
    from turkish_lipsync.blender import preferences

    return preferences.TurkishLipSyncPreferences.bl_rna


def operator_rna(idname: str):
    """The RNA of a registered operator, or None."""
    import bpy

    group, _, name = idname.partition(".")
    operator = getattr(getattr(bpy.ops, group, None), name, None)
    try:
        return operator.get_rna_type() if operator is not None else None
    except KeyError:  # bpy.ops resolves any name; an unregistered one has no RNA
        return None


def struct_of(variable: str, settings):
    """The RNA struct whose properties the panel draws through this variable, or None when unknown."""
    if variable == SETTINGS:
        return settings
    collection = COLLECTION_ITEMS.get(variable)
    return settings.properties[collection].fixed_type if collection else None


def path_of(item: Drawn) -> str:
    """How a script reaches the drawn property from the settings: "head", "cast[i].head"."""
    collection = COLLECTION_ITEMS.get(item.struct)
    return f"{collection}[i].{item.name}" if collection else item.name


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
        where = f"{item.file_name}:{item.line}"
        if item.kind == "operator":
            problems += [f"{where}: {problem}" for problem in operator_problems(item.name)]
        elif struct_of(item.struct, struct) is None:
            problems.append(
                f"{where}: draws {item.struct}.{item.name}, a property of another data block than the "
                "add-on's settings, which the reference cannot describe"
            )
        else:
            owner = struct_of(item.struct, struct)
            problems += [f"{where}: {problem}" for problem in property_problems(owner, item.name)]
    return problems


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
    if isinstance(test, ast.Attribute) and struct_of(getattr(test.value, "id", ""), struct) is not None:
        name = struct_of(test.value.id, struct).properties[test.attr].name
        return f"{name} is {'off' if negated else 'on'}"
    if (
        isinstance(test, ast.Compare)
        and isinstance(test.left, ast.Attribute)
        and struct_of(getattr(test.left.value, "id", ""), struct) is not None
        and len(test.ops) == 1
    ):
        owner = struct_of(test.left.value.id, struct)
        identifier = test.left.attr
        name = owner.properties[identifier].name
        values = ast.literal_eval(test.comparators[0])
        values = values if isinstance(values, tuple) else (values,)
        words = " or ".join(_value_name(owner, identifier, value) for value in values)
        positive = isinstance(test.ops[0], (ast.Eq, ast.In))
        return f"{name} is {'' if positive != negated else 'not '}{words}"
    chosen = _chosen_row(test)
    if chosen is not None and not negated:
        return f"a row of the {struct.properties[chosen].name} list is chosen"
    return f"`{ast.unparse(expression)}`"


def _chosen_row(test: ast.expr) -> str | None:
    """The collection of `0 <= settings.X_index < len(settings.X)` (a row of its list chosen), else None."""
    if not (isinstance(test, ast.Compare) and len(test.ops) == 2):
        return None
    index, length = test.comparators
    if not (isinstance(index, ast.Attribute) and index.attr.endswith("_index")):
        return None
    collection = index.attr.removesuffix("_index")
    if ast.unparse(length) != f"len({SETTINGS}.{collection})":
        return None
    return collection
