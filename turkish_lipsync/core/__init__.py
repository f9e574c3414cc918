"""The bpy-free core: Turkish text to timed viseme and emotion weights."""
