"""`frepcad export part.FCStd`: run by freecadcmd (headless) from the frepcad CLI.

Opens the document, applies --set overrides (Object.Property=value, Spreadsheet.alias=value
or Spreadsheet.A1=value), recomputes, and exports the chosen object with the CGAL check
(OpenSCAD's -D for FRep documents). The arguments come in FREPCAD_EXPORT_ARGS (JSON), since
freecadcmd's own value options crash on Debian's 0.20. Exit status: 0 written, 1 not
printable (nothing written), 2 bad input.
"""

import argparse
import json
import os
import sys


class UsageError(Exception):
    pass


def parse_args(argv):
    p = argparse.ArgumentParser(prog="frepcad export", add_help=False)
    p.add_argument("document")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--object")
    p.add_argument("--set", action="append", default=[], dest="sets")
    p.add_argument("--cells", type=int)
    p.add_argument("--resolution", type=float)
    p.add_argument("--format", default="")
    p.add_argument("--quiet", action="store_true")

    def fail(message):
        raise UsageError(message)

    p.error = fail
    return p.parse_args(argv)


def apply_override(doc, text):
    import FreeCAD
    if "=" not in text or "." not in text.split("=", 1)[0]:
        raise UsageError("--set %s: expected Object.Property=value" % text)
    target, value = text.split("=", 1)
    name, prop = target.split(".", 1)
    obj = doc.getObject(name) or next(iter(doc.getObjectsByLabel(name)), None)
    if obj is None:
        raise UsageError("--set %s: no object '%s' in %s" % (text, name, doc.Label))
    if obj.TypeId == "Spreadsheet::Sheet":
        cell = obj.getCellFromAlias(prop) or prop
        obj.set(cell, value)
        return
    if prop not in obj.PropertiesList:
        raise UsageError("--set %s: %s has no property '%s'; properties: %s"
                         % (text, obj.Label, prop, ", ".join(sorted(obj.PropertiesList))))
    driven = [e for p_, e in obj.ExpressionEngine if p_ == prop or p_.startswith(prop + ".")]
    if driven:
        raise UsageError("--set %s: %s.%s is driven by the expression '%s'; set what it reads "
                         "instead (e.g. the spreadsheet cell)" % (text, obj.Label, prop,
                                                                  driven[0]))
    current = getattr(obj, prop)
    try:
        if isinstance(current, FreeCAD.Units.Quantity):
            q = FreeCAD.Units.Quantity(value)
            setattr(obj, prop, q if str(q.Unit) != "Unit: ()" else float(value))
        elif isinstance(current, bool):
            setattr(obj, prop, value.lower() in ("1", "true", "yes", "on"))
        elif isinstance(current, int):
            setattr(obj, prop, int(value))
        elif isinstance(current, float):
            setattr(obj, prop, float(value))
        elif isinstance(current, FreeCAD.Vector):
            setattr(obj, prop, FreeCAD.Vector(*[float(v) for v in value.split(",")]))
        else:
            setattr(obj, prop, value)
    except (ValueError, TypeError) as e:
        raise UsageError("--set %s: %s" % (text, e))


def choose_object(doc, name):
    import FRepPolygonize
    import FRepTree
    if name:
        obj = doc.getObject(name) or next(iter(doc.getObjectsByLabel(name)), None)
        if obj is None:
            raise UsageError("--object %s: no such object in %s" % (name, doc.Label))
        return obj
    meshes = [o for o in doc.Objects
              if isinstance(getattr(o, "Proxy", None), FRepPolygonize.Polygonize)]
    if len(meshes) == 1:
        return meshes[0]
    tops = [o for o in doc.Objects if FRepTree.is_frep_feature(o)
            and not any(FRepTree.is_frep_feature(p) for p in o.InList)]
    if len(tops) == 1 and not meshes:
        return tops[0]
    raise UsageError("%s has %d Polygonize features and %d top-level FRep features; choose one "
                     "with --object NAME" % (doc.Label, len(meshes), len(tops)))


def report_stream():
    """fd 3 is frepcad's stdout (FreeCAD's own stdout chatter goes to /dev/null)."""
    try:
        return os.fdopen(3, "w")
    except OSError:
        return sys.stdout


def main(out):
    args = parse_args(json.loads(os.environ["FREPCAD_EXPORT_ARGS"]))
    import FreeCAD
    import FRepExport
    from FRepPaths import frepcore
    if not os.path.exists(args.document):
        raise UsageError("%s: no such file" % args.document)
    doc = FreeCAD.openDocument(os.path.abspath(args.document))
    for text in args.sets:
        apply_override(doc, text)
    obj = choose_object(doc, args.object)
    for o in doc.Objects:  # recompute everything: the saved results may be stale
        o.touch()
    doc.recompute()
    failed = [o for o in doc.Objects if not o.isValid()]
    if failed:
        raise UsageError("; ".join(o.getStatusString() for o in failed))
    try:
        report = FRepExport.export_objects([obj], args.output, progress=lambda f: True,
                                           cells=args.cells, fmt=args.format)
    except frepcore.NotPrintable as e:
        print(e.report["text"], file=out)
        print("frepcad: refusing to write %s: the mesh is not printable" % args.output,
              file=sys.stderr)
        return 1
    if not args.quiet:
        print(report["text"], file=out)
        print("wrote %s from %s (%s)" % (args.output, args.document, obj.Label), file=out)
    return 0


def run():
    out = report_stream()
    try:
        rc = main(out)
    except (UsageError, ValueError, OSError) as e:
        print("frepcad: %s" % e, file=sys.stderr)
        rc = 2
    except Exception as e:  # anything else is a bug: say so, never exit 0
        import traceback
        traceback.print_exc()
        print("frepcad: internal error: %s" % e, file=sys.stderr)
        rc = 3
    out.flush()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(rc)  # freecadcmd would exit 0 whatever happened


run()
