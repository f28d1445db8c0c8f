"""`frepcad export part.FCStd`: run by freecadcmd (headless) from the frepcad CLI.

Opens the document, applies --set overrides (Object.Property=value, Spreadsheet.alias=value
or Spreadsheet.A1=value), recomputes, and exports with the CGAL check
(OpenSCAD's -D for FRep documents): the objects --object names, else every visible top-level
solid (FRep features, Polygonize meshes, hsplines, Part solids and meshes), each its own
object in a 3MF and their union otherwise. The arguments come in FREPCAD_EXPORT_ARGS (JSON), since
freecadcmd's own value options crash on Debian's 0.20. Exit status (frepcore.EXIT_STATUS): 0
written, 1 not printable (nothing written), 2 bad input, 3 internal error, 130 cancelled.
"""

import argparse
import json
import math
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


def shortened(text, limit=80):
    """`text` whole when short, else its start and its length: a message echoes no 100,000
    characters."""
    return text if len(text) <= limit else "%s... (%d characters)" % (text[:limit], len(text))


TRUE_WORDS, FALSE_WORDS = ("1", "true", "yes", "on"), ("0", "false", "no", "off")


def finite(word, what):
    """`word` as a finite float, or a UsageError saying what `what` takes."""
    try:
        x = float(word)
    except ValueError:
        raise UsageError("%s: '%s' is not a number" % (what, shortened(word.strip())))
    if not math.isfinite(x):
        raise UsageError("%s: %s is not a finite number" % (what, shortened(word.strip())))
    return x


def parsed_value(obj, prop, value, what):
    """The value to give obj.prop for the text `value`, checked against the property's type:
    a quantity of the property's unit, a whole number, a finite number, a boolean word, three
    numbers for a vector, one of an enumeration's values, or text."""
    import FreeCAD
    current = getattr(obj, prop)
    value = value.strip()
    if not value:
        raise UsageError("%s: a value is needed after '='" % what)
    if isinstance(current, FreeCAD.Units.Quantity):
        unit = current.getUserPreferred()[2]
        try:
            q = FreeCAD.Units.Quantity(value)
        except Exception:  # FreeCAD's parser raises its own error types
            raise UsageError("%s: '%s' is not a quantity (a number, with a unit or without: "
                             "%s is taken then)" % (what, shortened(value), unit))
        if q.Unit == FreeCAD.Units.Unit():
            # a plain number: Python's reading (FreeCAD's parser reads 300 nines as 0)
            return FreeCAD.Units.Quantity(finite(value, what), current.Unit)
        if not math.isfinite(q.Value):
            raise UsageError("%s: %s is not a finite quantity" % (what, shortened(value)))
        if q.Unit != current.Unit:
            raise UsageError("%s: the property is in %s; '%s' is another kind of quantity"
                             % (what, unit, shortened(value)))
        return q
    if isinstance(current, bool):
        if value.lower() in TRUE_WORDS or value.lower() in FALSE_WORDS:
            return value.lower() in TRUE_WORDS
        raise UsageError("%s: '%s' is not a yes or no; allowed: %s" % (
            what, shortened(value), ", ".join(TRUE_WORDS + FALSE_WORDS)))
    if isinstance(current, int):
        try:
            return int(value)
        except ValueError:
            raise UsageError("%s: '%s' is not a whole number" % (what, shortened(value)))
    if isinstance(current, float):
        return finite(value, what)
    if isinstance(current, FreeCAD.Vector):
        words = value.split(",")
        if len(words) != 3:
            raise UsageError("%s: a vector takes three numbers x,y,z; got %d" % (what,
                                                                                 len(words)))
        return FreeCAD.Vector(*[finite(w, what) for w in words])
    if obj.getTypeIdOfProperty(prop) == "App::PropertyEnumeration":
        allowed = obj.getEnumerationsOfProperty(prop)
        if value not in allowed:
            raise UsageError("%s: '%s' is not one of its values; allowed: %s"
                             % (what, shortened(value), ", ".join(allowed)))
        return value
    if isinstance(current, str):
        return value
    raise UsageError("%s: a %s cannot be set from the command line; allowed: numbers, "
                     "quantities, yes/no, vectors, enumerations and text"
                     % (what, obj.getTypeIdOfProperty(prop)))


