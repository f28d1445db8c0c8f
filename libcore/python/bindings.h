// The parts of the frepcore module defined in their own translation units.
#pragma once

#include <pybind11/pybind11.h>

namespace frep {

// Each binds one subject of the frepcore module, in this order (frepcore_module.cpp).
void bindNode(pybind11::module_& m);     // node_bindings.cpp: Node, models and volume sources
void bindMesh(pybind11::module_& m);     // mesh_bindings.cpp: Mesh, mesh files, 3MF
void bindLattice(pybind11::module_& m);  // lattice_bindings.cpp: Lattice, deformations
void bindHSpline(pybind11::module_& m);  // hspline_bindings.cpp

// mesh_settings_bindings.cpp: frepcore.MeshSettings and mesh_settings_table()
void bindMeshSettings(pybind11::module_& m);
// vdb_reader_binding.cpp: the frepcad that reads .vdb files first, and vdb_reader()
void bindVdbReader(pybind11::module_& m);

}  // namespace frep
