"""integration/freecad/ccomp_post.py run as FreeCAD runs a post processor: the post is
imported by name and FreeCAD calls export(objectslist, filename, job.PostProcessorArgs),
with the output file's name (FreeCAD up to 0.21) or "-" (FreeCAD 1.0, which writes the text
export() returns). The FreeCAD modules a post imports are stubs (stubs/).

  CCOMP=build/src/ccomp python3 tests/cli/freecad/freecad_post_test.py
"""
import importlib
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
sys.path[:0] = [os.path.join(HERE, "stubs"), os.path.join(SOURCE, "integration", "freecad")]

BINARY = os.environ["CCOMP"]  # this build's ccomp
ZERO = os.path.join(SOURCE, "samples", "machines", "zero.yaml")


class Command:
    def __init__(self, name, **parameters):
        self.Name, self.Parameters = name, parameters


class Operation:
    """What FreeCAD hands a post: objects with a Label and a Path of Commands."""

    def __init__(self, label, commands):
        self.Name = self.Label = label

        class _Path:
            Commands = commands

        self.Path = _Path


def profile(x_far=30.0):
    return [Operation("Profile", [Command("G0", X=0.0, Y=0.0, Z=5.0), Command("G1", Z=-1.0, F=10.0),
                                  Command("G1", X=x_far, Y=0.0, F=10.0), Command("G0", Z=5.0)])]


def without_header(text):
    return "".join(line for line in text.splitlines(True) if not line.startswith("(ccomp "))


