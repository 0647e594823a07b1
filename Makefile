# uwscan: the two commands a newcomer runs are `make demo` and `make test`.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)

.PHONY: all deps build tool test demo bench sanitize tsan format clean

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD_DIR)/build.ninja:
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release

build: deps $(BUILD_DIR)/build.ninja
	cmake --build $(BUILD_DIR) -j $(JOBS)

# The command-line tool alone (what the demo runs), without the tests.
tool: deps $(BUILD_DIR)/build.ninja
	cmake --build $(BUILD_DIR) -j $(JOBS) --target uwscan

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

demo: tool
	$(BUILD_DIR)/bin/uwscan demo

bench: tool
	$(BUILD_DIR)/bin/uwscan bench projection

# Every test under AddressSanitizer and UndefinedBehaviorSanitizer
# (build-sanitize/; some 45 min on 2 cores, so not part of `make test`).
sanitize: deps
	bash scripts/sanitize.sh

# The tool's threads under ThreadSanitizer on small simulated scans
# (build-tsan/; some 5 min on 2 cores).
tsan: deps
	bash scripts/tsan.sh

format:
	clang-format -i $$(git ls-files '*.cc' '*.h')

clean:
	rm -rf $(BUILD_DIR)
