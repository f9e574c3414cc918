"""Thin operators: poll (saying why not), then one call into pipeline, errors reported, progress shown."""

from __future__ import annotations

import contextlib
import traceback
from collections.abc import Callable
from pathlib import Path

import bpy
import numpy as np

from ..core.base.errors import HeadError, LipSyncError
from ..core.faces.landmark_fallbacks import landmark_layout_in_box
from ..core.faces.reference import load_reference_head
from ..core.pipeline import LipSyncOptions
from ..core.scene import RoleChoice
from ..core.scene.speech import SceneSources, line_recordings_in
from ..core.speech.timeline import TABLE_CANNOT_FOLLOW_RECORDING
from ..core.text.script import Script, has_speakers, read_script, speaker_key
from . import character, exports, landmarks, mesh, pipeline, shapekeys
from .generate import generate
from .preferences import ADDON_PACKAGE, configure_speech_engine
from .properties import LAYER_VALUES

# What an operator's work returns: the line to report, and the warnings the user must see.
Outcome = tuple[str, tuple[str, ...]]


@contextlib.contextmanager
def progress_reporter(context: bpy.types.Context, title: str):
    """A progress(fraction, message) callback: cursor progress in the UI, stdout lines in background."""
    window_manager = context.window_manager
    use_cursor = window_manager is not None and not bpy.app.background
    if use_cursor:
        window_manager.progress_begin(0, 100)
    last_message = [""]

    def progress(fraction: float, message: str) -> None:
        if use_cursor:
            window_manager.progress_update(int(max(0.0, min(1.0, fraction)) * 100))
        if bpy.app.background and message != last_message[0]:
            print(f"{title}: {fraction * 100:5.1f}% {message}", flush=True)
        last_message[0] = message

    try:
        yield progress
    finally:
        if use_cursor:
            window_manager.progress_end()


def run_reported(operator: bpy.types.Operator, work: Callable[[], Outcome]) -> set[str]:
    """Every operator's one error path: warnings reported, any failure one line, the work not half-done.

    The work computes everything before it changes Blender data, so an error leaves the file as it was.
    Errors of ours say what to do; anything else is a bug, reported in one line with the traceback on the
    console.
    """
    try:
        message, warnings = work()
    except LipSyncError as error:
        operator.report({"ERROR"}, str(error))
        return {"CANCELLED"}
    except Exception as error:
        traceback.print_exc()
        operator.report(
            {"ERROR"}, f"{operator.bl_label} failed: {type(error).__name__}: {error} (details on the console)"
        )
        return {"CANCELLED"}
    for warning in warnings:
        operator.report({"WARNING"}, warning)
    operator.report({"INFO"}, message)
    return {"FINISHED"}


# A requirement of an operator: None where it is met, else why the operator cannot run (shown on its button).
Requirement = Callable[[bpy.types.Context], "str | None"]


class CheckedOperator:
    """An operator that runs when all its requirements are met, and otherwise says which is not."""

    requirements: tuple[Requirement, ...] = ()

    @classmethod
    def poll(cls, context) -> bool:
        for requirement in cls.requirements:
            reason = requirement(context)
            if reason:
                cls.poll_message_set(reason)
                return False
        return True


class ReportedOperator(CheckedOperator):
    """An operator whose execute runs its work(context) through run_reported."""

    def execute(self, context):
        return run_reported(self, lambda: self.work(context))


def settings_of(context: bpy.types.Context):
    return context.scene.turkish_lipsync


def chosen_head(context: bpy.types.Context) -> bpy.types.Object | None:
    """The head of the panel, else the active mesh."""
    head = settings_of(context).head
    if head is None and context.active_object is not None and context.active_object.type == "MESH":
        head = context.active_object
    return head


def object_mode(context) -> str | None:
    return "Switch to Object Mode first" if context.mode != "OBJECT" else None


