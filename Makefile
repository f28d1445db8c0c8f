# Thin wrapper around CMake. `make demo` and `make test` are the two set-up commands.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release

.PHONY: all deps configure build test acceptance fuzz install demo bench repair-comparison screenshots examples format clean

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
	/usr/bin/python3.11 tests/fuzz_cli.py $(BUILD_DIR)/bin/frepcad . $(FUZZ_CASES) $(FUZZ_SEED)

demo: build
	@bash scripts/demo.sh $(BUILD_DIR)

bench: build
	@bash scripts/bench.sh $(BUILD_DIR)

# frepcad repair beside admesh on 60 meshes broken on purpose (docs/manufacturing.md); the
# table goes to build/repair-comparison.md.
repair-comparison: build
	/usr/bin/python3.11 bench/repair_comparison.py $(BUILD_DIR)/bin/frepcad $(BUILD_DIR)/repair-comparison --markdown $(BUILD_DIR)/repair-comparison.md

# The example FreeCAD documents (examples/*.FCStd), rebuilt with the workbench.
examples: build
	BUILD_DIR=$(abspath $(BUILD_DIR)) /usr/bin/python3.11 examples/make_documents.py

# Screenshots for docs/ from the real GUI under Xvfb: the GUI smoke test's, and the node
# gallery (docs/gallery.md).
screenshots: build
	bash tests/gui/run_gui.sh $(BUILD_DIR) . $(BUILD_DIR)/gui
	cp $(BUILD_DIR)/gui/workbench-*.png $(BUILD_DIR)/gui/lattice-*.png $(BUILD_DIR)/gui/hspline-*.png docs/images/
	bash tests/gui/run_gallery.sh $(BUILD_DIR) . docs

format:
	clang-format -i $$(git ls-files '*.h' '*.cpp')

clean:
	rm -rf $(BUILD_DIR)
