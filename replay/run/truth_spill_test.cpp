// TruthSpill (issue 41): the run's truth on disk gives the metrics exactly what the whole
// stream in memory gives, and traj_truth.tum the same bytes.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "core/mapping/metrics.hpp"
#include "replay/run/trajectory.hpp"
#include "replay/run/truth_spill.hpp"

using namespace orthosonar;

namespace {

// A truth stream of n poses with irregular spacing (1-20 ms) and some repeated stamps.
std::vector<TruthPose> spill_test_truth(uint64_t seed, size_t n) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> dt_ms(0, 20);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<TruthPose> out;
  Time t = Time::from_ms(1000 + static_cast<int64_t>(seed % 100));
  for (size_t i = 0; i < n; ++i) {
    TruthPose p;
    t = t + Time::from_ms(dt_ms(rng));  // 0: a repeated stamp
    p.stamp = t;
    p.p_W = Vec3(10 * g(rng), 10 * g(rng), -5 + g(rng));
    p.q_W_V = Quat(g(rng), g(rng), g(rng), g(rng)).normalized();
    out.push_back(p);
  }
  return out;
}

std::string spill_file_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("truth spill: the subset interpolates every asked stamp as the whole stream does", "[truth_spill]") {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const auto truth = spill_test_truth(seed, 3000 + 700 * seed);  // several write blocks
    auto spill = run::TruthSpill::open();
    REQUIRE(spill.ok());
    for (const auto& p : truth) (*spill)->append(p);
    REQUIRE((*spill)->finish().ok());
    REQUIRE((*spill)->size() == truth.size());
    std::mt19937_64 rng(seed * 77);
    const int64_t t0 = truth.front().stamp.ns() - 50'000'000, t1 = truth.back().stamp.ns() + 50'000'000;
    std::uniform_int_distribution<int64_t> any(t0, t1);
    std::uniform_int_distribution<size_t> pick(0, truth.size() - 1);
    std::vector<Time> stamps;
    for (int i = 0; i < 200; ++i) stamps.push_back(i % 3 == 0 ? truth[pick(rng)].stamp : Time::from_ns(any(rng)));
    stamps.push_back(truth.front().stamp);
    stamps.push_back(truth.back().stamp);
    const auto subset = (*spill)->subset(stamps);
    REQUIRE(subset.ok());
    CHECK(subset->size() <= 2 + 2 * stamps.size());
    CHECK(subset->front() == truth.front());
    CHECK(subset->back() == truth.back());
    for (const Time t : stamps) {
      const auto whole = mapping::truth_pose_at(truth, t);
      const auto part = mapping::truth_pose_at(*subset, t);
      REQUIRE(whole.has_value() == part.has_value());
      if (whole) CHECK(whole->matrix() == part->matrix());  // bit for bit
    }
  }
}

TEST_CASE("truth spill: every pose read back bit for bit, the same TUM bytes, the shown poses 100 ms apart",
          "[truth_spill]") {
  const auto truth = spill_test_truth(7, 9000);
  auto spill = run::TruthSpill::open();
  REQUIRE(spill.ok());
  int64_t most = 0;
  for (const auto& p : truth) {
    (*spill)->append(p);
    most = std::max(most, (*spill)->memory_bytes());
  }
  // Memory while streaming: the write buffer (4096 poses), not the 9000 poses of the stream.
  CHECK(most > 0);
  CHECK(most <= static_cast<int64_t>(4096 * sizeof(TruthPose)));
  REQUIRE((*spill)->finish().ok());
  std::vector<TruthPose> back;
  REQUIRE((*spill)->for_each([&](const TruthPose& p) { back.push_back(p); }).ok());
  CHECK(back == truth);

  const auto dir = std::filesystem::temp_directory_path() / "orthosonar_truth_spill_test";
  std::filesystem::create_directories(dir);
  REQUIRE(run::write_tum((dir / "a.tum").string(), truth).ok());
  REQUIRE(run::write_tum((dir / "b.tum").string(), **spill).ok());
  CHECK(spill_file_text((dir / "a.tum").string()) == spill_file_text((dir / "b.tum").string()));
  CHECK_FALSE(spill_file_text((dir / "a.tum").string()).empty());
  std::filesystem::remove_all(dir);

  std::vector<TruthPose> shown;
  REQUIRE((*spill)->for_each_shown([&](const TruthPose& p) { shown.push_back(p); }).ok());
  REQUIRE(shown.size() > 10);
  CHECK(shown.size() == (*spill)->shown_count());
  CHECK(shown == run::TruthSpill::thin(truth));  // the same rule on disk and in memory
  CHECK(shown.front() == truth.front());
  size_t j = 0;
  for (size_t i = 0; i < truth.size() && j < shown.size(); ++i)
    if (truth[i] == shown[j]) ++j;
  CHECK(j == shown.size());  // a subsequence of the stream
  for (size_t k = 1; k < shown.size(); ++k) CHECK((shown[k].stamp - shown[k - 1].stamp).ns() >= 100'000'000);
}

TEST_CASE("truth spill: an empty stream has an empty subset and no poses", "[truth_spill]") {
  auto spill = run::TruthSpill::open();
  REQUIRE(spill.ok());
  REQUIRE((*spill)->finish().ok());
  CHECK((*spill)->empty());
  const auto subset = (*spill)->subset({Time::from_ms(5)});
  REQUIRE(subset.ok());
  CHECK(subset->empty());
}