def stored_as_asked(current, asked):
    """Whether FreeCAD kept the value it was given: a length property clamps -1 to 0 and an
    overflow to 0 without a word."""
    import FreeCAD
    if isinstance(asked, FreeCAD.Units.Quantity):
        current, asked = current.Value, asked.Value
    if isinstance(asked, float) and not isinstance(asked, bool):
        return abs(current - asked) <= 1e-9 * max(1.0, abs(asked))
    return True


def apply_override(doc, text):
    if "=" not in text or "." not in text.split("=", 1)[0]:
        raise UsageError("--set %s: expected Object.Property=value" % shortened(text))
    target, value = text.split("=", 1)
    name, prop = target.split(".", 1)
    what = "--set %s" % shortened(target)
    obj = doc.getObject(name) or next(iter(doc.getObjectsByLabel(name)), None)
    if obj is None:
        raise UsageError("%s: no object '%s' in %s" % (what, shortened(name), doc.Label))
    if obj.TypeId == "Spreadsheet::Sheet":
        if not value.strip():
            raise UsageError("%s: a value is needed after '='" % what)
        cell = obj.getCellFromAlias(prop) or prop
        obj.set(cell, value)
        return
    if prop not in obj.PropertiesList:
        raise UsageError("%s: %s has no property '%s'; properties: %s"
                         % (what, obj.Label, shortened(prop),
                            ", ".join(sorted(obj.PropertiesList))))
    driven = [e for p_, e in obj.ExpressionEngine if p_ == prop or p_.startswith(prop + ".")]
    if driven:
        raise UsageError("%s: %s.%s is driven by the expression '%s'; set what it reads "
                         "instead (e.g. the spreadsheet cell)" % (what, obj.Label, prop,
                                                                  driven[0]))
    asked = parsed_value(obj, prop, value, what)
    try:
        setattr(obj, prop, asked)
    except Exception as e:  # FreeCAD's range and type errors
        raise UsageError("%s: FreeCAD refuses '%s': %s" % (what, shortened(value.strip()), e))
    if not stored_as_asked(getattr(obj, prop), asked):
        raise UsageError("%s: %s is out of the property's range (FreeCAD would store %s)"
                         % (what, shortened(value.strip()), getattr(obj, prop)))


def exportable(obj):
    """Whether frepcad exports obj: an FRep feature or input (Part solids, PartDesign bodies,
    meshes: lattice-deformed, repaired, imported), a Polygonize feature or an hspline."""
    import FRepHSpline
    import FRepPolygonize
    import FRepTree
    return (isinstance(getattr(obj, "Proxy", None), FRepPolygonize.Polygonize)
            or FRepHSpline.is_hspline(obj) or FRepTree.is_frep_input(obj))


def top_level_solids(doc):
    """The visible exportable objects that no other exportable object is built from."""
    return [o for o in doc.Objects if exportable(o) and getattr(o, "Visibility", True)
            and not any(exportable(p) for p in o.InList)]


def candidates_text(doc, limit=20):
    """The objects frepcad can export, by name and label, for a message."""
    found = [o for o in doc.Objects if exportable(o)]
    names = [o.Name if o.Label == o.Name else "%s ('%s')" % (o.Name, shortened(o.Label, 40))
             for o in found[:limit]]
    return (", ".join(names) + (", ..." if len(found) > limit else "")) or "none"


