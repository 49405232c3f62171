#include "core/inference/object_inference.hpp"

#include <algorithm>
#include <cmath>

#include "core/perception/fusion.hpp"
#include "core/random.hpp"

namespace orthosonar::inference {
namespace {

constexpr uint64_t kFrameStream = 0x494e4645ull;  // "INFE"

int nearest_column(const std::vector<double>& bearings, double bearing) {
  int best = 0;
  double best_d = INFINITY;
  for (size_t c = 0; c < bearings.size(); ++c) {
    const double d = std::abs(bearings[c] - bearing);
    if (d < best_d) {
      best_d = d;
      best = static_cast<int>(c);
    }
  }
  return best;
}

}  // namespace

std::vector<FusedObservation> fused_observations(const SonarPing& h, const perception::FusionResult& fused) {
  std::vector<FusedObservation> out;
  out.reserve(fused.points.size());
  for (const perception::FusedPoint& p : fused.points) {
    FusedObservation o;
    o.pixel.row = static_cast<int>(std::lround(p.range_m / h.range_resolution_m)) - 1;
    o.pixel.col = nearest_column(h.bearings_rad, p.bearing_rad);
    o.z_h_m = static_cast<double>(p.range_m) * std::sin(static_cast<double>(p.elevation_rad));
    o.p_V = p.p_V;
    out.push_back(o);
  }
  return out;
}

std::vector<PixelRC> detection_pixels(const perception::FusionResult& fused) {
  std::vector<PixelRC> out;
  out.reserve(fused.detections_h.size());
  for (const auto& d : fused.detections_h) out.push_back({d.row, d.col});
  return out;
}

ObjectInference::ObjectInference(const InferenceConfig& config, Classifier classifier)
    : config_(config), classifier_(std::move(classifier)) {}

const HeightModel* ObjectInference::height_model(SemanticClass c) const {
  const auto it = classes_.find(c);
  return it == classes_.end() ? nullptr : &it->second.heights;
}

FrameResult ObjectInference::process(const SonarPing& h, const std::vector<PixelRC>& detections,
                                     const std::vector<FusedObservation>& fused) {
  FrameResult out;
  out.stats.detections = detections.size();
  if (h.image.size() != static_cast<size_t>(h.rows) * h.cols * h.bytes_per_pixel) {
    out.stats.bad_image = 1;  // no pixels to crop: nothing is inferred, and the caller sees why
    return out;
  }
  out.clusters = dbscan_clusters(detections, config_.dbscan);
  out.stats.clusters = out.clusters.size();
  if (out.clusters.empty()) return out;

  std::vector<cv::Mat> crops;
  crops.reserve(out.clusters.size());
  for (const Cluster& c : out.clusters) crops.push_back(crop_cluster(h, c, config_.crop));
  out.predictions = classifier_.classify(crops, derive_seed(config_.seed, kFrameStream, h.ping_id));

  std::map<PixelRC, std::vector<double>> heights_at;  // fused heights per h pixel
  for (const FusedObservation& o : fused) heights_at[o.pixel].push_back(o.z_h_m);

  const size_t n_beams = h.bearings_rad.size();
  for (size_t k = 0; k < out.clusters.size(); ++k) {
    const Prediction& pred = out.predictions[k];
    if (!pred.known) {
      ++out.stats.unknown;
      continue;
    }
    ++out.stats.known;
    const Cluster& cluster = out.clusters[k];
    std::vector<double> ranges, bearings;
    bool has_3d = false;
    for (const PixelRC& p : cluster.pixels) {
      ranges.push_back(h.range_of_row(p.row));
      bearings.push_back(static_cast<size_t>(p.col) < n_beams ? h.bearings_rad[static_cast<size_t>(p.col)] : 0.0);
      has_3d = has_3d || heights_at.count(p) > 0;
    }
    const auto it = classes_.find(pred.semantic);
    const bool class_has_model = it != classes_.end() && it->second.heights.updates() > 0;
    if (!has_3d && !class_has_model) continue;  // nothing to learn, nothing to predict

    ClassState& state = classes_.try_emplace(pred.semantic, ClassState{ClassReference(config_.registration),
                                                                         HeightModel(config_.height)}).first->second;
    const SightingFrame frame = sighting_frame(ranges, bearings);
    std::vector<Vec2> pts_obj(cluster.pixels.size());
    for (size_t i = 0; i < pts_obj.size(); ++i) pts_obj[i] = to_sighting(frame, ranges[i], bearings[i]);
    // The first sighting with 3D points founds the reference (paper §VI-B); later ones register.
    const std::optional<Registration> reg = state.reference.register_sighting(pts_obj);
    if (!reg) {
      ++out.stats.registration_failures;
      continue;
    }
    std::vector<Vec2> pts_ref(pts_obj.size());
    for (size_t i = 0; i < pts_obj.size(); ++i) pts_ref[i] = reg->T_ref_obj * pts_obj[i];

    // Bayes update (Eq. 8) for every fused point of this object.
    if (has_3d) {
      for (size_t i = 0; i < cluster.pixels.size(); ++i) {
        const auto h_it = heights_at.find(cluster.pixels[i]);
        if (h_it == heights_at.end()) continue;
        for (double z : h_it->second) {
          if (state.heights.update(pts_ref[i].x(), pts_ref[i].y(), z)) ++out.stats.bayes_updates;
        }
      }
      if (!reg->first_sighting) state.reference.add(pts_ref);
    }
    if (state.heights.updates() == 0) continue;

    // Two-sided MAP (Eqs. 9-10) for the 2D-only pixels, once per reference cell.
    std::map<CellKey, TwoSidedMap> map_of_cell;
    for (size_t i = 0; i < cluster.pixels.size(); ++i) {
      if (heights_at.count(cluster.pixels[i]) > 0) continue;
      const CellKey key = state.heights.cell_of(pts_ref[i].x(), pts_ref[i].y());
      auto m_it = map_of_cell.find(key);
      if (m_it == map_of_cell.end()) {
        m_it = map_of_cell.emplace(key, state.heights.map_estimate(pts_ref[i].x(), pts_ref[i].y())).first;
      }
      const TwoSidedMap& m = m_it->second;
      for (const auto& est : {m.below, m.above}) {
        if (!est || std::abs(est->z_m) >= ranges[i]) continue;
        const double phi = std::asin(est->z_m / ranges[i]);
        const Vec3 p_h = spherical_to_cartesian(ranges[i], bearings[i], phi);  // Eq. 1
        out.inferred_V.push_back((config_.T_V_h * p_h).cast<float>());
      }
    }
  }
  out.stats.inferred_points = out.inferred_V.size();
  return out;
}

}  // namespace orthosonar::inference
