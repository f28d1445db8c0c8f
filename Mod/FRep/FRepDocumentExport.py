"""`frepcad export part.FCStd`: run by freecadcmd (headless) from the frepcad CLI.

Opens the document, applies --set overrides (Object.Property=value, Spreadsheet.alias=value
or Spreadsheet.A1=value), recomputes, and exports the chosen object with the CGAL check
(OpenSCAD's -D for FRep documents). The arguments come in FREPCAD_EXPORT_ARGS (JSON), since
freecadcmd's own value options crash on Debian's 0.20. Exit status (frepcore.EXIT_STATUS): 0
written, 1 not printable (nothing written), 2 bad input, 3 internal error, 130 cancelled.
"""

import argparse
import json
import os
import signal
import sys


class UsageError(ValueError):
    """A bad option or document: exit status 2, one line."""


KEYS = ("document", "output", "format", "objects", "sets", "force", "quiet", "cells",
        "resolution", "bbox", "units", "settings")


def parse_args(options):
    """The options frepcad parsed (the same as for JSON models), as attributes."""
    if not isinstance(options, dict) or set(options) != set(KEYS):
        raise UsageError("internal: unexpected export options %r" % (options,))
    return argparse.Namespace(**options)


# A document is refused before FreeCAD opens it when it could cost memory or time out of
# proportion: more members or more bytes unpacked than any real document has.
MAX_MEMBERS = 20000
MAX_UNPACKED_BYTES = 1 << 30
MAX_DOCUMENT_XML_BYTES = 256 << 20


def validate_document(path):
    """The document must be a zip archive holding a well-formed Document.xml, and must not
    unpack to more than MAX_UNPACKED_BYTES (a zip bomb). Returns the object names and types
    that Document.xml declares."""
    import xml.etree.ElementTree as ET
    import zipfile
    if os.path.isdir(path):
        raise UsageError("%s: is a folder, not a FreeCAD document" % path)
    if not os.path.isfile(path):
        raise UsageError("%s: no such file, or not a regular file" % path)
    if not zipfile.is_zipfile(path):
        raise UsageError("%s: not a FreeCAD document (an .FCStd file is a zip archive)" % path)
    try:
        with zipfile.ZipFile(path) as z:
            infos = z.infolist()
            if len(infos) > MAX_MEMBERS:
                raise UsageError("%s: %d files in the archive; at most %d are read"
                                 % (path, len(infos), MAX_MEMBERS))
            unpacked = sum(i.file_size for i in infos)
            if unpacked > MAX_UNPACKED_BYTES:
                raise UsageError("%s: unpacks to %d bytes; at most %d are read (a damaged or "
                                 "hostile archive)" % (path, unpacked, MAX_UNPACKED_BYTES))
            if "Document.xml" not in z.namelist():
                raise UsageError("%s: not a FreeCAD document (no Document.xml in the archive)"
                                 % path)
            with z.open("Document.xml") as f:
                text = f.read(MAX_DOCUMENT_XML_BYTES + 1)
            if len(text) > MAX_DOCUMENT_XML_BYTES:
                raise UsageError("%s: Document.xml is larger than %d bytes"
                                 % (path, MAX_DOCUMENT_XML_BYTES))
    except (zipfile.BadZipFile, zipfile.LargeZipFile, OSError, EOFError, RuntimeError) as e:
        raise UsageError("%s: the archive is damaged: %s" % (path, e))
    try:
        root = ET.fromstring(text)
    except ET.ParseError as e:
        raise UsageError("%s: Document.xml is not well-formed XML (%s): the document is "
                         "truncated or damaged" % (path, e))
    if root.tag != "Document":
        raise UsageError("%s: Document.xml does not hold a FreeCAD document" % path)
    objects = root.find("Objects")
    declared = []
    if objects is not None:
        for o in objects.findall("Object"):
            declared.append((o.get("name"), o.get("type")))
    return declared


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
    except Exception as e:  # ValueError, TypeError, FreeCAD's range errors
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
    declared = validate_document(args.document)
    try:
        doc = FreeCAD.openDocument(os.path.abspath(args.document))
    except Exception as e:  # FreeCAD's own errors (Base.FreeCADError) are not ValueErrors
        raise UsageError("%s: FreeCAD cannot open it: %s" % (args.document, e))
    # Objects FreeCAD could not make (an unknown class or module, a damaged entry) are
    # dropped silently by openDocument: an export of what survived would be wrong.
    missing = [(n, t) for n, t in declared if doc.getObject(n) is None]
    if missing:
        raise UsageError("%s: %d object(s) could not be loaded: %s (unknown class or module, "
                         "or a damaged entry)" % (args.document, len(missing), ", ".join(
                             "%s (%s)" % (n, t) for n, t in missing[:5])))
    for text in args.sets:
        apply_override(doc, text)
    chosen = [choose_object(doc, name) for name in args.objects] or [choose_object(doc, "")]
    for o in doc.Objects:  # recompute everything: the saved results may be stale
        o.touch()
    try:
        doc.recompute()
    except Exception as e:
        raise UsageError("%s: recompute failed: %s" % (args.document, e))
    failed = [o for o in doc.Objects if not o.isValid()]
    if failed:
        raise UsageError("; ".join(o.getStatusString() for o in failed))
    # SIGTERM (frepcad passes Ctrl-C on as one) cancels at the next progress report, so
    # the temporary file is removed and nothing is written.
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(True))
    signal.signal(signal.SIGINT, lambda *_: stop.append(True))
    try:
        report = FRepExport.export_objects(
            chosen, args.output, progress=lambda f: not stop, cells=args.cells,
            resolution=args.resolution, bbox=args.bbox, fmt=args.format, force=args.force,
            unit=args.units or "mm", settings=args.settings)
    except frepcore.NotPrintable as e:
        print(e.report["text"], file=out)
        print("frepcad: refusing to write %s: the mesh is not printable (see reasons above; "
              "--force writes it anyway)" % args.output, file=sys.stderr)
        return frepcore.exit_status_of(e)
    except RuntimeError:
        if stop:
            print("frepcad: cancelled; nothing written", file=sys.stderr)
            return frepcore.EXIT_STATUS["cancelled"]
        raise
    if not args.quiet:
        print(report["text"], file=out)
        print("wrote %s from %s (%s)" % (args.output, args.document,
                                         ", ".join(o.Label for o in chosen)), file=out)
    return frepcore.EXIT_STATUS["done" if report["printable"] else "not_printable"]


def report_error(error):
    """Prints the one line for `error` and returns frepcad's exit status for it; an
    internal error (a bug) gets its traceback too."""
    try:
        from FRepPaths import frepcore
        rc = frepcore.exit_status_of(error)
        internal = rc == frepcore.EXIT_STATUS["internal_error"]
    except Exception:  # (no frepcore to say: whatever it is, it is not the user's)
        rc, internal = 3, True
    if internal:
        import traceback
        traceback.print_exc()
        print("frepcad: internal error (a bug: please report it): %s" % error, file=sys.stderr)
    else:
        print("frepcad: %s" % error, file=sys.stderr)
    return rc


def run():
    rc = 3  # (should anything below fail, never exit 0)
    try:
        out = report_stream()
        try:
            rc = main(out)
        except Exception as e:
            rc = report_error(e)
        out.flush()
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(rc)  # freecadcmd would exit 0 whatever happened


run()
