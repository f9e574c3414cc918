"""Blender extension entry point: the Blender layer registers everything."""


def register() -> None:
    from .turkish_lipsync import blender

    blender.register()


def unregister() -> None:
    from .turkish_lipsync import blender

    blender.unregister()
