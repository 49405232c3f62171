#include "core/inference/training_set.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/random.hpp"

namespace orthosonar::inference {
namespace {
constexpr uint64_t kSplitStream = 0x53504c54ull;    // "SPLT"
constexpr uint64_t kAugmentStream = 0x4155474dull;  // "AUGM"
}  // namespace

std::vector<LabelledCluster> labelled_clusters(const SonarPing& h, const SonarLabels& labels,
                                               const std::vector<PixelRC>& detections,
                                               const CropExtractionConfig& config) {
  std::vector<LabelledCluster> out;
  if (labels.rows != h.rows || labels.cols != h.cols || labels.semantic.size() != size_t{h.rows} * h.cols) return out;
  for (const Cluster& c : dbscan_clusters(detections, config.dbscan)) {
    std::array<size_t, kSemanticClassCount> votes{};
    for (const PixelRC& p : c.pixels) {
      const uint8_t s = labels.semantic[static_cast<size_t>(p.row) * labels.cols + static_cast<size_t>(p.col)];
      if (s < kSemanticClassCount) ++votes[s];
    }
    // Majority with ties to the lower class value (deterministic).
    const auto best = std::max_element(votes.begin(), votes.end());
    const double fraction = static_cast<double>(*best) / static_cast<double>(c.pixels.size());
    const auto semantic = static_cast<SemanticClass>(best - votes.begin());
    if (semantic == SemanticClass::kNone || fraction < config.min_majority) continue;
    out.push_back({crop_cluster(h, c, config.crop), semantic, fraction, h.ping_id});
  }
  return out;
}

TrainingSet build_training_set(const std::vector<LabelledCluster>& clusters, const TrainingSetConfig& config,
                               uint64_t seed) {
  TrainingSet set;
  std::array<std::vector<size_t>, kSemanticClassCount> by_class;
  for (size_t i = 0; i < clusters.size(); ++i) by_class[static_cast<size_t>(clusters[i].semantic)].push_back(i);
  for (size_t c = 0; c < by_class.size(); ++c) {
    std::vector<size_t> idx = by_class[c];
    if (static_cast<int>(idx.size()) < config.min_per_class) continue;
    const int label = static_cast<int>(set.classes.size());
    set.classes.push_back(static_cast<SemanticClass>(c));
    set.originals.push_back(idx.size());
    Rng rng(derive_seed(seed, kSplitStream, c));
    for (size_t i = idx.size(); i > 1; --i) std::swap(idx[i - 1], idx[rng.below(i)]);
    if (static_cast<int>(idx.size()) > config.max_per_class) idx.resize(static_cast<size_t>(config.max_per_class));
    const size_t n_hold = static_cast<size_t>(std::floor(config.holdout_fraction * static_cast<double>(idx.size())));
    for (size_t i = 0; i < n_hold; ++i) set.holdout.push_back({clusters[idx[i]].crop, label});
    const std::vector<size_t> train(idx.begin() + static_cast<std::ptrdiff_t>(n_hold), idx.end());
    for (size_t i : train) set.train.push_back({clusters[i].crop, label});
    Rng aug(derive_seed(seed, kAugmentStream, c));
    for (size_t k = train.size(); k < static_cast<size_t>(config.target_per_class) && !train.empty(); ++k) {
      const size_t src = train[k % train.size()];
      set.train.push_back({augment_crop(clusters[src].crop, aug, config.augment), label});
    }
  }
  return set;
}

}  // namespace orthosonar::inference
