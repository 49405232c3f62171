// Inference-based mapping on simulated marinas, in process (SPEC §8): a classifier trained
// on a short labelled marina2 mission classifies clusters of a different marina1 mission
// correctly, and the heights it infers for 2D-only piling pixels land on the true scene
// (distance to the ground-truth mesh). Prints per-frame counts, timings and the confusion
// of accepted classes against the simulator's labels.
#include <catch2/catch.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <optional>
#include <variant>

#include "core/inference/object_inference.hpp"
#include "core/inference/training_set.hpp"
#include "core/mapping/mesh_distance.hpp"
#include "core/perception/fusion.hpp"
#include "hal/sim/simulator.hpp"

using namespace orthosonar;
using namespace orthosonar::inference;

namespace {

struct Frame {
  SonarPing h, v;
  SonarLabels labels;
  SE3 T_W_V = SE3::Identity();
};

// Frames (h, v, h labels, truth pose at the h stamp) of a simulated mission.
std::vector<Frame> simulate(const std::string& scene_name, double duration_s, uint64_t seed) {
  auto scene = sim::builtin_scene(scene_name, 1);
  REQUIRE(scene.ok());
  sim::SimConfig cfg;
  cfg.duration_s = duration_s;
  cfg.seed = seed;
  cfg.labels = true;
  cfg.render_threads = 2;
  sim::Simulator simulator(std::move(*scene), cfg);
  std::vector<Frame> frames;
  Frame cur;
  bool have_h = false, have_labels = false, have_pose = false;
  for (;;) {
    sim::Pulled p = simulator.next();
    REQUIRE_FALSE(p.error.has_value());
    if (!p.event) break;
    Event& e = *p.event;
    if (e.channel == Channel::kSonarHorizontal) {
      cur = Frame{};
      cur.h = std::get<SonarPing>(e.payload);
      have_h = true;
      have_labels = have_pose = false;
    } else if (e.channel == Channel::kLabelsHorizontal && have_h) {
      cur.labels = std::get<SonarLabels>(e.payload);
      have_labels = true;
    } else if (e.channel == Channel::kTruthPose && have_h && !have_pose && e.stamp == cur.h.stamp) {
      const auto& t = std::get<TruthPose>(e.payload);
      cur.T_W_V.linear() = t.q_W_V.toRotationMatrix();
      cur.T_W_V.translation() = t.p_W;
      have_pose = true;
    } else if (e.channel == Channel::kSonarVertical && have_h && have_labels && have_pose) {
      cur.v = std::get<SonarPing>(e.payload);
      frames.push_back(std::move(cur));
      have_h = false;
    }
  }
  return frames;
}

}  // namespace

