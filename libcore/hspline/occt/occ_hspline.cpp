#include "hspline/occt/occ_hspline.h"

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRep_Builder.hxx>
#include <BinTools.hxx>
#include <BinTools_ShapeSet.hxx>
#include <GProp_GProps.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <algorithm>
#include <sstream>
#include <vector>

#include "base/atomic_file.h"
#include "base/errors.h"
#include "hspline/hspline_flatten.h"
#include "hspline/hspline_tessellate.h"

namespace frep {

namespace {

void occKnots(const SplineAxis& a, TColStd_Array1OfReal& knots, TColStd_Array1OfInteger& mults) {
  const OccStyleAxis o = occStyle(a);
  knots.Resize(1, static_cast<int>(o.knots.size()), false);
  mults.Resize(1, static_cast<int>(o.knots.size()), false);
  for (std::size_t q = 0; q < o.knots.size(); ++q)
    knots(int(q) + 1) = o.knots[q], mults(int(q) + 1) = o.mults[q];
}

Handle(Geom_BSplineSurface) occSurface(const FlatBSpline& f) {
  TColStd_Array1OfReal uk(1, 1), vk(1, 1);
  TColStd_Array1OfInteger um(1, 1), vm(1, 1);
  occKnots(f.u, uk, um);
  occKnots(f.v, vk, vm);
  TColgp_Array2OfPnt poles(1, f.u.count(), 1, f.v.count());
  for (int j = 1; j <= f.v.count(); ++j)
    for (int i = 1; i <= f.u.count(); ++i) {
      const Vec3& p = f.pole(ourPole(f.u, i - 1), ourPole(f.v, j - 1));
      poles(i, j) = gp_Pnt(p[0], p[1], p[2]);
    }
  try {
    return new Geom_BSplineSurface(poles, uk, vk, um, vm, 3, 3, f.u.isPeriodic(), f.v.isPeriodic());
  } catch (const Standard_Failure& e) {
    throw ModelError(std::string("OpenCASCADE refused the hspline's B-spline surface: ") +
                     e.GetMessageString());
  }
}

// OpenCASCADE's translators print statistics to standard output; a command's output is ours.
// Holds its console printers off while it lives.
class QuietOcc {
 public:
  QuietOcc() {
    const Handle(Message_Messenger)& m = Message::DefaultMessenger();
    for (Message_SequenceOfPrinters::Iterator p(m->Printers()); p.More(); p.Next())
      if (p.Value()->IsKind(STANDARD_TYPE(Message_PrinterOStream))) removed_.push_back(p.Value());
    for (const auto& p : removed_) m->RemovePrinter(p);
  }
  ~QuietOcc() {
    for (const auto& p : removed_) Message::DefaultMessenger()->AddPrinter(p);
  }

 private:
  std::vector<Handle(Message_Printer)> removed_;
};

OccShapeSummary summarise(const TopoDS_Shape& shape) {
  OccShapeSummary s;
  for (TopExp_Explorer e(shape, TopAbs_SOLID); e.More(); e.Next()) ++s.solids;
  for (TopExp_Explorer e(shape, TopAbs_SHELL); e.More(); e.Next()) ++s.shells;
  for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) ++s.faces;
  s.valid = BRepCheck_Analyzer(shape).IsValid();
  GProp_GProps props;
  if (s.solids > 0) {
    BRepGProp::VolumeProperties(shape, props);
    s.volume = props.Mass();
  }
  GProp_GProps area;
  BRepGProp::SurfaceProperties(shape, area);
  s.area = area.Mass();
  return s;
}

// The face of the flattened surface, or the solid it bounds when it is closed both ways.
TopoDS_Shape occShape(const FlatBSpline& f, TopoDS_Face* faceOut = nullptr) {
  Handle(Geom_BSplineSurface) surface = occSurface(f);
  try {
    const TopoDS_Face face = BRepBuilderAPI_MakeFace(surface, 1e-7);
    if (faceOut) *faceOut = face;
    if (!(f.u.isPeriodic() && f.v.isPeriodic())) return face;
    // A surface closed both ways bounds a solid on its own: one face, one shell.
    BRep_Builder builder;
    TopoDS_Shell shell;
    builder.MakeShell(shell);
    builder.Add(shell, face);
    shell.Closed(true);
    TopoDS_Solid solid = BRepBuilderAPI_MakeSolid(shell);
    // Outward when the surface's own normals (du x dv) enclose a positive volume; our sign
    // test is a 48 x 48 sum, where OpenCASCADE's OrientClosedSolid classifies points.
    if (enclosedVolume(f) < 0) solid.Reverse();
    return solid;
  } catch (const Standard_Failure& e) {
    throw ModelError(std::string("OpenCASCADE could not make a face or solid of the hspline: ") +
                     e.GetMessageString());
  }
}

}  // namespace

