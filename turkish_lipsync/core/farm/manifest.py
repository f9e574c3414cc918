"""An episode: the scene files of one folder and the episode.toml beside them, read and checked.

A scene is one file: a script with speakers (`AYŞE: Merhaba!` lines, or JSML VOICE elements) or a plain
JSML text one head speaks, named by its file name without the extension. episode.toml says how the episode
is rendered ([episode]), what every scene is made with ([defaults]) and what one scene changes
([scene."01-kafe"]); a scene's settings become the scripts/render.py arguments of its build. Every error
names the file and line, all of them at once.
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from ..base.errors import LipSyncError, MarkupError
from ..base.files import read_user_text
from ..batch.arguments import DEFAULT_FPS, DEFAULT_RESOLUTION, resolution
from ..pipeline import (
    AMOUNT_RANGE,
    INTERPOLATION_CHOICES,
    MOTION_CHOICES,
    RATE_RANGE,
    TIMING_CHOICES,
    identifiers,
)
from ..scene.cast import known_variants
from ..text.script import Script, read_script, speaker_key
from ..text.utterance import build_utterance

MANIFEST_NAME = "episode.toml"
SCENE_SUFFIXES = (".txt", ".jsml")
HEAD_SUFFIXES = (".obj", ".glb", ".gltf", ".fbx")
ENGINES = ("CYCLES", "EEVEE", "WORKBENCH")
MAX_CHUNK = 150  # Deadline Cloud's largest chunk of frames
SCENE_NAME = re.compile(r"^[\w][\w .-]{0,47}$")  # a step's name is the scene's and the step's, 64 at most


Problem = str | None  # what is wrong with a value (the troubleshooting page lists these), or None


class EpisodeError(LipSyncError):
    """An episode that cannot become a job: every problem found, each as FILE:LINE: what is wrong."""

    def __init__(self, problems: list[str]) -> None:
        self.problems = tuple(problems)
        super().__init__("\n".join(problems))


@dataclass(frozen=True)
class RenderSettings:
    """How every scene of the episode is rendered ([episode] of episode.toml)."""

    fps: float = DEFAULT_FPS
    resolution: tuple[int, int] = DEFAULT_RESOLUTION
    engine: str = "CYCLES"
    samples: int = 16
    chunk_size: int = 25


@dataclass(frozen=True)
class Scene:
    name: str
    file: Path
    script: Script | None  # None: a plain text one head speaks
    arguments: tuple[str, ...]  # scripts/render.py's arguments of its build, every path absolute
    inputs: tuple[Path, ...]  # every file it is made from (the build is done again when one changes)
    where: str  # where its settings are written, for errors found later ("episode.toml:12")


@dataclass(frozen=True)
class Episode:
    folder: Path
    title: str
    manifest: Path | None
    render: RenderSettings
    scenes: tuple[Scene, ...]

    def scene(self, name: str) -> Scene:
        for scene in self.scenes:
            if scene.name == name:
                return scene
        raise EpisodeError(
            [f"{self.folder}: no scene {name!r}; its scenes are {', '.join(s.name for s in self.scenes)}"]
        )


# ---------------------------------------------------------------- where a key is written


_BARE = r"[A-Za-z0-9_-]+"
_QUOTED = r'"(?:[^"\\]|\\.)*"|\'[^\']*\''
_KEY_PART = rf"(?:{_BARE}|{_QUOTED})"
_DOTTED = rf"{_KEY_PART}(?:\s*\.\s*{_KEY_PART})*"
_HEADER = re.compile(rf"^\s*\[\s*({_DOTTED})\s*\]")
_ASSIGNMENT = re.compile(rf"({_DOTTED})\s*=")


def _key_path(dotted: str) -> tuple[str, ...]:
    return tuple(
        part.strip()[1:-1] if part.strip()[:1] in "\"'" else part.strip()
        for part in re.findall(rf"{_KEY_PART}", dotted)
    )


def key_lines(text: str) -> dict[tuple[str, ...], int]:
    """The line each table and key is written on (1-based): a table's header, a key's assignment, and the
    keys of an inline table on its line. Enough of TOML to point at what the manifest holds."""
    lines: dict[tuple[str, ...], int] = {}
    table: tuple[str, ...] = ()
    for number, line in enumerate(text.splitlines(), start=1):
        header = _HEADER.match(line)
        if header:
            table = _key_path(header.group(1))
            lines.setdefault(table, number)
            continue
        assignment = re.match(rf"\s*({_DOTTED})\s*=(.*)$", line)
        if not assignment:
            continue
        key = table + _key_path(assignment.group(1))
        for depth in range(len(table) + 1, len(key) + 1):  # a dotted key defines its tables too
            lines.setdefault(key[:depth], number)
        for inner in _ASSIGNMENT.finditer(assignment.group(2)):
            lines.setdefault(key + _key_path(inner.group(1)), number)
    return lines


@dataclass
class _Manifest:
    """The parsed manifest and the lines of its keys; problems are gathered, not raised one by one."""

    path: Path | None
    data: dict
    lines: dict[tuple[str, ...], int]
    problems: list[str] = field(default_factory=list)

    def where(self, *key: str) -> str:
        if self.path is None:
            return "(no episode.toml)"
        for depth in range(len(key), 0, -1):
            if key[:depth] in self.lines:
                return f"{self.path}:{self.lines[key[:depth]]}"
        return f"{self.path}:1"

    def problem(self, key: tuple[str, ...], message: str) -> None:
        """A problem of the manifest's key (its line, or its table's)."""
        self.problems.append(f"{self.where(*key)}: {message}")

    def problem_at(self, place: Path | str, message: str) -> None:
        """A problem of another file (a scene's script, the folder)."""
        self.problems.append(f"{place}: {message}")


def _read_manifest(path: Path | None) -> _Manifest:
    if path is None:
        return _Manifest(None, {}, {})
    text = read_user_text(path, "episode manifest")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        found = re.search(r"\(at line (\d+), column (\d+)\)", str(error))
        reason = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(error))
        place = f"{path}:{found.group(1)}:{found.group(2)}" if found else str(path)
        line = text.splitlines()[int(found.group(1)) - 1] if found else ""
        if re.match(r"\s*[^\s\"'=]*[^\x00-\x7f]", line):
            reason += ' (a name with Turkish letters is written in quotes: "Ayşe" = ...)'
        raise EpisodeError([f"{place}: not valid TOML: {reason}"]) from None
    return _Manifest(path, data, key_lines(text))


