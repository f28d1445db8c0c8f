"""Checked export of FRep solids: File > Export "FRep mesh (*.stl *.obj *.ply)" and
"FRep 3MF (*.3mf)", the Export command and `frepcad export part.FCStd` all come here.

The solid is meshed from its tree (not from the preview), checked with CGAL, and written
through a temporary file and a rename: a mesh that fails the check, a cancel or an error
leaves no file. Selected Polygonize features export with their own box and resolution.
A 3MF holds each selected object as an object of its own (named by its label), each checked
as the file holds it.
"""

import os

import FreeCAD

import FRepErrors
import FRepHSpline
import FRepMeshing
import FRepPolygonize
import FRepTree
from FRepPaths import frepcore

FILTER = "FRep mesh (*.stl *.obj *.ply)"
FILTER_3MF = "FRep 3MF (*.3mf)"


def export(objects, filename):
    """FreeCAD's export filter entry point."""
    try:
        report = export_objects(objects, filename)
        FreeCAD.Console.PrintMessage(report["text"] + "\n")
    except Exception as e:
        FreeCAD.Console.PrintError("FRep export: %s\n" % e)
        if FreeCAD.GuiUp:
            from PySide import QtGui
            QtGui.QMessageBox.critical(None, "FRep export", str(e))
        raise


def solid_and_box(objects, cells=None, resolution=None, bbox=None):
    """The union of the objects' solids and its meshing box and cell size (libcore's box
    policy, through frepcore.automatic_box)."""
    if not objects:
        raise ValueError("nothing to export: select FRep features or Polygonize features")
    shapes, boxes = [], []
    for obj in objects:
        refuse_failed(obj)
        if isinstance(getattr(obj, "Proxy", None), FRepPolygonize.Polygonize):
            if obj.Source is None:
                raise ValueError("%s: property 'Source' is empty" % obj.Label)
            shape = FRepTree.shape_of(obj.Source)
            boxes.append(FRepPolygonize.meshing_box(obj, shape))
        elif FRepHSpline.is_hspline(obj):
            try:
                shape = frepcore.from_mesh(mesh_of(obj), name=obj.Label)
            except OSError as e:  # open: not a solid (the message names it)
                raise ValueError(str(e))
        elif FRepTree.is_frep_input(obj):
            shape = FRepTree.shape_of(obj)
        else:
            raise ValueError("%s is not an FRep input, a Polygonize feature or an hspline; "
                             "accepted: %s" % (FRepTree.describe(obj), FRepTree.ACCEPTED))
        shapes.append(shape)
    solid = shapes[0] if len(shapes) == 1 else frepcore.union(*shapes)
    if len(objects) == 1 and boxes and cells is None and resolution is None and bbox is None:
        return solid, boxes[0]
    label = ", ".join(o.Label for o in objects)
    try:
        return solid, frepcore.automatic_box(solid, cells=cells, resolution=resolution,
                                             bbox=bbox)
    except frepcore.EmptySolid as e:  # (not printable, which the exit status tells apart)
        raise frepcore.EmptySolid("%s: %s" % (label, e))
    except ValueError as e:
        raise ValueError("%s: %s" % (label, e))


def is_plain_mesh(obj):
    """A Mesh feature of FreeCAD's own (imported, repaired, made by another workbench), or an
    hspline (its own tessellation), not a feature whose mesh is the preview of a solid."""
    return obj.TypeId == "Mesh::Feature" or FRepHSpline.is_hspline(obj)


def kept_as_it_is(obj, cells, resolution, bbox, settings):
    """Whether obj is written as its own mesh: a plain mesh, and no box, size or meshing
    setting asked for (any of them means: mesh it again)."""
    return (is_plain_mesh(obj) and cells is None and resolution is None and bbox is None
            and not settings)


def mesh_of(obj):
    """The frepcore mesh of a plain mesh (is_plain_mesh), placed: a Mesh feature's own, an
    hspline's surface tessellated within the document's solid tolerance."""
    import FRepSolids
    if FRepHSpline.is_hspline(obj):
        tolerance = FRepSolids.solid_tolerance(obj.Document, obj.Shape)
        if obj.Placement.isIdentity():
            return FRepHSpline.hspline_of(obj).tessellate(tolerance)
        import MeshPart
        return FRepSolids.as_frepcore_mesh(MeshPart.meshFromShape(
            Shape=obj.Shape, LinearDeflection=tolerance,
            AngularDeflection=FRepSolids.ANGULAR_DEFLECTION, Relative=False))
    return FRepSolids.as_frepcore_mesh(obj.Mesh)  # (its points already placed)


