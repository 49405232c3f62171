#include "replay/run/sweep_store.hpp"

#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#include "core/memory.hpp"
#include "replay/mcap/zstd_frame.hpp"

namespace orthosonar::run {
namespace {

// How many of the most recent beam tables a new ping's table is compared with: a device
// keeps one table per mount and frequency, so a short list finds it; a source whose every
// ping has a table of its own costs a few comparisons per ping, not a search of all.
constexpr size_t kRecentTables = 8;

}  // namespace

uint32_t SweepEvents::table_of(std::vector<double> bearings) {
  for (auto it = recent_tables_.rbegin(); it != recent_tables_.rend(); ++it)
    if (tables_[*it] == bearings) {
      const uint32_t t = *it;
      recent_tables_.erase(std::next(it).base());
      recent_tables_.push_back(t);
      return t;
    }
  bearings.shrink_to_fit();
  tables_.push_back(std::move(bearings));
  const auto t = static_cast<uint32_t>(tables_.size() - 1);
  recent_tables_.push_back(t);
  if (recent_tables_.size() > kRecentTables) recent_tables_.erase(recent_tables_.begin());
  return t;
}

void SweepEvents::push_back(Event e) {
  Slot s;
  s.stamp = e.stamp;
  s.sequence = e.sequence;
  s.channel = e.channel;
  const auto put = [&](Kind kind, auto& store, auto&& payload) {
    s.kind = kind;
    s.index = static_cast<uint32_t>(store.size());
    store.push_back(std::move(payload));
  };
  std::visit(
      [&](auto&& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, SonarPing>) {
          ping_table_.push_back(table_of(std::move(p.bearings_rad)));
          p.bearings_rad = {};
          put(Kind::kPing, pings_, std::move(p));
        } else if constexpr (std::is_same_v<T, DvlReading>) {
          put(Kind::kDvl, dvl_, std::move(p));
        } else if constexpr (std::is_same_v<T, ImuReading>) {
          put(Kind::kImu, imu_, std::move(p));
        } else if constexpr (std::is_same_v<T, DepthReading>) {
          put(Kind::kDepth, depth_, std::move(p));
        } else if constexpr (std::is_same_v<T, TruthPose>) {
          put(Kind::kTruth, truth_, std::move(p));
        } else if constexpr (std::is_same_v<T, SonarLabels>) {
          put(Kind::kLabels, labels_, std::move(p));
        } else {
          static_assert(std::is_same_v<T, GyroReading>);
          put(Kind::kGyro, gyro_, std::move(p));
        }
      },
      std::move(e.payload));
  slots_.push_back(s);
}

void SweepEvents::finish() {
  std::stable_sort(slots_.begin(), slots_.end(), [](const Slot& a, const Slot& b) {
    if (a.stamp != b.stamp) return a.stamp < b.stamp;
    if (a.channel != b.channel) return a.channel < b.channel;
    return a.sequence < b.sequence;
  });
  slots_.shrink_to_fit();
  recent_tables_.clear();
  recent_tables_.shrink_to_fit();
}

Event SweepEvents::at(size_t i) const {
  const Slot& s = slots_[i];
  Event e;
  e.stamp = s.stamp;
  e.sequence = s.sequence;
  e.channel = s.channel;
  switch (s.kind) {
    case Kind::kPing: {
      SonarPing p = pings_[s.index];
      p.bearings_rad = tables_[ping_table_[s.index]];
      e.payload = std::move(p);
      break;
    }
    case Kind::kDvl: e.payload = dvl_[s.index]; break;
    case Kind::kImu: e.payload = imu_[s.index]; break;
    case Kind::kDepth: e.payload = depth_[s.index]; break;
    case Kind::kTruth: e.payload = truth_[s.index]; break;
    case Kind::kLabels: e.payload = labels_[s.index]; break;
    case Kind::kGyro: e.payload = gyro_[s.index]; break;
  }
  return e;
}

