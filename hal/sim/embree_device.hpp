#pragma once
// The one Embree device configuration of the simulator, with its numerics pinned
// (docs/ARCHITECTURE.md, "Cross-machine determinism: pinned numerics").
//
// Embree picks its kernels per CPU: on an AVX2 machine the BVH is 8 wide and the triangle
// test uses FMA, on an SSE machine it is 4 wide without FMA, so a ray can land on a
// different float distance (and a grazing ray on a different triangle). `isa=sse2` pins the
// lowest ISA every x86-64 CPU has, so every machine runs the same BVH builder, traversal and
// intersection kernels; `threads=1` gives a deterministic BVH build.
#include <string>

namespace orthosonar::sim {

inline constexpr const char* kEmbreePinnedIsa = "sse2";
inline constexpr const char* kEmbreeDeviceConfig = "threads=1,set_affinity=0,isa=sse2";

struct EmbreeIsaReport {
  std::string config;       // kEmbreeDeviceConfig
  std::string intersector;  // the single-ray intersector Embree selected, e.g. "sse2::BVH4Triangle4Intersector1Pluecker"
  std::string isa;          // its ISA prefix ("sse2"), the effective value of the pin
  std::string cpu_targets;  // what this CPU could have run ("SSE SSE2 ... AVX2"), for information
  bool ok = false;          // the device was created and isa == kEmbreePinnedIsa
  std::string error;        // when !ok
};

// Creates a device with kEmbreeDeviceConfig (plus verbose=2), commits a one-triangle robust
// scene as the renderer does, and reads the intersector Embree selected from its console
// output (Embree 3 has no query for it). File descriptor 1 is redirected to a temporary
// file meanwhile: call it from a command-line tool, never concurrently with other output.
EmbreeIsaReport embree_isa_report();

}  // namespace orthosonar::sim
