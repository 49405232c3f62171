// orthosonar_bench: every *_bench.cpp in the tree, one Google Benchmark executable.
#include <benchmark/benchmark.h>

BENCHMARK_MAIN();