double occSurfaceDeviation(const HSpline& h, int n) {
  const FlatBSpline f = flatten(h);
  Handle(Geom_BSplineSurface) s = occSurface(f);
  double worst = 0;
  const SplineAxis &u = h.level(0).u, &v = h.level(0).v;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      // Irregular steps, so samples fall on knots and between them.
      const double a = u.lo() + (u.hi() - u.lo()) * (i == n ? 1.0 : (i + 0.37 * (i % 3)) / n);
      const double b = v.lo() + (v.hi() - v.lo()) * (j == n ? 1.0 : (j + 0.29 * (j % 4)) / n);
      const Vec3 ours = h.evaluate(std::min(a, u.hi()), std::min(b, v.hi())).position;
      const gp_Pnt theirs = s->Value(std::min(a, u.hi()), std::min(b, v.hi()));
      worst = std::max(worst, vlength(vsub(ours, {theirs.X(), theirs.Y(), theirs.Z()})));
    }
  return worst;
}

std::string hsBrepBinary(const HSpline& h, bool solid) {
  const FlatBSpline f = flatten(h);
  Box3 box{f.poles[0], f.poles[0]};
  for (const Vec3& p : f.poles) box = boxHull(box, {p, p});
  const double side = (box.hi[0] - box.lo[0]) + (box.hi[1] - box.lo[1]) + (box.hi[2] - box.lo[2]);
  const double tolerance = std::max(side / 300 * 0.5 * 0.25, 1e-6);
  TopoDS_Face face;
  TopoDS_Shape shape = occShape(f, &face);
  if (!solid) shape = face;
  const HsTessellation t = tessellate(f, tolerance);
  Handle(Poly_Triangulation) mesh = new Poly_Triangulation(
      static_cast<int>(t.mesh.positions.size()), static_cast<int>(t.mesh.triangles.size()), false);
  for (std::size_t k = 0; k < t.mesh.positions.size(); ++k) {
    const auto& p = t.mesh.positions[k];
    mesh->SetNode(static_cast<int>(k) + 1, gp_Pnt(p[0], p[1], p[2]));
  }
  for (std::size_t k = 0; k < t.mesh.triangles.size(); ++k) {
    const auto& tri = t.mesh.triangles[k];
    mesh->SetTriangle(static_cast<int>(k) + 1,
                      Poly_Triangle(int(tri[0]) + 1, int(tri[1]) + 1, int(tri[2]) + 1));
  }
  mesh->Deflection(tolerance);
  BRep_Builder().UpdateFace(face, mesh);
  // The layout Part.Shape.importBinary reads (FreeCAD's TopoShape::exportBinary): the shape
  // set, then the shape's index, its location's index and its orientation.
  BinTools_ShapeSet set;
  set.SetWithTriangles(Standard_True);
  const int shapeId = set.Add(shape);
  const int locationId = set.Locations().Index(shape.Location());
  std::ostringstream out(std::ios::binary);
  set.Write(out);
  BinTools::PutInteger(out, shapeId);
  BinTools::PutInteger(out, locationId);
  BinTools::PutInteger(out, static_cast<int>(shape.Orientation()));
  return out.str();
}

OccShapeSummary writeHsStep(const HSpline& h, const std::string& path) {
  const FlatBSpline f = flatten(h);
  const TopoDS_Shape shape = occShape(f);
  const OccShapeSummary summary = summarise(shape);
  if (!summary.valid)
    throw ModelError("OpenCASCADE's check finds the hspline's shape invalid; nothing was written");
  AtomicFile file(path);
  QuietOcc quiet;
  STEPControl_Writer writer;
  Interface_Static::SetCVal("write.step.schema", "AP214IS");
  if (writer.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone)
    throw ModelError("OpenCASCADE could not translate the hspline to STEP");
  if (writer.Write(file.temporaryPath().c_str()) != IFSelect_RetDone)
    throw FileError(path + ": OpenCASCADE could not write the STEP file");
  file.commit();
  return summary;
}

OccShapeSummary readStepSummary(const std::string& path) {
  QuietOcc quiet;
  STEPControl_Reader reader;
  if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
    throw FileError(path + ": OpenCASCADE cannot read it as STEP");
  if (reader.TransferRoots() == 0) throw FileError(path + ": the STEP file holds no shape");
  return summarise(reader.OneShape());
}

}  // namespace frep
