"""What the tests of scripts/render.py and of video files share: running the script, decoding its videos."""

import subprocess
import sys
from pathlib import Path

import numpy as np

REPOSITORY = Path(__file__).resolve().parents[1]
RENDER_SCRIPT = REPOSITORY / "scripts" / "render.py"


def run_render(*arguments, cwd=None) -> subprocess.CompletedProcess:
    """scripts/render.py run as a pipeline runs it, in a process of its own (the caller judges its status)."""
    return subprocess.run(
        [sys.executable, str(RENDER_SCRIPT), *map(str, arguments)],
        capture_output=True, text=True, timeout=600, check=False, cwd=cwd,
    )  # fmt: skip


def decoded_media(path: Path) -> tuple[list[np.ndarray], np.ndarray]:
    """Every video frame (RGB) and audio sample (channel rows) of a file, in one pass over its packets."""
    import av

    frames, audio = [], []
    with av.open(str(path)) as container:
        for frame in container.decode(*container.streams):
            if isinstance(frame, av.VideoFrame):
                frames.append(frame.to_ndarray(format="rgb24"))
            else:
                audio.append(frame.to_ndarray())
    return frames, np.concatenate(audio, axis=1) if audio else np.zeros((1, 0))