# ---------------------------------------------------------------- the settings a scene may have


def _choice(choices):
    names = identifiers(choices)

    def check(value) -> Problem:
        return None if value in names else f"must be one of {', '.join(names)}"

    return check


def _number(low: float, high: float):
    def check(value) -> Problem:
        if isinstance(value, bool) or not isinstance(value, int | float) or not low <= value <= high:
            return f"must be a number from {low:g} to {high:g}"
        return None

    return check


def _flag(value) -> Problem:
    return None if isinstance(value, bool) else "must be true or false"


def _seed(value) -> Problem:
    good = isinstance(value, int) and not isinstance(value, bool) and value >= 0
    return None if good else "must be a whole number of at least 0"


def _voice(value) -> Problem:
    variant, *numbers = str(value).split(":")
    try:
        [float(number) for number in numbers]
    except ValueError:
        numbers = ["", "", ""]
    if variant.lower() not in (*known_variants(), "female", "male") or len(numbers) > 2:
        return f"must be one of {', '.join(known_variants())}, female or male, optionally :PITCH:RATE"
    return None


# setting -> (render.py flag, what its value is): "file", "folder", "head" are paths beside the manifest
PATH_SETTINGS = {
    "head": ("--head", "head"),
    "audio": ("--audio", "file"),
    "line_audio": ("--line-audio", "folder"),
    "cues": ("--cues", "file"),
    "mapping": ("--mapping", "file"),
}
# setting -> (render.py flag, the check of each speaker's value or None for a path)
SPEAKER_SETTINGS = {
    "cast": ("--cast", None),
    "voice": ("--voice", _voice),
    "speaker_emotion": ("--speaker-emotion", _number(0.0, 1.0)),
    "speaker_audio": ("--speaker-audio", None),
}
VALUE_SETTINGS = {
    "timing": _choice(TIMING_CHOICES),
    "motion": _choice(MOTION_CHOICES),
    "interpolation": _choice(INTERPOLATION_CHOICES),
    "rate": _number(*RATE_RANGE),
    "emotion_strength": _number(0.0, 1.0),
    "seed": _seed,
    **{layer: _flag for layer in ("gaze", "blinks", "head_motion", "expression")},
    **{amount: _number(*AMOUNT_RANGE) for amount in ("gaze_amount", "blink_amount", "head_amount")},
    "expression_amount": _number(*AMOUNT_RANGE),
}
ONE_HEAD_ONLY = {"head"}
SPEAKERS_ONLY = set(SPEAKER_SETTINGS) | {"line_audio"}
KNOWN = sorted(set(PATH_SETTINGS) | set(SPEAKER_SETTINGS) | set(VALUE_SETTINGS))


