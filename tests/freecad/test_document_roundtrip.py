"""The csg example built with the workbench's features, exported with the checked export,
saved, and reopened bit-identically: after a reopen, a recompute of every feature and a save,
every object of the saved document (Document.xml from <Objects> on) and every other file in
it is byte for byte the same, and the reopened document exports the same mesh, byte for
byte. (The document's own header changes on its own: the save's date, and FreeCAD flags
its Material and Meta maps once a document has been restored.)"""

import os
import zipfile

import FreeCAD

import FRepExamples
import FRepExport


def document_files(path):
    """The saved document's files; of Document.xml, its objects."""
    with zipfile.ZipFile(path) as z:
        files = {name: z.read(name) for name in z.namelist()}
    xml = files["Document.xml"]
    assert xml.count(b"<Objects ") == 1
    files["Document.xml"] = xml[xml.index(b"<Objects "):]
    return files


def test_csg_saves_reopens_and_exports_identically(doc, tmp_path):
    part = FRepExamples.build_csg(doc)
    doc.recompute()
    first = str(tmp_path / "first.stl")
    report = FRepExport.export_objects([part], first, cells=64)
    assert report["printable"] and report["written"]
    saved = str(tmp_path / "csg.FCStd")
    doc.saveAs(saved)
    FreeCAD.closeDocument(doc.Name)
    before = document_files(saved)

    again = FreeCAD.openDocument(saved)
    try:
        assert sorted(o.Name for o in again.Objects) == sorted(
            ["Cube", "Ball", "Core", "HoleX", "HoleY", "HoleZ", "Part"])
        for obj in again.Objects:
            obj.touch()
        again.recompute()
        assert not [o.Label for o in again.Objects if "Invalid" in o.State]
        second = str(tmp_path / "second.stl")
        FRepExport.export_objects([again.getObject("Part")], second, cells=64)
        assert open(first, "rb").read() == open(second, "rb").read()
        again.save()  # (to the same file: its name is in the document)
    finally:
        FreeCAD.closeDocument(again.Name)
    after = document_files(saved)
    assert sorted(before) == sorted(after)
    changed = [name for name in before if before[name] != after[name]]
    assert not changed, changed
