import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_the_core_imports_and_runs_with_bpy_unavailable():
    # A meta-path finder that refuses bpy and mathutils: any import of them in the core fails loudly.
    program = """
import sys
class Refuse:
    def find_spec(self, name, path=None, target=None):
        if name.split('.')[0] in ('bpy', 'mathutils', 'bmesh'):
            raise ImportError('blocked: ' + name)
sys.meta_path.insert(0, Refuse())
import importlib, pkgutil
import turkish_lipsync.core as core
for module in pkgutil.walk_packages(core.__path__, 'turkish_lipsync.core.'):
    importlib.import_module(module.name)
from turkish_lipsync.core.text.utterance import build_utterance
from turkish_lipsync.core.speech.timing import table_timeline
from turkish_lipsync.core.motion import weight_tracks
tracks = weight_tracks(table_timeline(build_utterance('Merhaba, benim adım Erdem.')), 25, mode='thesis')
print(len(tracks.tracks))
"""
    result = subprocess.run(
        [sys.executable, "-c", program], cwd=ROOT, capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 0, result.stderr
    assert int(result.stdout.split()[-1]) > 5
