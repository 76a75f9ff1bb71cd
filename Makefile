# Pelt's commands. `make demo` and `make test` set up everything they need on a fresh Debian
# machine with Rust and Python 3.11, and are quick when nothing changed.

SHELL := /bin/bash
.DEFAULT_GOAL := test

PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
VERSION := $(shell sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -n 1)
APT_PACKAGES := g++ mesa-vulkan-drivers libvulkan1 libegl1 libegl-mesa0 libgl1-mesa-dri \
	xvfb xauth libx11-xcb1 libxcursor1 libxi6 libxrandr2 libxkbcommon0 libxkbcommon-x11-0 chromium
PY_REQUIREMENTS := bpy==5.0.1 pytest==9.2.0 maturin==1.16.0 ruff==0.17.6 hypothesis==6.140.0 jsonschema==4.25.1 \
	flip-evaluator==1.7 mypy==2.4.1
PLOT_REQUIREMENTS := matplotlib==3.11.2
# The Khronos glTF-Validator (a JavaScript library), pinned; installed into build/node.
GLTF_VALIDATOR := gltf-validator@2.0.0-dev.3.10
VALIDATOR_STAMP := build/node/.validator-stamp
# Where tests/gltf_export.rs writes the files the validator checks.
GLTF_CHECK_DIR := target/tmp/gltf-check
# The three.js runtime of the glTF extension, its npm packages pinned by its package-lock.json.
THREE_DIR := runtimes/three
THREE_STAMP := $(THREE_DIR)/node_modules/.ci-stamp
# The wgpu preview's frame the three.js runtime is compared with (runtimes/three/reference/).
THREE_REFERENCE := target/tmp/three-reference
# The character the add-on exports in the user-flow test, which the runtime draws too.
THREE_BLENDER_DIR := target/tmp/three-blender

# Everything the wheel is built from.
RUST_SOURCES := Cargo.toml Cargo.lock pyproject.toml $(shell find crates/pelt-core crates/pelt-render crates/pelt-python \
	-type f -not -path '*/tests/*' 2>/dev/null) $(shell find python -type f 2>/dev/null)
ADDON_SOURCES := $(shell find addon -type f -not -path '*/__pycache__/*' 2>/dev/null)
WHEEL_STAMP := build/wheels/.stamp
INSTALL_STAMP := $(VENV)/.pelt-installed
ZIP := dist/pelt-$(VERSION)-linux_x64.zip
# Pelt's node trees built once, which the add-on appends on a first bake (addon/blender/templates.py).
TEMPLATES := addon/assets/node_templates.blend
TEMPLATE_SOURCES := $(addprefix addon/blender/,node_graph.py materials.py geonodes.py templates.py) addon/io/names.py

# Mesa prints a warning without a runtime folder; the tests and the renderer do not need a real one.
export XDG_RUNTIME_DIR ?= /tmp/pelt-runtime-$(shell id -u)
# A build from scratch gains nothing from incremental caches, which double the disk it takes.
ifdef CI
export CARGO_INCREMENTAL ?= 0
endif
# cargo test links the `python` feature's test binaries against libpython.
export LD_LIBRARY_PATH := $(shell $(PYTHON) -c 'import sysconfig; print(sysconfig.get_config_var("LIBDIR") or "")'):$(LD_LIBRARY_PATH)

.PHONY: demo test bench package setup system-deps check-rust check-gltf check-three check-python check-fuzz fuzz clean

demo: setup
	$(PY) blender_scripts/demo.py

test: setup $(ZIP) check-rust check-gltf check-three check-python check-fuzz

setup: system-deps $(INSTALL_STAMP) $(TEMPLATES)
	@mkdir -p -m 700 $(XDG_RUNTIME_DIR)

# A C++ compiler (meshopt's library, and ꟻLIP's for the image metrics, feature `metrics`);
# Mesa's Vulkan (lavapipe)
# and GL drivers: a real GPU device on machines without a GPU; a virtual
# X server and the X libraries winit loads, for the `pelt view` test (tests/viewer.rs); Node.js
# and npm for the glTF validator when no npm is on the PATH; Chromium for the three.js runtime's
# browser test (check-three).
system-deps:
	@missing=$$(for p in $(APT_PACKAGES); do \
		dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q 'ok installed' || echo $$p; done); \
	command -v npm >/dev/null || missing="$$missing nodejs npm"; \
	if [ -n "$$missing" ]; then \
		if [ "$$(id -u)" = 0 ]; then \
			echo "installing $$missing"; \
			apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null; \
		else \
			echo "warning: missing Debian packages: $$missing (install them as root)"; \
		fi; \
	fi

$(VENV)/.requirements: Makefile
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q $(PY_REQUIREMENTS)
	touch $@

$(WHEEL_STAMP): $(VENV)/.requirements $(RUST_SOURCES)
	rm -f build/wheels/pelt-*.whl
	$(VENV)/bin/maturin build --release --quiet -o build/wheels
	touch $@

$(INSTALL_STAMP): $(WHEEL_STAMP)
	$(PY) -m pip install -q --force-reinstall --no-deps build/wheels/pelt-*.whl
	touch $@

$(TEMPLATES): $(INSTALL_STAMP) $(TEMPLATE_SOURCES) blender_scripts/build_node_templates.py
	@mkdir -p -m 700 $(XDG_RUNTIME_DIR)
	$(PY) blender_scripts/build_node_templates.py $@