def _path_problem(folder: Path, value, kind: str) -> Problem:
    if not isinstance(value, str) or not value.strip():
        return "must be a path (in quotes), relative to episode.toml's folder"
    path = folder / value
    if kind == "folder":
        return None if path.is_dir() else f"{value}: no such folder beside episode.toml"
    if not path.is_file():
        return f"{value}: no such file beside episode.toml"
    if kind == "head" and path.suffix.lower() not in HEAD_SUFFIXES:
        return f"{value}: a head is a {', '.join(HEAD_SUFFIXES)} file (a scene is built in a new file)"
    if kind == "cast" and path.suffix.lower() not in (*HEAD_SUFFIXES, ".blend"):
        return f"{value}: a speaker's head is a {', '.join(HEAD_SUFFIXES)} or .blend file"
    return None


def _check_setting(manifest: _Manifest, folder: Path, key: tuple[str, ...], value) -> bool:
    """One setting of [defaults] or of a scene's table checked; False (and a problem noted) when wrong."""
    name = key[-1]
    problem = None
    if name in PATH_SETTINGS:
        problem = _path_problem(folder, value, PATH_SETTINGS[name][1])
    elif name in SPEAKER_SETTINGS:
        if not isinstance(value, dict):
            problem = f"must be a table of speakers, e.g. {name}.Ali = ..."
        for speaker, chosen in value.items() if isinstance(value, dict) else ():
            check = SPEAKER_SETTINGS[name][1]
            if check is None and not (name == "cast" and chosen == "default"):
                kind = "cast" if name == "cast" else "file"
                speaker_problem = _path_problem(folder, chosen, kind)
            else:
                speaker_problem = check(chosen) if check is not None else None
            if speaker_problem:
                manifest.problem((*key, speaker), f"{name}.{speaker} {speaker_problem}")
    elif name in VALUE_SETTINGS:
        problem = VALUE_SETTINGS[name](value)
    else:
        problem = f"is not a setting of a scene; the settings are {', '.join(KNOWN)}"
    if problem:
        manifest.problem(key, f"{name} {problem}")
    return problem is None


# ---------------------------------------------------------------- the episode


def _render_settings(manifest: _Manifest) -> RenderSettings:
    def engine(value) -> Problem:
        return None if str(value).upper() in ENGINES else f"must be one of {', '.join(ENGINES)}"

    def whole(low: int, high: int):
        in_range = _number(low, high)

        def check(value) -> Problem:
            return in_range(value) or (None if isinstance(value, int) else "must be a whole number")

        return check

    section = manifest.data.get("episode", {})
    found = {}
    checks = {
        "fps": (_number(1, 240), float),
        "engine": (engine, lambda value: str(value).upper()),
        "samples": (whole(1, 4096), int),
        "chunk_size": (whole(1, MAX_CHUNK), int),
    }
    for name, (check, kind) in checks.items():
        if name in section:
            problem = check(section[name])
            if problem:
                manifest.problem(("episode", name), f"{name} {problem}")
            else:
                found[name] = kind(section[name])
    if "resolution" in section:
        try:
            found["resolution"] = resolution(str(section["resolution"]))
        except Exception as error:  # argparse.ArgumentTypeError: the message says what is wrong
            manifest.problem(("episode", "resolution"), str(error))
    unknown = set(section) - {*checks, "resolution", "title", "scenes"}
    for name in sorted(unknown):
        manifest.problem(
            ("episode", name),
            f"{name} is not a setting of [episode]; they are title, scenes, fps, resolution, engine, "
            "samples, chunk_size",
        )
    return RenderSettings(**found)