TEST_CASE("a classifier trained on marina2 maps pilings of marina1 in 3D", "[golden]") {
  InferenceRuntime::configure(1, 1);
  const perception::FusionConfig fusion;
  // Train on marina2 (labels from the simulator).
  std::vector<LabelledCluster> labelled;
  for (const Frame& f : simulate("marina2", 16.0, 3)) {
    std::vector<PixelRC> det;
    for (const auto& d : perception::cfar_detect(f.h, fusion.cfar_h)) det.push_back({d.row, d.col});
    for (auto& c : labelled_clusters(f.h, f.labels, det)) labelled.push_back(std::move(c));
  }
  TrainingSetConfig tcfg;
  tcfg.target_per_class = 200;
  const TrainingSet set = build_training_set(labelled, tcfg, 5);
  REQUIRE(std::count(set.classes.begin(), set.classes.end(), SemanticClass::kPiling) == 1);
  Classifier net({}, set.classes, 5);
  TrainConfig train;
  train.epochs = 8;
  net.train(set.train, train, 5);
  size_t correct = 0, total = 0;
  for (const auto& a : net.evaluate(set.holdout, 5)) {
    correct += a.correct;
    total += a.samples;
  }
  std::printf("held-out accuracy %zu/%zu over %zu classes\n", correct, total, set.classes.size());
  CHECK(static_cast<double>(correct) >= 0.85 * static_cast<double>(total));

  // Run inference on every frame of a marina1 mission.
  const std::vector<Frame> frames = simulate("marina1", 24.0, 9);
  REQUIRE(frames.size() > 100);
  InferenceConfig icfg;
  icfg.T_V_h = fusion.T_V_h;
  ObjectInference inf(icfg, std::move(net));
  auto scene = sim::builtin_scene("marina1", 1);
  const mapping::MeshDistance truth(scene->mesh);
  size_t ambiguous = 0;  // accepted clusters without a 60 % label majority (not judged)
  size_t accepted = 0, accepted_right = 0, inferred = 0, fused = 0, clusters = 0, updates = 0, reg_fail = 0;
  std::vector<double> err_inferred, ms;
  std::map<std::pair<int, int>, size_t> confusion;  // (predicted, majority label) -> clusters
  for (const Frame& f : frames) {
    const auto fr = perception::fuse_pair(f.h, f.v, fusion);
    fused += fr.points.size();
    const auto t0 = std::chrono::steady_clock::now();
    const FrameResult r = inf.process(f.h, detection_pixels(fr), fused_observations(f.h, fr));
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    for (size_t k = 0; k < r.clusters.size(); ++k) {
      if (!r.predictions[k].known) continue;
      std::map<uint8_t, size_t> votes;
      for (const PixelRC& p : r.clusters[k].pixels) ++votes[f.labels.semantic[static_cast<size_t>(p.row) * f.labels.cols + static_cast<size_t>(p.col)]];
      const auto best = std::max_element(votes.begin(), votes.end(), [](auto& a, auto& b) { return a.second < b.second; });
      // Judge only clusters with a clear label, as training does (min_majority 0.6): a
      // piling standing at a dock's edge merges with it into one cluster of either label.
      if (static_cast<double>(best->second) < 0.6 * static_cast<double>(r.clusters[k].pixels.size())) {
        ++ambiguous;
        continue;
      }
      ++accepted;
      ++confusion[{static_cast<int>(r.predictions[k].semantic), static_cast<int>(best->first)}];
      if (best->first == static_cast<uint8_t>(r.predictions[k].semantic)) ++accepted_right;
    }
    for (const auto& p : r.inferred_V) err_inferred.push_back(truth.distance(f.T_W_V * p.cast<double>()));
    inferred += r.inferred_V.size();
    clusters += r.stats.clusters;
    updates += r.stats.bayes_updates;
    reg_fail += r.stats.registration_failures;
  }
  std::sort(err_inferred.begin(), err_inferred.end());
  std::sort(ms.begin(), ms.end());
  const double median_err = err_inferred.empty() ? 1e9 : err_inferred[err_inferred.size() / 2];
  std::printf("frames %zu, accepted clusters %zu (%zu agree with labels), fused points %zu, inferred points %zu, "
              "median inferred error %.3f m, per-frame ms median %.1f max %.1f; clusters %zu, Bayes updates %zu, "
              "registration failures %zu\n",
              frames.size(), accepted, accepted_right, fused, inferred, median_err, ms[ms.size() / 2], ms.back(),
              clusters, updates, reg_fail);
  std::printf("accepted clusters without a clear label (not judged): %zu\n", ambiguous);
  for (const auto& [k, n] : confusion)
    std::printf("predicted %s, labelled %s: %zu clusters\n", semantic_class_name(static_cast<SemanticClass>(k.first)),
                semantic_class_name(static_cast<SemanticClass>(k.second)), n);
  std::fflush(stdout);
  CHECK(accepted > 50);
  // Cross-scene: the marina2 crops never show marina1's view along the breakwater, where a
  // row of pilings seen end-on forms long clusters that look like a dock edge (about 200
  // of ~1450 accepted clusters are called dock). 86 % agree; 80 % is the floor.
  CHECK(static_cast<double>(accepted_right) >= 0.8 * static_cast<double>(accepted));
  CHECK(inferred > fused / 2);  // inference adds substantially to the fused cloud
  CHECK(median_err < 0.3);      // and the inferred heights land on the scene
}
