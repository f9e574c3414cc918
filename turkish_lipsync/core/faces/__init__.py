"""Faces without Blender: the reference head, the ARKit unit names, and the viseme/emotion recipes."""
