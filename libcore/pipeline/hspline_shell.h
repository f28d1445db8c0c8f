// A strut lattice in a shell along an hspline: the model `frepcad hspline lattice` writes and
// the workbench's Struts along hspline command imports. The lattice's cells follow the
// surface's parameters through an FFD lattice fitted to it (lattice/surface_lattice.h).
#pragma once

#include <string>

#include "frep/model_json.h"
#include "hspline/hspline.h"

namespace frep {

struct HsplineShellSettings {
  double thickness = 0.0;  // the shell's, > 0
  double cell = 0.0;       // the cells' side; 0: half the thickness
  std::string cellType = "octet";
  double radius = 0.0;  // the struts'; 0: a tenth of a cell
  // The fitted lattice's divisions along u and v; 0: level 0's CVs less one (at most 24).
  int divisionsU = 0, divisionsV = 0;
  // Struts straight between their ends' images (the ffd node's struts = straight) rather than
  // curved with the surface.
  bool straight = false;
};

struct HsplineShell {
  Model model;   // ffd(intersection(strut_lattice, box)), the box [0, size]
  Vec3 size{};   // the surface's lengths along its parameters, and the thickness
  Vec3 cells{};  // the cells' sides (round a closed surface: whole cells a turn)
  int divisions[2] = {0, 0};
  double deviation = 0.0;  // how closely the lattice follows the surface (SurfaceLattice)
};

// `source` names the surface in the model's description. Throws ModelError naming the
// setting that is wrong (a thickness that is not positive, a cell type that is not known,
// divisions out of range).
HsplineShell hsplineShellLattice(const HSpline& surface, const HsplineShellSettings& settings,
                                 const std::string& source);

}  // namespace frep
