#pragma once
// Helpers for the batch library's tests (header-only; not installed): a case folder and a
// verify plan over small input files that need not be real fixtures (keys hash bytes only).
#include <filesystem>
#include <fstream>
#include <string>

#include "replay/batch/plan.hpp"
#include "replay/fixture/testing.hpp"

namespace orthosonar::batch::testing {

inline void write_file(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
}

// `n` fixtures f0.mcap.. with f<i>.digest.json beside them, planned as a verify plan in
// <dir>/plan (written).
inline Plan verify_plan(const std::filesystem::path& dir, int n) {
  VerifyPlanSpec spec;
  for (int i = 0; i < n; ++i) {
    const auto f = dir / "in" / ("f" + std::to_string(i) + ".mcap");
    write_file(f, "fixture bytes " + std::to_string(i));
    write_file(dir / "in" / ("f" + std::to_string(i) + ".digest.json"), "{}");
    spec.inputs.push_back(f.string());
  }
  auto plan = plan_verify(spec, (dir / "plan").string());
  if (!plan.ok()) throw std::runtime_error(plan.error().message);
  if (Status s = write_plan(*plan, true); !s.ok()) throw std::runtime_error(s.error().message);
  return *plan;
}

}  // namespace orthosonar::batch::testing