def _export_mesh_as_it_is(obj, filename, fmt, force, progress):
    """A mesh that is the part itself is written as it is, after the same check: meshing it
    again (through its distance field) would only change it."""
    name = os.path.basename(filename)
    mesh = mesh_of(obj)
    if mesh.triangle_count == 0:
        raise ValueError("%s: the mesh is empty" % obj.Label)

    def work(tick):
        report = mesh.check(name, tick)
        if not report["printable"] and not force:
            raise frepcore.NotPrintable("%s: not written, the mesh is not printable: %s"
                                        % (filename, "; ".join(report["reasons"])), report)
        try:
            mesh.write(filename, fmt, tick)
        except frepcore.Cancelled:
            raise RuntimeError("export of %s cancelled; no file written" % name)
        report["written"] = True
        return report

    if progress is not None:
        return work(progress)
    return FRepMeshing.run_with_progress("Exporting %s" % name, work)


def refuse_failed(obj):
    """A ValueError when anything obj is built from failed its last recompute. (obj itself
    is meshed from its properties, which the tree checks again; its own failure may have
    been a cancelled preview.)"""
    why = FRepErrors.built_on_failed(obj, "recompute before exporting")
    if why:
        raise ValueError(why)


def settings_for(obj, given):
    """The meshing settings an object exports with: a Polygonize feature's own, else the
    defaults, with `given` (a dict of meshing options: frepcad export's flags) over them."""
    own = isinstance(getattr(obj, "Proxy", None), FRepPolygonize.Polygonize)
    settings = FRepPolygonize.settings_of(obj) if own else None
    return frepcore.mesh_settings(settings, **(given or {}))


def export_objects(objects, filename, progress=None, cells=None, fmt="", resolution=None,
                   bbox=None, force=False, unit="mm", settings=None):
    """Meshes, checks and writes (libcore's export pipeline); returns the check report (a
    dict with 'text' and 'written'). A single Polygonize feature exports with its own
    meshing settings; `settings` (a dict of meshing options, as frepcore's export takes
    them) go over them. A .3mf holds each object as its own, in `unit`; other formats the
    objects' union.

    Raises frepcore.NotPrintable (nothing written) when the check fails and force is not
    given, RuntimeError when cancelled (nothing written), ValueError for bad input.
    """
    if fmt == "3mf-beams":
        return _export_beams(objects, filename, progress, cells, resolution, bbox, force,
                             settings, unit)
    if filename.lower().endswith(".3mf") or fmt == "3mf":
        return _export_3mf(objects, filename, progress, cells, resolution, bbox, force,
                           settings, unit)
    if unit != "mm":
        raise ValueError("%s: a unit applies to a 3MF output only" % os.path.basename(filename))
    if len(objects) == 1 and kept_as_it_is(objects[0], cells, resolution, bbox, settings) and \
            not filename.lower().endswith(".vdb"):
        return _export_mesh_as_it_is(objects[0], filename, fmt, force, progress)
    solid, (box, cell) = solid_and_box(objects, cells, resolution, bbox)
    name = os.path.basename(filename)
    if filename.lower().endswith(".vdb"):
        return _export_level_set(solid, box, cell, filename, progress)
    # a single Polygonize feature exports as it meshes
    chosen = settings_for(objects[0] if len(objects) == 1 else None, settings)

    def work(tick):
        try:
            report = solid.export(filename, resolution=cell, bbox=box, format=fmt,
                                  progress=tick, force=force, settings=chosen)
        except frepcore.Cancelled:
            raise RuntimeError("export of %s cancelled; no file written" % name)
        FRepMeshing.warn_thin_parts(name, report and report.get("thin_parts"))
        FRepMeshing.report_straightened(name, report and report.get("straightened"))
        return report

    if progress is not None:
        return work(progress)
    return FRepMeshing.run_with_progress("Exporting %s" % name, work)