$(ZIP): $(WHEEL_STAMP) $(ADDON_SOURCES) $(TEMPLATES) scripts/package_extension.py
	$(PY) scripts/package_extension.py build/wheels/pelt-*.whl --out dist

package: setup $(ZIP)

# Every crate of the workspace (crates/*) and the `pelt` package's integration tests (tests/*.rs).
check-rust:
	cargo fmt --all --check
	python3 scripts/module_arrows.py
	cargo clippy --workspace --all-targets --all-features -- -D warnings
	cargo test --workspace --all-features

$(VALIDATOR_STAMP): Makefile | system-deps
	npm install --silent --no-audit --no-fund --prefix build/node $(GLTF_VALIDATOR)
	touch $@

# Suzanne and a multi-object scene in both glTF modes, through the Khronos validator: 0 errors.
check-gltf: $(VALIDATOR_STAMP)
	rm -rf $(GLTF_CHECK_DIR)
	PELT_GLTF_OUT=$(GLTF_CHECK_DIR) cargo test --workspace --all-features --quiet --test gltf_export
	node scripts/validate_gltf.mjs $(GLTF_CHECK_DIR)/*.glb

$(THREE_STAMP): $(THREE_DIR)/package-lock.json | system-deps
	npm ci --silent --no-audit --no-fund --prefix $(THREE_DIR)
	touch $@

# The three.js runtime (runtimes/three): its unit tests, then its example in headless Chromium
# drawing the skinned, animated character check-gltf writes, the one the add-on exports in the
# user-flow test (run here to write it), and the frames the wgpu preview drew of a nodding Suzanne, with
# and without guard hairs, under PRT, and of a long-furred sphere whose hair thins (mean luminance
# in the browser test, then a ꟻLIP bound each).
check-three: setup check-gltf $(THREE_STAMP)
	$(PY) $(THREE_DIR)/reference/make_reference.py $(THREE_REFERENCE)
	rm -rf $(THREE_BLENDER_DIR) && mkdir -p $(THREE_BLENDER_DIR)
	PELT_THREE_OUT=$(CURDIR)/$(THREE_BLENDER_DIR) $(PY) -m pytest -q tests/blender/test_export_skinned.py -k user_flow
	PELT_GLB=$(CURDIR)/$(GLTF_CHECK_DIR)/character_engine.glb PELT_REFERENCE=$(CURDIR)/$(THREE_REFERENCE) \
		PELT_BLENDER_GLB=$(CURDIR)/$(THREE_BLENDER_DIR)/blender_character.glb npm test --prefix $(THREE_DIR)
	$(PY) $(THREE_DIR)/reference/compare.py $(THREE_REFERENCE)/preview.png $(THREE_DIR)/test/out/reference_three.png
	$(PY) $(THREE_DIR)/reference/compare.py $(THREE_REFERENCE)/strands_preview.png $(THREE_DIR)/test/out/strands_three.png 0.10
	$(PY) $(THREE_DIR)/reference/compare.py $(THREE_REFERENCE)/prt_preview.png $(THREE_DIR)/test/out/prt_reference_three.png 0.035
	$(PY) $(THREE_DIR)/reference/compare.py $(THREE_REFERENCE)/thin_preview.png $(THREE_DIR)/test/out/thin_three.png 0.02

check-python: setup
	$(VENV)/bin/ruff check addon blender_scripts scripts tests/blender tests/fuzz python runtimes/three/reference
	$(VENV)/bin/ruff format --check addon blender_scripts scripts tests/blender tests/fuzz python runtimes/three/reference
	$(PY) -m pytest tests/blender

# A short fuzz of every public entry point (Rust and Python), each target in a process with a time
# and memory limit; `cargo test` (check-rust) has built the Rust driver.
check-fuzz: setup check-rust
	$(PY) scripts/fuzz.py --cases 300 --binary target/debug/examples/fuzz --time-limit 600

# The long run behind docs/reliability.md (FUZZ_CASES per target; hours on 2 cores at 10⁶).
FUZZ_CASES ?= 1000000
fuzz: setup
	cargo build --release --example fuzz
	@mkdir -p out
	$(PY) scripts/fuzz.py --cases $(FUZZ_CASES) --binary target/release/examples/fuzz \
		--time-limit 86400 --json out/fuzz.json

# The full set (the image cases alone take about 35 minutes on 2 cores): docs/benchmarks.md, and
# docs/accuracy.md with its plot and pictures under docs/accuracy/.
bench: setup $(VENV)/.plotting
	cargo build --release -p pelt-cli --features metrics
	@mkdir -p out
	./target/release/pelt bench --json out/bench.json --pictures docs/accuracy
	$(PY) blender_scripts/bench_transfer.py --json out/bench_blender.json
	$(PY) blender_scripts/bench_preview.py --json out/bench_preview.json
	$(PY) scripts/bench_report.py --out docs/benchmarks.md out/bench.json out/bench_blender.json \
		out/bench_preview.json
	$(PY) scripts/accuracy_report.py docs/accuracy.md docs/accuracy out/bench.json

# matplotlib, for the accuracy plot only (make bench).
$(VENV)/.plotting: $(VENV)/.requirements
	$(PY) -m pip install -q $(PLOT_REQUIREMENTS)
	touch $@

clean:
	rm -rf build dist out $(VENV) addon/assets
	cargo clean