def _scene_files(manifest: _Manifest, folder: Path, given: list[Path]) -> list[Path]:
    listed = manifest.data.get("episode", {}).get("scenes")
    if given:
        files = given
    elif listed is not None:
        if not isinstance(listed, list) or not all(isinstance(item, str) for item in listed):
            manifest.problem(("episode", "scenes"), "scenes must be a list of file names, in quotes")
            return []
        files = [folder / item for item in listed]
        for item, path in zip(listed, files, strict=True):
            if not path.is_file():
                manifest.problem(("episode", "scenes"), f"scenes: {item}: no such file beside episode.toml")
    else:
        files = sorted(p for p in folder.iterdir() if p.is_file() and p.suffix.lower() in SCENE_SUFFIXES)
    names: dict[str, Path] = {}
    for path in files:
        if path.suffix.lower() not in SCENE_SUFFIXES:
            manifest.problem(("episode", "scenes"), f"{path.name}: a scene is a .txt or .jsml file")
        elif not SCENE_NAME.match(path.stem):
            manifest.problem(
                ("episode", "scenes"),
                f"{path.name}: a scene's name (its file name without the extension) is letters, digits, "
                "spaces, '.', '_' and '-', 48 at most; rename the file",
            )
        elif path.stem in names:
            manifest.problem(
                ("episode", "scenes"), f"{names[path.stem].name} and {path.name} are both scene {path.stem}"
            )
        names[path.stem] = path
    if not files and not manifest.problems:
        manifest.problem_at(folder, "no scenes (.txt or .jsml files) in the episode")
    return [path for path in files if path.is_file()]


def read_episode(paths: list[Path], only: str | None = None) -> Episode:
    """The episode a folder, its episode.toml, or a list of its scene files makes; EpisodeError lists every
    problem (a manifest line, a script's line and column). With `only`, that scene alone is read (a farm's
    build of one scene is not stopped by another scene's file)."""
    folder, manifest_path, given = _locate(paths)
    manifest = _read_manifest(manifest_path)
    render = _render_settings(manifest)
    defaults = manifest.data.get("defaults", {})
    for key, value in defaults.items():
        _check_setting(manifest, folder, ("defaults", key), value)
    files = _scene_files(manifest, folder, given)
    tables = manifest.data.get("scene", {})
    for name in tables:
        if name not in {path.stem for path in files}:
            manifest.problem(
                ("scene", name),
                f'[scene."{name}"] names no scene of the episode; its scenes are '
                f"{', '.join(path.stem for path in files)}",
            )
    names = [path.stem for path in files]
    if only is not None and only not in names:
        manifest.problem_at(folder, f"no scene {only!r}; its scenes are {', '.join(names)}")
    scenes = []
    for path in files if only is None else [path for path in files if path.stem == only]:
        scene = _scene(manifest, folder, path, render, defaults, tables.get(path.stem, {}))
        if scene is not None:
            scenes.append(scene)
    if manifest.problems:
        raise EpisodeError(sorted(manifest.problems, key=_place))
    title = str(manifest.data.get("episode", {}).get("title", folder.name))
    return Episode(folder, title, manifest_path, render, tuple(scenes))


def _place(problem: str) -> tuple[str, int]:
    """A problem's file and line, to list them in the order they are written."""
    found = re.match(r"(.*?):(\d+)", problem)
    return (found.group(1), int(found.group(2))) if found else (problem, 0)


