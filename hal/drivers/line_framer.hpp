#pragma once
// Splits a byte stream into text lines ('\n', optional '\r'); over-long lines are dropped and
// counted as malformed (a device spewing garbage never grows the buffer without bound).
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace orthosonar::hal::drivers {

class LineFramer {
 public:
  explicit LineFramer(size_t max_line = 4096) : max_line_(max_line) {}
  void push(std::span<const uint8_t> bytes) {
    for (uint8_t b : bytes) {
      if (b == '\n') {
        if (!overflow_) lines_.push_back(std::move(cur_));
        cur_.clear();
        overflow_ = false;
      } else if (!overflow_) {
        cur_.push_back(static_cast<char>(b));
        if (cur_.size() > max_line_) {
          overflow_ = true;
          ++overlong_;
          cur_.clear();
        }
      }
    }
  }
  std::optional<std::string> pop() {
    if (next_ >= lines_.size()) {
      lines_.clear();
      next_ = 0;
      return std::nullopt;
    }
    std::string s = std::move(lines_[next_++]);
    if (!s.empty() && s.back() == '\r') s.pop_back();
    return s;
  }
  uint64_t overlong() const { return overlong_; }

 private:
  size_t max_line_;
  std::string cur_;
  bool overflow_ = false;
  std::vector<std::string> lines_;
  size_t next_ = 0;
  uint64_t overlong_ = 0;
};

}  // namespace orthosonar::hal::drivers
