// `orthosonar train-classifier`: trains the inference classifier (SPEC §8) on simulated
// data. For each scene, the simulator runs with per-pixel labels; every `stride`-th
// horizontal ping goes through CFAR and DBSCAN exactly as in the pipeline, each cluster's
// crop is labelled with the majority class of its pixels, the crops are split (held-out
// per class), the training part augmented, and the CNN trained with a fixed seed. Prints
// held-out accuracy per class and writes the model (torch archive) to -o.
// --test-scenes: scenes the model was not trained on (e.g. leave one scene out); every
// labelled cluster of theirs is classified and the accuracy printed separately from the
// held-out split, which is a random split of crops from the same missions as the training
// crops (neighbouring pings of the same structures), so it overstates what the model does
// on a new place (docs/INFERENCE.md).
// Defaults: marina1, marina2 and harbor, 300 s each (piling, dock, boat, seawall, hull;
// 60-80 s on 2 cores). Trained on the marinas alone it knew only piling and dock and accepted
// crops of other structures (the aircraft wreck) as one of them (docs/INFERENCE.md).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "core/inference/classifier.hpp"
#include "core/inference/training_set.hpp"
#include "core/perception/cfar.hpp"
#include "core/perception/fusion.hpp"
#include "hal/sim/simulator.hpp"
#include "tools/cli.hpp"