def choose_objects(doc, names):
    """The objects named by --object (by name or label), else every visible top-level solid."""
    chosen = []
    for name in names:
        obj = doc.getObject(name) or next(iter(doc.getObjectsByLabel(name)), None)
        if obj is None:
            raise UsageError("--object %s: no such object in %s; it can export: %s"
                             % (name, doc.Label, candidates_text(doc)))
        if not exportable(obj):
            raise UsageError("--object %s: %s (%s) is not a solid, mesh or FRep feature; %s "
                             "can export: %s" % (name, obj.Label, obj.TypeId, doc.Label,
                                                 candidates_text(doc)))
        chosen.append(obj)
    if chosen:
        return chosen
    tops = top_level_solids(doc)
    if not tops:
        raise UsageError("%s has no visible solid to export; it can export: %s (choose with "
                         "--object NAME)" % (doc.Label, candidates_text(doc)))
    return tops


def quiet_console_errors(quiet):
    """FreeCAD's console prints errors on stderr: off while the document recomputes."""
    import FreeCAD
    try:
        FreeCAD.Console.SetStatus("Console", "Err", not quiet)
    except Exception:  # (no such observer in this FreeCAD: its lines stay)
        pass


def report_stream():
    """fd 3 is frepcad's stdout (FreeCAD's own stdout chatter goes to /dev/null)."""
    try:
        return os.fdopen(3, "w")
    except OSError:
        return sys.stdout


def is_empty_solid(obj):
    """Whether obj is an FRep input whose solid has no point inside (its feature fails with
    "the result is empty")."""
    import FRepTree
    if not FRepTree.is_frep_input(obj):
        return False
    try:
        return FRepTree.shape_of(obj).bounds()["empty"]
    except ValueError:
        return False


def main(out):
    args = parse_args(json.loads(os.environ["FREPCAD_EXPORT_ARGS"]))
    import FreeCAD
    import FRepExport
    from FRepPaths import frepcore
    declared = validate_document(args.document)
    quiet_console_errors(True)  # (a damaged value is named below, by its object)
    try:
        doc = FreeCAD.openDocument(os.path.abspath(args.document))
    except Exception as e:  # FreeCAD's own errors (Base.FreeCADError) are not ValueErrors
        raise UsageError("%s: FreeCAD cannot open it: %s" % (args.document, e))
    finally:
        quiet_console_errors(False)
    # Objects FreeCAD could not make (an unknown class or module, a damaged entry) are
    # dropped silently by openDocument: an export of what survived would be wrong.
    missing = [(n, t) for n, t in declared if doc.getObject(n) is None]
    if missing:
        raise UsageError("%s: %d object(s) could not be loaded: %s (unknown class or module, "
                         "or a damaged entry)" % (args.document, len(missing), ", ".join(
                             "%s (%s)" % (n, t) for n, t in missing[:5])))
    for text in args.sets:
        apply_override(doc, text)
    chosen = choose_objects(doc, args.objects)
    is_3mf = args.output.lower().endswith(".3mf") or args.format == "3mf"
    if len(chosen) > 1 and not is_3mf and not args.quiet:
        print("frepcad: %s: exporting the union of %s (a .3mf keeps each its own object; "
              "--object NAME exports one)" % (args.document, ", ".join(o.Label for o in chosen)),
              file=sys.stderr)
    for o in doc.Objects:  # recompute everything: the saved results may be stale
        o.touch()
    # FreeCAD reports each failed feature on its console ("Error: ...", then "Recompute
    # failed! Please check report view."): the failures are gathered below into one line.
    quiet_console_errors(True)
    try:
        doc.recompute()
    except Exception as e:
        raise UsageError("%s: recompute failed: %s" % (args.document, e))
    finally:
        quiet_console_errors(False)
    failed = [o for o in doc.Objects if not o.isValid()]
    if failed:
        message = "; ".join(o.getStatusString() for o in failed)
        if all(is_empty_solid(o) for o in failed):  # nothing to print: the verdict, as frepcad's
            raise frepcore.EmptySolid(message)
        raise UsageError(message)
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