def head_chosen(context) -> str | None:
    return "Choose the head object in the Lip Sync panel" if chosen_head(context) is None else None


def key_source_ready(context) -> str | None:
    settings = settings_of(context)
    if settings.key_source == "obj_folder" and not settings.obj_folder:
        return "Choose the folder of OBJ models in the Lip Sync panel"
    if settings.key_source == "arkit" and chosen_head(context) is None:
        return "Choose a head with its own ARKit shape keys (the reference head has none)"
    if settings.key_source == "convention" and chosen_head(context) is None:
        return "Choose a head with visemes of its own (the reference head has none)"
    return None


def keys_built(context) -> str | None:
    """The head speaks through its keys or its face rig; the reason why not, where it cannot."""
    head = chosen_head(context)
    return character.speech_problem(head) if head is not None else None


def speaks_a_script(context) -> bool:
    """Whether Generate speaks a script with speakers: the Text has speakers, or (a file, not read at every
    redraw) the cast list has been filled from one."""
    settings = settings_of(context)
    if settings.source_kind == "TEXT":
        return settings.text is not None and has_speakers(settings.text.as_string())
    return len(settings.cast) > 0


def head_ready(context) -> str | None:
    """One head needs choosing, with its keys; a script's heads are its cast's (default heads included)."""
    if speaks_a_script(context):
        return None
    return head_chosen(context) or keys_built(context)


def text_chosen(context) -> str | None:
    settings = settings_of(context)
    if settings.source_kind == "TEXT" and settings.text is None:
        return "Choose the Text to speak in the Lip Sync panel"
    if settings.source_kind == "FILE" and not settings.file_path:
        return "Choose the JSML file to speak in the Lip Sync panel"
    return None


def source_chosen(context) -> str | None:
    """A text to speak is chosen, or a cue file that may hold its own (a Papagayo project does), or a
    recording, whose words are then recognised from the audio."""
    settings = settings_of(context)
    if settings.cue_file or settings.recording:
        return None
    if settings.source_kind == "TEXT" and settings.text is None:
        return "Choose the Text to speak in the Lip Sync panel"
    if settings.source_kind == "FILE" and not settings.file_path:
        return "Choose the JSML file to speak in the Lip Sync panel"
    return None


def timing_follows_recording(context) -> str | None:
    settings = settings_of(context)
    if settings.recording and settings.timing == "table" and not settings.cue_file:
        return TABLE_CANNOT_FOLLOW_RECORDING
    return None


def speech_generated(context) -> str | None:
    if exports.in_conversation(context.scene, chosen_head(context)):
        return None
    if chosen_head(context) is None:
        return "Choose the head object in the Lip Sync panel"
    action = character.record_holder(chosen_head(context), pipeline.RECORD_PROPERTY)
    if action is None or pipeline.RECORD_PROPERTY not in action:
        return "Generate the animation first: the head has no speech to export"
    return None


def head_landmarks(head: bpy.types.Object) -> tuple[dict[str, np.ndarray], tuple[str, ...]]:
    """The face landmarks of the head's rest shape in its own coordinates, and warnings.

    The user's markers where there are some, else what the builder would find (from the shape, else from the
    head's own mouth and blink keys). Where no face is found, the reference's layout scaled into the head's
    bounds, for the user to move onto the face: the markers workflow works on any head.
    """
    if len(head.data.polygons) == 0:
        raise HeadError(f"{head.name!r} has no faces; a head needs a surface to find a face on.")
    to_local = mesh.world_to_local_linear(head, "show the landmarks")
    warnings: tuple[str, ...] = ()
    try:
        found = shapekeys.head_landmarks(head)
    except HeadError as error:
        reference = load_reference_head()
        world = mesh.world_rest_coordinates(head)
        skin = reference.vertices[reference.parts["skin"]]
        found = landmark_layout_in_box(reference.landmarks, skin, world.min(axis=0), world.max(axis=0))
        warnings = (
            f"{error} The markers are placed by the head's size only: move each one onto its place on the "
            "face (nose tip, lips, mouth corners, chin, eye corners, lids), then build the keys.",
        )
    offset = mesh.world_matrix(head)[:3, 3]
    local = {name: (np.asarray(point, np.float64) - offset) @ to_local.T for name, point in found.items()}
    return local, warnings