namespace orthosonar::cli {
namespace {

struct TrainArgs {
  std::string scenes = "marina1,marina2,harbor";
  double duration_s = 300.0;
  uint64_t seed = 1;
  uint64_t scene_seed = 1;
  std::string resolution = "full";
  int stride = 2;
  int epochs = 40;
  int per_class = 800;
  int threads = 2;
  std::string out;
  std::string test_scenes;   // evaluated after training, never trained on
  uint64_t test_seed = 2;    // mission seed of the test scenes
};

std::vector<std::string> split_csv(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Simulates `name` with labels and appends the labelled clusters of every `stride`-th
// horizontal ping to `clusters`, exactly as the pipeline's CFAR and DBSCAN see them.
Status collect_labelled_clusters(const TrainArgs& a, const std::string& name, uint64_t mission_seed,
                                 sim::Resolution resolution, std::vector<inference::LabelledCluster>& clusters,
                                 std::chrono::steady_clock::time_point t0) {
  const perception::CfarConfig cfar = perception::FusionConfig{}.cfar_h;
  auto scene = sim::builtin_scene(name, a.scene_seed);
  if (!scene) return scene.error();
  sim::SimConfig cfg;
  cfg.duration_s = a.duration_s;
  cfg.seed = mission_seed;
  cfg.resolution = resolution;
  cfg.labels = true;
  cfg.render_threads = std::max(1, a.threads);
  sim::Simulator simulator(std::move(*scene), cfg);
  std::optional<SonarPing> last_h;
  size_t pings = 0, before = clusters.size();
  for (;;) {
    sim::Pulled p = simulator.next();
    if (p.error) return Error{"simulator: " + p.error->message};
    if (p.end_of_stream || !p.event) break;
    Event& e = *p.event;
    if (e.channel == Channel::kSonarHorizontal) {
      last_h = std::get<SonarPing>(std::move(e.payload));
    } else if (e.channel == Channel::kLabelsHorizontal && last_h) {
      const auto& labels = std::get<SonarLabels>(e.payload);
      if (labels.ping_id != last_h->ping_id || (pings++ % static_cast<size_t>(a.stride)) != 0) continue;
      std::vector<inference::PixelRC> det;
      for (const auto& d : perception::cfar_detect(*last_h, cfar)) det.push_back({d.row, d.col});
      auto got = inference::labelled_clusters(*last_h, labels, det);
      for (auto& c : got) clusters.push_back(std::move(c));
    }
  }
  std::printf("scene %s (mission seed %llu): %zu pings, %zu labelled clusters (%.1f s)\n", name.c_str(),
              static_cast<unsigned long long>(mission_seed), pings, clusters.size() - before, seconds_since(t0));
  return {};
}

int run_train(const TrainArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  auto resolution = sim::parse_resolution(a.resolution);
  if (!resolution) {
    std::cerr << "train-classifier: " << resolution.error().message << "\n";
    return 2;
  }
  if (a.out.empty() || a.stride < 1 || a.duration_s <= 0.0) {
    std::cerr << "train-classifier: need -o <model file>, --stride >= 1 and --duration > 0\n";
    return 2;
  }
  // Torch runs single-threaded so the model bits do not depend on the machine's cores;
  // the simulator renders with `threads` (its bytes are the same for any count).
  inference::InferenceRuntime::configure(1, a.seed);
  std::vector<inference::LabelledCluster> clusters;
  for (const std::string& name : split_csv(a.scenes)) {
    if (auto st = collect_labelled_clusters(a, name, a.seed, *resolution, clusters, t0); !st) {
      std::cerr << "train-classifier: " << st.error().message << "\n";
      return 2;
    }
  }
  inference::TrainingSetConfig tcfg;
  tcfg.target_per_class = a.per_class;
  const inference::TrainingSet set = inference::build_training_set(clusters, tcfg, a.seed);
  if (set.classes.size() < 2) {
    std::cerr << "train-classifier: fewer than two classes with enough samples (" << clusters.size()
              << " labelled clusters); simulate longer\n";
    return 2;
  }
  inference::Classifier net({}, set.classes, a.seed);
  inference::TrainConfig train;
  train.epochs = a.epochs;
  const double loss = net.train(set.train, train, a.seed);
  std::printf("trained on %zu crops (%zu classes), last-epoch loss %.4f (%.1f s)\n", set.train.size(),
              set.classes.size(), loss, seconds_since(t0));
  std::printf("%-10s %9s %8s %9s %11s\n", "class", "originals", "held-out", "accuracy", "mc-accepted");
  size_t correct = 0, total = 0;
  const auto acc = net.evaluate(set.holdout, a.seed);
  for (size_t c = 0; c < acc.size(); ++c) {
    correct += acc[c].correct;
    total += acc[c].samples;
    std::printf("%-10s %9zu %8zu %8.1f%% %10.1f%%\n", semantic_class_name(acc[c].semantic), set.originals[c],
                acc[c].samples, 100.0 * acc[c].accuracy(),
                acc[c].samples ? 100.0 * static_cast<double>(acc[c].accepted) / static_cast<double>(acc[c].samples) : 0.0);
  }
  std::printf("overall held-out accuracy %.1f%% (%zu/%zu)\n",
              total ? 100.0 * static_cast<double>(correct) / static_cast<double>(total) : 0.0, correct, total);
  if (!a.test_scenes.empty()) {
    // Scenes never trained on: every labelled cluster of theirs, no split, no augmentation.
    std::vector<inference::LabelledCluster> unseen;
    for (const std::string& name : split_csv(a.test_scenes)) {
      if (auto st = collect_labelled_clusters(a, name, a.test_seed, *resolution, unseen, t0); !st) {
        std::cerr << "train-classifier: test scene: " << st.error().message << "\n";
        return 2;
      }
    }
    std::vector<inference::LabelledCrop> test;
    std::map<SemanticClass, size_t> unknown_to_model;
    for (const auto& c : unseen) {
      const auto it = std::find(set.classes.begin(), set.classes.end(), c.semantic);
      if (it == set.classes.end()) ++unknown_to_model[c.semantic];
      else test.push_back({c.crop, static_cast<int>(it - set.classes.begin())});
    }
    std::printf("unseen scenes %s: %zu labelled clusters, %zu of classes the model knows\n", a.test_scenes.c_str(),
                unseen.size(), test.size());
    for (const auto& [cls, n] : unknown_to_model)
      std::printf("  %-10s %zu clusters (class not in the model; not scored)\n", semantic_class_name(cls), n);
    std::printf("%-10s %9s %9s %11s\n", "class", "unseen", "accuracy", "mc-accepted");
    size_t u_correct = 0, u_total = 0;
    for (const auto& r : net.evaluate(test, a.seed)) {
      u_correct += r.correct;
      u_total += r.samples;
      std::printf("%-10s %9zu %8.1f%% %10.1f%%\n", semantic_class_name(r.semantic), r.samples, 100.0 * r.accuracy(),
                  r.samples ? 100.0 * static_cast<double>(r.accepted) / static_cast<double>(r.samples) : 0.0);
    }
    std::printf("overall accuracy on unseen scenes %.1f%% (%zu/%zu)\n",
                u_total ? 100.0 * static_cast<double>(u_correct) / static_cast<double>(u_total) : 0.0, u_correct,
                u_total);
  }
  std::ofstream f(a.out, std::ios::binary);
  const std::string bytes = net.serialize();
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!f) {
    std::cerr << "train-classifier: cannot write '" << a.out << "'\n";
    return 2;
  }
  std::printf("model written to %s (%zu bytes, %.1f s)\n", a.out.c_str(), bytes.size(), seconds_since(t0));
  return 0;
}

const bool registered_train_classifier = register_command(
    {"train-classifier", "Train the inference classifier on simulated, labelled sonar data",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<TrainArgs>();
       sub.add_option("--scenes", a->scenes, "Built-in scenes, comma separated")->capture_default_str();
       sub.add_option("--duration", a->duration_s, "Simulated seconds per scene")->capture_default_str();
       sub.add_option("--seed", a->seed, "Seed of the simulation, split, augmentation and training")->capture_default_str();
       sub.add_option("--scene-seed", a->scene_seed, "Scene geometry seed")->capture_default_str();
       sub.add_option("--resolution", a->resolution, "full or reduced")->capture_default_str();
       sub.add_option("--stride", a->stride, "Use every n-th horizontal ping")->capture_default_str();
       sub.add_option("--epochs", a->epochs, "Training epochs")->capture_default_str();
       sub.add_option("--per-class", a->per_class, "Training crops per class after augmentation")->capture_default_str();
       sub.add_option("--threads", a->threads, "Simulator render threads (training is single-threaded)")->capture_default_str();
       sub.add_option("-o,--out", a->out, "Model file to write")->required();
       sub.add_option("--test-scenes", a->test_scenes,
                      "Built-in scenes to evaluate on after training, never trained on (comma separated)");
       sub.add_option("--test-seed", a->test_seed, "Mission seed of the --test-scenes missions")->capture_default_str();
       return [a] { return run_train(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