def _export_3mf(objects, filename, progress, cells, resolution, bbox, force, settings,
                unit="mm"):
    """Every object its own 3MF object: meshed with its own box (a Polygonize feature with its
    settings), all checked as the file holds them, written only when all pass (or force)."""
    name = os.path.basename(filename)
    if not objects:
        raise ValueError("nothing to export: select FRep features or Polygonize features")
    labels = [o.Label for o in objects]
    if len(set(labels)) != len(labels):
        raise ValueError("%s: two selected objects share a label; 3MF objects are named by "
                         "their labels" % name)

    def work(tick):
        meshes = []
        share = 0.8 / len(objects)
        for i, obj in enumerate(objects):
            if kept_as_it_is(obj, cells, resolution, bbox, settings):
                meshes.append((obj.Label, mesh_of(obj)))  # the part itself, as it is
                continue
            meshed = isinstance(getattr(obj, "Proxy", None), FRepPolygonize.Polygonize)
            # a Polygonize feature keeps its own settings unless the caller gives a box or size
            own = meshed and len(objects) > 1
            solid, (box, cell) = solid_and_box([obj], None if own else cells,
                                               None if own else resolution,
                                               None if own else bbox)
            mesh = solid.node.mesh(box, cell, frepcore.progress_part(tick, i * share, share),
                                   False, settings_for(obj, None if own else settings))
            FRepMeshing.warn_thin_parts(obj.Label, getattr(mesh, "thin_parts", None))
            FRepMeshing.report_straightened(obj.Label, getattr(mesh, "straightened", None))
            meshes.append((obj.Label, mesh))
        doc = objects[0].Document
        report = frepcore.write_3mf(
            meshes, filename, unit=unit, force=force,
            metadata={"Title": doc.Label, "Application": "FRepCAD workbench for FreeCAD"},
            progress=frepcore.progress_part(tick, 0.8, 0.2))
        report["triangles"] = sum(m.triangle_count for _, m in meshes)
        if not report["written"]:
            refused = [o["name"] for o in report["objects"] if not o["printable"]]
            raise frepcore.NotPrintable("%s: not written: %s not printable" % (
                name, ", ".join(refused)), report)
        return report

    def guarded(tick):
        try:
            return work(tick)
        except frepcore.Cancelled:
            raise RuntimeError("export of %s cancelled; no file written" % name)

    if progress is not None:
        return guarded(progress)
    return FRepMeshing.run_with_progress("Exporting %s" % name, guarded)


def _export_beams(objects, filename, progress, cells, resolution, bbox, force, settings,
                  unit="mm"):
    """A strut lattice's struts as a 3MF beam lattice (frepcad export --beams): the one
    selected object must be a strut lattice cut to a part or an infill with a strut lattice;
    the part's mesh clips the beams; an infill's skin is a mesh beside them, its beams ending
    in the skin."""
    name = os.path.basename(filename)
    if len(objects) != 1:
        raise ValueError("%s: a beam lattice 3MF is made of one object: select the strut "
                         "lattice's intersection with a part, or an infill with struts" % name)
    if not filename.lower().endswith(".3mf"):
        raise ValueError("%s: a beam lattice is written as a .3mf" % name)
    solid, (box, cell) = solid_and_box(objects, cells, resolution, bbox)
    chosen = settings_for(objects[0], settings)

    def work(tick):
        try:
            report = solid.export_beams(filename, resolution=cell, bbox=box, unit=unit,
                                        progress=tick, force=force, settings=chosen)
        except frepcore.Cancelled:
            raise RuntimeError("export of %s cancelled; no file written" % name)
        report["triangles"] = report["clip_triangles"] + report["skin_triangles"]
        summary = "wrote %s: %s" % (name, report["summary"])
        if report["notes"]:
            summary += "; %s" % report["notes"]
        report["text"] = summary
        return report

    if progress is not None:
        return work(progress)
    return FRepMeshing.run_with_progress("Exporting %s" % name, work)


def _export_level_set(solid, box, cell, filename, progress):
    """The solid as an OpenVDB level set, a voxel per cell; a report dict like a mesh's."""
    name = os.path.basename(filename)

    def work(tick):
        try:
            info = solid.to_vdb(filename, voxel=cell, bbox=box, progress=tick)
        except frepcore.Cancelled:
            raise RuntimeError("export of %s cancelled; no file written" % name)
        return {"text": "wrote %s: %s" % (name, info["text"]), "written": True, "grid": info}

    if progress is not None:
        return work(progress)
    return FRepMeshing.run_with_progress("Exporting %s" % name, work)