class TURKISH_LIPSYNC_OT_build_shape_keys(ReportedOperator, bpy.types.Operator):
    """Build the Turkish viseme and emotion shape keys on the head (the reference head when none is chosen)"""

    bl_idname = "turkish_lipsync.build_shape_keys"
    bl_label = "Build Shape Keys"
    bl_options = {"REGISTER", "UNDO"}
    requirements = (object_mode, key_source_ready)

    @staticmethod
    def work(context) -> Outcome:
        settings = settings_of(context)
        from_folder = settings.key_source == "obj_folder"
        mapped = settings.key_source in ("auto", "convention") and settings.mapping_file
        with progress_reporter(context, "Build shape keys") as progress:
            report = pipeline.build_keys(
                context,
                chosen_head(context),
                arkit_keys=settings.arkit_keys,
                source=settings.key_source,
                obj_folder=bpy.path.abspath(settings.obj_folder) if from_folder else None,
                mapping_file=bpy.path.abspath(settings.mapping_file) if mapped else None,
                empowered=settings.empowered,
                rho=settings.rho,
                progress=progress,
            )
        settings.head = bpy.data.objects[report.head]
        return (
            f"Shape keys built on {report.head} (from {report.convention or report.source})",
            report.warnings,
        )


class TURKISH_LIPSYNC_OT_generate(ReportedOperator, bpy.types.Operator):
    """Speak the text: key the head's mouth shapes and emotions, and put the speech in the sequencer"""

    bl_idname = "turkish_lipsync.generate"
    bl_label = "Generate Animation"
    bl_options = {"REGISTER", "UNDO"}
    requirements = (object_mode, head_ready, source_chosen, timing_follows_recording)

    @staticmethod
    def work(context) -> Outcome:
        settings = settings_of(context)
        head = chosen_head(context)
        configure_speech_engine(context)
        source = source_of(settings)
        script = read_script(source) if source else None
        if script is not None:
            fill_cast(settings, script)  # the cast list brought up to the script before it is cast
        with progress_reporter(context, "Generate") as progress:
            result = generate(
                context,
                source,
                options_of(settings),
                head=head,
                choices=choices_of(settings) if script is not None else None,
                sources=sources_of(settings) if script is not None else None,
                audio_folder=settings.audio_folder,
                package=ADDON_PACKAGE,
                progress=progress,
                gaze_target=settings.gaze_target.name if settings.gaze_target else "",
            )
        if script is None:
            settings.head = head
            what = f"{result.phone_count} phones"
        else:
            for member in settings.cast:  # the heads the cast got (default heads included), for the next run
                if member.head is None and member.name in result.heads:
                    member.head = bpy.data.objects[result.heads[member.name]]
            what = f"{len(script.lines)} lines of {len(result.heads)} characters"
        message = (
            f"{what} keyed over {result.duration:.2f} s (frames {result.frame_start}-{result.frame_end})"
        )
        return message, result.warnings


def fill_cast(settings, script: Script) -> int:
    """The panel's cast list made the script's speakers, in the order they first speak: a speaker already
    listed keeps what was chosen for them; returns how many were added."""
    chosen = {speaker_key(member.name): index for index, member in enumerate(settings.cast)}
    added = 0
    for speaker in script.speakers:
        if speaker.key not in chosen:
            member = settings.cast.add()
            member.name = speaker.name
            if speaker.gender is not None:
                member.gender = speaker.gender
            added += 1
    keys = [speaker.key for speaker in script.speakers]
    for index in reversed(range(len(settings.cast))):
        if speaker_key(settings.cast[index].name) not in keys:
            settings.cast.remove(index)
    for position, key in enumerate(keys):
        current = next(i for i, member in enumerate(settings.cast) if speaker_key(member.name) == key)
        settings.cast.move(current, position)
    settings.cast_index = min(settings.cast_index, max(len(settings.cast) - 1, 0))
    return added


