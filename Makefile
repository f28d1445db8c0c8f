# Thin wrapper around CMake. `make demo` and `make test` are the two set-up commands.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release
# The Python FreeCAD runs, as the configure step found it (cmake/FreeCADPython.cmake).
PYTHON = $(shell sed -n 's/^FREP_PYTHON=//p' $(BUILD_DIR)/frep-env.sh 2>/dev/null)

.PHONY: all deps configure build test acceptance test-trixie package test-package fuzz install demo bench repair-comparison screenshots examples format clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@if [ ! -f $(BUILD_DIR)/build.ninja ]; then \
	  cmake -S . -B $(BUILD_DIR) -G Ninja $(CMAKE_FLAGS); fi

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)
	@bash scripts/install-workbench.sh

# Every test but the fine-resolution tier; `make acceptance` runs that tier (CI runs both).
test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) -LE acceptance

acceptance: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) -L acceptance

# The whole `make test` again on Debian trixie with FreeCAD 1.0, in a debootstrap root cached
# under build/trixie, then the package built there installed into a clean trixie root
# (tests/trixie/run.sh; root, or sudo).
test-trixie:
	@bash tests/trixie/run.sh $(BUILD_DIR)

# A Debian package for the distribution this runs on (cmake/Packaging.cmake), built in its
# own folder with the system layout: /usr/bin/frepcad, the workbench in FreeCAD's system Mod
# folder, frepcore for the system Python. Writes build/frepcad_VERSION-1~CODENAME_ARCH.deb.
PACKAGE_BUILD_DIR = $(BUILD_DIR)/package
package: deps
	cmake -S . -B $(PACKAGE_BUILD_DIR) -G Ninja $(CMAKE_FLAGS) -DCMAKE_INSTALL_PREFIX=/usr \
	  -DFREP_MOD_DIR=share/freecad/Mod -DFREP_PYTHON_DIR=lib/python3/dist-packages \
	  -DFREP_BUILD_TESTS=OFF
	cmake --build $(PACKAGE_BUILD_DIR) -j $(JOBS)
	rm -f $(PACKAGE_BUILD_DIR)/frepcad_*.deb $(BUILD_DIR)/frepcad_*.deb
	cd $(PACKAGE_BUILD_DIR) && cpack -G DEB
	cp $(PACKAGE_BUILD_DIR)/frepcad_*.deb $(BUILD_DIR)/
	@ls $(BUILD_DIR)/frepcad_*.deb

# The package of this machine's own release, installed with apt into a clean root of that
# release (debootstrap; the bare root cached in PACKAGE_CACHE), where FreeCAD loads the
# workbench from the system Mod folder and frepcad exports (tests/package/run.sh; root, or sudo).
PACKAGE_CACHE ?= $(BUILD_DIR)/debian
test-package: package
	@bash tests/package/run.sh $(PACKAGE_CACHE) $$(. /etc/os-release && echo $$VERSION_CODENAME) \
	  $$(ls $(BUILD_DIR)/frepcad_*.deb)

# Installs frepcad and the workbench (with frepcore inside it) where FreeCAD finds them, no
# source tree needed: PREFIX/bin/frepcad and PREFIX/share/FreeCAD/Mod/FRep (FreeCAD's user Mod
# folder for the default PREFIX).
PREFIX ?= $(HOME)/.local
install: build
	cmake --install $(BUILD_DIR) --prefix $(PREFIX)

# The fuzz test at length: FUZZ_CASES mutations (default 50,000), FUZZ_SEED to vary them.
FUZZ_CASES ?= 50000
FUZZ_SEED ?= $(shell date +%s)
fuzz: build
	$(PYTHON) tests/fuzz_cli.py $(BUILD_DIR)/bin/frepcad . $(FUZZ_CASES) $(FUZZ_SEED)

demo: build
	@bash scripts/demo.sh $(BUILD_DIR)

bench: build
	@bash scripts/bench.sh $(BUILD_DIR)

# frepcad repair beside admesh on 60 meshes broken on purpose, and on the cases a repair must
# not destroy (docs/manufacturing.md); the tables go to build/repair-comparison.md and
# build/repair-judgement.md.
repair-comparison: build
	$(PYTHON) bench/repair_comparison.py $(BUILD_DIR)/bin/frepcad $(BUILD_DIR)/repair-comparison --markdown $(BUILD_DIR)/repair-comparison.md
	$(PYTHON) bench/repair_judgement.py $(BUILD_DIR)/bin/frepcad $(BUILD_DIR)/repair-judgement --markdown $(BUILD_DIR)/repair-judgement.md

# The example FreeCAD documents (examples/*.FCStd), rebuilt with the workbench.
examples: build
	BUILD_DIR=$(abspath $(BUILD_DIR)) $(PYTHON) examples/make_documents.py

# Screenshots for docs/ from the real GUI under Xvfb: the GUI smoke test's, and the node
# gallery (docs/gallery.md).
screenshots: build
	bash tests/gui/run_gui.sh $(BUILD_DIR) . $(BUILD_DIR)/gui
	cp $(BUILD_DIR)/gui/workbench-*.png $(BUILD_DIR)/gui/lattice-*.png $(BUILD_DIR)/gui/hspline-*.png docs/images/
	mkdir -p docs/images/panels && cp $(BUILD_DIR)/gui/panels/*.png docs/images/panels/
	bash tests/gui/run_gallery.sh $(BUILD_DIR) . docs

format:
	clang-format -i $$(git ls-files '*.h' '*.cpp')

clean:
	rm -rf $(BUILD_DIR)
