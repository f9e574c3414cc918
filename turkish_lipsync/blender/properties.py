"""The panel's settings, stored per scene (so they are saved in the .blend and undone with it)."""

from __future__ import annotations

import bpy
from bpy.props import (
    BoolProperty,
    CollectionProperty,
    EnumProperty,
    FloatProperty,
    IntProperty,
    PointerProperty,
    StringProperty,
)

from ..core.base.choices import Choice
from ..core.faces.key_sources import KEY_SOURCE_CHOICES, RHO_RANGE
from ..core.faces.rig_mappings import rig_templates
from ..core.faces.rig_poses import pose_target_label, pose_targets
from ..core.interchange import export_choices
from ..core.pipeline import (
    AMOUNT_RANGE,
    INTERPOLATION_CHOICES,
    MOTION_CHOICES,
    RATE_RANGE,
    TIMING_CHOICES,
    LipSyncOptions,
)
from ..core.scene.cast import PITCH_RANGE
from ..core.scene.cast import RATE_RANGE as VOICE_RATE_RANGE
from ..core.scene.tables import conversation_table

DEFAULTS = LipSyncOptions()


def enum_items(choices: tuple[Choice, ...]) -> tuple[tuple[str, str, str], ...]:
    return tuple((choice.identifier, choice.label, choice.description) for choice in choices)


def _is_mesh(_settings, obj) -> bool:
    return obj.type == "MESH"


# A living layer on, off, or as the motion model has it (on for the natural model, off for the thesis's).
LAYER_STATES = (
    ("AUTO", "Auto", "As the motion has it: on for Natural, off for Thesis"),
    ("ON", "On", "On for either motion"),
    ("OFF", "Off", "Off"),
)
LAYER_VALUES = {"AUTO": None, "ON": True, "OFF": False}


def _layer(name: str, description: str):
    return EnumProperty(name=name, items=LAYER_STATES, default="AUTO", description=description)


def _amount(name: str, description: str):
    return FloatProperty(
        name=name,
        default=1.0,
        min=AMOUNT_RANGE[0],
        max=AMOUNT_RANGE[1],
        soft_max=1.5,
        description=description,
    )


# The face-rig mappings that come with the extension, then the character's own poses alone.
OWN_POSES = "own_poses"
FACE_RIG_ITEMS = (
    *((template.name, template.title, template.description) for template in rig_templates()),
    (OWN_POSES, "Own Poses", "Only the poses recorded for this character below"),
)
POSE_TARGET_DESCRIPTION = "A viseme, emotion, blink or look key, or an ARKit unit"
# What a pose may be recorded for.
POSE_TARGET_ITEMS = tuple(
    (target, pose_target_label(target), POSE_TARGET_DESCRIPTION, "NONE", number)
    for number, target in enumerate(pose_targets())
)


VOICE_LABELS = {"female": "Female", "male": "Male"}
VOICE_DESCRIPTIONS = {
    "female": "A woman's voice: a variant of eSpeak NG's Turkish voice",
    "male": "A man's voice: a variant of eSpeak NG's Turkish voice",
}


def _voice_items() -> tuple[tuple[str, str, str], ...]:
    """Auto, then every eSpeak NG variant the cast gives, numbered per gender as the panel shows them."""
    voices = conversation_table().voices
    items = [("AUTO", "Auto", "The cast's voice for the speaker's gender, distinct from the others'")]
    for gender, variants in (("female", voices.female), ("male", voices.male)):
        for number, variant in enumerate(variants, start=1):
            items.append((variant, f"{VOICE_LABELS[gender]} {number}", VOICE_DESCRIPTIONS[gender]))
    return tuple(items)


class TurkishLipSyncCastMember(bpy.types.PropertyGroup):
    """One speaker of a script with speakers (its name: the script's), and who plays them: a row of the
    panel's cast list."""

    head: PointerProperty(
        name="Head",
        type=bpy.types.Object,
        poll=_is_mesh,
        description="The head that plays this speaker (empty: a default head of its own, in a tone of its "
        "own, standing beside the others)",
    )
    gender: EnumProperty(
        name="Gender",
        items=(
            (
                "AUTO",
                "Auto",
                "As the script says, else as the name says, else the gender the cast has fewest of",
            ),
            ("female", "Female", "A woman's voice"),
            ("male", "Male", "A man's voice"),
        ),
        default="AUTO",
        description="Whose voice the speaker gets when the voice is Auto",
    )
    voice: EnumProperty(
        name="Voice",
        items=_voice_items(),
        default="AUTO",
        description="The speech engine's voice for this speaker",
    )
    pitch: FloatProperty(
        name="Voice Pitch",
        default=1.0,
        min=PITCH_RANGE[0],
        max=PITCH_RANGE[1],
        description="Multiplier of the chosen voice's pitch (with an Auto voice, the cast chooses it)",
    )
    voice_rate: FloatProperty(
        name="Voice Rate",
        default=1.0,
        min=VOICE_RATE_RANGE[0],
        max=VOICE_RATE_RANGE[1],
        description="Multiplier of the chosen voice's speaking rate (with an Auto voice, the cast chooses "
        "it)",
    )
    emotion_strength: FloatProperty(
        name="Emotion Strength",
        default=1.0,
        min=0.0,
        max=1.0,
        subtype="FACTOR",
        description="How strongly this speaker's emotions show, times the Speech panel's Emotion Strength",
    )
    recording: StringProperty(  # a path; its button (recording_browser.py) shows only what can be read
        name="Speaker Recording",
        description="This speaker's track of the scene (WAV, FLAC, OGG, MP3, M4A, or a video's sound), "
        "starting where the scene starts and silent while the others speak; give one to every speaker, or "
        "one Own Recording of the whole scene",
    )


