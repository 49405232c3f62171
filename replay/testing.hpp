#pragma once
// Helpers for tests of the replay folder (header-only; not part of the library API).
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "replay/fixture.hpp"

namespace orthosonar::replay::testing {

// A fresh directory under $ORTHOSONAR_TEST_OUT (or the system temp dir).
inline std::string test_dir(const std::string& name) {
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  const std::filesystem::path base = env != nullptr ? std::filesystem::path(env)
                                                    : std::filesystem::temp_directory_path() / "orthosonar_test";
  const auto dir = base / "replay" / name;
  std::filesystem::create_directories(dir);
  return dir.string();
}

// $ORTHOSONAR_TEST_OUT/<group>/<test name with non-alphanumerics as '_'>: one directory per
// test case (ctest runs cases as parallel processes). `fresh` empties it first.
inline std::filesystem::path case_dir(const std::string& group, std::string test_name, bool fresh = false) {
  for (char& c : test_name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  const std::filesystem::path d =
      std::filesystem::path(env != nullptr ? env : std::filesystem::temp_directory_path().string()) / group / test_name;
  if (fresh) std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline std::vector<uint8_t> read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), {});
}

inline void write_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

inline Status write_fixture(const std::string& path, const std::vector<Event>& events,
                            const FixtureMetadata& meta = {}, const WriterOptions& o = {}) {
  auto w = FixtureWriter::open(path, meta, o);
  if (!w) return w.error();
  for (const auto& e : events)
    if (auto s = (*w)->write(e); !s) return s;
  return (*w)->close();
}

// Every event of a fixture, or the first error.
struct ReadBack {
  std::vector<Event> events;
  std::string error;  // empty when the stream ended cleanly
  RecoveryReport recovery;
  FixtureMetadata metadata;
};
inline ReadBack read_fixture(const std::string& path) {
  ReadBack out;
  auto src = FixtureSource::open(path);
  if (!src) {
    out.error = src.error().message;
    return out;
  }
  out.recovery = (*src)->recovery();
  out.metadata = (*src)->metadata();
  for (;;) {
    auto p = (*src)->next();
    if (p.error) {
      out.error = p.error->message;
      return out;
    }
    if (p.end_of_stream) return out;
    out.events.push_back(std::move(*p.event));
  }
}

}  // namespace orthosonar::replay::testing
