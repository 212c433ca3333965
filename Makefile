# tricot — the two commands a new user needs are `make demo` and `make test`.
BUILD ?= build
JOBS  ?= 2
CMAKE_FLAGS ?=

.PHONY: all deps configure build python test test-fast bench demo sanitize fuzz clean

all: build

deps:
	@scripts/install-deps

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

configure: deps $(BUILD)/build.ninja

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# The `tricot` Python module alone (build/python; the default build makes it too):
#   PYTHONPATH=build/python python3 -c "import tricot"
python: configure
	cmake --build $(BUILD) -j $(JOBS) --target python

# All tests, slow ones included (CI runs this).
test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# Unit tests only, for the edit–compile–test loop.
test-fast: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) -L unit

bench: configure
	cmake --build $(BUILD) -j $(JOBS) --target benchmarks
	@for b in $(BUILD)/bench/*_benchmark; do echo "== $$b"; $$b --benchmark_counters_tabular=true || exit 1; done

# The whole chain on the §4 campaign (install, configure, then only the tricot binary: a first run
# does not wait for the tests to compile).
demo: configure
	cmake --build $(BUILD) -j $(JOBS) --target tricot
	$(BUILD)/tricot demo -o out/demo

# AddressSanitizer + UBSan: unit tests and examples in build-sanitize/ (scripts/sanitize.sh; not in CI).
sanitize:
	JOBS=$(JOBS) scripts/sanitize.sh

# libFuzzer harnesses of fuzz/ with clang in build-fuzz/, FUZZ_SECONDS each (scripts/fuzz.sh; not in CI).
fuzz: configure
	JOBS=$(JOBS) BUILD=build-fuzz PREBUILT=$(BUILD) scripts/fuzz.sh

clean:
	rm -rf $(BUILD)