def choices_of(settings) -> dict[str, RoleChoice]:
    """What the cast list chose for each speaker (Auto leaves it to the cast)."""
    choices = {}
    for member in settings.cast:
        chosen_voice = member.voice != "AUTO"
        choices[member.name] = RoleChoice(
            head=member.head.name if member.head is not None else "",
            gender=None if member.gender == "AUTO" else member.gender,
            variant=member.voice if chosen_voice else None,
            pitch=member.pitch if chosen_voice else None,
            rate=member.voice_rate if chosen_voice else None,
            emotion_strength=settings.emotion_strength * member.emotion_strength,
            recording=Path(bpy.path.abspath(member.recording)) if member.recording else None,
        )
    return choices


def sources_of(settings) -> SceneSources:
    """Where a scene's speech comes from: the Own Recording (the whole scene), the cast's recordings (set in
    choices_of), a folder of line recordings, or a cue file."""
    lines: tuple[Path, ...] = ()
    if settings.line_recordings:
        lines = line_recordings_in(Path(bpy.path.abspath(settings.line_recordings)))
    return SceneSources(
        scene_recording=Path(bpy.path.abspath(settings.recording)) if settings.recording else None,
        line_recordings=lines,
        cues=Path(bpy.path.abspath(settings.cue_file)) if settings.cue_file else None,
    )


class TURKISH_LIPSYNC_OT_fill_cast(ReportedOperator, bpy.types.Operator):
    """List the script's speakers in the cast, keeping what was chosen for those already listed"""

    bl_idname = "turkish_lipsync.fill_cast"
    bl_label = "Fill Cast from Script"
    bl_options = {"REGISTER", "UNDO"}
    requirements = (object_mode, text_chosen)

    @staticmethod
    def work(context) -> Outcome:
        settings = settings_of(context)
        source = source_of(settings)
        script = read_script(source)
        if script is None:
            raise LipSyncError(
                'The text has no speakers: write its lines as <VOICE NAME="..."> elements or as '
                '"NAME: text" lines (a screenplay) to have several characters speak them.'
            )
        added = fill_cast(settings, script)
        return f"{len(settings.cast)} speakers in the cast ({added} new)", ()


def options_of(settings) -> LipSyncOptions:
    """The core's options from the panel's settings (the frame rate is the scene's, set by generate)."""
    recording = Path(bpy.path.abspath(settings.recording)) if settings.recording else None
    cues = Path(bpy.path.abspath(settings.cue_file)) if settings.cue_file else None
    layers = {
        layer: LAYER_VALUES[getattr(settings, f"{layer}_layer")]
        for layer in ("gaze", "blinks", "head_motion", "expression")
    }
    return LipSyncOptions.from_attributes(settings, recording=recording, cues=cues, **layers)


def source_of(settings) -> str:
    """The panel's text; empty when only a cue file is given (its own text is then spoken) or only a
    recording, with no text or an empty one (what it says is then recognised)."""
    text_name = settings.text.name if settings.source_kind == "TEXT" and settings.text else ""
    file_path = settings.file_path if settings.source_kind == "FILE" else ""
    if (settings.cue_file or settings.recording) and not (text_name or file_path):
        return ""
    return pipeline.read_source(text_name, file_path, allow_empty=bool(settings.recording))