def _locate(paths: list[Path]) -> tuple[Path, Path | None, list[Path]]:
    """(the episode's folder, its manifest if any, the scene files given one by one)."""
    if not paths:
        raise EpisodeError(["give the episode: its folder, its episode.toml, or its scene files"])
    missing = [str(path) for path in paths if not path.exists()]
    if missing:
        raise EpisodeError([f"{path}: no such file or folder" for path in missing])
    if len(paths) == 1 and paths[0].is_dir():
        folder = paths[0].resolve()
        manifest = folder / MANIFEST_NAME
        return folder, manifest if manifest.is_file() else None, []
    if len(paths) == 1 and paths[0].suffix.lower() == ".toml":
        return paths[0].resolve().parent, paths[0].resolve(), []
    else:
        folders = {path.resolve().parent for path in paths}
        if len(folders) > 1 or any(path.is_dir() for path in paths):
            raise EpisodeError(["the scene files of an episode are in one folder, beside its episode.toml"])
        folder, given = folders.pop(), [path.resolve() for path in paths]
    manifest = folder / MANIFEST_NAME
    return folder, manifest if manifest.is_file() else None, given


def _scene(manifest, folder, path, render, defaults: dict, own: dict) -> Scene | None:
    """One scene: its file read (a script's errors with line and column), its settings merged and checked."""
    key = ("scene", path.stem)
    try:
        source = read_user_text(path, "scene's script")
        script = read_script(source) if source.strip() else None
        if script is None and source.strip():
            build_utterance(source)  # a plain text's markup checked now, not on the farm
    except MarkupError as error:
        manifest.problem_at(f"{path}:{error.line}:{error.column}", error.message)
        return None
    except LipSyncError as error:
        manifest.problem_at(path, str(error))
        return None
    if not source.strip():
        manifest.problem_at(path, "the scene's file is empty")
        return None
    good = all(_check_setting(manifest, folder, (*key, name), value) for name, value in own.items())
    wrong = ONE_HEAD_ONLY if script is not None else SPEAKERS_ONLY
    for name in sorted(wrong & set(own)):
        kind = "a script with speakers: give their heads with cast" if script else "one head's text"
        manifest.problem((*key, name), f"{name} does not fit scene {path.stem}: it is {kind}")
        good = False
    if script is not None:
        speakers = {speaker.key for speaker in script.speakers}
        for name in SPEAKER_SETTINGS:
            for speaker in own.get(name, {}) if isinstance(own.get(name), dict) else ():
                if speaker_key(speaker) not in speakers:
                    manifest.problem(
                        (*key, name, speaker),
                        f"{name}.{speaker}: {speaker} does not speak in {path.name}; its speakers are "
                        f"{', '.join(s.name for s in script.speakers)}",
                    )
                    good = False
    if not good:
        return None
    settings = {name: value for name, value in defaults.items() if name not in wrong}
    for name, value in own.items():
        settings[name] = {**settings.get(name, {}), **value} if name in SPEAKER_SETTINGS else value
    arguments, inputs = _render_arguments(folder, path, script, settings, render)
    where = manifest.where(*key) if key in manifest.lines else str(path)
    return Scene(path.stem, path, script, arguments, inputs, where)


def _render_arguments(folder, path, script, settings, render) -> tuple[tuple[str, ...], tuple[Path, ...]]:
    """scripts/render.py's arguments of the scene's build and the files it reads."""
    width, height = render.resolution
    arguments = ["--jsml", str(path), "--fps", f"{render.fps:g}", "--resolution", f"{width}x{height}"]
    inputs = [path]
    speakers = {speaker.key for speaker in script.speakers} if script else set()
    for name, value in settings.items():
        if name in PATH_SETTINGS:
            found = (folder / value).resolve()
            arguments += [PATH_SETTINGS[name][0], str(found)]
            inputs += sorted(p for p in found.iterdir() if p.is_file()) if found.is_dir() else [found]
        elif name in SPEAKER_SETTINGS:
            for speaker, chosen in value.items():
                if speaker_key(speaker) not in speakers:
                    continue  # [defaults] may cast the whole series; a scene's speakers take theirs
                if SPEAKER_SETTINGS[name][1] is None and chosen != "default":
                    chosen = str((folder / chosen).resolve())
                    inputs.append(Path(chosen))
                arguments += [SPEAKER_SETTINGS[name][0], f"{speaker}={chosen}"]
        elif isinstance(value, bool):
            arguments.append(f"--{'' if value else 'no-'}{name.replace('_', '-')}")
        else:
            arguments += [f"--{name.replace('_', '-')}", str(value)]
    return tuple(arguments), tuple(dict.fromkeys(inputs))
