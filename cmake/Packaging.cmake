# `make package`: a Debian package for the distribution it is built on (CPack's DEB
# generator; docs/architecture.md says why not debhelper). The package build is configured
# with CMAKE_INSTALL_PREFIX=/usr, FREP_MOD_DIR=share/freecad/Mod (FreeCAD's system Mod
# folder) and FREP_PYTHON_DIR=lib/python3/dist-packages (frepcore for the system Python that
# FreeCAD runs); the Makefile's `package` target does that in its own build folder.

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME frepcad)
set(CPACK_PACKAGE_VENDOR "FRepCAD developers")
set(CPACK_PACKAGE_CONTACT "FRepCAD developers <dev@frepcad.invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "function-representation (FRep) CAD: FreeCAD workbench and checked mesh exporter")
set(CPACK_PACKAGE_DESCRIPTION
    "FRepCAD models solids as exact implicit functions (primitives, R-function set operations, \
blends, deformations, lattices, TPMS infills, hierarchical B-spline surfaces) and turns them \
into meshes that CGAL proves closed, manifold and free of self-intersections. This package \
holds the frepcad command-line exporter, the FRep workbench for FreeCAD and the frepcore \
Python module.")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://frepcad.invalid")

# The release names the distribution: a package built on bookworm and one built on trixie
# link different library versions and must not be mistaken for each other.
set(_frep_codename unknown)
if(EXISTS /etc/os-release)
  file(STRINGS /etc/os-release _frep_os REGEX "^VERSION_CODENAME=")
  string(REGEX REPLACE "^VERSION_CODENAME=\"?([a-z]*)\"?$" "\\1" _frep_codename "${_frep_os}")
endif()
set(CPACK_DEBIAN_PACKAGE_RELEASE "1~${_frep_codename}")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)

# Libraries through dpkg-shlibdeps; FreeCAD and the exact Python the module was built for by
# hand (an extension module does not link libpython, so shlibdeps cannot see it).
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
math(EXPR _frep_next_minor "${Python_VERSION_MINOR} + 1")
set(CPACK_DEBIAN_PACKAGE_DEPENDS
    "freecad (>= 0.20), python3 (>= ${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}), \
python3 (<< ${Python_VERSION_MAJOR}.${_frep_next_minor})")
# Dask brick jobs (frepcad export --bricks) and the repair comparison's reference.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3-distributed")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "admesh")

include(CPack)