class TurkishLipSyncSettings(bpy.types.PropertyGroup):
    head: PointerProperty(
        name="Head",
        type=bpy.types.Object,
        poll=_is_mesh,
        description="The head mesh that speaks; its teeth, tongue and eyes follow it",
    )
    source_kind: EnumProperty(
        name="Source",
        items=(
            ("TEXT", "Text", "A Text datablock of this file (Text Editor)"),
            ("FILE", "File", "A JSML or plain-text file on disk"),
        ),
        default="TEXT",
        description="Where the Turkish text (plain or JSML markup) comes from",
    )
    text: PointerProperty(name="Text", type=bpy.types.Text, description="Turkish text, plain or JSML markup")
    file_path: StringProperty(
        name="File", subtype="FILE_PATH", description="A UTF-8 file with Turkish text, plain or JSML markup"
    )
    timing: EnumProperty(
        name="Timing",
        items=enum_items(TIMING_CHOICES),
        default=DEFAULTS.timing,
        description="How the mouth shapes are timed against the speech",
    )
    rate: FloatProperty(
        name="Speaking Rate",
        default=DEFAULTS.rate,
        min=RATE_RANGE[0],
        max=RATE_RANGE[1],
        soft_min=0.5,
        soft_max=2.0,
        description="Multiplier of the speaking rate (1 is the engine's normal speed)",
    )
    emotion_strength: FloatProperty(
        name="Emotion Strength",
        default=DEFAULTS.emotion_strength,
        min=0.0,
        max=1.0,
        subtype="FACTOR",
        description="How strongly the emotions of the markup show on the face",
    )
    motion: EnumProperty(
        name="Motion",
        items=enum_items(MOTION_CHOICES),
        default=DEFAULTS.motion,
        description="How the weights move between mouth shapes",
    )
    interpolation: EnumProperty(
        name="Interpolation",
        items=enum_items(INTERPOLATION_CHOICES),
        default=DEFAULTS.interpolation,
        description="Interpolation of the shape-key keyframes",
    )
    key_source: EnumProperty(
        name="Shape-Key Source",
        items=enum_items(KEY_SOURCE_CHOICES),
        default="auto",
        description="What the mouth shapes and emotions are built from",
    )
    mapping_file: StringProperty(
        name="Mapping File",
        subtype="FILE_PATH",
        description="Your own TOML file naming the head's keys for the Turkish visemes (empty: the keys are "
        "recognised by their names)",
    )
    obj_folder: StringProperty(
        name="OBJ Folder",
        subtype="DIR_PATH",
        description="The head's OBJ models, same vertices in the same order (a.obj, ..., Neutral.obj)",
    )
    empowered: BoolProperty(
        name="Empowered Emotions",
        default=False,
        description="Store the emotion keys exaggerated by the empowering constant (thesis eq. 5.2), for "
        "keying them by hand; generated animation needs plain keys (its thesis mode empowers by itself)",
    )
    rho: FloatProperty(
        name="Empowering Constant",
        default=3.0,
        min=RHO_RANGE[0],
        max=RHO_RANGE[1],
        soft_max=5.0,
        description="How many times stronger the empowered emotions are (ρ in the thesis, which uses 3)",
    )
    face_rig: EnumProperty(
        name="Face Rig",
        items=FACE_RIG_ITEMS,
        default=FACE_RIG_ITEMS[0][0],
        description="The poses of the head's armature that make the visemes and emotions (Use Face Rig "
        "keeps the choice with the character)",
    )
    jaw_bone: StringProperty(
        name="Jaw Bone",
        description="The armature's bone that opens the jaw, for the Jaw Bone mapping (empty: found by its "
        "name)",
    )
    pose_target: EnumProperty(
        name="Pose For",
        items=POSE_TARGET_ITEMS,
        description="What the recorded pose stands for: a viseme, an emotion, a blink or look, or one of the "
        "52 ARKit units",
    )
    pose_action: PointerProperty(
        name="Pose Action",
        type=bpy.types.Action,
        description="An action or pose asset that holds a pose of the rig, for Record from Action",
    )
    pose_frame: IntProperty(
        name="Pose Frame",
        default=1,
        min=-1048574,
        max=1048574,  # Blender's own frame limits
        description="The frame of the Pose Action that holds the pose",
    )
    arkit_keys: BoolProperty(
        name="Keep ARKit Keys",
        default=False,
        description="Also keep the 52 ARKit face-unit shape keys the mouth shapes are built from",
    )
    recording: StringProperty(  # a path; its button (recording_browser.py) shows only what can be read
        name="Own Recording",
        description="Your own recording of the same text (WAV, FLAC, OGG, MP3, M4A, or the sound of a video: "
        "MP4, MOV, MKV, WebM): the mouth follows it and it becomes the sound (empty: the synthetic voice). "
        "With no text, what it says is recognised (a few seconds for each minute of speech)",
    )
    audio_folder: StringProperty(
        name="Audio Folder",
        subtype="DIR_PATH",
        description="Where the speech WAV is saved (empty: a folder next to the saved .blend file)",
    )
    render_engine: EnumProperty(
        name="Render Engine",
        items=(
            ("AUTO", "Automatic", "EEVEE where OpenGL is available, Cycles otherwise"),
            ("EEVEE", "EEVEE", "Fast, needs OpenGL"),
            ("CYCLES", "Cycles", "Path tracing on the CPU, works everywhere"),
            ("WORKBENCH", "Workbench", "Solid shading preview, needs OpenGL"),
        ),
        default="AUTO",
        description="The engine that renders the video",
    )
    render_samples: IntProperty(
        name="Samples", default=16, min=1, max=4096, description="Render samples per pixel (EEVEE and Cycles)"
    )
    output_path: StringProperty(
        name="Video",
        subtype="FILE_PATH",
        default="//lipsync.mp4",
        description="The MP4 file to write (H.264 video with AAC audio)",
    )
    cue_file: StringProperty(
        name="Cue File",
        subtype="FILE_PATH",
        description="A Rhubarb (.tsv, .json, .xml), Papagayo (.pgo) or Moho (.dat) file that times the mouth "
        "shapes instead of the speech engine; the recording is then its sound; a .pgo brings its text",
    )
    export_format: EnumProperty(
        name="Format",
        items=enum_items(export_choices()),
        default="rhubarb-json",
        description="What Export Animation writes, and for which tools",
    )
    export_path: StringProperty(
        name="Export File",
        subtype="FILE_PATH",
        default="//speech",
        description="The file Export Animation writes; its extension follows the format",
    )
    gaze_layer: _layer("Gaze", "Eyes that hold the camera (or the target) and look away with saccades")
    gaze_amount: _amount("Gaze Amount", "How far the eyes look away (1 the usual)")
    blinks_layer: _layer("Blinks", "Blinks at pauses, phrase ends and large gaze shifts")
    blink_amount: _amount("Blink Amount", "How often the eyes blink (1 about 17 a minute)")
    head_motion_layer: _layer("Head Motion", "Nods, turns and tilts from the voice's pitch and loudness")
    head_amount: _amount("Head Amount", "How far the head moves (1 a few degrees)")
    expression_layer: _layer(
        "Expression", "Brows rising on pitch accents and emphasis, emotions that breathe at their apex"
    )
    expression_amount: _amount("Expression Amount", "How strongly the brows and emotions live")
    seed: IntProperty(
        name="Seed", default=0, min=0, description="Another seed gives other glances, blinks and head moves"
    )
    gaze_target: PointerProperty(
        name="Gaze Target",
        type=bpy.types.Object,
        description="The object the eyes seek while talking (empty: the scene's camera)",
    )
    cast: CollectionProperty(
        type=TurkishLipSyncCastMember,
        name="Cast",
        description="Who plays each speaker of a script with speakers, filled from the script",
    )
    cast_index: IntProperty(
        name="Cast Row", default=0, min=0, description="The speaker chosen in the cast list"
    )
    line_recordings: StringProperty(
        name="Line Recordings",
        subtype="DIR_PATH",
        description="A folder of recordings, one per line of the script, in the order of their file names "
        "(empty: the lines are synthesised, or the Own Recording holds the whole scene)",
    )
    gltf_path: StringProperty(
        name="glTF File",
        subtype="FILE_PATH",
        default="//speech.glb",
        description="The .glb file Export glTF writes: the head, its shape keys and the speech animation "
        "(the speech WAV goes beside it)",
    )


CLASSES = (TurkishLipSyncCastMember, TurkishLipSyncSettings)


def register() -> None:
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.turkish_lipsync = PointerProperty(type=TurkishLipSyncSettings)


def unregister() -> None:
    del bpy.types.Scene.turkish_lipsync
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