class TURKISH_LIPSYNC_OT_show_landmarks(ReportedOperator, bpy.types.Operator):
    """Find the face landmarks on the head and show them as markers to move where they are off"""

    bl_idname = "turkish_lipsync.show_landmarks"
    bl_label = "Show Landmarks"
    bl_options = {"REGISTER", "UNDO"}
    requirements = (object_mode, head_chosen)

    @staticmethod
    def work(context) -> Outcome:
        head = chosen_head(context)
        context.view_layer.update()  # the head's matrix_world is stale right after a transform change
        found, warnings = head_landmarks(head)
        markers = landmarks.show_landmark_markers(head, found, scene=context.scene)
        settings_of(context).head = head
        return (
            f"{len(markers)} landmark markers on {head.name}: move any that are off, then build keys",
            warnings,
        )


def markers_shown(context) -> str | None:
    if landmarks.read_landmark_markers(chosen_head(context)) is None:
        return "The head has no landmark markers"
    return None


class TURKISH_LIPSYNC_OT_clear_landmarks(ReportedOperator, bpy.types.Operator):
    """Remove the head's landmark markers: the next build finds the landmarks automatically again"""

    bl_idname = "turkish_lipsync.clear_landmarks"
    bl_label = "Clear Landmarks"
    bl_options = {"REGISTER", "UNDO"}
    requirements = (object_mode, head_chosen, markers_shown)

    @staticmethod
    def work(context) -> Outcome:
        head = chosen_head(context)
        return f"Removed {landmarks.remove_landmark_markers(head)} markers from {head.name}", ()


def output_chosen(context) -> str | None:
    if not settings_of(context).output_path:
        return "Choose the video file to write in the Lip Sync panel"
    return None


def something_to_film(context) -> str | None:
    nothing = chosen_head(context) is None and not pipeline.conversation_heads(context.scene)
    if context.scene.camera is None and nothing:
        return "Choose the head (to frame a camera on it) or add a camera"
    return None


class TURKISH_LIPSYNC_OT_render(CheckedOperator, bpy.types.Operator):
    """Render the frame range to an MP4 with the speech, adding a camera and lights on the face if missing"""

    bl_idname = "turkish_lipsync.render"
    bl_label = "Render Video"
    bl_options = {"REGISTER", "UNDO"}
    requirements = (object_mode, output_chosen, something_to_film)

    _prepared: pipeline.PreparedRender | None = None
    _timer = None
    _state: dict | None = None

    def execute(self, context):
        """Blocking render (background mode and scripts calling the operator)."""
        settings = settings_of(context)

        def render() -> Outcome:
            with progress_reporter(context, "Render") as progress:
                result = pipeline.render_video(
                    context,
                    chosen_head(context),
                    settings.output_path,
                    engine=settings.render_engine,
                    samples=settings.render_samples,
                    progress=progress,
                )
            return f"Rendered {result.frame_count} frames with {result.engine} to {result.path}", ()

        return run_reported(self, render)

    def invoke(self, context, _event):
        """Render as a job: Blender stays responsive, shows progress, and Esc cancels it."""
        if bpy.app.background:
            return self.execute(context)
        settings = settings_of(context)

        def prepare() -> Outcome:
            self._prepared = pipeline.prepare_render(
                context,
                chosen_head(context),
                settings.output_path,
                engine=settings.render_engine,
                samples=settings.render_samples,
            )
            return "", ()

        if run_reported(self, prepare) != {"FINISHED"}:
            return {"CANCELLED"}
        self._state = {"done": False, "cancelled": False}
        handlers = bpy.app.handlers
        handlers.render_complete.append(self._on_complete)
        handlers.render_cancel.append(self._on_cancel)
        if bpy.ops.render.render("INVOKE_DEFAULT", animation=True) == {"CANCELLED"}:
            self._remove_handlers()
            pipeline.cancel_render(context, self._prepared)
            self.report({"ERROR"}, "Blender could not start the render; see the console.")
            return {"CANCELLED"}
        self._timer = context.window_manager.event_timer_add(0.5, window=context.window)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def _on_complete(self, _scene, _depsgraph=None):
        self._state["done"] = True

    def _on_cancel(self, _scene, _depsgraph=None):
        self._state["cancelled"] = True

    def _remove_handlers(self) -> None:
        handlers = bpy.app.handlers
        for handler_list, handler in (
            (handlers.render_complete, self._on_complete),
            (handlers.render_cancel, self._on_cancel),
        ):
            if handler in handler_list:
                handler_list.remove(handler)

    def modal(self, context, event):
        if event.type != "TIMER" or not (self._state["done"] or self._state["cancelled"]):
            return {"PASS_THROUGH"}
        self._remove_handlers()
        context.window_manager.event_timer_remove(self._timer)
        if self._state["cancelled"]:
            pipeline.cancel_render(context, self._prepared)
            self.report({"WARNING"}, "Render cancelled: the scene is as it was and no partial video is kept.")
            return {"CANCELLED"}
        prepared = self._prepared
        return run_reported(
            self,
            lambda: (
                f"Rendered {prepared.frame_count} frames with {prepared.engine} to "
                f"{pipeline.finish_render(context, prepared).path}",
                (),
            ),
        )


