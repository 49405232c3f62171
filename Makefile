# Thin conveniences over CMake presets; the README's commands are the reference.
.PHONY: deps build test demo asan fuzz bench clean
deps:
	bash tools/install-deps
build: deps
	cmake --preset release && cmake --build --preset release -j2
test: build
	xvfb-run -a ctest --preset release -j2
demo: build
	xvfb-run -a build/release/tools/orthosonar demo -o out/demo
asan: deps
	cmake --preset asan && cmake --build --preset asan -j2 && xvfb-run -a ctest --preset asan -j2 && tools/fuzz-all 15
fuzz: deps
	cmake --preset fuzz && cmake --build --preset fuzz -j2 && FUZZ_BUILD=build/fuzz tools/fuzz-all 15
bench: build
	build/release/orthosonar_bench
clean:
	rm -rf build
