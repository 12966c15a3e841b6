"""FreeCAD Path/CAM post-processor wrapper: post with an existing post processor, then
compensate the G-code with ccomp.

Copy beside your posts (e.g. ~/.local/share/FreeCAD/Macro) as `ccomp_linuxcnc_post.py`,
set BASE_POST to the post processor it wraps (or give --ccomp-base), and choose it in the
Job's output settings. FreeCAD calls export(objectslist, filename, argstring) with the Job's
"Arguments" (PostProcessorArgs) as argstring. This wrapper takes its own settings from there
and hands the rest, unchanged, to the base post:

  --ccomp-model PATH   the machine model (YAML); else $CCOMP_MODEL
  --ccomp-tools PATH   the tool table (optional); else $CCOMP_TOOLS
  --ccomp PATH         the ccomp binary; else $CCOMP, else ccomp on PATH
  --ccomp-base NAME    the post processor it wraps; else BASE_POST below
  --ccomp-args=TEXT    any more ccomp options, as on a command line (repeatable); else
                       $CCOMP_ARGS: --sensor bed=21 --dialect fanuc --work-offset G54=X0,Y0,Z-400

e.g. Arguments: --no-show-editor --ccomp-model /etc/ccomp/machine.yaml
                --ccomp-args="--sensor bed=21 --sensor spindle=30"

FreeCAD up to 0.21 passes the output file's name: the base post writes it and this wrapper
compensates it in place (keeping name.orig). FreeCAD 1.0 passes "-" and writes the text
export() returns itself: this wrapper then returns the compensated text. A refusal raises
CcompError with ccomp's message (file:line:column); nothing compensated is written then.
tests/cli/integration_test.cpp runs it as FreeCAD does (tests/cli/freecad/, with stubs of the
FreeCAD modules a post imports).
"""
import argparse
import importlib
import os
import shlex
import subprocess

BASE_POST = "linuxcnc_post"  # the FreeCAD post processor this one wraps

TOOLTIP = "Posts with %s, then compensates the machine's errors with ccomp." % BASE_POST

# No abbreviations: a base post's own option must never be taken for one of ours.
parser = argparse.ArgumentParser(prog="ccomp_post", add_help=False, allow_abbrev=False)
parser.add_argument("--ccomp-model", help="machine model (YAML); default $CCOMP_MODEL")
parser.add_argument("--ccomp-tools", help="tool table (optional); default $CCOMP_TOOLS")
parser.add_argument("--ccomp", help="the ccomp binary; default $CCOMP, else ccomp on PATH")
parser.add_argument("--ccomp-base", help="the post processor to wrap; default %s" % BASE_POST)
# Written --ccomp-args=TEXT: argparse would take a TEXT starting with '-' for an option.
parser.add_argument("--ccomp-args", action="append",
                    help="more ccomp options as on a command line (repeatable); default $CCOMP_ARGS")

TOOLTIP_ARGS = parser.format_help() + "Other arguments go to the wrapped post processor."


class CcompError(RuntimeError):
    """ccomp could not be run, or refused the program."""


def settings(argstring=""):
    """This wrapper's settings from the post's argument string, then the environment.
    Returns (settings, the arguments left for the base post, as a string)."""
    try:
        ours, rest = parser.parse_known_args(shlex.split(argstring or ""))
    except (ValueError, SystemExit) as e:  # an unbalanced quote; a flag without its value
        raise CcompError("ccomp_post: cannot read the post processor arguments %r: %s" % (argstring, e))
    texts = ours.ccomp_args or [os.environ.get("CCOMP_ARGS", "")]  # given at all, they replace $CCOMP_ARGS
    try:
        options = [a for text in texts for a in shlex.split(text)]
    except ValueError as e:
        raise CcompError("ccomp_post: cannot read the ccomp options %r: %s" % (" ".join(texts), e))
    s = {
        "ccomp": ours.ccomp or os.environ.get("CCOMP") or "ccomp",
        "options": options,
        "model": ours.ccomp_model or os.environ.get("CCOMP_MODEL"),
        "tools": ours.ccomp_tools or os.environ.get("CCOMP_TOOLS"),
        "base": ours.ccomp_base or BASE_POST,
    }
    if not s["model"]:
        raise CcompError(
            "ccomp_post: no machine model: add --ccomp-model /path/to/machine.yaml to the Job's "
            "post processor arguments, or set CCOMP_MODEL in FreeCAD's environment"
        )
    return s, " ".join(shlex.quote(a) for a in rest)


def _run(s, arguments, text=None):
    command = [s["ccomp"]] + arguments + ["-m", s["model"]]
    if s["tools"]:
        command += ["--tool-table", s["tools"]]
    command += s.get("options", [])
    try:
        return subprocess.run(command, input=text, capture_output=True, text=True)
    except OSError as e:  # no such binary, not executable
        raise CcompError(
            "ccomp_post: cannot run ccomp as %r (%s): give its path with --ccomp or CCOMP" % (s["ccomp"], e)
        )


def _refused(what, result):
    return CcompError("ccomp refused %s (exit %d):\n%s" % (what, result.returncode, result.stderr))


def compensate(path, s=None):
    """Rewrites the G-code file at `path` with ccomp, in place (keeping path.orig).
    Raises CcompError with ccomp's message when ccomp refuses. Returns ccomp's warnings."""
    s = s or settings()[0]
    result = _run(s, [path, "--in-place"])
    if result.returncode != 0:
        raise _refused(path, result)
    return result.stderr


def compensate_text(gcode, s=None):
    """The compensated text of `gcode` (ccomp reads standard input, writes standard output)."""
    s = s or settings()[0]
    result = _run(s, ["-", "-o", "-", "-q"], text=gcode)
    if result.returncode != 0:
        raise _refused("the posted program", result)
    return result.stdout


def export(objectslist, filename, argstring):
    """FreeCAD's post-processor entry point."""
    s, rest = settings(argstring)
    base = importlib.import_module(s["base"])
    gcode = base.export(objectslist, filename, rest)
    if gcode is None:  # the base post refused its arguments or the objects (it said why)
        return None
    if filename == "-":
        return compensate_text(gcode, s)
    compensate(filename, s)
    with open(filename) as f:
        return f.read()


if __name__ == "__main__":
    import sys

    # python3 ccomp_post.py [--ccomp-model M] [--ccomp-tools T] [--ccomp BIN] [--ccomp-args=..] part.nc ...
    try:
        s, rest = settings(" ".join(shlex.quote(a) for a in sys.argv[1:]))
        for program in shlex.split(rest):
            sys.stderr.write(compensate(program, s))
    except CcompError as e:
        sys.exit(str(e))
