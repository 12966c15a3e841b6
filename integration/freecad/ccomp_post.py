"""FreeCAD Path/CAM post-processor wrapper: post with an existing post processor, then
compensate the file with ccomp.

Copy beside your posts (e.g. ~/.local/share/FreeCAD/Macro) as `ccomp_linuxcnc_post.py`,
set BASE_POST to the post processor it wraps, and choose it in the Job's output settings.
Configure with environment variables or the constants below:
  CCOMP        the ccomp binary (default: ccomp on PATH)
  CCOMP_MODEL  the machine model (YAML)
  CCOMP_TOOLS  the tool table (optional)
tests/cli/integration_test.cpp runs compensate() on a real file.
"""
import importlib
import os
import subprocess

BASE_POST = "linuxcnc_post"  # the FreeCAD post processor this one wraps

TOOLTIP = "Posts with %s, then compensates the machine's errors with ccomp." % BASE_POST


def compensate(path):
    """Rewrites the G-code file at `path` with ccomp, in place (keeping path.orig).
    Raises RuntimeError with ccomp's message when ccomp refuses."""
    command = [os.environ.get("CCOMP", "ccomp"), path, "-m", os.environ["CCOMP_MODEL"], "--in-place"]
    if os.environ.get("CCOMP_TOOLS"):
        command += ["--tool-table", os.environ["CCOMP_TOOLS"]]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError("ccomp refused %s (exit %d):\n%s" % (path, result.returncode, result.stderr))
    return result.stderr  # warnings, if any


def export(objectslist, filename, argstring):
    """FreeCAD's post-processor entry point."""
    base = importlib.import_module(BASE_POST)
    gcode = base.export(objectslist, filename, argstring)
    if filename != "-":
        compensate(filename)
        with open(filename) as f:
            gcode = f.read()
    return gcode


if __name__ == "__main__":
    import sys

    for program in sys.argv[1:]:
        sys.stderr.write(compensate(program))
