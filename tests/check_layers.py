#!/usr/bin/env python3
"""Layering of libcore: each folder is a layer and may include only the layers below it.

    base   <- lattice               (FFD lattices: forward and inverse maps, folds)
    base   <- hspline               (hierarchical B-spline surfaces; hspline/occt/ alone knows
                                     OpenCASCADE)
    lattice <- frep <- mesh         (mesh meshes any Field: it knows frep's field seam; frep's
                                     ffd node pulls fields back through a lattice, mesh FFD
                                     pushes vertices forward)
    base   <- io                    (readers and writers know no fields)
    base   <- check                 (the CGAL judge knows no fields and no mesher)
    frep, check <- simplify         (guarded collapses: the field for distances, the check's
                                     exact face-pair test for every collapse)
    frep, io, check <- volume       (OpenVDB grids and mesh distances as fields: io reads the
                                     meshes, check judges them before they become solids)
    check, volume, mesh, simplify <- repair
                                    (CGAL's local repairs, then a rebuild through a level set
                                     meshed by the mesher and simplified; judged by check)
    all of them <- pipeline         (the export: box policy, mesh, check, write)
    python: the bindings, above all of them

Heavy libraries stay in the one layer (file) that uses them, and nothing in libcore outside
the bindings knows Python or FreeCAD. Usage: check_layers.py LIBCORE_DIR; exit 1 and one line
per violation ("file:line: what"), 0 when clean. --self-test plants a violation in a copy and
checks that it is caught.
"""
import os
import re
import shutil
import sys
import tempfile

ALLOWED = {
    "base": {"base"},
    "frep": {"base", "lattice", "frep"},
    "mesh": {"base", "lattice", "frep", "mesh"},
    "io": {"base", "io"},
    "check": {"base", "check"},
    "simplify": {"base", "frep", "check", "simplify"},
    "volume": {"base", "lattice", "frep", "io", "check", "volume"},
    "lattice": {"base", "lattice"},
    "hspline": {"base", "hspline"},
    "repair": {"base", "lattice", "frep", "mesh", "io", "check", "volume", "simplify", "repair"},
    "pipeline": {"base", "frep", "mesh", "io", "check", "simplify", "volume", "lattice",
                 "repair", "hspline", "pipeline"},
    "python": {"base", "frep", "mesh", "io", "check", "simplify", "volume", "lattice",
               "repair", "pipeline", "hspline", "python"},
}
# <header prefix>: the layers (or layer/file) that may include it
LIBRARIES = {
    "CGAL/": {"check/mesh_check.cpp", "check/face_pair_test.cpp", "check/cgal_surface.cpp",
              "check/volume_nesting.cpp",
              "check/mesh_deviation.cpp", "check/printability.cpp", "repair/cgal_repair.cpp",
              "volume/mesh_distance.cpp", "volume/voronoi_foam.cpp"},
    "openvdb/": {"volume"},
    "OpenMesh/": {"mesh/openmesh_bridge.h", "mesh/openmesh_bridge.cpp",
                  "hspline/hspline_attach.cpp"},
    "tbb/": {"mesh", "simplify", "check/self_intersections.cpp", "check/mesh_check.cpp",
             "check/partitioned_check.cpp", "check/mesh_check_passes.h",
             "check/volume_nesting.cpp",
             "check/printability.cpp",
             "volume/grid_ffd.cpp",
             "pipeline/accuracy.cpp", "volume/level_sets.cpp",
             "python/frepcore_module.cpp"},
    "nlohmann/": {"frep", "check", "lattice/lattice_file.cpp"},
    "nanoflann": {"frep/instances.cpp"},
    "Model/COM/": {"io/mesh_3mf.cpp"},  # lib3mf
    "Eigen/": {"base/affine.cpp", "base/qef.cpp", "lattice/surface_lattice.cpp"},
    ".hxx": {"hspline/occt/occ_hspline.cpp"},  # OpenCASCADE (its headers have no folder)
    "pybind11/": {"python"},
    "Python.h": {"python"},
}
FORBIDDEN_EVERYWHERE = ("App/", "Gui/", "Base/", "Mod/")  # FreeCAD's own headers

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def violations(root):
    found = []
    for layer in sorted(os.listdir(root)):
        folder = os.path.join(root, layer)
        if not os.path.isdir(folder):
            continue
        if layer not in ALLOWED:
            found.append(f"{layer}/: a folder that is no known layer (add it to check_layers.py)")
            continue
        for dirpath, _, files in os.walk(folder):
            for name in sorted(files):
                if not name.endswith((".h", ".cpp", ".hpp")):
                    continue
                path = os.path.join(dirpath, name)
                rel = os.path.relpath(path, root)
                with open(path, encoding="utf-8") as f:
                    for number, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        if not m:
                            continue
                        header = m.group(2)
                        where = f"{rel}:{number}"
                        target = header.split("/")[0] if "/" in header else None
                        if m.group(1) == '"' and target in ALLOWED:
                            if target not in ALLOWED[layer]:
                                found.append(f"{where}: layer {layer}/ includes {header}, "
                                             f"but may include only {sorted(ALLOWED[layer])}")
                            continue
                        for prefix, users in LIBRARIES.items():
                            matches = header.endswith(prefix) if prefix.startswith(".") else header.startswith(prefix)
                            if matches and layer not in users and rel not in users:
                                found.append(f"{where}: {header} belongs in {sorted(users)} only")
                        if layer != "python" and header.startswith(FORBIDDEN_EVERYWHERE):
                            found.append(f"{where}: libcore knows no FreeCAD ({header})")
    return found


def self_test(root):
    with tempfile.TemporaryDirectory() as tmp:
        copy = os.path.join(tmp, "libcore")
        shutil.copytree(root, copy, ignore=shutil.ignore_patterns("*.o", "__pycache__"))
        with open(os.path.join(copy, "frep", "field.h"), "a", encoding="utf-8") as f:
            f.write('\n#include "mesh/mesher.h"\n')
        with open(os.path.join(copy, "check", "mesh_check.h"), "a", encoding="utf-8") as f:
            f.write('\n#include "frep/tree.h"\n#include <tbb/parallel_for.h>\n')
        found = violations(copy)
        expected = ["layer frep/ includes mesh/mesher.h", "layer check/ includes frep/tree.h",
                    "tbb/parallel_for.h belongs in"]
        missing = [e for e in expected if not any(e in v for v in found)]
        for v in found:
            print("planted:", v)
        if missing:
            print("check_layers self-test: not caught:", missing)
            return 1
        print("check_layers self-test: every planted violation caught")
        return 0


def main(argv):
    if len(argv) == 3 and argv[1] == "--self-test":
        return self_test(argv[2])
    if len(argv) != 2:
        print(__doc__)
        return 2
    found = violations(argv[1])
    for v in found:
        print(v)
    if found:
        print(f"check_layers: {len(found)} violation(s)")
        return 1
    print("check_layers: every include follows the layers")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
