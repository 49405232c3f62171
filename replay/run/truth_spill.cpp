#include "replay/run/truth_spill.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "core/memory.hpp"

namespace orthosonar::run {
namespace {

constexpr size_t kRecordBytes = 64;  // stamp (int64), p_W (3 double), q_W_V (x y z w double)
constexpr size_t kBufferPoses = 4096;

void encode(const TruthPose& p, uint8_t* out) {
  const int64_t ns = p.stamp.ns();
  const double v[7] = {p.p_W.x(), p.p_W.y(), p.p_W.z(), p.q_W_V.x(), p.q_W_V.y(), p.q_W_V.z(), p.q_W_V.w()};
  std::memcpy(out, &ns, 8);
  std::memcpy(out + 8, v, sizeof v);
}

TruthPose decode(const uint8_t* in) {
  int64_t ns = 0;
  double v[7];
  std::memcpy(&ns, in, 8);
  std::memcpy(v, in + 8, sizeof v);
  TruthPose p;
  p.stamp = Time::from_ns(ns);
  p.p_W = Vec3(v[0], v[1], v[2]);
  p.q_W_V = Quat(v[6], v[3], v[4], v[5]);  // Eigen's constructor takes w first
  return p;
}

}  // namespace

Result<std::unique_ptr<TruthSpill>> TruthSpill::open() {
  std::FILE* f = std::tmpfile();
  if (f == nullptr) return Error{std::string("ground truth: no temporary file for the truth poses: ") + std::strerror(errno)};
  return std::unique_ptr<TruthSpill>(new TruthSpill(f));
}

TruthSpill::~TruthSpill() {
  if (file_ != nullptr) std::fclose(file_);
}

bool TruthSpill::show(Time stamp, Time& last, bool& first) {
  if (!first && (stamp - last).ns() < kShownSpacingNs) return false;
  last = stamp;
  first = false;
  return true;
}

std::vector<TruthPose> TruthSpill::thin(const std::vector<TruthPose>& truth) {
  std::vector<TruthPose> shown;
  Time last;
  bool first = true;
  for (const TruthPose& p : truth)
    if (show(p.stamp, last, first)) shown.push_back(p);
  return shown;
}

void TruthSpill::append(const TruthPose& p) {
  if (show(p.stamp, last_shown_, none_shown_)) ++shown_count_;
  if (buffer_.empty()) buffer_.reserve(kBufferPoses);
  buffer_.push_back(p);
  ++count_;
  if (buffer_.size() >= kBufferPoses) (void)flush_buffer();
}

Status TruthSpill::flush_buffer() {
  if (!error_.empty()) return Error{error_};
  if (buffer_.empty()) return {};
  std::vector<uint8_t> bytes(buffer_.size() * kRecordBytes);
  for (size_t i = 0; i < buffer_.size(); ++i) encode(buffer_[i], bytes.data() + i * kRecordBytes);
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size() || std::fflush(file_) != 0) {
    error_ = std::string("ground truth: writing the truth poses to a temporary file failed: ") + std::strerror(errno);
    return Error{error_};
  }
  written_ += buffer_.size();
  buffer_.clear();
  return {};
}

Status TruthSpill::finish() {
  if (Status s = flush_buffer(); !s.ok()) return s;
  buffer_.shrink_to_fit();
  return {};
}

Status TruthSpill::read(size_t first, size_t n, std::vector<TruthPose>& out) const {
  if (!error_.empty()) return Error{error_};
  if (first + n > written_) return Error{"ground truth: reading poses past those written (finish() first)"};
  std::vector<uint8_t> bytes(n * kRecordBytes);
  const int fd = fileno(file_);
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t got = ::pread(fd, bytes.data() + done, bytes.size() - done,
                                static_cast<off_t>(first * kRecordBytes + done));
    if (got <= 0) {
      if (got < 0 && errno == EINTR) continue;
      return Error{std::string("ground truth: reading the truth poses back failed: ") +
                   (got < 0 ? std::strerror(errno) : "short read")};
    }
    done += static_cast<size_t>(got);
  }
  for (size_t i = 0; i < n; ++i) out.push_back(decode(bytes.data() + i * kRecordBytes));
  return {};
}

Result<std::vector<TruthPose>> TruthSpill::subset(const std::vector<Time>& stamps) const {
  std::vector<size_t> wanted;
  if (count_ == 0) return std::vector<TruthPose>{};
  wanted.push_back(0);
  wanted.push_back(count_ - 1);
  std::vector<TruthPose> one;
  for (const Time t : stamps) {
    // The first pose with stamp >= t (std::lower_bound's answer), by bisection on the file.
    size_t lo = 0, len = count_;
    while (len > 0) {
      const size_t half = len / 2;
      one.clear();
      if (Status s = read(lo + half, 1, one); !s.ok()) return s.error();
      if (one[0].stamp < t) {
        lo += half + 1;
        len -= half + 1;
      } else {
        len = half;
      }
    }
    if (lo < count_) wanted.push_back(lo);
    if (lo > 0) wanted.push_back(lo - 1);
  }
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  std::vector<TruthPose> out;
  out.reserve(wanted.size());
  for (const size_t i : wanted)
    if (Status s = read(i, 1, out); !s.ok()) return s.error();
  return out;
}

Status TruthSpill::for_each(const std::function<void(const TruthPose&)>& f) const {
  std::vector<TruthPose> block;
  for (size_t first = 0; first < written_; first += kBufferPoses) {
    block.clear();
    if (Status s = read(first, std::min(kBufferPoses, written_ - first), block); !s.ok()) return s;
    for (const TruthPose& p : block) f(p);
  }
  return {};
}

Status TruthSpill::for_each_shown(const std::function<void(const TruthPose&)>& f) const {
  Time last;
  bool first = true;
  return for_each([&](const TruthPose& p) {
    if (show(p.stamp, last, first)) f(p);
  });
}

int64_t TruthSpill::memory_bytes() const { return heap_bytes(buffer_); }

}  // namespace orthosonar::run
