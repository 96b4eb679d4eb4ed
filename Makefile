# Two entry points, both safe on a fresh Debian machine:
#   make run   installs what is missing, builds (Release) and runs the main job
#   make test  installs what is missing, builds and runs every test with ctest
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
SCENE ?= scenes/cart_rail_boxes.yaml
OUT ?= out

.PHONY: run test deps configure build bench clean

run: build
	$(BUILD_DIR)/bin/stridemap experiment cart-rail --sensor urg --scene $(SCENE) --out $(OUT) --seed 1

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

deps:
	@bash tools/install-deps.sh

configure: deps
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

bench: build
	@bash tools/run-benchmarks.sh $(BUILD_DIR)

clean:
	rm -rf $(BUILD_DIR) $(OUT)