int64_t SweepEvents::memory_bytes() const {
  int64_t n = heap_bytes(slots_) + heap_bytes(pings_) + heap_bytes(ping_table_) + heap_bytes(tables_) +
              heap_bytes(dvl_) + heap_bytes(imu_) + heap_bytes(depth_) + heap_bytes(truth_) +
              heap_bytes(labels_) + heap_bytes(gyro_);
  for (const auto& p : pings_) n += heap_bytes(p);
  for (const auto& t : tables_) n += heap_bytes(t);
  return n;
}

hal::Pulled SweepEventSource::next() {
  if (index_ >= events_.size()) return hal::Pulled::end();
  return hal::Pulled::of(events_.at(index_++));
}

// ---- fusion results ----

namespace {

class Writer {
 public:
  template <class T>
  void put(T v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const size_t at = out.size();
    out.resize(at + sizeof v);
    std::memcpy(out.data() + at, &v, sizeof v);
  }
  std::vector<uint8_t> out;
};

class Reader {
 public:
  explicit Reader(const std::vector<uint8_t>& in) : in_(in) {}
  template <class T>
  T get() {
    T v;
    if (at_ + sizeof v > in_.size()) throw std::runtime_error("sweep fusion cache: a cached result is cut short");
    std::memcpy(&v, in_.data() + at_, sizeof v);
    at_ += sizeof v;
    return v;
  }
  bool done() const { return at_ == in_.size(); }

 private:
  const std::vector<uint8_t>& in_;
  size_t at_ = 0;
};

// Column-wise: all rows (as deltas: row-major lists give small, repeating numbers), then all
// columns, then all intensities, which zstd compresses far better than 12-byte records.
void put_detections(Writer& w, const std::vector<perception::Detection>& d) {
  w.put<uint64_t>(d.size());
  int prev = 0;
  for (const auto& x : d) {
    w.put<int32_t>(x.row - prev);
    prev = x.row;
  }
  for (const auto& x : d) w.put<int32_t>(x.col);
  for (const auto& x : d) w.put<float>(x.intensity);
}

std::vector<perception::Detection> get_detections(Reader& r) {
  std::vector<perception::Detection> d(r.get<uint64_t>());
  int prev = 0;
  for (auto& x : d) {
    x.row = prev + r.get<int32_t>();
    prev = x.row;
  }
  for (auto& x : d) x.col = r.get<int32_t>();
  for (auto& x : d) x.intensity = r.get<float>();
  return d;
}

// The float members of a fused point after p_V, each written as a column.
constexpr float perception::FusedPoint::*kPointFloats[] = {
    &perception::FusedPoint::range_m,     &perception::FusedPoint::bearing_rad, &perception::FusedPoint::elevation_rad,
    &perception::FusedPoint::intensity_h, &perception::FusedPoint::intensity_v, &perception::FusedPoint::confidence,
    &perception::FusedPoint::run_near_m,  &perception::FusedPoint::run_far_m,   &perception::FusedPoint::elevation_sigma_rad};

struct CCtxFree {
  void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};

}  // namespace

std::vector<uint8_t> serialise_fusion(const perception::FusionResult& r) {
  Writer w;
  for (const size_t v : {r.candidates_h, r.candidates_v, r.subproblems, r.matches, r.culled_low_confidence, r.sloped_face})
    w.put<uint64_t>(v);
  w.put<uint64_t>(r.points.size());
  for (int k = 0; k < 3; ++k)
    for (const auto& p : r.points) w.put<float>(p.p_V[k]);
  for (float perception::FusedPoint::*f : kPointFloats)
    for (const auto& p : r.points) w.put<float>(p.*f);
  for (const auto& p : r.points) w.put<uint8_t>(static_cast<uint8_t>(p.elevation_from));
  put_detections(w, r.detections_h);
  put_detections(w, r.detections_v);
  return std::move(w.out);
}

