# Two entry points for a fresh Debian 12 machine: `make demo` and `make test`.
# Both install the Debian packages they need first (scripts/install_deps.sh, as root).
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?=
DEMO_INPUT ?= test_data/samp11-utm-ground.pcd
DEMO_OUTPUT ?= $(BUILD_DIR)/demo/samp11-utm-ground.ply
BENCH_MAX_N ?= 1000000
PACKAGE_BUILD_DIR ?= build-package
PREFIX ?= /usr/local

.PHONY: all deps configure build test demo bench bench-threads bench-scale compare install package format clean docs-pictures

all: build

deps:
	@bash scripts/install_deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

demo: build
	@mkdir -p $(dir $(DEMO_OUTPUT))
	@$(BUILD_DIR)/pcd_to_mesh $(DEMO_INPUT) $(DEMO_OUTPUT)
	@echo "demo mesh written to $(DEMO_OUTPUT)"

# docs/benchmarks.md and docs/img/bench_ns_per_point.png, from scratch
# (tools/bench/run_bench.sh, which runs tools/bench/run_lattice_bench.sh for the DEM
# rasters): about 8 minutes at the default BENCH_MAX_N=1000000, about 15 at 10000000 on 2
# cores; BENCH_MAX_N=100000000 adds the 1e8-cell raster (about 10 minutes more, ~20 GB
# for CGAL's run, left out when MemAvailable cannot hold it). Builds only what it runs;
# GP3/Poisson rows need compare_methods (skipped with a note when it cannot be built).
bench: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target bench_triangulation verify_delaunay pcd_to_mesh \
	  bench_cache_blocks
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target compare_methods || \
	  echo "bench: compare_methods could not be built: no GP3/Poisson rows"
	@bash tools/bench/run_bench.sh $(BUILD_DIR) $(BENCH_MAX_N)

# tools/bench/bench_threads: thread scaling of the core pipeline, PCL-free and linked
# statically, to copy to and run on any x86-64 Linux machine (`bench_threads --help`).
bench-threads: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target bench_threads
	@echo "bench-threads: $(BUILD_DIR)/tools/bench/bench_threads"

# docs/scaling.md §5 table: synthetic LiDAR tiles (tools/bench/make_lidar_tiles.cpp)
# meshed in memory and tiled under SCALE_LIMIT; SCALE_N points (space-separated list).
# Needs about 110 B/point of disk in SCALE_WORK; POINT_FORMAT=0 writes 20-byte LAS
# points instead of 28 (run_scale.sh).
SCALE_N ?= 10000000
SCALE_LIMIT ?= 2G
SCALE_WORK ?= $(BUILD_DIR)/scale
bench-scale: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target make_lidar_tiles pcd_to_mesh
	@bash tools/bench/run_scale.sh $(BUILD_DIR) $(SCALE_WORK) $(SCALE_LIMIT) $(SCALE_N)

# docs/reconstruction.md's before/after pictures into docs/img (tools/docs_pictures.cpp;
# the shared DEMs and samp11 are skipped when ../shared/data is absent).
docs-pictures: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target docs-pictures

# docs/comparison.md and docs/img/compare/: VTS against GP3, Poisson and Ball-Pivoting
# (tools/compare/run_compare.sh, about 15 minutes on 2 cores). Builds only what it runs.
compare: deps
	@bash scripts/install_compare_deps.sh
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release -DPCL_VTS_BUILD_COMPARE=ON $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target compare_methods
	@bash tools/compare/run_compare.sh $(BUILD_DIR)

# cmake --install: libraries, headers, pcd_to_mesh, the CMake package and the
# pkg-config files under PREFIX (default /usr/local; e.g. make install PREFIX=$$HOME/.local).
install: build
	@cmake --install $(BUILD_DIR) --prefix $(PREFIX)

# The Debian package pcl-vts_<version>_<arch>.deb (CPack, cmake/PclVtsPackage.cmake), built
# in its own folder configured for /usr (libraries in /usr/lib/<multiarch>), without
# tests, benchmarks or compare tools. Install it with apt-get install ./pcl-vts_*.deb;
# dpkg-deb -I shows its Depends (dpkg-shlibdeps), dpkg-deb -c its files.
package: deps
	@cmake -S . -B $(PACKAGE_BUILD_DIR) -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=/usr \
	  -DPCL_VTS_BUILD_TESTS=OFF -DPCL_VTS_BUILD_BENCH=OFF -DPCL_VTS_BUILD_COMPARE=OFF \
	  $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(PACKAGE_BUILD_DIR) -j $(JOBS)
	@cd $(PACKAGE_BUILD_DIR) && cpack -G DEB

format:
	@clang-format -i $$(git ls-files '*.cpp' '*.hpp' '*.h')

clean:
	@rm -rf $(BUILD_DIR) $(PACKAGE_BUILD_DIR)
