"""The plain functions behind the operators and the batch script: build keys, generate, render.

Everything that can fail (markup, speech engine, data tables) runs before Blender data is touched, so an
error leaves the file as it was. Functions take and return names, never keep Blender references.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import bpy
import numpy as np

from ..core.base.errors import HeadError, TextError
from ..core.base.files import read_user_text
from ..core.base.model import (
    VISEME_KEY_PREFIX,
    viseme_key_name,
)
from ..core.interchange.animation_record import AnimationRecord, record_from_json
from . import character, compat, face_rig, heads, keyframes, linking, living, render, sequencer, shapekeys
from .living_rig import find_rig
from .owned_keys import owned_keys
from .scene_record import conversation_record
from .shapekeys import BuildReport

Progress = Callable[[float, str], None]


def _no_progress(_fraction: float, _message: str) -> None:
    pass


@dataclass(frozen=True)
class RenderResult:
    path: str
    engine: str
    frame_count: int
    seconds: float
    camera_added: bool
    lights_added: bool


# ---------------------------------------------------------------- heads


def head_objects(head: bpy.types.Object) -> list[bpy.types.Object]:
    """The head and the meshes that follow it (teeth, tongue, eyes)."""
    return [head, *heads.find_head_parts(head)]


def build_keys(
    context: bpy.types.Context,
    head: bpy.types.Object | None,
    *,
    arkit_keys: bool = False,
    progress=None,
    source: str = "auto",
    obj_folder: str | None = None,
    mapping_file: str | None = None,
    empowered: bool = False,
    rho: float = 3.0,
) -> BuildReport:
    """Build (or rebuild) the TR_* shape keys on head, creating the reference head when head is None.

    source, obj_folder, mapping_file, empowered and rho go to shapekeys.build_shape_keys. A reference head
    created here is removed again when the build fails, so a failure leaves the file as it was. Returns the
    build's report (the head's name, where the keys came from, warnings for the user).
    """
    progress = progress or _no_progress
    created: list[bpy.types.Object] = []
    if head is not None and face_rig.is_linked(head):
        raise HeadError(
            f"{head.name!r} is linked from {face_rig.library_path(head)}: build its shape keys there, in the "
            "character's own file (then Make Keys Linkable), save it, and reload the library here."
        )
    linkable = head is not None and linking.is_linkable(head)
    if head is None:
        progress(0.05, "Creating the reference head")
        parts = heads.create_reference_head(context)
        head, created = parts["head"], list(parts.values())
    progress(0.2, f"Building shape keys on {head.name}")
    try:
        report = shapekeys.build_shape_keys(
            head,
            source=source,
            obj_folder=obj_folder or None,
            mapping_file=mapping_file or None,
            empowered=empowered,
            rho=rho,
            arkit_keys=arkit_keys,
        )
    except Exception:
        for obj in created:
            mesh = obj.data
            bpy.data.objects.remove(obj, do_unlink=True)
            if mesh is not None and mesh.users == 0:
                bpy.data.meshes.remove(mesh)
        raise
    if linkable:  # keys built anew are driven as the old ones were
        linking.make_keys_linkable(head, heads.find_head_parts(head))
    progress(1.0, "Shape keys built")
    return report


def has_lipsync_keys(head: bpy.types.Object) -> bool:
    """Whether a build of ours left its visemes on the head (by our mark: a user's TR_* keys do not count)."""
    return any(name.startswith(VISEME_KEY_PREFIX) for name in owned_keys(head))


# ---------------------------------------------------------------- text


def read_source(text_name: str = "", file_path: str = "", allow_empty: bool = False) -> str:
    """The JSML source: a Blender Text datablock, else a file; empty only where allowed (a recording's
    words are recognised)."""
    if text_name:
        text = bpy.data.texts.get(text_name)
        if text is None:
            raise TextError(f"There is no Text named {text_name!r}: choose a Text in the Lip Sync panel.")
        source = text.as_string()
    elif file_path:
        source = read_user_text(Path(bpy.path.abspath(file_path)), "JSML file", TextError)
    else:
        raise TextError("No text to speak: choose a Text datablock or a JSML file in the Lip Sync panel.")
    if not source.strip() and not allow_empty:
        raise TextError("The text is empty: write some Turkish text (plain or JSML) to speak.")
    return source


def own_keys_held(head: bpy.types.Object) -> list[tuple[str, float]]:
    """The head's own shape keys (not ours) held at a value, not animated: the face speaks on top of them."""
    key = getattr(head.data, "shape_keys", None)
    if key is None:
        return []
    ours = set(owned_keys(head).values())
    action = key.animation_data.action if key.animation_data else None
    animated = {fc.data_path for fc in compat.all_action_fcurves(action)} if action is not None else set()
    return [
        (block.name, block.value)
        for block in key.key_blocks
        if block != key.reference_key
        and block.name not in ours
        and abs(block.value) > 1e-4
        and not block.mute
        and keyframes.curve_data_path(block.name) not in animated
    ]


def own_keys_held_warning(head: bpy.types.Object) -> tuple[str, ...]:
    held = own_keys_held(head)
    if not held:
        return ()
    shown = ", ".join(f"{name} {value:.2f}" for name, value in held[:4])
    more = f" and {len(held) - 4} more" if len(held) > 4 else ""
    return (
        f"{len(held)} of {head.name!r}'s own shape keys hold a value ({shown}{more}): the speech plays on "
        "top of them, which can deform the face. Set them to 0 (Shape Keys > Clear Shape Key Values, or "
        "render.py --own-keys-at-rest) unless you mean them.",
    )


def put_own_keys_at_rest(head: bpy.types.Object) -> int:
    """The head's own held keys set to 0 (asked for: render.py --own-keys-at-rest); returns how many."""
    held = own_keys_held(head)
    blocks = head.data.shape_keys.key_blocks if held else {}
    for name, _value in held:
        blocks[name].value = 0.0
    return len(held)


RECORD_PROPERTY = "tr_lipsync_animation"  # on the action of a head's keys: what Generate made


def animation_record(head: bpy.types.Object) -> AnimationRecord | None:
    """What Generate made on this head, or None where it has no generated animation."""
    action = character.record_holder(head, RECORD_PROPERTY)
    if action is None or RECORD_PROPERTY not in action:
        return None
    return record_from_json(str(action[RECORD_PROPERTY]), f"the action {action.name!r}")


# ---------------------------------------------------------------- render


def frame_head(scene: bpy.types.Scene, head: bpy.types.Object | None) -> dict[str, bool]:
    """Our camera and lights in front of the head's face, whichever way it looks (render.frame_face); in a
    conversation, in front of every character's (a two-shot, or three-...)."""
    characters = conversation_heads(scene)
    if characters and (head is None or head in characters):
        return frame_conversation(scene, characters)
    if head is None:
        return render.frame_face(scene, [])
    return render.frame_face(scene, head_objects(head), find_rig(head).frame)


def conversation_heads(scene: bpy.types.Scene) -> list[bpy.types.Object]:
    """The heads of the scene's last conversation (empty where it has none)."""
    record = conversation_record(scene)
    return record.head_objects() if record is not None else []


def group_facing(rigs: list) -> np.ndarray:
    """The way a group of heads faces together (columns: left, up, forward; up the world's Z): the mean of
    their facings, level; -Y where they face every way."""
    forward = np.sum([rig.frame[:, 2] for rig in rigs], axis=0) if rigs else np.zeros(3)
    forward[2] = 0.0
    if np.linalg.norm(forward) < 1e-6:
        return render.FACING_MINUS_Y
    forward /= np.linalg.norm(forward)
    up = np.array([0.0, 0.0, 1.0])
    return np.column_stack([np.cross(up, forward), up, forward])


def frame_conversation(scene: bpy.types.Scene, heads: list[bpy.types.Object]) -> dict[str, bool]:
    """Our camera and lights framing every character's face, facing the way the group faces; the user's
    own camera and lights stay."""
    with living.at_rest(scene):
        rigs = [find_rig(head) for head in heads]
    objects = [obj for head in heads for obj in head_objects(head)]
    return render.frame_face(scene, objects, group_facing(rigs), group=True)


@dataclass(frozen=True, eq=False)
class PreparedRender:
    """A scene set up to render the video, and what to undo if the render is cancelled."""

    path: Path
    engine: str
    frame_count: int
    settings: render.SceneSettings
    framed: dict[str, bool]
    started: float


def prepare_render(
    context: bpy.types.Context,
    head: bpy.types.Object | None,
    out_path: str,
    *,
    engine: str = "AUTO",
    samples: int | None = None,
    resolution: tuple[int, int] | None = None,
) -> PreparedRender:
    """Frame the face (camera and lights only where missing), set the engine and MP4 output."""
    scene = context.scene
    if not out_path:
        raise render.RenderError("No output file: choose where to write the video (an .mp4 path).")
    path = Path(bpy.path.abspath(out_path))
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise render.RenderError(f"Cannot create the folder {path.parent}: {error.strerror}.") from error
    chosen = render.choose_engine(engine)
    settings = render.SceneSettings.of(scene)
    render.configure_output(scene, path, resolution)
    framed = frame_head(scene, head)
    render.configure_engine(scene, chosen, samples)
    return PreparedRender(
        path=path,
        engine=chosen,
        frame_count=scene.frame_end - scene.frame_start + 1,
        settings=settings,
        framed=framed,
        started=time.perf_counter(),
    )


def finish_render(
    context: bpy.types.Context, prepared: PreparedRender, progress: Progress | None = None
) -> RenderResult:
    """After Blender rendered: check the file, add the speech where Blender could not, report."""
    progress = progress or _no_progress
    path = prepared.path
    if not path.is_file():
        raise render.RenderError(f"Blender did not write {path}; see the console for the render error.")
    wav = sequencer.speech_wav_of(context.scene)
    if not compat.HAS_AUDIO and wav is not None and wav.is_file():
        progress(0.97, "Adding the speech to the video")
        render.mux_audio(path, wav)
    progress(1.0, f"Wrote {path}")
    return RenderResult(
        path=str(path),
        engine=prepared.engine,
        frame_count=prepared.frame_count,
        seconds=time.perf_counter() - prepared.started,
        camera_added=prepared.framed["camera"],
        lights_added=prepared.framed["lights"],
    )


def cancel_render(context: bpy.types.Context, prepared: PreparedRender) -> None:
    """A cancelled render leaves the scene as it was and no partial video behind."""
    prepared.settings.restore(context.scene)
    prepared.path.unlink(missing_ok=True)


def render_video(
    context: bpy.types.Context,
    head: bpy.types.Object | None,
    out_path: str,
    *,
    progress: Progress | None = None,
    **settings,
) -> RenderResult:
    """Render the frame range to an MP4 with the speech, blocking (batch; the panel renders modally).

    settings are prepare_render's: engine, samples, resolution.
    """
    progress = progress or _no_progress
    prepared = prepare_render(context, head, out_path, **settings)
    frame_count = prepared.frame_count
    progress(0.05, f"Rendering {frame_count} frames with {prepared.engine} to {prepared.path}")

    def after_frame(rendered_scene, _depsgraph=None):
        done = rendered_scene.frame_current - rendered_scene.frame_start + 1
        progress(0.05 + 0.9 * done / max(1, frame_count), f"Rendered frame {done}/{frame_count}")

    bpy.app.handlers.render_post.append(after_frame)
    try:
        bpy.ops.render.render(animation=True, scene=context.scene.name)
    finally:
        bpy.app.handlers.render_post.remove(after_frame)
    return finish_render(context, prepared, progress)


def widest_mouth_frame(head: bpy.types.Object) -> int | None:
    """The frame where the open-mouth viseme peaks: a telling still of the speech (None without keys)."""
    key = getattr(head.data, "shape_keys", None)
    action = key.animation_data.action if key is not None and key.animation_data else None
    if action is None:
        return None
    name = owned_keys(head).get(viseme_key_name("a"))
    if name is None:
        return None
    wanted = keyframes.curve_data_path(name)
    for fcurve in compat.all_action_fcurves(action):
        if fcurve.data_path == wanted and len(fcurve.keyframe_points):
            best = max(fcurve.keyframe_points, key=lambda point: point.co[1])
            return round(best.co[0])
    return None


def render_still(
    context: bpy.types.Context,
    head: bpy.types.Object | None,
    out_path: str,
    *,
    frame: int | None = None,
    engine: str = "AUTO",
    samples: int | None = None,
    resolution: tuple[int, int] | None = None,
) -> str:
    """One frame to PNG (for the manual and checks), framed and lit like the video; returns the path."""
    scene = context.scene
    path = Path(bpy.path.abspath(out_path))
    path.parent.mkdir(parents=True, exist_ok=True)
    chosen = render.choose_engine(engine)
    if resolution is not None:
        scene.render.resolution_x, scene.render.resolution_y = resolution
    frame_head(scene, head)
    render.configure_engine(scene, chosen, samples)
    settings = scene.render.image_settings
    saved = (scene.render.filepath, settings.file_format, scene.frame_current)
    if frame is None:
        frame = (widest_mouth_frame(head) if head is not None else None) or scene.frame_current
    try:
        compat.set_image_output(settings, "PNG")
        scene.render.filepath = str(path)
        scene.frame_set(int(frame))
        bpy.ops.render.render(write_still=True, scene=scene.name)
    finally:
        scene.render.filepath = saved[0]
        if saved[1] == "FFMPEG":
            compat.set_video_output(settings)
        else:
            settings.file_format = saved[1]
        scene.frame_set(saved[2])
    if not path.is_file():
        raise render.RenderError(f"Blender did not write {path}; see the console for the render error.")
    return str(path)
