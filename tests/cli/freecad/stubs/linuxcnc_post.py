"""A minimal post processor shaped like FreeCAD's own (PathScripts/post/*_post.py): it
imports FreeCAD and PathScripts, reads its argument string with argparse (add_help=False) and
returns None when an argument is unknown, writes the file unless the name is "-", and returns
the G-code. It records the argument string it was given, so the test can see that the
wrapper's own arguments did not reach it."""
import argparse
import shlex

import FreeCAD
from FreeCAD import Units
from PathScripts import PathUtils, PostUtils  # noqa: F401 (imported as real posts do)

parser = argparse.ArgumentParser(prog="linuxcnc", add_help=False)
parser.add_argument("--no-show-editor", action="store_true")
parser.add_argument("--precision", default="4")

TOOLTIP_ARGS = parser.format_help()
received = []  # every argument string export() was given


def export(objectslist, filename, argstring):
    received.append(argstring)
    try:
        args = parser.parse_args(shlex.split(argstring))
    except SystemExit:  # argparse exits on an unknown argument; FreeCAD's posts return None
        return None
    fmt = "." + args.precision + "f"
    gcode = "G17 G90\nG21\n"
    for obj in objectslist:
        PathUtils.findParentJob(obj)
        for c in obj.Path.Commands:
            words = [c.Name]
            for p in ["X", "Y", "Z", "F"]:
                if p in c.Parameters:
                    v = c.Parameters[p]
                    if p == "F":
                        v = Units.Quantity(v, FreeCAD.Units.Velocity).getValueAs("mm/min")
                    words.append(p + format(v, fmt))
            gcode += " ".join(words) + "\n"
    gcode += "M5\nM2\n"
    if filename != "-":
        with open(filename, "w") as f:
            f.write(gcode)
    return gcode
