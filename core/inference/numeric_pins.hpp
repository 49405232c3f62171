#pragma once
// Process-wide numeric pins (docs/ARCHITECTURE.md, "Cross-machine determinism: pinned
// numerics"): what the libraries under the core would otherwise choose from the CPU or the
// machine's core count, fixed so that the same inputs give the same bits on any x86-64
// machine.
//
//   orthosonar::inference::apply_numeric_pins();   // first thing in main(), before any
//                                                  // torch operator, OpenCV call or solve
//
// The CLI calls it at startup (tools/main.cpp); so does the run API. A library user that
// drives the pipeline directly calls it once, before anything else. Embree's pin is not
// process-wide: it is in every device the simulator creates (hal/sim/embree_device.hpp).
#include <string>
#include <vector>

namespace orthosonar::inference {

struct NumericPin {
  std::string name;       // e.g. "torch.aten_cpu_capability"
  std::string pinned;     // the value asked for
  std::string effective;  // what the library reports now
  bool ok = false;        // the pin took (effective matches pinned)
  std::string note;       // how it is applied, or why it could not be
};

// Applies every pin (idempotent; cheap: no query, nothing printed).
//   torch:  ATen CPU capability "default", oneDNN max ISA sse41, intra- and inter-op threads 1
//   BLAS:   1 thread, when the BLAS that is loaded has a thread control (OpenBLAS, BLIS, MKL)
//   OpenCV: 1 thread, and its runtime CPU dispatch off (baseline SIMD only, no IPP)
//   Eigen:  1 thread
void apply_numeric_pins();

// The pins and their effective values, without changing anything (note: the first query
// of ATen's capability or oneDNN's ISA fixes them, so apply the pins first).
std::vector<NumericPin> numeric_pins_report();

}  // namespace orthosonar::inference
