"""chainmail: interlocking-ring fabric through several physics models, from Python.

    import chainmail
    scene = chainmail.load_scene("curtain.json", {"weave.rows": 8, "weave.cols": 8})
    sim = chainmail.Simulation(scene, "plausible", knobs={"iterations": 20})
    sim.step(n=100)
    sim.positions        # (N, 3) float64, a read-only view of the current frame
    chainmail.run(scene, backends=["plausible", "ode"])   # summary.json as a dict

docs/python.md describes every function.
"""
import csv as _csv
import os as _os
import shutil as _shutil

# an installed package lives in <prefix>/lib/python3.X/dist-packages/chainmail: its data folder
# (scenes, shaders, plot script) and its `chainmail` binary are under the same prefix
_here = _os.path.dirname(_os.path.abspath(__file__))
_prefix = _os.path.normpath(_os.path.join(_here, "..", "..", "..", ".."))
if not _os.environ.get("CHAINMAIL_DATA_DIR") and _os.path.isdir(
        _os.path.join(_prefix, "share", "chainmail", "scenes")):
    _os.environ["CHAINMAIL_DATA_DIR"] = _os.path.join(_prefix, "share", "chainmail")

from ._chainmail import (SceneError, UsageError, OutputError, Scene,  # noqa: E402
                         Simulation, __version__, backends, load_scene, run)
try:
    from ._chainmail import render  # noqa: F401  (absent in a build without the renderer)
except ImportError:
    pass
from . import _chainmail  # noqa: E402


def _executable():
    """the `chainmail` binary that runs sweep points"""
    installed = _os.path.join(_prefix, "bin", "chainmail")
    if _os.environ.get("CHAINMAIL_EXECUTABLE"):
        return _os.environ["CHAINMAIL_EXECUTABLE"]
    if _os.path.isfile(installed):
        return installed
    try:
        from ._build import BINARY  # the build tree's
        if _os.path.isfile(BINARY):
            return BINARY
    except ImportError:
        pass
    return _shutil.which("chainmail") or "chainmail"


_chainmail._set_executable(_executable())


def sweep(scene, vary, backends=(), out=None, jobs=1, cache="", progress=False, threads=0):
    """`chainmail sweep`: one run per point of the grid `vary` (["KEY=v1,v2", ...]).

    Writes the sweep folder (default results/<scene>/sweep) and returns
    {"folder": path, "points": [one dict per row of sweep.csv]}: numbers as float, true/false as
    bool, an empty cell as None, anything else (backend, verdict) as the text.
    """
    if isinstance(vary, str):
        vary = [vary]
    folder = _chainmail._sweep(scene, list(vary), list(backends), out, jobs, cache, progress,
                               threads)
    with open(_os.path.join(folder, "sweep.csv"), newline="") as f:
        points = [{key: _cell(value) for key, value in row.items()} for row in _csv.DictReader(f)]
    return {"folder": folder, "points": points}


def _cell(text):
    """A sweep.csv cell as the value it writes."""
    if text == "":
        return None
    if text in ("true", "false"):
        return text == "true"
    try:
        return float(text)
    except ValueError:
        return text


__all__ = ["SceneError", "UsageError", "OutputError", "Scene", "Simulation", "backends", "load_scene", "run",
           "sweep", "render", "__version__"]
