"""Where a head's TR keys may come from: the choices of the panel's Shape-Key Source and render.py's
--key-source, once."""

from __future__ import annotations

from ..base.choices import Choice

KEY_SOURCE_CHOICES = (
    Choice("auto", "Auto", "The head's own visemes or ARKit keys, else a transfer from the reference head"),
    Choice(
        "convention",
        "Own Visemes",
        "The head's own visemes (Oculus, VRM, Azure, Papagayo) or those a mapping file names",
    ),
    Choice("arkit", "Own ARKit Keys", "Build from the head's own ARKit-named shape keys (jawOpen, ...)"),
    Choice(
        "transfer",
        "Transfer from Reference",
        "Carry the reference head's face units over, registered with the face landmarks",
    ),
    Choice(
        "obj_folder",
        "Folder of OBJ Models",
        "The thesis's way: one homeomorphic OBJ model per viseme (a.obj, bpa.obj, ..., Neutral.obj)",
    ),
)
RHO_RANGE = (1.0, 10.0)  # the empowering constant of thesis eq. 5.2 (the thesis uses 3)