perception::FusionResult deserialise_fusion(const std::vector<uint8_t>& bytes) {
  Reader rd(bytes);
  perception::FusionResult r;
  for (size_t* v : {&r.candidates_h, &r.candidates_v, &r.subproblems, &r.matches, &r.culled_low_confidence, &r.sloped_face})
    *v = static_cast<size_t>(rd.get<uint64_t>());
  r.points.resize(static_cast<size_t>(rd.get<uint64_t>()));
  for (int k = 0; k < 3; ++k)
    for (auto& p : r.points) p.p_V[k] = rd.get<float>();
  for (float perception::FusedPoint::*f : kPointFloats)
    for (auto& p : r.points) p.*f = rd.get<float>();
  for (auto& p : r.points) {
    const auto from = rd.get<uint8_t>();
    if (from > static_cast<uint8_t>(perception::FusedPoint::Elevation::sloped_face))
      throw std::runtime_error("sweep fusion cache: a cached point's elevation source is " + std::to_string(from));
    p.elevation_from = static_cast<perception::FusedPoint::Elevation>(from);
  }
  r.detections_h = get_detections(rd);
  r.detections_v = get_detections(rd);
  if (!rd.done()) throw std::runtime_error("sweep fusion cache: a cached result has bytes past its end");
  return r;
}

void FusionCache::put(Time h_stamp, Time v_stamp, const perception::FusionResult& r) {
  thread_local std::unique_ptr<ZSTD_CCtx, CCtxFree> cctx(ZSTD_createCCtx());
  const std::vector<uint8_t> raw = serialise_fusion(r);
  std::vector<uint8_t> packed(ZSTD_compressBound(raw.size()));
  const size_t n = cctx ? ZSTD_compressCCtx(cctx.get(), packed.data(), packed.size(), raw.data(), raw.size(), 1)
                        : ZSTD_compress(packed.data(), packed.size(), raw.data(), raw.size(), 1);
  if (ZSTD_isError(n)) throw std::runtime_error(std::string("sweep fusion cache: zstd: ") + ZSTD_getErrorName(n));
  packed.resize(n);
  packed.shrink_to_fit();
  std::lock_guard lock(mu_);
  auto& slot = blobs_[{h_stamp.ns(), v_stamp.ns()}];
  bytes_ += static_cast<int64_t>(packed.capacity()) - static_cast<int64_t>(slot.capacity());
  slot = std::move(packed);
}

std::optional<perception::FusionResult> FusionCache::get(Time h_stamp, Time v_stamp) const {
  const std::vector<uint8_t>* packed = nullptr;
  {
    std::lock_guard lock(mu_);
    const auto it = blobs_.find({h_stamp.ns(), v_stamp.ns()});
    if (it == blobs_.end()) return std::nullopt;
    packed = &it->second;  // never changed or erased once the preparation pass is over
  }
  const unsigned long long size = ZSTD_getFrameContentSize(packed->data(), packed->size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN)
    throw std::runtime_error("sweep fusion cache: a cached result is not a zstd frame");
  std::vector<uint8_t> raw(static_cast<size_t>(size));
  const auto n = replay::mcap::zstd_decompress(packed->data(), packed->size(), raw.data(), raw.size());
  if (!n.ok() || *n != raw.size())
    throw std::runtime_error("sweep fusion cache: zstd: " + (n.ok() ? std::string("short result") : n.error().message));
  return deserialise_fusion(raw);
}

size_t FusionCache::size() const {
  std::lock_guard lock(mu_);
  return blobs_.size();
}

int64_t FusionCache::memory_bytes() const {
  std::lock_guard lock(mu_);
  // A std::map node: the key, the vector and three pointers and a colour.
  return bytes_ + static_cast<int64_t>(blobs_.size() * (sizeof(std::pair<int64_t, int64_t>) + sizeof(std::vector<uint8_t>) + 32));
}

}  // namespace orthosonar::run
