"""What a user reads in the report view when a feature fails: run in a real FreeCAD process
(freecadcmd prints the report view's lines to its output), since FreeCAD imported as a module
prints nothing."""

import os
import subprocess
import textwrap

SCRIPT = textwrap.dedent("""
    import os
    import sys
    import FreeCAD
    import FRepExport
    import FRepFeatures as F

    def say(*words):
        print("@@", *words, flush=True)

    doc = FreeCAD.newDocument("Errors")
    ball = F.make("sphere", doc, name="Ball", radius=1)
    grow = F.make("offset", doc, inputs=[ball], name="Grow")
    doc.recompute()
    say("made", ball.State, grow.State)
    ball.Radius = 0
    doc.recompute()
    say("failed", ball.State, grow.State, getattr(sys, "tracebacklimit", "unset"))
    try:
        FRepExport.export_objects([grow], os.environ["FREP_TEST_OUTPUT"])
        say("exported")
    except ValueError as e:
        say("refused", e)
    ball.Radius = 2
    doc.recompute()
    say("fixed", ball.State, grow.State)
    # a bug (not a user's error) keeps its traceback, also right after a user's error
    ball.Radius = 0
    doc.recompute()
    F.FRepFeature.local_shape = lambda self, obj, builder: 1 / 0
    ball.Radius = 3
    doc.recompute()
    say("bug", ball.State, grow.State)
""")


def run_freecad(tmp_path):
    script = tmp_path / "errors.py"
    script.write_text(SCRIPT)
    env = dict(os.environ, FREP_TEST_OUTPUT=str(tmp_path / "grow.stl"))
    out = subprocess.run(["freecadcmd", str(script)], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True, timeout=120, env=env)
    return out.stdout


def said(text, what):
    lines = [line[3:] for line in text.splitlines() if line.startswith("@@ " + what)]
    assert len(lines) == 1, text
    return lines[0]


def test_user_error_is_one_line_dependents_wait_export_refuses(tmp_path):
    text = run_freecad(tmp_path)
    assert said(text, "made") == "made ['Up-to-date'] ['Up-to-date']"
    # the report view: the object, the property and what is allowed, in one line
    line = "Error: Ball: property 'Radius' = 0 mm is out of range; allowed: (0, inf) mm"
    assert text.count(line) == 2, text  # (the radius was set to 0 twice)
    # the dependent is not left "up to date" with the old result; tracebacks are back on
    assert said(text, "failed") == "failed ['Touched', 'Invalid'] ['Touched'] unset"
    assert said(text, "refused") == (
        "refused Grow is built on Ball, which failed its last recompute (Ball: property "
        "'Radius' = 0 mm is out of range; allowed: (0, inf) mm); fix it and recompute "
        "before exporting")
    assert not (tmp_path / "grow.stl").exists()
    assert said(text, "fixed") == "fixed ['Up-to-date'] ['Up-to-date']"
    # the only traceback is the bug's
    assert text.count("Traceback (most recent call last)") == 1, text
    assert "ZeroDivisionError" in text
    assert said(text, "bug") == "bug ['Touched', 'Invalid'] ['Touched']"