class FreecadPost(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="ccomp_post_")
        self.addCleanup(shutil.rmtree, self.dir)
        for name in ("CCOMP", "CCOMP_MODEL", "CCOMP_TOOLS", "CCOMP_ARGS"):
            os.environ.pop(name, None)
        # A machine whose X stops at 100 mm: a program going further is refused (exit 7).
        self.small = os.path.join(self.dir, "small.yaml")
        with open(self.small, "w") as f:
            f.write("name: small\naxes: {X: {min: -100, max: 100}, Y: {min: -100, max: 100}, Z: {min: -50, max: 50}}\n")
        # FreeCAD loads the post by its module name, fresh for each export.
        for name in ("ccomp_post", "linuxcnc_post"):
            sys.modules.pop(name, None)
        self.post = importlib.import_module("ccomp_post")
        self.base = importlib.import_module("linuxcnc_post")

    def args(self, model, extra="--no-show-editor"):
        return "%s --ccomp %s --ccomp-model %s" % (extra, BINARY, model)

    def test_file_name_compensated_in_place(self):  # FreeCAD 0.19 .. 0.21
        out = os.path.join(self.dir, "part one.ngc")
        text = self.post.export(profile(), out, self.args(ZERO, "--no-show-editor --precision 3"))
        self.assertEqual(self.base.received, ["--no-show-editor --precision 3"])  # ours taken out
        with open(out) as f:
            written = f.read()
        with open(out + ".orig") as f:
            posted = f.read()
        self.assertEqual(text, written)
        self.assertTrue(written.startswith("(ccomp "), written)
        self.assertIn("G1 X30.000 Y0.000 F600.000\n", posted)
        self.assertEqual(without_header(written), posted)

    def test_dash_returns_the_compensated_text(self):  # FreeCAD 1.0 writes what export() returns
        text = self.post.export(profile(), "-", self.args(ZERO))
        self.assertTrue(text.startswith("(ccomp "), text)
        self.assertEqual(without_header(text), self.base.export(profile(), "-", "--no-show-editor"))
        self.assertEqual(os.listdir(self.dir), ["small.yaml"])  # nothing written

    def test_environment_when_the_arguments_say_nothing(self):
        os.environ.update(CCOMP=BINARY, CCOMP_MODEL=ZERO)
        text = self.post.export(profile(), "-", "")
        self.assertTrue(text.startswith("(ccomp ") and "'zero'" in text.splitlines()[0], text)
        # The arguments win over the environment.
        os.environ["CCOMP_MODEL"] = os.path.join(self.dir, "no-such.yaml")
        self.assertIn("'small'", self.post.export(profile(), "-", "--ccomp-model " + self.small).splitlines()[0])

    def test_no_model_is_a_clear_error(self):
        with self.assertRaises(self.post.CcompError) as caught:
            self.post.export(profile(), "-", "--no-show-editor --ccomp " + BINARY)
        self.assertIn("--ccomp-model", str(caught.exception))
        self.assertIn("CCOMP_MODEL", str(caught.exception))
        self.assertEqual(self.base.received, [])  # refused before posting

    def test_no_binary_is_a_clear_error(self):
        with self.assertRaises(self.post.CcompError) as caught:
            self.post.export(profile(), "-", "--ccomp /nowhere/ccomp --ccomp-model " + ZERO)
        self.assertIn("cannot run ccomp as '/nowhere/ccomp'", str(caught.exception))

    def test_refusal_carries_ccomps_message(self):
        out = os.path.join(self.dir, "far.ngc")
        for filename in (out, "-"):
            with self.assertRaises(self.post.CcompError) as caught:
                self.post.export(profile(x_far=150.0), filename, self.args(self.small))
            self.assertIn("exit 7", str(caught.exception))
            self.assertIn("axis X would go to 150", str(caught.exception))
        with open(out) as f:
            self.assertNotIn("(ccomp ", f.read())  # the posted file left uncompensated
        self.assertFalse(os.path.exists(out + ".orig"))

    def test_any_ccomp_option_passes_through(self):
        # The full sample HMC has thermal terms: refused without its sensors (the missing one
        # named), compensated with them, given as --ccomp-args (repeatable) or $CCOMP_ARGS, the
        # same as ccomp by hand.
        hmc = os.path.join(SOURCE, "samples", "machines", "hmc-xyzb.yaml")
        with self.assertRaises(self.post.CcompError) as caught:
            self.post.export(profile(), "-", self.args(hmc))
        self.assertRegex(str(caught.exception), r"sensor.*bed|bed.*sensor")
        sensors = ["--sensor", "bed=24", "--sensor", "column=23", "--sensor", "spindle=31", "--time", "3600"]
        posted = self.base.export(profile(), "-", "--no-show-editor")
        by_hand = subprocess.run([BINARY, "-", "-o", "-", "-q", "-m", hmc] + sensors + ["--tolerance", "0.002"],
                                 input=posted, capture_output=True, text=True)
        self.assertEqual(by_hand.returncode, 0, by_hand.stderr)
        self.assertNotEqual(without_header(by_hand.stdout), posted, "the thermal model moves the points")
        arguments = self.args(hmc) + ' --ccomp-args="%s" --ccomp-args="--tolerance 0.002"' % " ".join(sensors)
        self.base.received.clear()
        self.assertEqual(self.post.export(profile(), "-", arguments), by_hand.stdout)
        self.assertEqual(self.base.received, ["--no-show-editor"])  # ours taken out
        # A single option written with '=' (argparse would take a bare '--exact' for an option).
        self.assertTrue(self.post.export(profile(), "-", arguments + " --ccomp-args=--exact").startswith("(ccomp "))
        # From the environment when the arguments give none; the arguments win.
        os.environ["CCOMP_ARGS"] = " ".join(sensors) + " --tolerance 0.002"
        self.assertEqual(self.post.export(profile(), "-", self.args(hmc)), by_hand.stdout)
        with self.assertRaises(self.post.CcompError) as caught:
            self.post.export(profile(), "-", self.args(hmc) + " --ccomp-args=--dialect=klingon")
        self.assertIn("exit 2", str(caught.exception))
        os.environ.pop("CCOMP_ARGS")
        # The file form (FreeCAD 0.21): compensated in place with the options.
        out = os.path.join(self.dir, "hmc.ngc")
        self.post.export(profile(), out, arguments)
        with open(out) as f:
            self.assertEqual(f.read(), by_hand.stdout)

    def test_unbalanced_quote_in_the_ccomp_options_is_a_clear_error(self):
        with self.assertRaises(self.post.CcompError) as caught:
            self.post.export(profile(), "-", self.args(ZERO) + " --ccomp-args='--sensor \"bed=2'")
        self.assertIn("cannot read the ccomp options", str(caught.exception))

    def test_base_post_refusing_its_arguments_returns_none(self):
        self.assertIsNone(self.post.export(profile(), "-", self.args(ZERO, "--no-such-option")))


if __name__ == "__main__":
    unittest.main(verbosity=2)
