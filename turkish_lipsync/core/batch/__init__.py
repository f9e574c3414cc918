"""The batch command (scripts/render.py) without Blender: its flags, their checks, the options they choose,
and the command itself, which hands the Blender work to turkish_lipsync/blender/batch.py and joins a farm's
chunks with the core alone. An episode's farm steps (core/farm) build their scenes with the same flags."""