def export_file_chosen(context) -> str | None:
    chosen = settings_of(context).export_path
    if not chosen:
        return "Choose the file to export to in the Lip Sync panel"
    if chosen.startswith("//") and not bpy.data.filepath:
        return "Save the .blend first, or choose an absolute path to export to"
    return None


def gltf_file_chosen(context) -> str | None:
    return (
        "Choose the glTF file to write in the Lip Sync panel" if not settings_of(context).gltf_path else None
    )


class TURKISH_LIPSYNC_OT_export_animation(ReportedOperator, bpy.types.Operator):
    """Write the speech for other tools: Rhubarb mouth cues, Moho switch data, Papagayo or ARKit CSV"""

    bl_idname = "turkish_lipsync.export_animation"
    bl_label = "Export Animation"
    bl_options = {"REGISTER"}
    requirements = (object_mode, speech_generated, export_file_chosen)

    @staticmethod
    def work(context) -> Outcome:
        settings = settings_of(context)
        path = exports.export_path_for(settings.export_path, settings.export_format)
        results = exports.export_speech(context, chosen_head(context), settings.export_format, path)
        written = ", ".join(str(result.path) for result in results)
        return f"Exported {settings.export_format} to {written}", tuple(
            warning for result in results for warning in result.warnings
        )


class TURKISH_LIPSYNC_OT_export_gltf(ReportedOperator, bpy.types.Operator):
    """Export the head, its shape keys and the speech animation as .glb, the speech WAV beside it"""

    bl_idname = "turkish_lipsync.export_gltf"
    bl_label = "Export glTF"
    bl_options = {"REGISTER"}
    requirements = (object_mode, speech_generated, gltf_file_chosen)

    @staticmethod
    def work(context) -> Outcome:
        path = settings_of(context).gltf_path
        results = exports.export_speech_gltf(context, chosen_head(context), path)
        if len(results) > 1:  # a conversation: the scene and each character
            return f"Exported {', '.join(result.path for result in results)}", ()
        result = results[0]
        sound = f", the speech in {result.wav_path}" if result.wav_path else ", no speech WAV in the scene"
        return f"Exported {result.path} ({result.morph_targets} morph targets){sound}", ()


CLASSES = (
    TURKISH_LIPSYNC_OT_build_shape_keys,
    TURKISH_LIPSYNC_OT_show_landmarks,
    TURKISH_LIPSYNC_OT_clear_landmarks,
    TURKISH_LIPSYNC_OT_fill_cast,
    TURKISH_LIPSYNC_OT_generate,
    TURKISH_LIPSYNC_OT_render,
    TURKISH_LIPSYNC_OT_export_animation,
    TURKISH_LIPSYNC_OT_export_gltf,
)

register, unregister = bpy.utils.register_classes_factory(CLASSES)
